/**
 * @file rs_ident.c
 * @brief Stator resistance identified while magnetising (rs_ident.h).
 */
#include "dtc/rs_ident.h"

/* A rotor turning faster than this (electrical) while magnetising is not at
 * rest: the standstill model does not hold, nothing is applied. The error of
 * the standstill model grows about as 0.3 % x (omega_e / (1 rad/s))^2 (-1.3 %
 * at 2 rad/s, -10 % at 6 rad/s against the exact machine), so 2 rad/s keeps
 * it well inside the 10 % tolerance. */
#define RS_IDENT_MAX_SPEED_RAD_S R(2.0)
/* The speed estimate is judged from this time of magnetising on (the flux
 * reference ramp takes about 0.13 s with the defaults). */
#define RS_IDENT_SPEED_FROM_S R(0.15)
/* Less charge than this (A s, e.g. 2 A for 0.1 s) says too little about Rs. */
#define RS_IDENT_MIN_CHARGE_AS R(0.2)

void rs_ident_cfg_derive(rs_ident_cfg *c, const motor_model *m, real_t period_s, real_t tol_frac)
{
    real_t ls = m->Ls_H;
    real_t lr = m->Lr_H;
    real_t sigma = R(1.0) - num_div(num_mul(m->Lm_H, m->Lm_H), num_mul(ls, lr));
    c->tol_frac = tol_frac;
    c->rs_model_ohm = m->Rs_ohm;
    c->sigma_ls_H = num_mul(sigma, ls);
    c->lm_H = m->Lm_H;
    c->lm_lr = num_div(m->Lm_H, lr);
    c->T_over_tr = num_div(num_mul(period_s, m->Rr_ohm), lr);
    c->period_s = period_s;
    c->half_period_s = num_mul(R(0.5), period_s);
}

void rs_ident_reset(rs_ident *s)
{
    for (int k = 0; k < 2; k++)
        s->v_int_Vs[k] = s->i_int_As[k] = s->is_A[k] = s->psi_r_Wb[k] = R(0.0);
    s->speed_max_rad_s = R(0.0);
    s->t_s = R(0.0);
}

void rs_ident_step(rs_ident *s, const rs_ident_cfg *c, const real_t v_V[2], const real_t is_A[2],
                   real_t omega_e_rad_s)
{
    real_t w = num_abs(omega_e_rad_s);
    if (s->t_s >= RS_IDENT_SPEED_FROM_S && !(w <= s->speed_max_rad_s))
        s->speed_max_rad_s = w; /* (a NaN estimate counts as turning) */
    s->t_s += c->period_s;
    for (int k = 0; k < 2; k++) {
        /* is(t) piecewise linear between samples: trapezoid; v constant over the period */
        s->i_int_As[k] += num_mul(c->half_period_s, s->is_A[k] + is_A[k]);
        s->psi_r_Wb[k] += num_mul(c->T_over_tr, num_mul(c->lm_H, is_A[k]) - s->psi_r_Wb[k]);
        s->is_A[k] = is_A[k];
        s->v_int_Vs[k] += num_mul(c->period_s, v_V[k]);
    }
}

real_t rs_ident_result(const rs_ident *s, const rs_ident_cfg *c)
{
    real_t num = R(0.0), den = R(0.0);
    for (int k = 0; k < 2; k++) {
        /* the flux-linkage terms at the end of the last period: the voltage of
         * that period has been integrated, the current sampled at its start */
        real_t drop = s->v_int_Vs[k] - num_mul(c->sigma_ls_H, s->is_A[k]) - num_mul(c->lm_lr, s->psi_r_Wb[k]);
        num += num_mul(drop, s->i_int_As[k]);
        den += num_mul(s->i_int_As[k], s->i_int_As[k]);
    }
    real_t rs = c->rs_model_ohm;
    if (!(den > num_mul(RS_IDENT_MIN_CHARGE_AS, RS_IDENT_MIN_CHARGE_AS)) ||
        !(s->speed_max_rad_s <= RS_IDENT_MAX_SPEED_RAD_S))
        return rs;
    real_t id = num_div(num, den);
    if (!(id >= num_mul(R(0.5), rs) && id <= num_mul(R(2.0), rs)))
        return rs;
    return num_abs(id - rs) > num_mul(c->tol_frac, rs) ? id : rs;
}
