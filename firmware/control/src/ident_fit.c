/**
 * @file ident_fit.c
 * @brief The estimators of the identification run (dtc/ident_fit.h).
 */
#include "dtc/ident_fit.h"

#include <stddef.h>
#include <string.h>

/* Natural logarithm of @p x > 0 (the fit's grid in log Tr): x = m 2^e with
 * m in [1, 2), ln m = 2 atanh(s), s = (m - 1) / (m + 1) <= 1/3, by its series
 * to s^11 (error below 1e-7). Not for the tick: the background's fit only. */
static real_t ident_ln(real_t x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    int e = (int)((u >> 23) & 0xFFu) - 127;
    u = (u & 0x007FFFFFu) | 0x3F800000u;
    real_t m;
    memcpy(&m, &u, sizeof m);
    real_t s = num_div(m - R(1.0), m + R(1.0));
    real_t s2 = num_mul(s, s);
    real_t p = R(1.0) / R(11.0);
    p = num_mac(p, s2, R(1.0) / R(9.0));
    p = num_mac(p, s2, R(1.0) / R(7.0));
    p = num_mac(p, s2, R(1.0) / R(5.0));
    p = num_mac(p, s2, R(1.0) / R(3.0));
    p = num_mac(p, s2, R(1.0));
    return num_mac(R(2.0) * s, p, num_mul((real_t)e, R(0.693147180559945)));
}

/* ------------------------------------------------------------------ least squares */

void ident_lsq_init(ident_lsq *q, uint32_t n)
{
    if (n < 1u)
        n = 1u;
    if (n > IDENT_LSQ_MAX)
        n = IDENT_LSQ_MAX;
    for (uint32_t i = 0u; i < IDENT_LSQ_MAX; i++) {
        for (uint32_t j = 0u; j < IDENT_LSQ_MAX; j++)
            q->r[i][j] = R(0.0);
        q->qty[i] = R(0.0);
    }
    q->rss = R(0.0);
    q->n = n;
    q->rows = 0u;
}

void ident_lsq_add(ident_lsq *q, real_t x[], real_t y)
{
    uint32_t n = q->n;
    for (uint32_t j = 0u; j < n; j++) {
        real_t xj = x[j];
        if (xj == R(0.0))
            continue;
        real_t rjj = q->r[j][j];
        real_t h = num_sqrt_nonneg(num_mac(rjj, rjj, num_mul(xj, xj)));
        real_t c = num_div(rjj, h), s = num_div(xj, h);
        q->r[j][j] = h;
        for (uint32_t k = j + 1u; k < n; k++) {
            real_t t = q->r[j][k];
            q->r[j][k] = num_mac(c, t, num_mul(s, x[k]));
            x[k] = num_mac(c, x[k], -num_mul(s, t));
        }
        real_t t = q->qty[j];
        q->qty[j] = num_mac(c, t, num_mul(s, y));
        y = num_mac(c, y, -num_mul(s, t));
    }
    q->rss = num_mac(y, y, q->rss);
    q->rows++;
}

int ident_lsq_solve(const ident_lsq *q, real_t coef[])
{
    uint32_t n = q->n;
    real_t dmax = R(0.0);
    for (uint32_t j = 0u; j < n; j++)
        if (num_abs(q->r[j][j]) > dmax)
            dmax = num_abs(q->r[j][j]);
    if (!(dmax > R(0.0)))
        return -1;
    for (uint32_t jj = n; jj-- > 0u;) {
        real_t d = q->r[jj][jj];
        if (!(num_abs(d) > num_mul(R(1e-6), dmax)))
            return -1;
        real_t acc = q->qty[jj];
        for (uint32_t k = jj + 1u; k < n; k++)
            acc -= num_mul(q->r[jj][k], coef[k]);
        coef[jj] = num_div(acc, d);
    }
    return 0;
}

/* ------------------------------------------------------------------ standstill DC steps */

#define IDENT_ROTOR_GRID 24u
#define IDENT_ROTOR_GOLDEN 30u
#define IDENT_ROTOR_MIN_BINS 8u

/* One evaluation of the linear problem at the rotor time constant @p tr_s:
 * the residual sum of squares (a negative value when it cannot be solved);
 * the coefficients (Rs, R_R, u_off, psi0) into @p coef when not NULL. */
