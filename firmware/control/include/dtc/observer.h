/**
 * @file observer.h
 * @brief Kubota-style adaptive full-order flux observer with speed and
 *        stator-resistance adaptation, discretised for the control period.
 *
 * Model (stationary alpha-beta frame, amplitude-invariant Clarke, written with
 * complex numbers x = x_alpha + j x_beta; omega is the ELECTRICAL rotor speed):
 *
 *   d is/dt    = -(Rs b + a_r) is + c (1/Tr - j omega) psi_r + b v
 *   d psi_r/dt =  (Lm/Tr) is      + (-1/Tr + j omega) psi_r
 *
 * with b = 1/(sigma Ls), a_r = (1 - sigma)/(sigma Tr), c = Lm/(sigma Ls Lr),
 * Tr = Lr/Rr, sigma = 1 - Lm^2/(Ls Lr). The observer adds G (is_hat - is);
 * G puts the observer poles at k times the motor poles (Kubota 1993, exact
 * for this structure). Adaptation (e = is - is_hat):
 *
 *   omega_hat  = kp eps + ki integral(eps),  eps = Im(conj(e') psi_r_hat) (= e_alpha psi_r_beta_hat -
 *                e_beta psi_r_alpha_hat for e' = e), e' = e exp(-j phi),
 *                phi = sgn(omega_hat) regen_angle shape(|omega_hat| / regen_speed) below regen_speed
 *                while the estimated torque and the torque command both brake the rotation,
 *                else 0; shape 0.4 at standstill, 1 from 0.2 to 0.45, 0 at 1 (observer.c)
 *   dRs_hat/dt = -ki_rs (e . is_hat)
 *
 * Why the error is rotated at low speed: with the plain law (phi = 0) the
 * speed adaptation of this observer is unstable in the regenerating mode at
 * low stator frequency (a load driving the motor at 300 rpm with rated torque
 * ran away). Rotating the current error that feeds the speed law moves the
 * unstable region away (the idea of Hinkkanen and Luomi, "Stabilization of
 * regenerating-mode operation in sensorless induction motor drives by
 * full-order flux observer design", IEEE TIE 2004; the angle and its fade
 * here were chosen by the SIL capability sweep, docs/envelope.md section 6).
 * Near zero stator frequency no law helps: the machine is not observable there,
 * so the drive lowers the flux until the stator frequency opposes the rotation
 * (ctl_supervise.c, regen_flux_factor; regen_low_flux), and the rotation is then a
 * quarter of its angle (found on the capability sweep, docs/envelope.md section 6).
 *
 * Discretisation: the 2x2 complex system is advanced over one period with the
 * matrix exponential of the zero-order-hold step expanded to fourth order
 * (Horner form): x+ = x + T (y + T/2 A (y + T/3 A (y + T/4 A y))), y = A x + u.
 * The local error, about (|lambda| T)^5 / 120, is 2e-8 at 60 Hz and 200 us
 * (6e-7 at 120 Hz), so the rotating part keeps its phase at rated frequency;
 * forward Euler, first order, drifts by percents within a few cycles
 * (tests/unit/test_observer.cpp compares both with the exact ZOH solution).
 *
 * Timing: called at tick k with the current sampled at t_k and the voltage
 * that the inverter applies from t_k to t_{k+1} (the actuation latched at tick
 * k-1), the step returns the estimates at t_k and advances the state to
 * t_{k+1}; the advanced state is the one-period-ahead prediction the DTC
 * selects on (delay compensation).
 */
#ifndef DTC_OBSERVER_H
#define DTC_OBSERVER_H

#include <stdbool.h>

