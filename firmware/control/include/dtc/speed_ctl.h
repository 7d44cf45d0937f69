/**
 * @file speed_ctl.h
 * @brief The three speed controllers (IP, nominal, RBFN) behind one interface.
 *
 * Plant model of the speed loop (paper eq. 4-5): d(omega)/dt = A_n omega + B_n Te* + eps,
 * A_n = -B/J, B_n = K_T/J with K_T = 1 (the DTC makes Te follow Te*), so the
 * uncertainty eps is in rad/s^2 (mechanical).
 *
 * Sign convention (all controllers): e_x = X_d - X_q (reference minus estimate).
 * A braking load makes eps < 0, the speed drops, e_x > 0, the RBFN weights fall,
 * eps_hat goes negative and the torque command rises.
 *
 * Design notes, equations, discretisation and tuning: docs/speed_control.md.
 */
#ifndef DTC_SPEED_CTL_H
#define DTC_SPEED_CTL_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/motor_model.h"
#include "dtc/rbfn.h"
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
    real_t gamma_w;       /**< weight adaptation gain, (rad/s^2) / (rad/s) / s */
    real_t gamma_zeta;    /**< bound adaptation gain, (rad/s^2) / (rad/s) / s */
    real_t m_w;           /**< projection radius M_w on |W|, rad/s^2 */
    uint32_t n_nodes;     /**< number of nodes, 1..RBFN_NODES_MAX */
    real_t centre[RBFN_NODES_MAX]; /**< Gaussian centres m_q, rad/s of speed error */
    real_t width[RBFN_NODES_MAX];  /**< Gaussian widths sigma_q, rad/s (> 0) */
    real_t boundary_rad_s;         /**< boundary layer of the robust term; 0 = pure sign */
    real_t zeta_dead_zone_rad_s;   /**< |e_x| below this does not grow the bound */
    real_t zeta_max;               /**< ceiling of the adaptive bound, rad/s^2 */
    real_t zeta_leak;              /**< sigma-leakage of the bound, 1/s (0 = none) */
    rbfn_grid grid;                /**< derived (speed_cfg_derive): the uniform-grid basis constants */
} rbfn_cfg;

typedef struct {
    speed_mode mode;      /**< active controller (switchable while running) */
    real_t te_max_Nm;     /**< torque-command limit, N m */
    real_t ramp_rad_s2;   /**< speed-reference slew-rate limit, rad/s^2 (0 = none) */
    /** Reference model of the nominal and RBFN controllers: X_d and dX_d/dt are
     *  the states of d2x/dt2 = wn^2 (r - x) - 2 zeta wn dx/dt driven by the
     *  ramped reference r, i.e. the IP's own closed loop (eq. 1), so all three
     *  controllers ask for the same speed response. 0 = no model: X_d and
     *  dX_d/dt are taken from speed_in as they are (paper eq. 6/11 literally). */
    real_t ref_wn_rad_s;
    real_t ref_zeta;      /**< damping of the reference model */
    ip_cfg ip;
    nominal_cfg nominal;
    rbfn_cfg rbfn;
} speed_cfg;

