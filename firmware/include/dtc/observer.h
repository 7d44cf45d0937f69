/**
 * @file observer.h
 * @brief Kubota-style adaptive full-order flux observer with speed and
 *        stator-resistance adaptation, discretised for the control period.
 */
#ifndef DTC_OBSERVER_H
#define DTC_OBSERVER_H

#include "dtc/motor_model.h"
#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    real_t k_gain;            /**< observer pole multiplier k (poles = k * motor poles), >= 1 */
    real_t kp_speed;          /**< speed adaptation proportional gain */
    real_t ki_speed;          /**< speed adaptation integral gain */
    real_t ki_rs;             /**< stator-resistance adaptation gain (0 = off) */
    real_t speed_lpf_hz;      /**< low-pass filter of the estimated speed for the speed loop, Hz */
} observer_cfg;

#ifdef __cplusplus
}
#endif

#endif /* DTC_OBSERVER_H */
