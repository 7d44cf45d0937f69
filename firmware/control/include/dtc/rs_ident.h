/**
 * @file rs_ident.h
 * @brief Stator resistance identified while magnetising, before each run.
 *
 * Why at standstill: running, Rs and the speed share the observer's one
 * current error and at low stator frequency they are not separately
 * observable (a running Rs law broke the speed estimate, docs/envelope.md
 * section 6). While the flux is built before a run the rotor is at rest and
 * the torque is zero; the stator equation is then linear in Rs with nothing
 * unknown but Rs:
 *
 *   v = Rs is + sigma Ls dis/dt + (Lm/Lr) dpsi_r/dt,
 *   dpsi_r/dt = (Lm is - psi_r) / Tr            (current model, omega = 0)
 *
 * Integrated over the magnetising interval (is and psi_r start at zero):
 *
 *   integral(v) - sigma Ls is(t) - (Lm/Lr) psi_r(t) = Rs integral(is),
 *
 * solved for Rs by least squares over both axes. The stator warms with a time
 * constant of many minutes, so the value found at each start holds for the
 * run. A value within rs_ident_tol of the model's Rs is not applied: the
 * model's Rs is kept exactly (a correctly commissioned drive runs as before);
 * a winding warmer (or colder) than that is corrected. Not applied either:
 * values outside 0.5..2 x the model's Rs, too little current to judge, or a
 * rotor that turned (estimated speed beyond RS_IDENT_MAX_SPEED_RAD_S, judged
 * once the flux is built: before that the speed estimate has no flux to work
 * with and swings without meaning).
 *
 * Assumed: is and psi_r are zero at the start. A restart while the rotor flux
 * of the last run has not decayed (Tr = 0.27 s for the 10 hp motor) reads Rs
 * off by up to +-6 % 0.1 s after a stop, +-3 % after 0.3 s, +-1 % after 0.6 s
 * (inside the tolerance on its own).
 */
#ifndef DTC_RS_IDENT_H
#define DTC_RS_IDENT_H

#include <stdbool.h>

#include "dtc/motor_model.h"
#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Per-configuration constants (rs_ident_cfg_derive). */
typedef struct {
    real_t tol_frac;        /**< |Rs_id / Rs_model - 1| at or below which Rs_model is kept, 0..1 */
    real_t rs_model_ohm;    /**< the motor model's Rs, ohm */
    real_t sigma_ls_H;      /**< sigma Ls, H */
    real_t lm_H;            /**< Lm, H */
    real_t lm_lr;           /**< Lm / Lr */
    real_t T_over_tr;       /**< period / Tr */
    real_t period_s;        /**< control period, s */
    real_t half_period_s;   /**< period_s / 2 (the trapezoid's weight), s */
} rs_ident_cfg;

/** Accumulators of one magnetising interval (caller owned). */
typedef struct {
    real_t v_int_Vs[2];     /**< integral of the applied voltage, V s */
    real_t i_int_As[2];     /**< integral of the stator current, A s */
    real_t is_A[2];         /**< the last stator current, A */
    real_t psi_r_Wb[2];     /**< current-model rotor flux at standstill, Wb */
    real_t speed_max_rad_s; /**< largest |estimated electrical speed| once the flux is built, rad/s */
    real_t t_s;             /**< time since the start of the interval, s */
} rs_ident;

/** Constants from the motor model, the period and the tolerance. Context: BG. */
void rs_ident_cfg_derive(rs_ident_cfg *c, const motor_model *m, real_t period_s, real_t tol_frac);

/** Start a new interval (at the start of magnetising). Context: ISR or BG. */
void rs_ident_reset(rs_ident *s);

/**
 * One period of magnetising: @p v_V the voltage applied over the period that
 * starts at the sample, @p is_A the current sampled at its start (alpha-beta),
 * @p omega_e_rad_s the observer's speed estimate. ~30 operations. Context: ISR.
 */
void rs_ident_step(rs_ident *s, const rs_ident_cfg *c, const real_t v_V[2], const real_t is_A[2],
                   real_t omega_e_rad_s);

/**
 * The stator resistance to run with, ohm: the identified one when it is
 * credible and differs from the model's by more than tol_frac, else the
 * model's exactly. Context: ISR (at the end of magnetising) or BG.
 */
real_t rs_ident_result(const rs_ident *s, const rs_ident_cfg *c);

#ifdef __cplusplus
}
#endif

#endif /* DTC_RS_IDENT_H */
