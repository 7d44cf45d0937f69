/**
 * @file speed_ctl.c
 * @brief Speed-loop front end: defaults, derived gains, checks, init/reset,
 *        the mode dispatch with bumpless switching, and the reference ramp.
 */
#include "dtc/speed_ctl.h"

#include <stdbool.h>
#include <string.h>

/* Screen NaN and infinities without libm classification macros (x - x is
 * 0 only for finite x). */
static int is_finite(real_t x) { return (x - x) == R(0.0); }

/* All of three finite, in one compare: each x - x is exactly 0 when x is
 * finite, and a NaN or an infinity makes the sum NaN. */
static int all_finite3(real_t a, real_t b, real_t c)
{
    return ((a - a) + (b - b) + (c - c)) == R(0.0);
}

void speed_cfg_default(speed_cfg *cfg, const motor_model *m)
{
    /* Tuning and the measurements behind it: docs/speed_control.md. */
    memset(cfg, 0, sizeof *cfg);
    cfg->mode = SPEED_MODE_RBFN;
    cfg->te_max_Nm = R(80.0);    /* 2 x rated torque, below the 88 N m pull-out */
    cfg->ramp_rad_s2 = R(100.0); /* 500 rpm in 0.52 s, 4.5 N m of acceleration torque */

    /* IP (eq. 3): wn sets the small-signal bandwidth of every controller
     * (10-90 % rise 3.36 / wn = 0.34 s at zeta = 1, no overshoot). */
    cfg->ip.wn_rad_s = R(10.0);
    cfg->ip.zeta = R(1.0);
    /* The nominal and RBFN controllers track the IP's own nominal closed loop. */
    cfg->ref_wn_rad_s = cfg->ip.wn_rad_s;
    cfg->ref_zeta = cfg->ip.zeta;

    /* Nominal: no integral action, so a torque bias b leaves e = b / (J K_x);
     * 40 1/s keeps the ~0.15 N m bias of the sensorless DTC under 1 rpm. */
    cfg->nominal.k_x = R(40.0);

    rbfn_cfg *r = &cfg->rbfn;
    r->k = R(20.0);          /* = the IP's proportional action 2 zeta wn: not a faster loop */
    r->gamma_w = R(4000.0);  /* learning rate: a rated load step is learned in ~0.1 s */
    r->gamma_zeta = R(1000.0);
    r->n_nodes = 5u;
    /* M_w, centres and widths from the torque limit and J (docs/envelope.md) */
    speed_rbfn_size(r, cfg->te_max_Nm, m->J_kgm2);
    r->boundary_rad_s = R(1.0);        /* sat(e / 1 rad/s) instead of sgn(e): no chattering */
    r->zeta_dead_zone_rad_s = R(1.0);  /* ~10 rpm: above speed-estimate noise and small steps */
    r->zeta_max = R(200.0);            /* 9 N m of robust torque at most */
    r->zeta_leak = R(0.5);             /* the bound relaxes over ~2 s after a transient */

    speed_cfg_derive(cfg, m);
}

void speed_rbfn_size(rbfn_cfg *r, real_t te_max_Nm, real_t J_kgm2)
{
    uint32_t n = r->n_nodes;
    if (n < 1u)
        n = 1u;
    if (n > RBFN_NODES_MAX)
        n = RBFN_NODES_MAX;
    /* The largest uncertainty the loop can ever have to cancel: a load at the
     * torque limit, as an acceleration. */
    real_t eps_max = num_div(te_max_Nm, J_kgm2 > R(0.0) ? J_kgm2 : R(1.0));
    /* Every weight must be able to hold eps_max (|eps_hat| <= max w_q and a
     * constant load needs all of them there): |W| = sqrt(n) eps_max, +25 %. */
    r->m_w = num_mul(R(1.25) * num_sqrt((real_t)n), eps_max);
    /* Peak speed error of the learning loop e'' + K e' + gamma_w e = eps for a
     * load step at the torque limit is of the order eps_max / sqrt(gamma_w):
     * the outermost centres sit there, so the nodes that learn during the dip
     * are the ones that act as the error returns to zero. */
    real_t g = r->gamma_w > R(1.0) ? r->gamma_w : R(1.0);
    real_t e_span = num_div(eps_max, num_sqrt(g));
    if (!(e_span > R(0.1)))
        e_span = R(0.1);
    if (n == 1u) {
        r->centre[0] = R(0.0);
        r->width[0] = e_span;
    } else {
        real_t half = R(0.5) * (real_t)(n - 1u);
        real_t spacing = num_div(e_span, half);
        for (uint32_t q = 0u; q < n; q++) {
            r->centre[q] = num_mul((real_t)q - half, spacing);
            r->width[q] = R(0.75) * spacing; /* neighbours overlap: z ~ 0.4 half-way */
        }
    }
    for (uint32_t q = n; q < RBFN_NODES_MAX; q++) {
        r->centre[q] = R(0.0);
        r->width[q] = R(0.0);
    }
}