/** Inputs of one speed-controller step. */
typedef struct {
    real_t omega_ref_rad_s;     /**< X_d: reference (after the ramp limiter), rad/s mechanical */
    real_t domega_ref_rad_s2;   /**< dX_d/dt, rad/s^2 */
    real_t omega_est_rad_s;     /**< X_q: estimated speed, rad/s mechanical */
    real_t te_limit_Nm;         /**< present torque limit, N m (field weakening, pull-out at the
                                     present flux: the supervision, ctl_supervise.c); 0 or less: te_max_Nm alone */
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

/** What the RBFN's learning half has to do (speed_rbfn_learn). */
enum rbfn_learn {
    RBFN_LEARN_NONE = 0,        /**< nothing commanded since the last learning */
    RBFN_LEARN_STEP = 1,        /**< the weight and bound updates of the last command */
    RBFN_LEARN_PROJECT = 2,     /**< limited in the winding-up direction: only keep |W| <= M_w */
};

/** RBFN controller state. */
typedef struct {
    real_t w[RBFN_NODES_MAX];   /**< output weights W */
    real_t zeta_bar;            /**< adaptive bound of the robust term, rad/s^2 */
    real_t z[RBFN_NODES_MAX];   /**< basis of the last command (for its learning), Z / z_scale */
    real_t z_scale;             /**< Z = z x z_scale (rbfn_grid_eval leaves the normalisation to the learning) */
    real_t e_learn;             /**< speed error e_x of the last command, rad/s */
    real_t w_norm;              /**< |W| after the last learning */
    uint32_t learn;             /**< enum rbfn_learn: the last command's learning, still to do */
} rbfn_state;

/** The speed controller: all three states, so switching mode is bumpless. */
typedef struct {
    speed_mode active;          /**< mode of the last step (a change resets the new one) */
    ip_state ip;
    rbfn_state rbfn;
    real_t ref_x_rad_s;         /**< reference-model speed X_d, rad/s */
    real_t ref_v_rad_s2;        /**< reference-model acceleration dX_d/dt, rad/s^2 */
    real_t te_last_Nm;          /**< torque command of the last step, N m (bumpless switch) */
} speed_ctl;

/** Error codes of speed_cfg_check() (negative, one per violated rule). */
enum speed_cfg_error {
    SPEED_CFG_OK = 0,
    SPEED_CFG_E_MODE = -1,      /**< mode is not one of speed_mode */
    SPEED_CFG_E_TE_MAX = -2,    /**< te_max_Nm not > 0 */
    SPEED_CFG_E_RAMP = -3,      /**< ramp_rad_s2 < 0 */
    SPEED_CFG_E_IP = -4,        /**< wn_rad_s or zeta not > 0 */
    SPEED_CFG_E_NOMINAL = -5,   /**< k_x not > 0 */
    SPEED_CFG_E_RBFN_GAIN = -6, /**< k not > 0, or gamma_w, gamma_zeta, boundary, dead zone, leak < 0 */
    SPEED_CFG_E_RBFN_NODES = -7,/**< n_nodes outside 1..RBFN_NODES_MAX or a width not > 0 */
    SPEED_CFG_E_RBFN_BOUND = -8,/**< m_w not > 0 or zeta_max < 0 */
    SPEED_CFG_E_MOTOR = -9,     /**< motor J not > 0 or B < 0 */
    SPEED_CFG_E_REF_MODEL = -10,/**< ref_wn_rad_s < 0, or ref_zeta not > 0 with a model */
};

/**
 * Fill @p cfg with the default tuning for motor @p m (the tuning that
 * reproduces the paper's CASE1/CASE2, docs/speed_control.md) and derive the
 * IP gains. ctl_cfg_default() calls this. Context: BG.
 */
void speed_cfg_default(speed_cfg *cfg, const motor_model *m);

/**
 * Size the RBFN to the drive: from the torque limit @p te_max_Nm (> 0) and
 * the inertia @p J_kgm2 (> 0), with r->n_nodes and r->gamma_w already set,
 * write r->m_w = 1.25 sqrt(n) te_max / J (every weight can hold the
 * acceleration of a load at the torque limit), and n centres evenly spaced
 * over +-e_span, e_span = (te_max / J) / sqrt(gamma_w) rad/s (the order of
 * the peak speed error of a load step at the torque limit), widths 0.75 x
 * the spacing; unused nodes are zeroed. speed_cfg_default() calls it; call it
 * again after changing te_max_Nm, J or gamma_w to keep any load up to the
 * torque limit learnable (docs/envelope.md). Context: BG.
 */
void speed_rbfn_size(rbfn_cfg *r, real_t te_max_Nm, real_t J_kgm2);

/** Compute derived gains (IP ki, kp from wn, zeta, J, B per eq. 3). Context: BG. */
void speed_cfg_derive(speed_cfg *cfg, const motor_model *m);

/**
 * Check a configuration before it is published.
 * @return SPEED_CFG_OK, or the first violated rule (enum speed_cfg_error).
 * The step functions stay safe (bounded loops, no division by zero) even
 * with a configuration that fails this check. Context: BG.
 */
int speed_cfg_check(const speed_cfg *cfg, const motor_model *m);

/** Initialise all controllers to zero state. Context: BG. */
void speed_ctl_init(speed_ctl *s, const speed_cfg *cfg);

/** Reset all controller states (weights to 0, bound to 0, integrator to @p te_now_Nm,
 *  reference model to rest at 0 rad/s). Context: ISR or BG. */
void speed_ctl_reset(speed_ctl *s, real_t te_now_Nm);

/** Put the reference model at rest at @p omega_rad_s (e.g. when restarting a
 *  spinning motor, together with the ramp state). Context: ISR or BG. */
void speed_ctl_set_ref(speed_ctl *s, real_t omega_rad_s);

/**
 * One speed-loop step with the controller selected by cfg->mode.
 * The IP uses in->omega_ref_rad_s directly; the nominal and RBFN controllers
 * use the reference model's X_d, dX_d/dt (see speed_cfg.ref_wn_rad_s). The
 * model runs in every mode, so a mode change finds it in step.
 * When cfg->mode differs from the mode of the previous step the new
 * controller is first initialised from the last torque command (bumpless).
 * A non-finite input gives a zero torque command and leaves the controller
 * states untouched; a non-finite result (a NaN gain) gives a zero command and
 * restarts the controllers from rest, so no NaN stays in a state.
 * @param dt_s step, s (the control period). Context: ISR.
 */
void speed_ctl_step(speed_ctl *s, const speed_cfg *cfg, const motor_model *m, real_t dt_s,
                    const speed_in *in, speed_out *out);

/**
 * speed_ctl_step in two halves, for a caller that spreads the RBFN's work
 * over two ticks: speed_ctl_command is speed_ctl_step without the RBFN's
 * weight and bound updates, which speed_ctl_learn then does (with step
 * @p dt_s; it writes out->w_norm and out->zeta_bar when it did them; nothing
 * for the IP and nominal controllers, which do all in the command). Call
 * speed_ctl_learn after each speed_ctl_command and before the next (a learning
 * still pending when the mode changes is dropped); the
 * controller's commands are then those of speed_ctl_step. Context: ISR.
 */
void speed_ctl_command(speed_ctl *s, const speed_cfg *cfg, const motor_model *m, real_t dt_s,
                       const speed_in *in, speed_out *out);
void speed_ctl_learn(speed_ctl *s, const speed_cfg *cfg, real_t dt_s, speed_out *out);

/**
 * Slew-rate limiter of the speed reference: moves @p prev_rad_s towards
 * @p target_rad_s by at most @p max_step_rad_s (>= 0; 0 or less means no limit,
 * the target is returned). Call once per period with max_step = ramp * dt;
 * dX_d/dt is then (result - prev) / dt. Pure; context: ANY.
 */
real_t speed_ref_ramp(real_t prev_rad_s, real_t target_rad_s, real_t max_step_rad_s);

/* ---- the individual controllers (used by speed_ctl_step; public for tests) ---- */

/**
 * IP step (eq. 1-3): Te* = integ - kp X, integ += ki e dt,
 * with conditional integration at the torque limit (anti-windup). Context: ISR.
 */
void speed_ip_step(ip_state *s, const ip_cfg *cfg, const motor_model *m, real_t te_max_Nm,
                   real_t dt_s, const speed_in *in, speed_out *out);

/** Initialise the IP integrator so that its next command equals @p te_now_Nm at speed @p omega_rad_s. Context: ISR or BG. */
void speed_ip_bumpless(ip_state *s, const ip_cfg *cfg, real_t te_now_Nm, real_t omega_rad_s);

/** Nominal step (eq. 6 with eps = 0). Stateless. Context: ISR. */
void speed_nominal_step(const nominal_cfg *cfg, const motor_model *m, real_t te_max_Nm,
                        const speed_in *in, speed_out *out);

/**
 * RBFN step (eq. 8-14, 21): output U = U_o + U_p limited to +-te_max_Nm
 * (>= 0, N m), then the weight and bound updates (frozen in the winding-up
 * direction while the command is limited). Context: ISR.
 */
void speed_rbfn_step(rbfn_state *s, const rbfn_cfg *cfg, const motor_model *m, real_t te_max_Nm,
                     real_t dt_s, const speed_in *in, speed_out *out);

/**
 * The RBFN step in two halves, for a caller that spreads them over two ticks
 * (te_max_Nm >= 0, N m, as for speed_rbfn_step):
 * speed_rbfn_command computes the basis, the output and the limited command
 * (out: te_ref_Nm, eps_hat; w_norm and zeta_bar of the last learning) and
 * keeps the basis and error; speed_rbfn_learn then does that command's weight
 * and bound updates (or only the projection, anti-windup) with step @p dt_s
 * and, if it did one, writes out->w_norm and out->zeta_bar. It must run after
 * each command and before the next; speed_rbfn_step is the two in a row.
 * Context: ISR.
 */
void speed_rbfn_command(rbfn_state *s, const rbfn_cfg *cfg, const motor_model *m, real_t te_max_Nm,
                        const speed_in *in, speed_out *out);
void speed_rbfn_learn(rbfn_state *s, const rbfn_cfg *cfg, real_t dt_s, speed_out *out);

/**
 * Initialise the RBFN so that its next command at input @p in equals
 * @p te_now_Nm: bound to 0, all weights equal to the eps_hat that gives that
 * command (projected onto |W| <= M_w). Context: ISR or BG.
 */
void speed_rbfn_bumpless(rbfn_state *s, const rbfn_cfg *cfg, const motor_model *m,
                         real_t te_now_Nm, const speed_in *in);

#ifdef __cplusplus
}
#endif

#endif /* DTC_SPEED_CTL_H */
