/**
 * @file dtc3l.h
 * @brief Three-level direct torque control: comparators, sector, 19-vector table,
 *        neutral-point balancing and low-speed torque-ripple reduction.
 */
#ifndef DTC_DTC3L_H
#define DTC_DTC3L_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/num.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    real_t psi_ref_Wb;        /**< stator-flux reference, Wb */
    real_t premag_s;          /**< pre-magnetisation time before speed control, s */
    real_t flux_band_Wb;      /**< flux hysteresis band (half width), Wb */
    real_t torque_band_Nm;    /**< torque comparator band (half width of the inner level), N m */
    bool ripple_reduction;    /**< duty-split ripple reduction at low speed */
    real_t ripple_speed_max_rad_s; /**< apply ripple reduction below this |speed|, rad/s */
    real_t np_band_V;         /**< |vc1 - vc2| below which the small vector is left to alternate, V */
} dtc3l_cfg;

#ifdef __cplusplus
}
#endif

#endif /* DTC_DTC3L_H */