static real_t ident_rotor_eval(const ident_bin bins[], uint32_t n_bins, real_t bin_s, real_t tr_s, real_t coef[4],
                               uint32_t *used, real_t *span_V)
{
    real_t a = num_exp(-num_div(bin_s, tr_s));
    real_t k = num_mul(num_div(tr_s, bin_s), R(1.0) - a); /* a bin's mean of exp(-t/Tr) over its start value */
    real_t f = R(0.0), g = R(1.0);
    ident_lsq q;
    ident_lsq_init(&q, 4u);
    for (uint32_t b = 0u; b < n_bins; b++) {
        const ident_bin *x = &bins[b];
        if (x->n_i == 0u)
            break; /* the record ends here */
        real_t i = num_div(x->i_sum_A, (real_t)x->n_i);
        real_t fb = num_mac(f - i, k, i);
        if (x->use != 0u && x->n_v != 0u) {
            real_t row[4] = {i, i - fb, R(1.0), num_mul(g, k)};
            ident_lsq_add(&q, row, num_div(x->v_sum_V, (real_t)x->n_v));
        }
        f = num_mac(f - i, a, i);
        g = num_mul(g, a);
    }
    if (used != NULL)
        *used = q.rows;
    real_t c[4];
    if (q.rows < IDENT_ROTOR_MIN_BINS || ident_lsq_solve(&q, c) != 0)
        return R(-1.0);
    if (coef != NULL) {
        for (int j = 0; j < 4; j++)
            coef[j] = c[j];
        /* the rms of the fitted transient R_R (i - i_f) over the bins used */
        real_t s2 = R(0.0);
        f = R(0.0);
        for (uint32_t b = 0u; b < n_bins && bins[b].n_i != 0u; b++) {
            real_t i = num_div(bins[b].i_sum_A, (real_t)bins[b].n_i);
            real_t fb = num_mac(f - i, k, i);
            if (bins[b].use != 0u && bins[b].n_v != 0u) {
                real_t e = num_mul(c[1], i - fb);
                s2 = num_mac(e, e, s2);
            }
            f = num_mac(f - i, a, i);
        }
        if (span_V != NULL)
            *span_V = num_sqrt(num_div(s2, (real_t)q.rows));
    }
    return q.rss;
}

/* V_b = Rs I_b + u_off over the bins used: the DC fit without a rotor (status 1). */
static void ident_rotor_plain(const ident_bin bins[], uint32_t n_bins, ident_rotor_fit_out *out)
{
    ident_lsq q;
    ident_lsq_init(&q, 2u);
    for (uint32_t b = 0u; b < n_bins && bins[b].n_i != 0u; b++) {
        if (bins[b].use == 0u || bins[b].n_v == 0u)
            continue;
        real_t row[2] = {num_div(bins[b].i_sum_A, (real_t)bins[b].n_i), R(1.0)};
        ident_lsq_add(&q, row, num_div(bins[b].v_sum_V, (real_t)bins[b].n_v));
    }
    real_t c[2];
    if (q.rows < IDENT_ROTOR_MIN_BINS || ident_lsq_solve(&q, c) != 0)
        return;
    out->rs_ohm = c[0];
    out->u_off_V = c[1];
    out->resid_V = num_sqrt(num_div(q.rss, (real_t)q.rows));
    out->used = q.rows;
    out->status = 1;
}