void speed_cfg_derive(speed_cfg *cfg, const motor_model *m)
{
    /* Eq. 3 with K_T = 1: K_I = wn^2 J, K_P = 2 zeta wn J - B. */
    real_t wn = cfg->ip.wn_rad_s;
    cfg->ip.ki = num_mul(num_mul(wn, wn), m->J_kgm2);
    cfg->ip.kp = R(2.0) * num_mul(num_mul(cfg->ip.zeta, wn), m->J_kgm2) - m->B_Nms;
    rbfn_cfg *r = &cfg->rbfn;
    uint32_t n = r->n_nodes;
    rbfn_grid_derive(&r->grid, r->centre, r->width, n >= 1u && n <= RBFN_NODES_MAX ? n : 0u);
}

int speed_cfg_check(const speed_cfg *cfg, const motor_model *m)
{
    if (cfg->mode != SPEED_MODE_IP && cfg->mode != SPEED_MODE_NOMINAL && cfg->mode != SPEED_MODE_RBFN)
        return SPEED_CFG_E_MODE;
    if (!(m->J_kgm2 > R(0.0)) || !(m->B_Nms >= R(0.0)))
        return SPEED_CFG_E_MOTOR;
    if (!(cfg->te_max_Nm > R(0.0)))
        return SPEED_CFG_E_TE_MAX;
    if (!(cfg->ramp_rad_s2 >= R(0.0)))
        return SPEED_CFG_E_RAMP;
    if (!(cfg->ip.wn_rad_s > R(0.0)) || !(cfg->ip.zeta > R(0.0)))
        return SPEED_CFG_E_IP;
    if (!(cfg->ref_wn_rad_s >= R(0.0)) || (cfg->ref_wn_rad_s > R(0.0) && !(cfg->ref_zeta > R(0.0))))
        return SPEED_CFG_E_REF_MODEL;
    if (!(cfg->nominal.k_x > R(0.0)))
        return SPEED_CFG_E_NOMINAL;
    const rbfn_cfg *r = &cfg->rbfn;
    if (!(r->k > R(0.0)) || !(r->gamma_w >= R(0.0)) || !(r->gamma_zeta >= R(0.0)) ||
        !(r->boundary_rad_s >= R(0.0)) || !(r->zeta_dead_zone_rad_s >= R(0.0)) || !(r->zeta_leak >= R(0.0)))
        return SPEED_CFG_E_RBFN_GAIN;
    if (r->n_nodes < 1u || r->n_nodes > RBFN_NODES_MAX)
        return SPEED_CFG_E_RBFN_NODES;
    for (uint32_t q = 0u; q < r->n_nodes; q++) {
        if (!(r->width[q] > R(0.0)) || !is_finite(r->centre[q]) || !is_finite(r->width[q]))
            return SPEED_CFG_E_RBFN_NODES;
    }
    if (!(r->m_w > R(0.0)) || !(r->zeta_max >= R(0.0)))
        return SPEED_CFG_E_RBFN_BOUND;
    return SPEED_CFG_OK;
}

void speed_ctl_init(speed_ctl *s, const speed_cfg *cfg)
{
    memset(s, 0, sizeof *s);
    s->active = cfg->mode;
}

void speed_ctl_reset(speed_ctl *s, real_t te_now_Nm)
{
    memset(&s->rbfn, 0, sizeof s->rbfn);
    s->ip.integ_Nm = te_now_Nm;
    s->te_last_Nm = te_now_Nm;
    s->ref_x_rad_s = R(0.0);
    s->ref_v_rad_s2 = R(0.0);
}

void speed_ctl_set_ref(speed_ctl *s, real_t omega_rad_s)
{
    s->ref_x_rad_s = omega_rad_s;
    s->ref_v_rad_s2 = R(0.0);
}

/* Advance the reference model one period (semi-implicit Euler: the speed
 * uses the new acceleration; stable and within 1 % of the continuous model
 * for wn T < 0.02) and give the controllers X_d and dX_d/dt from it. */
static void ref_model_step(speed_ctl *s, const speed_cfg *cfg, real_t dt_s, const speed_in *in,
                           speed_in *model_in)
{
    *model_in = *in;
    real_t wn = cfg->ref_wn_rad_s;
    if (wn > R(0.0)) {
        real_t acc = num_mac(num_mul(wn, wn), in->omega_ref_rad_s - s->ref_x_rad_s,
                             -num_mul(R(2.0) * num_mul(cfg->ref_zeta, wn), s->ref_v_rad_s2));
        s->ref_v_rad_s2 = num_mac(acc, dt_s, s->ref_v_rad_s2);
        s->ref_x_rad_s = num_mac(s->ref_v_rad_s2, dt_s, s->ref_x_rad_s);
        model_in->omega_ref_rad_s = s->ref_x_rad_s;
        model_in->domega_ref_rad_s2 = s->ref_v_rad_s2;
    } else {
        /* No model: follow the input, so that enabling one later starts in place. */
        s->ref_x_rad_s = in->omega_ref_rad_s;
        s->ref_v_rad_s2 = in->domega_ref_rad_s2;
    }
}

