/**
 * @file motor_model.h
 * @brief Nominal induction-motor parameters as the firmware knows them.
 */
#ifndef DTC_MOTOR_MODEL_H
#define DTC_MOTOR_MODEL_H

#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Nominal T-equivalent parameters (stator-referred) and mechanics. */
typedef struct {
    real_t Rs_ohm;        /**< stator resistance, ohm */
    real_t Rr_ohm;        /**< rotor resistance, ohm */
    real_t Ls_H;          /**< stator inductance Lls + Lm, H */
    real_t Lr_H;          /**< rotor inductance Llr + Lm, H */
    real_t Lm_H;          /**< magnetising inductance, H */
    real_t pole_pairs;    /**< p */
    real_t J_kgm2;        /**< nominal inertia, kg m^2 */
    real_t B_Nms;         /**< nominal viscous friction, N m s/rad */
} motor_model;

#ifdef __cplusplus
}
#endif

#endif /* DTC_MOTOR_MODEL_H */