void ident_rotor_fit(const ident_bin bins[], uint32_t n_bins, real_t bin_s, real_t tr_lo_s, real_t tr_hi_s,
                     ident_rotor_fit_out *out)
{
    /* a Tr found beyond the record's length: no transient was there */
    const real_t tr_no_rotor_s = num_mul((real_t)n_bins, bin_s);
    out->rs_ohm = out->rr_ref_ohm = out->tr_s = out->lm_ref_H = out->u_off_V = out->psi0_V = R(0.0);
    out->resid_V = out->v_span_V = R(0.0);
    out->used = 0u;
    out->status = -1;
    if (!(bin_s > R(0.0) && tr_lo_s > R(0.0) && tr_hi_s > tr_lo_s))
        return;
    /* the grid on log Tr: ratio r between neighbours */
    real_t r = num_exp(num_div(ident_ln(num_div(tr_hi_s, tr_lo_s)), (real_t)(IDENT_ROTOR_GRID - 1u)));
    real_t best_rss = R(-1.0), best_tr = tr_lo_s, tr = tr_lo_s;
    for (uint32_t j = 0u; j < IDENT_ROTOR_GRID; j++, tr = num_mul(tr, r)) {
        real_t rss = ident_rotor_eval(bins, n_bins, bin_s, tr, NULL, NULL, NULL);
        if (rss >= R(0.0) && (best_rss < R(0.0) || rss < best_rss)) {
            best_rss = rss;
            best_tr = tr;
        }
    }
    if (best_rss < R(0.0))
        return;
    /* golden section on log Tr over the neighbours of the best grid point */
    const real_t gr = R(0.381966011); /* 2 - golden ratio */
    real_t lo = ident_ln(num_div(best_tr, r)), hi = ident_ln(num_mul(best_tr, r));
    real_t x1 = lo + num_mul(gr, hi - lo), x2 = hi - num_mul(gr, hi - lo);
    real_t f1 = ident_rotor_eval(bins, n_bins, bin_s, num_exp(x1), NULL, NULL, NULL);
    real_t f2 = ident_rotor_eval(bins, n_bins, bin_s, num_exp(x2), NULL, NULL, NULL);
    for (uint32_t it = 0u; it < IDENT_ROTOR_GOLDEN; it++) {
        /* a failed evaluation (negative) counts as the worse side */
        bool left = f1 >= R(0.0) && (f2 < R(0.0) || f1 < f2);
        if (left) {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = lo + num_mul(gr, hi - lo);
            f1 = ident_rotor_eval(bins, n_bins, bin_s, num_exp(x1), NULL, NULL, NULL);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = hi - num_mul(gr, hi - lo);
            f2 = ident_rotor_eval(bins, n_bins, bin_s, num_exp(x2), NULL, NULL, NULL);
        }
    }
    real_t tr_fit = num_exp(num_mul(R(0.5), lo + hi));
    real_t c[4];
    uint32_t used = 0u;
    real_t span = R(0.0);
    real_t rss = ident_rotor_eval(bins, n_bins, bin_s, tr_fit, c, &used, &span);
    if (rss < R(0.0))
        return;
    real_t resid = num_sqrt(num_div(rss, (real_t)used));
    if (tr_fit > tr_no_rotor_s || !(c[1] > R(0.0)) || !(span > R(3.0) * resid)) {
        /* no rotor transient to see (a Tr longer than the record makes R_R (i - i_f)
         * look like R_R i and share Rs; a transient of no resistance or below the
         * noise is none): the two-level fit alone */
        ident_rotor_plain(bins, n_bins, out);
        return;
    }
    out->rs_ohm = c[0];
    out->rr_ref_ohm = c[1];
    out->u_off_V = c[2];
    out->psi0_V = c[3];
    out->tr_s = tr_fit;
    out->lm_ref_H = num_mul(c[1], tr_fit);
    out->resid_V = resid;
    out->v_span_V = span;
    out->used = used;
    out->status = 0;
}

/* ------------------------------------------------------------------ transient inductance */

void ident_hf_reset(ident_hf_sums *s)
{
    s->s11 = s->s12 = s->s22 = s->s1 = s->s2 = s->n = R(0.0);
    s->sy1 = s->sy2 = s->sy = s->syy = R(0.0);
}

int ident_hf_solve(const ident_hf_sums *s, real_t period_s, real_t *lsig_H, real_t *r_hf_ohm, real_t *misfit)
{
    *lsig_H = *r_hf_ohm = R(0.0);
    *misfit = R(1.0);
    if (!(s->n >= R(8.0)) || !(s->s11 > R(0.0)) || !(period_s > R(0.0)))
        return -1;
    /* the normal equations M theta = b, solved by Gaussian elimination with partial pivoting */
    real_t m[3][4] = {{s->s11, s->s12, s->s1, s->sy1}, {s->s12, s->s22, s->s2, s->sy2}, {s->s1, s->s2, s->n, s->sy}};
    for (int col = 0; col < 3; col++) {
        int piv = col;
        for (int row = col + 1; row < 3; row++)
            if (num_abs(m[row][col]) > num_abs(m[piv][col]))
                piv = row;
        if (piv != col)
            for (int k = 0; k < 4; k++) {
                real_t t = m[col][k];
                m[col][k] = m[piv][k];
                m[piv][k] = t;
            }
        if (!(num_abs(m[col][col]) > num_mul(R(1e-7), num_abs(s->s11) + num_abs(s->s22) + s->n)))
            return -1;
        for (int row = col + 1; row < 3; row++) {
            real_t f = num_div(m[row][col], m[col][col]);
            for (int k = col; k < 4; k++)
                m[row][k] -= num_mul(f, m[col][k]);
        }
    }
    real_t th[3];
    for (int row = 2; row >= 0; row--) {
        real_t acc = m[row][3];
        for (int k = row + 1; k < 3; k++)
            acc -= num_mul(m[row][k], th[k]);
        th[row] = num_div(acc, m[row][row]);
    }
    *lsig_H = th[0];
    *r_hf_ohm = num_div(th[1], period_s);
    real_t rss = s->syy - num_mul(th[0], s->sy1) - num_mul(th[1], s->sy2) - num_mul(th[2], s->sy);
    real_t scale = num_mul(num_abs(th[0]), num_sqrt(num_div(s->s11, s->n)));
    *misfit = scale > R(0.0) ? num_div(num_sqrt(num_div(rss, s->n)), scale) : R(1.0);
    return th[0] > R(0.0) ? 0 : -1;
}