real_t speed_ref_ramp(real_t prev_rad_s, real_t target_rad_s, real_t max_step_rad_s)
{
    if (!(max_step_rad_s > R(0.0)))
        return target_rad_s;
    real_t d = target_rad_s - prev_rad_s;
    return prev_rad_s + num_limit(d, max_step_rad_s);
}

/* Prepare the controller we switch to so that its first command equals the
 * last one applied: no torque step when the mode changes while running. */
static void switch_mode(speed_ctl *s, const speed_cfg *cfg, const motor_model *m, const speed_in *in)
{
    s->rbfn.learn = RBFN_LEARN_NONE; /* an RBFN command's learning still pending is dropped */
    switch (cfg->mode) {
    case SPEED_MODE_IP:
        speed_ip_bumpless(&s->ip, &cfg->ip, s->te_last_Nm, in->omega_est_rad_s);
        break;
    case SPEED_MODE_RBFN:
        speed_rbfn_bumpless(&s->rbfn, &cfg->rbfn, m, s->te_last_Nm, in);
        break;
    case SPEED_MODE_NOMINAL: /* stateless: nothing to align */
    default:
        break;
    }
    s->active = cfg->mode;
}

/* speed_ctl_step, with the RBFN's learning left for speed_ctl_learn when @p defer. */
static void speed_ctl_run(speed_ctl *s, const speed_cfg *cfg, const motor_model *m, real_t dt_s,
                          const speed_in *in, speed_out *out, bool defer)
{
    if (!all_finite3(in->omega_ref_rad_s, in->domega_ref_rad_s2, in->omega_est_rad_s) ||
        !(dt_s > R(0.0)) || !(m->J_kgm2 > R(0.0))) {
        /* Refuse garbage: zero torque, state kept for when inputs recover. */
        memset(out, 0, sizeof *out);
        s->te_last_Nm = R(0.0);
        return;
    }
    speed_in min;
    ref_model_step(s, cfg, dt_s, in, &min);
    if (cfg->mode != s->active)
        switch_mode(s, cfg, m, cfg->mode == SPEED_MODE_IP ? in : &min);

    real_t te_max = cfg->te_max_Nm > R(0.0) ? cfg->te_max_Nm : R(0.0);
    if (in->te_limit_Nm > R(0.0) && in->te_limit_Nm < te_max)
        te_max = in->te_limit_Nm;
    /* The states and outputs screened below: the IP and nominal controllers
     * set eps_hat to exactly 0, so only the RBFN's is added in. */
    real_t screen;
    switch (cfg->mode) {
    case SPEED_MODE_IP:
        speed_ip_step(&s->ip, &cfg->ip, m, te_max, dt_s, in, out);
        screen = R(0.0);
        break;
    case SPEED_MODE_NOMINAL:
        speed_nominal_step(&cfg->nominal, m, te_max, &min, out);
        screen = R(0.0);
        break;
    case SPEED_MODE_RBFN:
        if (defer)
            speed_rbfn_command(&s->rbfn, &cfg->rbfn, m, te_max, &min, out);
        else
            speed_rbfn_step(&s->rbfn, &cfg->rbfn, m, te_max, dt_s, &min, out);
        screen = out->eps_hat - out->eps_hat;
        break;
    default: /* every controller above writes all of out */
        memset(out, 0, sizeof *out);
        screen = R(0.0);
        break;
    }
    if (!(all_finite3(out->te_ref_Nm, s->ref_x_rad_s, s->ref_v_rad_s2) && screen == R(0.0))) {
        /* Only a broken configuration (a NaN gain) gets here: give no torque
         * and restart from rest rather than carry NaN in the states. */
        memset(out, 0, sizeof *out);
        speed_ctl_reset(s, R(0.0));
        speed_ctl_set_ref(s, in->omega_est_rad_s);
    }
    s->te_last_Nm = out->te_ref_Nm;
}

void speed_ctl_step(speed_ctl *s, const speed_cfg *cfg, const motor_model *m, real_t dt_s,
                    const speed_in *in, speed_out *out)
{
    speed_ctl_run(s, cfg, m, dt_s, in, out, false);
}

void speed_ctl_command(speed_ctl *s, const speed_cfg *cfg, const motor_model *m, real_t dt_s,
                       const speed_in *in, speed_out *out)
{
    speed_ctl_run(s, cfg, m, dt_s, in, out, true);
}

void speed_ctl_learn(speed_ctl *s, const speed_cfg *cfg, real_t dt_s, speed_out *out)
{
    if (s->rbfn.learn != RBFN_LEARN_NONE)
        speed_rbfn_learn(&s->rbfn, &cfg->rbfn, dt_s, out);
}
