/**
 * @file speed_rbfn.c
 * @brief RBFN speed controller (paper eq. 8-14, 21).
 *
 * U = U_o + U_p, limited to +-te_max:
 *   U_o = B_n^-1 [dX_d/dt - A_n X - eps_hat + K e]          (eq. 11)
 *   U_p = B_n^-1 zeta_bar s(e),  s = sgn or sat(e / phi)    (eq. 13)
 * then, for the next tick (forward Euler):
 *   W        <- Proj_{|W| <= M_w}(W - gamma_w e Z T)          (eq. 14, 21)
 *   zeta_bar <- min(zeta_max, zeta_bar
 *               + T [gamma_zeta max(|e| - dead_zone, 0) - leak zeta_bar])
 * Both updates are skipped while the command is limited and the error would
 * push it further into the limit (they would only wind up).
 * The step is two halves (speed_rbfn_command, speed_rbfn_learn), so that a
 * caller can put them in different ticks (dtc/ctl_schedule.h); the learning uses the basis
 * and error of the command and must run before the next command.
 * e = X_d - X (rad/s), eps and eps_hat in rad/s^2, B_n = 1/J, A_n = -B/J.
 * Design and tuning: docs/speed_control.md.
 */
#include "dtc/speed_ctl.h"

#include "dtc/rbfn.h"

static uint32_t node_count(const rbfn_cfg *cfg)
{
    uint32_t n = cfg->n_nodes;
    if (n - 1u >= RBFN_NODES_MAX) /* 0 wraps round: one compare for 1..RBFN_NODES_MAX */
        n = n == 0u ? 1u : RBFN_NODES_MAX;
    return n;
}

/* The robust term's switching function: sgn(e), or sat(e / phi) inside the
 * boundary layer |e| < phi (continuous, so no chattering at e = 0). */
static real_t robust_switch(real_t e, real_t phi)
{
    if (phi > R(0.0)) {
        /* num_limit(e / phi, 1) with the tests on e, the same bits: outside
         * [-phi, phi] the limit gives +-1 however e / phi rounds; inside, the
         * rounded quotient stays within [-1, 1]; the division only inside the
         * layer. */
        if (e > phi)
            return R(1.0);
        if (e < -phi)
            return R(-1.0);
        return num_div(e, phi);
    }
    return num_sign(e);
}

void speed_rbfn_command(rbfn_state *s, const rbfn_cfg *cfg, const motor_model *m, real_t te_max_Nm,
                        const speed_in *in, speed_out *out)
{
    uint32_t n = node_count(cfg);
    real_t x = in->omega_est_rad_s;
    real_t e = in->omega_ref_rad_s - x;

    real_t eps_hat;
    if (cfg->grid.n == n) { /* derived for this configuration: one exp() instead of n */
        eps_hat = rbfn_grid_eval(&cfg->grid, cfg->centre, n, e, s->w, s->z, &s->z_scale);
    } else {
        rbfn_basis(cfg->centre, cfg->width, n, e, s->z);
        s->z_scale = R(1.0);
        eps_hat = rbfn_output(s->w, s->z, n);
    }
    real_t robust = num_mul(s->zeta_bar, robust_switch(e, cfg->boundary_rad_s));

    /* B_n^-1 [...] = J [...]; -A_n X / B_n = B X. */
    real_t acc = num_mac(cfg->k, e, in->domega_ref_rad_s2 - eps_hat) + robust; /* rad/s^2 */
    real_t u = num_mac(m->J_kgm2, acc, num_mul(m->B_Nms, x));
    /* te = num_limit(u, te_max_Nm), and adapt unless limited in the direction
     * the error pushes (anti-windup): at +limit with e > 0 both laws would
     * raise U further. Written as one chain of tests, each compare once;
     * te_max_Nm >= 0 (speed_ctl_run clamps it), so at most one limit holds. */
    real_t te = u;
    uint32_t learn = RBFN_LEARN_STEP;
    if (u < -te_max_Nm) {
        te = -te_max_Nm;
        if (e < R(0.0))
            learn = RBFN_LEARN_PROJECT;
    } else if (u > te_max_Nm) {
        te = te_max_Nm;
        if (e > R(0.0))
            learn = RBFN_LEARN_PROJECT;
    }
    s->e_learn = e;
    s->learn = learn;

    out->te_ref_Nm = te;
    out->eps_hat = eps_hat;
    out->w_norm = s->w_norm;
    out->zeta_bar = s->zeta_bar;
}

void speed_rbfn_learn(rbfn_state *s, const rbfn_cfg *cfg, real_t dt_s, speed_out *out)
{
    uint32_t n = node_count(cfg);
    real_t e = s->e_learn;
    if (s->learn == RBFN_LEARN_STEP) {
        s->w_norm = rbfn_update_projected(s->w, s->z, n, e, num_mul(num_mul(cfg->gamma_w, dt_s), s->z_scale), cfg->m_w);
        real_t excess = num_abs(e) - cfg->zeta_dead_zone_rad_s;
        real_t grow = excess > R(0.0) ? num_mul(cfg->gamma_zeta, excess) : R(0.0);
        real_t zb = s->zeta_bar + num_mul(grow - num_mul(cfg->zeta_leak, s->zeta_bar), dt_s);
        s->zeta_bar = num_sat(zb, R(0.0), cfg->zeta_max > R(0.0) ? cfg->zeta_max : R(0.0));
    } else if (s->learn == RBFN_LEARN_PROJECT) {
        s->w_norm = rbfn_project(s->w, n, cfg->m_w); /* keeps the invariant if M_w was lowered */
    } else {
        return; /* nothing commanded since the last learning */
    }
    s->learn = RBFN_LEARN_NONE;
    out->w_norm = s->w_norm;
    out->zeta_bar = s->zeta_bar;
}

void speed_rbfn_step(rbfn_state *s, const rbfn_cfg *cfg, const motor_model *m, real_t te_max_Nm,
                     real_t dt_s, const speed_in *in, speed_out *out)
{
    speed_rbfn_command(s, cfg, m, te_max_Nm, in, out);
    speed_rbfn_learn(s, cfg, dt_s, out);
}

void speed_rbfn_bumpless(rbfn_state *s, const rbfn_cfg *cfg, const motor_model *m,
                         real_t te_now_Nm, const speed_in *in)
{
    uint32_t n = node_count(cfg);
    real_t x = in->omega_est_rad_s;
    real_t e = in->omega_ref_rad_s - x;
    /* With zeta_bar = 0 and equal weights w (the z_q sum to 1, so eps_hat = w):
     * te_now = J (dX_d/dt - w + K e) + B X  =>  w = dX_d/dt + K e - (te_now - B X) / J. */
    real_t w = in->domega_ref_rad_s2 + num_mul(cfg->k, e) -
               num_div(te_now_Nm - num_mul(m->B_Nms, x), m->J_kgm2 > R(0.0) ? m->J_kgm2 : R(1.0));
    for (uint32_t q = 0u; q < RBFN_NODES_MAX; q++)
        s->w[q] = q < n ? w : R(0.0);
    s->w_norm = rbfn_project(s->w, n, cfg->m_w);
    s->zeta_bar = R(0.0);
    s->learn = RBFN_LEARN_NONE; /* a step commanded before the switch learns nothing now */
}
