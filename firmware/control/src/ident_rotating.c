/**
 * @file ident_rotating.c
 * @brief The rotating part of the identification run (dtc/ident_rotating.h).
 */
#include "dtc/ident_rotating.h"

static void ident_rot_window_reset(ident_rot_window *w)
{
    w->p_VsA = w->q_VsA = w->i2_A2 = w->psi2_Wb2 = w->te_Nm = w->w_rad_s = R(0.0);
    w->w_late_rad_s = w->te2_Nm2 = R(0.0);
    w->n = 0u;
}

void ident_rot_reset(ident_rot *s, real_t rs_ohm)
{
    s->stage = IDENT_ROTATING_START;
    s->tick = s->ticks_total = s->held = 0u;
    s->rs_ohm = rs_ohm;
    s->psi_Wb[0] = s->psi_Wb[1] = R(0.0);
    s->v_prev_V[0] = s->v_prev_V[1] = R(0.0);
    s->i_prev_A[0] = s->i_prev_A[1] = R(0.0);
    s->w_e_rad_s = R(0.0);
    s->flux_on = false;
    s->win_open = false;
    s->win_w0_rad_s = R(0.0);
    s->win_t_s = R(0.0);
    s->up.t_s = s->up.dw_rad_s = s->up.te_int_Nms = R(0.0);
    s->down = s->up;
    ident_rot_window_reset(&s->no_load);
    ident_rot_window_reset(&s->friction);
}

/* The voltage model to t_k: psi_k = psi_{k-1} (1 - wc T) + T (v_{k-1} - Rs (i_{k-1} + i_k) / 2),
 * and the stator frequency from the flux's turn over the period. */
static void ident_rot_flux(ident_rot *s, const ident_rot_cfg *c, const real_t i[2])
{
    real_t T = c->period_s, keep = R(1.0) - num_mul(c->wc_rad_s, T);
    real_t p0 = s->psi_Wb[0], p1 = s->psi_Wb[1];
    real_t h = num_mul(R(0.5), s->rs_ohm);
    real_t n0 = num_mac(p0, keep, num_mul(T, s->v_prev_V[0] - num_mul(h, s->i_prev_A[0] + i[0])));
    real_t n1 = num_mac(p1, keep, num_mul(T, s->v_prev_V[1] - num_mul(h, s->i_prev_A[1] + i[1])));
    real_t m2 = num_mac(n0, n0, num_mul(n1, n1));
    if (m2 > R(0.0)) {
        real_t w = num_div(num_div(num_mul(p0, n1) - num_mul(p1, n0), m2), T);
        s->w_e_rad_s = num_mac(c->w_lpf_a, w - s->w_e_rad_s, s->w_e_rad_s);
    }
    s->psi_Wb[0] = n0;
    s->psi_Wb[1] = n1;
}

/* One window's sums at this tick; false while the stator frequency is too low for the voltage model. */
static bool ident_rot_measure(const ident_rot *s, const ident_rot_cfg *c, const real_t i[2], real_t *te, real_t *p,
                              real_t *q, real_t *psi2)
{
    real_t w = s->w_e_rad_s;
    *te = *p = *q = *psi2 = R(0.0);
    if (!(num_abs(w) > R(3.0) * c->wc_rad_s))
        return false;
    real_t k = num_div(c->wc_rad_s, w);
    /* psi = psi_leaky (1 - j wc / w) */
    real_t pa = num_mac(k, s->psi_Wb[1], s->psi_Wb[0]);
    real_t pb = num_mac(-k, s->psi_Wb[0], s->psi_Wb[1]);
    *q = num_mul(pa, i[1]) - num_mul(pb, i[0]);
    *p = num_mac(pa, i[0], num_mul(pb, i[1]));
    *te = num_mul(num_mul(R(1.5), c->pole_pairs), *q);
    *psi2 = num_mac(pa, pa, num_mul(pb, pb));
    return true;
}

static void ident_rot_next(ident_rot *s, ident_rot_stage st)
{
    s->stage = st;
    s->tick = 0u;
    s->held = 0u;
    s->win_open = false;
}

/* A speed-change window between @p w_from and @p w_to (either order of the
 * two): opens when the speed passes w_from, closes when it passes w_to. */
static void ident_rot_change(ident_rot *s, const ident_rot_cfg *c, real_t w, real_t te, bool valid, bool rising,
                             real_t w_from, real_t w_to, ident_speed_window *win)
{
    if (win->t_s > R(0.0))
        return; /* done */
    bool past_from = rising ? w >= w_from : w <= w_from;
    bool past_to = rising ? w >= w_to : w <= w_to;
    if (!s->win_open) {
        if (past_from && !past_to && valid) {
            s->win_open = true;
            s->win_w0_rad_s = w;
            s->win_t_s = R(0.0);
            win->te_int_Nms = R(0.0);
        }
        return;
    }
    win->te_int_Nms = num_mac(te, c->period_s, win->te_int_Nms);
    s->win_t_s += c->period_s;
    if (past_to) {
        win->t_s = s->win_t_s;
        win->dw_rad_s = w - s->win_w0_rad_s;
        s->win_open = false;
    }
}

/* Towards the speed @p w_ref: at the inertia test's torque while farther than
 * w_near (the speed loop's ramp, set for the drive's use, need not be fast),
 * then the speed loop. True once within w_near. */