/* ------------------------------------------------------------------ rotating */

real_t ident_lm_from_no_load(real_t p_VsA, real_t q_VsA, real_t i2_A2, real_t psi2_Wb2, real_t lsig_H, real_t *i0_A)
{
    if (i0_A != NULL)
        *i0_A = R(0.0);
    real_t a = p_VsA - num_mul(lsig_H, i2_A2);
    if (!(a > R(0.0)) || !(i2_A2 > R(0.0)) || !(psi2_Wb2 > R(0.0)))
        return R(0.0);
    real_t r = num_div(q_VsA, a), l2 = num_mul(lsig_H, lsig_H);
    real_t c = num_mul(l2, num_mac(r, r, R(1.0)));
    real_t psi2 = psi2_Wb2, lm = R(0.0), i02 = R(0.0);
    for (int pass = 0; pass < 3; pass++) {
        real_t b = num_div(psi2, a) - R(2.0) * lsig_H;
        real_t disc = num_mac(b, b, -R(4.0) * c);
        if (!(disc >= R(0.0)) || !(b > R(0.0)))
            return R(0.0);
        lm = num_mul(R(0.5), b + num_sqrt_nonneg(disc));
        i02 = num_mul(num_div(a, lm), num_mac(r, r, R(1.0)));
        /* the flux ripple's share of |psi|^2 out for the next pass */
        real_t ripple = i2_A2 - i02;
        psi2 = psi2_Wb2 - num_mul(l2, ripple > R(0.0) ? ripple : R(0.0));
    }
    if (i0_A != NULL)
        *i0_A = num_sqrt(i02);
    return lm;
}

real_t ident_inertia(const ident_speed_window *a, const ident_speed_window *d)
{
    real_t den = num_mul(a->dw_rad_s, d->t_s) - num_mul(d->dw_rad_s, a->t_s);
    if (!(num_abs(den) > R(0.0)) || !(a->t_s > R(0.0)) || !(d->t_s > R(0.0)))
        return R(0.0);
    return num_div(num_mul(a->te_int_Nms, d->t_s) - num_mul(d->te_int_Nms, a->t_s), den);
}

real_t ident_friction(real_t te1_Nm, real_t w1_rad_s, real_t te2_Nm, real_t w2_rad_s)
{
    real_t dw = w2_rad_s - w1_rad_s;
    if (!(num_abs(dw) > R(0.0)))
        return R(0.0);
    return num_div(te2_Nm - te1_Nm, dw);
}

/* ------------------------------------------------------------------ T model */

int ident_t_model(real_t lsig_H, real_t lm_ref_H, real_t rr_ref_ohm, ident_t_params *t)
{
    t->lm_H = t->ls_H = t->lr_H = t->rr_ohm = R(0.0);
    if (!(lsig_H > R(0.0) && lm_ref_H > R(0.0) && rr_ref_ohm > R(0.0)))
        return -1;
    real_t ls = lm_ref_H + lsig_H;
    t->ls_H = ls;
    t->lr_H = ls;
    t->lm_H = num_sqrt(num_mul(lm_ref_H, ls));
    t->rr_ohm = num_div(num_mul(rr_ref_ohm, ls), lm_ref_H);
    return 0;
}