#include "dtc/motor_model.h"
#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Coefficients derived from the motor model (observer_cfg_derive). */
typedef struct {
    real_t b;             /**< 1/(sigma Ls), 1/H */
    real_t a_r;           /**< (1 - sigma)/(sigma Tr), 1/s */
    real_t c;             /**< Lm/(sigma Ls Lr), 1/H */
    real_t inv_tr;        /**< 1/Tr = Rr/Lr, 1/s */
    real_t lm_tr;         /**< Lm/Tr, ohm */
    real_t lm_lr;         /**< Lm/Lr */
    real_t sigma_ls;      /**< sigma Ls, H */
    real_t inv_c;         /**< 1/c = sigma Ls Lr / Lm, H (Kubota gain) */
    real_t kt;            /**< 1.5 p Lm/Lr: Te = kt (psi_r x is), N m/(Wb A) */
    real_t pole_pairs;    /**< p */
    real_t inv_pole_pairs; /**< 1/p */
    real_t rs_nom_ohm;    /**< nominal Rs, ohm (reset value of the adaptation) */
    real_t rs_min_ohm;    /**< lower clamp of the Rs adaptation, ohm */
    real_t rs_max_ohm;    /**< upper clamp of the Rs adaptation, ohm */
    real_t period_s;      /**< step T, s */
    real_t lpf_alpha;     /**< speed low-pass: 1 - exp(-2 pi f T), 0..1 */
    real_t omega_max_rad_s; /**< clamp of the electrical speed estimate, rad/s */
    real_t inv_regen_speed; /**< 1 / regen_speed_rad_s, s/rad */
    /* per-configuration products the step would otherwise form every tick */
    real_t ki_speed_T;    /**< ki_speed x T, (rad/s) / (A Wb) */
    real_t ki_rs_T;       /**< ki_rs x T, ohm / A^2 */
    real_t gain_k1;       /**< k_gain - 1 (Kubota gain) */
    real_t gain_k21;      /**< k_gain^2 - 1 */
    real_t gain_inv_c_k1; /**< inv_c x (k_gain - 1), H */
    real_t kt_b;          /**< kt x b: dTe/dt per volt per Wb of rotor flux, N m/(s V Wb) */
    real_t c_inv_tr;      /**< c x inv_tr: real part of the model's a12, 1/(H s) */
    real_t nom_a11;       /**< the model's a11 = -(Rs b + a_r) at rs_nom_ohm, 1/s */
    real_t nom_g_is0;     /**< Re g_is at rs_nom_ohm (observer_gain), 1/s */
    real_t nom_g_psi0;    /**< Re g_psi at rs_nom_ohm (observer_gain), ohm */
    real_t nom_kt_a11_tr; /**< kt (a11 - 1/Tr) at rs_nom_ohm: the torque slope's part in psi_r x is, N m/(s Wb A) */
    real_t one_minus_lpf_alpha; /**< 1 - lpf_alpha */
    real_t lpf_alpha_pp;  /**< lpf_alpha / p: the speed low-pass's input weight on omega_e */
    real_t h_T[3];        /**< T/4, T/3, T/2 (as T x 0.25, 0.333333333, 0.5): the ZOH series' steps, s */
    real_t regen_cos[2];  /**< cos of the regenerating-mode rotation on its plateau (observer.c,
                               rotate_for_regeneration), [normal, regen_low_flux] */
    real_t regen_sin[2];  /**< sin of that rotation for omega_e >= 0 (negated below), [normal, regen_low_flux] */
} observer_model;

typedef struct {
    real_t k_gain;            /**< observer pole multiplier k (poles = k * motor poles), >= 1 */
    real_t kp_speed;          /**< speed adaptation proportional gain, (rad/s) / (A Wb) (electrical) */
    real_t ki_speed;          /**< speed adaptation integral gain, (rad/s^2) / (A Wb) (electrical) */
    real_t ki_rs;             /**< stator-resistance adaptation gain, ohm/(s A^2) (0 = off) */
    real_t regen_angle_rad;   /**< largest rotation of the current error in the speed law, rad,
                                   0..1.5 (0 = off); see rotate_for_regeneration in observer.c */
    real_t regen_speed_rad_s; /**< |omega_e| (electrical) where that rotation has faded to 0, rad/s, > 0 */
    real_t speed_lpf_hz;      /**< low-pass filter of the estimated speed for the speed loop, Hz (0 = none) */
    observer_model m;         /**< derived by observer_cfg_derive(); do not edit */
} observer_cfg;

/** Observer state (caller owned). Complex quantities as [alpha, beta]. */
typedef struct {
    real_t is_A[2];           /**< estimated stator current, A (t_{k+1} after a step) */
    real_t psi_r_Wb[2];       /**< estimated rotor flux, Wb (t_{k+1} after a step) */
    real_t omega_e_rad_s;     /**< adapted electrical rotor speed, rad/s */
    real_t omega_int_rad_s;   /**< integral part of the speed adaptation, rad/s */
    real_t omega_m_filt_rad_s;/**< low-pass filtered mechanical speed, rad/s */
    real_t rs_ohm;            /**< adapted stator resistance, ohm */
    real_t te_cmd_Nm;         /**< torque the drive commands in this period, N m; set by the caller
                                   before observer_step (0: none; gates the regenerating-mode rotation) */
    bool regen_low_flux;      /**< set by the caller: the flux is lowered so that the stator frequency
                                   opposes the rotation (ctl_supervise.c, regen_flux_factor); the
                                   regenerating-mode rotation is then REGEN_LOW_FLUX_SCALE of its angle */
} observer;