static bool ident_rot_goto(ident_rot *s, const ident_rot_cfg *c, real_t w, real_t w_ref, ident_out *out)
{
    real_t e = w_ref - w;
    if (num_abs(e) > c->w_near_rad_s) {
        out->mode = IDENT_OUT_TORQUE;
        out->te_ref_Nm = e > R(0.0) ? c->te_J_Nm : -c->te_J_Nm;
        s->held = 0u;
        return false;
    }
    out->mode = IDENT_OUT_SPEED;
    out->speed_ref_rad_s = w_ref;
    return true;
}

/* A steady-speed window: settle within w_tol for settle_ticks, then sum window_ticks; true when complete. */
static bool ident_rot_hold(ident_rot *s, const ident_rot_cfg *c, real_t w, real_t w_ref, const real_t i[2],
                           ident_rot_window *win, ident_out *out)
{
    if (!ident_rot_goto(s, c, w, w_ref, out) && win->n == 0u)
        return false;
    out->mode = IDENT_OUT_SPEED; /* once the window is open, the speed loop only */
    out->te_ref_Nm = R(0.0);
    out->speed_ref_rad_s = w_ref;
    if (win->n >= c->window_ticks)
        return true;
    if (s->held < c->settle_ticks) {
        s->held = num_abs(w - w_ref) <= c->w_tol_rad_s ? s->held + 1u : 0u;
        return false;
    }
    real_t te = R(0.0), p = R(0.0), q = R(0.0), psi2 = R(0.0);
    if (!ident_rot_measure(s, c, i, &te, &p, &q, &psi2))
        return false;
    win->psi2_Wb2 += psi2;
    win->p_VsA += p;
    win->q_VsA += q;
    win->i2_A2 = num_mac(i[0], i[0], num_mac(i[1], i[1], win->i2_A2));
    win->te_Nm += te;
    win->te2_Nm2 = num_mac(te, te, win->te2_Nm2);
    win->w_rad_s += w;
    if (2u * win->n >= c->window_ticks)
        win->w_late_rad_s += w;
    win->n++;
    return win->n >= c->window_ticks;
}

ident_rot_status ident_rot_step(ident_rot *s, const ident_rot_cfg *c, const ident_in *in, ident_out *out)
{
    const real_t *iabc = in->i_abc_A;
    real_t i[2] = {num_mul(R(0.333333333), R(2.0) * iabc[0] - iabc[1] - iabc[2]),
                   num_mul(NUM_INV_SQRT3, iabc[1] - iabc[2])};
    out->mode = IDENT_OUT_TORQUE;
    out->te_ref_Nm = R(0.0);
    out->speed_ref_rad_s = R(0.0);
    if (s->flux_on) {
        ident_rot_flux(s, c, i);
    } else if (in->control_running) {
        /* seeded with the drive's observer flux: the leak need not wash out a wrong start */
        s->flux_on = true;
        s->psi_Wb[0] = in->psi_s_Wb[0];
        s->psi_Wb[1] = in->psi_s_Wb[1];
    }
    s->v_prev_V[0] = in->v_ab_V[0];
    s->v_prev_V[1] = in->v_ab_V[1];
    s->i_prev_A[0] = i[0];
    s->i_prev_A[1] = i[1];
    s->ticks_total++;
    s->tick++;
    if (s->stage != IDENT_ROTATING_START && s->stage != IDENT_ROTATING_END && s->tick > c->timeout_ticks)
        return IDENT_ROT_TIMEOUT;

    real_t w = in->omega_m_rad_s;
    real_t te = R(0.0), p = R(0.0), q = R(0.0), psi2 = R(0.0);
    bool valid = ident_rot_measure(s, c, i, &te, &p, &q, &psi2);
    switch (s->stage) {
    case IDENT_ROTATING_START:
        s->held = in->control_running ? s->held + 1u : 0u;
        if (s->held >= c->start_ticks)
            ident_rot_next(s, IDENT_ROTATING_ACCEL);
        break;
    case IDENT_ROTATING_ACCEL:
        out->te_ref_Nm = c->te_J_Nm;
        ident_rot_change(s, c, w, te, valid, true, c->w_a_rad_s, c->w_b_rad_s, &s->up);
        if (w >= c->w_top_rad_s)
            ident_rot_next(s, IDENT_ROTATING_DECEL);
        break;
    case IDENT_ROTATING_DECEL:
        out->te_ref_Nm = -c->te_J_Nm;
        ident_rot_change(s, c, w, te, valid, false, c->w_b_rad_s, c->w_a_rad_s, &s->down);
        if (w <= c->w_bottom_rad_s)
            ident_rot_next(s, IDENT_ROTATING_NO_LOAD);
        break;
    case IDENT_ROTATING_NO_LOAD:
        if (ident_rot_hold(s, c, w, c->w1_rad_s, i, &s->no_load, out))
            ident_rot_next(s, IDENT_ROTATING_FRICTION);
        break;
    case IDENT_ROTATING_FRICTION:
        if (ident_rot_hold(s, c, w, c->w2_rad_s, i, &s->friction, out))
            ident_rot_next(s, IDENT_ROTATING_STOP);
        break;
    case IDENT_ROTATING_STOP:
        if (!ident_rot_goto(s, c, w, R(0.0), out))
            break;
        s->held = num_abs(w) <= c->w_tol_rad_s ? s->held + 1u : 0u;
        if (s->held >= c->settle_ticks / 4u + 1u) {
            ident_rot_next(s, IDENT_ROTATING_END);
            out->mode = IDENT_OUT_OFF;
            return IDENT_ROT_FINISHED;
        }
        break;
    default:
        out->mode = IDENT_OUT_OFF;
        return IDENT_ROT_FINISHED;
    }
    return IDENT_ROT_RUNNING;
}
