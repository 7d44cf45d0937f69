/**
 * @file speed_ctl.h
 * @brief The three speed controllers (IP, nominal, RBFN) behind one interface.
 *
 * Plant model of the speed loop (paper eq. 4-5): d(omega)/dt = A_n omega + B_n Te* + eps,
 * A_n = -B/J, B_n = K_T/J with K_T = 1 (the DTC makes Te follow Te*), so the
 * uncertainty eps is in rad/s^2 (mechanical).
 */
#ifndef DTC_SPEED_CTL_H
#define DTC_SPEED_CTL_H

#include <stdint.h>

#include "dtc/motor_model.h"
#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RBFN_NODES_MAX 9 /**< largest number of Gaussian nodes */

typedef enum {
    SPEED_MODE_IP = 0,
    SPEED_MODE_NOMINAL = 1,
    SPEED_MODE_RBFN = 2,
} speed_mode;

/** IP controller (eq. 1-3). */
typedef struct {
    real_t wn_rad_s;      /**< closed-loop natural frequency, rad/s */
    real_t zeta;          /**< damping ratio */
    real_t ki;            /**< derived (eq. 3): N m / rad */
    real_t kp;            /**< derived (eq. 3): N m s / rad */
} ip_cfg;

/** Nominal controller (eq. 6 with eps = 0). */
typedef struct {
    real_t k_x;           /**< error gain K_x, 1/s */
} nominal_cfg;

/** RBFN controller (eq. 8-14, 21). Input of the network: the speed error e_x, rad/s. */
typedef struct {
    real_t k;             /**< error gain K, 1/s */
    real_t gamma_w;       /**< weight adaptation gain */
    real_t gamma_zeta;    /**< bound adaptation gain */
    real_t m_w;           /**< projection radius M_w on |W| */
    uint32_t n_nodes;     /**< number of nodes, 1..RBFN_NODES_MAX */
    real_t centre[RBFN_NODES_MAX]; /**< Gaussian centres m_q, rad/s of speed error */
    real_t width[RBFN_NODES_MAX];  /**< Gaussian widths sigma_q, rad/s (> 0) */
    real_t boundary_rad_s;         /**< boundary layer of the robust term; 0 = pure sign */
    real_t zeta_dead_zone_rad_s;   /**< |e_x| below this does not grow the bound */
    real_t zeta_max;               /**< ceiling of the adaptive bound, rad/s^2 */
} rbfn_cfg;

typedef struct {
    speed_mode mode;      /**< active controller (switchable while running) */
    real_t te_max_Nm;     /**< torque-command limit, N m */
    real_t ramp_rad_s2;   /**< speed-reference slew-rate limit, rad/s^2 (0 = none) */
    ip_cfg ip;
    nominal_cfg nominal;
    rbfn_cfg rbfn;
} speed_cfg;

/** Inputs of one speed-controller step. */
typedef struct {
    real_t omega_ref_rad_s;     /**< X_d: reference (after the ramp limiter), rad/s mechanical */
    real_t domega_ref_rad_s2;   /**< dX_d/dt, rad/s^2 */
    real_t omega_est_rad_s;     /**< X_q: estimated speed, rad/s mechanical */
} speed_in;

/** Outputs of one speed-controller step. */
typedef struct {
    real_t te_ref_Nm;           /**< torque command, limited to +-te_max_Nm */
    real_t eps_hat;             /**< RBFN estimate of eps, rad/s^2 (0 for IP and nominal) */
    real_t w_norm;              /**< |W| (0 for IP and nominal) */
    real_t zeta_bar;            /**< adaptive bound (0 for IP and nominal) */
} speed_out;

/** IP controller state. */
typedef struct {
    real_t integ_Nm;            /**< integral part of the torque command, N m */
} ip_state;

/** RBFN controller state. */
typedef struct {
    real_t w[RBFN_NODES_MAX];   /**< output weights W */
    real_t zeta_bar;            /**< adaptive bound of the robust term, rad/s^2 */
    real_t eps_hat;             /**< last network output, rad/s^2 */
} rbfn_state;

/** The speed controller: all three states, so switching mode is bumpless. */
typedef struct {
    speed_mode active;          /**< mode of the last step (a change resets the new one) */
    ip_state ip;
    rbfn_state rbfn;
} speed_ctl;

/** Compute derived gains (IP ki, kp from wn, zeta, J, B per eq. 3). Context: BG. */
void speed_cfg_derive(speed_cfg *cfg, const motor_model *m);

/** Initialise all controllers to zero state. Context: BG. */
void speed_ctl_init(speed_ctl *s, const speed_cfg *cfg);

/** Reset all controller states (weights to 0, bound to 0, integrator to @p te_now_Nm). Context: ISR or BG. */
void speed_ctl_reset(speed_ctl *s, real_t te_now_Nm);

/**
 * One speed-loop step with the controller selected by cfg->mode.
 * @param dt_s step, s (the control period). Context: ISR.
 */
void speed_ctl_step(speed_ctl *s, const speed_cfg *cfg, const motor_model *m, real_t dt_s,
                    const speed_in *in, speed_out *out);

#ifdef __cplusplus
}
#endif

#endif /* DTC_SPEED_CTL_H */