/** What a step returns: estimates at t_k and the prediction for t_{k+1}. */
typedef struct {
    /* at t_k (the sample instant) */
    real_t psi_s_Wb[2];       /**< stator flux, Wb (sigma Ls is_meas + Lm/Lr psi_r_hat) */
    real_t psi_s_abs_Wb;      /**< |psi_s|, Wb */
    real_t te_Nm;             /**< torque kt (psi_r_hat x is_meas), N m */
    real_t omega_m_rad_s;     /**< mechanical speed estimate, filtered, rad/s */
    /* predicted for t_{k+1} with the voltage of the coming period. (The
     * unfiltered speed and the predicted rotor flux are the state's
     * observer.omega_e_rad_s and psi_r_Wb, not copied here, nor is the
     * current error, which nothing reads.) */
    real_t is_pred_A[2];      /**< stator current, A */
    real_t psi_s_pred_Wb[2];  /**< stator flux, Wb */
    real_t te_pred_Nm;        /**< torque, N m */
    real_t dte0_Nm_s;         /**< dTe/dt at t_{k+1} under a zero voltage, N m/s */
    real_t dte_dv[2];         /**< dTe/dt per volt of v_alpha, v_beta at t_{k+1}, N m/(s V) */
} observer_out;

/**
 * Derive the model coefficients of @p cfg from @p m and the period.
 * Requires Ls > Lm, Lr > Lm, all parameters > 0. Context: BG.
 */
void observer_cfg_derive(observer_cfg *cfg, const motor_model *m, real_t period_s);

/** Initialise @p s: zero flux and current, zero speed, nominal Rs. Context: BG or ISR. */
void observer_init(observer *s, const observer_cfg *cfg);

/**
 * Kubota gain for electrical speed @p omega_e_rad_s and resistance @p rs_ohm:
 * g_is = g1 + j g2 (on the current equation), g_psi = g3 + j g4 (on the
 * rotor-flux equation), both multiplying (is_hat - is). Pure; context: ANY.
 */
void observer_gain(const observer_cfg *cfg, real_t omega_e_rad_s, real_t rs_ohm,
                   real_t g_is[2], real_t g_psi[2]);

/**
 * The discretised model alone: advance x = [is_alpha, is_beta, psi_r_alpha,
 * psi_r_beta] over one period at the fixed electrical speed @p omega_e_rad_s
 * with the constant inputs u_is (V/H -> A/s, added to d is/dt) and u_psi
 * (added to d psi_r/dt). observer_step uses it with u_is = b v - g_is e,
 * u_psi = -g_psi e. Pure; context: ANY.
 */
void observer_model_advance(const observer_model *m, real_t rs_ohm, real_t omega_e_rad_s,
                            const real_t x[4], const real_t u_is[2], const real_t u_psi[2],
                            real_t x_next[4]);

/**
 * One observer period, the inputs as scalars (they arrive in FPU registers:
 * no stores and loads through the stack). Context: ISR.
 * @param is_a_A, is_b_A  stator current sampled at t_k, alpha and beta, A
 * @param v_a_V, v_b_V    mean stator voltage applied from t_k to t_{k+1}, alpha and beta, V
 * @param[out] out        estimates at t_k and the prediction for t_{k+1}
 * @p s, @p cfg and @p out are distinct objects (the definition declares them restrict).
 */
void observer_step_ab(observer *s, const observer_cfg *cfg, real_t is_a_A, real_t is_b_A, real_t v_a_V, real_t v_b_V,
                      observer_out *out);

/**
 * One observer period (observer_step_ab with the inputs as alpha-beta pairs). Context: ISR.
 * @param is_meas_A   stator current sampled at t_k, alpha-beta, A
 * @param v_applied_V mean stator voltage applied from t_k to t_{k+1}, alpha-beta, V
 * @param[out] out    estimates at t_k and the prediction for t_{k+1}
 */
static inline void observer_step(observer *s, const observer_cfg *cfg, const real_t is_meas_A[2],
                                 const real_t v_applied_V[2], observer_out *out)
{
    observer_step_ab(s, cfg, is_meas_A[0], is_meas_A[1], v_applied_V[0], v_applied_V[1], out);
}

#ifdef __cplusplus
}
#endif

#endif /* DTC_OBSERVER_H */
