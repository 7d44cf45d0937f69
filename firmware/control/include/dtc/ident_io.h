/**
 * @file ident_io.h
 * @brief What the identification run and the drive exchange every control
 *        tick (dtc/ident.h: ident_step).
 */
#ifndef DTC_IDENT_IO_H
#define DTC_IDENT_IO_H

#include <stdbool.h>

#include "dtc/num.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** This tick's inputs. */
typedef struct {
    real_t i_abc_A[3];     /**< phase currents sampled at t_k, A */
    real_t vc1_V, vc2_V;   /**< capacitor voltages sampled at t_k, V */
    real_t v_ab_V[2];      /**< stator voltage (alpha, beta) the inverter applies from t_k to t_{k+1}
                                (the actuation latched at the last tick), as the drive reconstructs it
                                from the states, the capacitor voltages, the device drops and the
                                dead time, V */
    real_t omega_m_rad_s;  /**< the drive's estimate of the mechanical speed, rad/s (rotating part) */
    real_t psi_s_Wb[2];    /**< the drive's observer stator flux at t_k, Wb (seeds the voltage model
                                of the rotating part; zeros will do, at the cost of a slower start) */
    bool run;              /**< the run command stands: false on a disable, a quick stop, a lost master */
    bool fault;            /**< the drive has latched a fault */
    bool control_running;  /**< the drive's own control is magnetised and running (rotating part) */
} ident_in;

/** What the drive does with this tick. */
typedef enum {
    IDENT_OUT_OFF = 0,     /**< gates off now */
    IDENT_OUT_ACTUATE = 1, /**< latch ident_out.act for t_{k+1}..t_{k+2}, gates on */
    IDENT_OUT_TORQUE = 2,  /**< the drive's own control with the torque command te_ref_Nm (no speed loop) */
    IDENT_OUT_SPEED = 3,   /**< the drive's own control with the speed reference speed_ref_rad_s */
} ident_out_mode;

/** This tick's output. */
typedef struct {
    ident_out_mode mode;
    hal_actuation act;      /**< IDENT_OUT_ACTUATE: the vectors and duty for the next period */
    real_t te_ref_Nm;       /**< IDENT_OUT_TORQUE: the torque command, N m */
    real_t speed_ref_rad_s; /**< IDENT_OUT_SPEED: the mechanical speed reference, rad/s */
} ident_out;

#ifdef __cplusplus
}
#endif

#endif /* DTC_IDENT_IO_H */
