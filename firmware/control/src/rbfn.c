/**
 * @file rbfn.c
 * @brief Normalised Gaussian RBF network: basis, output, projected update.
 */
#include "dtc/rbfn.h"

#include <stdbool.h>

/* Relative margin taken off the projection radius: the float norm of n <= 9
 * terms is within a few ulps of the exact norm, so projecting onto
 * m_w (1 - 16 ulps) guarantees that the exact norm stays <= m_w. */
#define RBFN_PROJ_MARGIN R(1.9e-6)

void rbfn_basis(const real_t *centre, const real_t *width, uint32_t n, real_t x, real_t *z)
{
    real_t dmin = R(0.0);
    for (uint32_t q = 0u; q < n; q++) {
        real_t s = width[q] > R(1e-6) ? width[q] : R(1e-6);
        /* Clamped so that u * u stays finite for any finite x. */
        real_t u = num_limit(num_div(x - centre[q], s), R(1e15));
        z[q] = R(0.5) * u * u; /* exponent, before the shift */
        if (q == 0u || z[q] < dmin)
            dmin = z[q];
    }
    real_t sum = R(0.0);
    for (uint32_t q = 0u; q < n; q++) {
        z[q] = num_exp(dmin - z[q]); /* in (0, 1], the nearest node gives 1 */
        sum += z[q];
    }
    /* sum >= 1 for finite x; a NaN input gives NaN, which callers screen out. */
    real_t inv = num_div(R(1.0), sum);
    for (uint32_t q = 0u; q < n; q++)
        z[q] = num_mul(z[q], inv);
}

void rbfn_grid_derive(rbfn_grid *g, const real_t *centre, const real_t *width, uint32_t n)
{
    g->n = 0u;
    g->inv_width = g->inv_spacing = g->d = g->half_d2 = R(0.0);
    g->q = R(1.0);
    g->last_node = R(0.0);
    if (n < 1u || !(width[0] > R(1e-6)))
        return;
    real_t h = n >= 2u ? centre[1] - centre[0] : R(1.0);
    if (!(h > R(0.0)) || !(h < R(1e30)))
        return;
    for (uint32_t k = 0u; k < n; k++) {
        if (width[k] != width[0])
            return;
        if (k >= 1u && !(num_abs(centre[k] - centre[k - 1u] - h) <= num_mul(R(1e-5), h)))
            return;
    }
    real_t inv_width = num_div(R(1.0), width[0]);
    real_t d = n >= 2u ? num_mul(h, inv_width) : R(0.0);
    /* q = exp(-d^2) must be a normal float: num_exp gives 0 below -87.33, and
     * then the recurrence's downward ratio rho = q / r is 0 (every node below
     * the nearest one lost) or, where r is 0 too, 0 / 0 = NaN (d = 10 gave NaN
     * for every node at x midway between two of them). A grid that sparse
     * (nodes 9 widths apart) takes rbfn_basis. d^2 <= 80 also keeps
     * grid_terms' exp argument u d - d^2 / 2 (|u| <= 1e15) finite, never
     * inf - inf = NaN (num_expf_not_nan). */
    if (!(num_mul(d, d) <= RBFN_GRID_D2_MAX))
        return;
    g->inv_width = inv_width;
    g->inv_spacing = num_div(R(1.0), h);
    g->d = d;
    g->half_d2 = num_mul(R(0.5), num_mul(g->d, g->d));
    g->q = num_exp(-num_mul(g->d, g->d));
    g->last_node = (real_t)(n - 1u);
    g->n = n;
}

/* The unnormalised terms of rbfn_basis_grid into v (the nearest node 1) and,
 * if @p weighted, sum w_k v_k into *wv; returns their sum (>= 1, NaN for NaN x).
 * @p weighted is a constant at each call, not a test of w against NULL: a
 * constant folds away, a test of the caller's state would stay. */
static inline real_t grid_terms(const rbfn_grid *g, const real_t *centre, uint32_t n, real_t x, bool weighted,
                                const real_t *w, real_t *v_out, real_t *wv)
{
    /* nearest node (written so that huge |x| never reaches the integer conversion),
     * and r: z[k + 1] / z[k] going up from it (rho below: z[k - 1] / z[k] going
     * down, r rho = q), r = exp(u d - d^2 / 2) with u = (x - m_ks) / s */
    real_t t = num_mul(x - centre[0], g->inv_spacing);
    uint32_t ks;
    real_t r;
    if (t > R(0.0) && t < g->last_node) { /* (real_t)(n - 1), n == g->n */
        ks = (uint32_t)(t + R(0.5));
        /* Between the outer nodes x is within half a spacing of node ks of
         * the exact grid, and node ks is within ks x 1e-5 spacings of it (the
         * centres' tolerance in rbfn_grid_derive), so |u| <= (1/2 + delta) d
         * with delta = 1e-5 ks (no clamp needed) and the argument lies in
         * [-(1 + delta) d^2, delta d^2]: inside [-87.3, 88.7] for d^2 <=
         * RBFN_GRID_D2_MAX = 80 and any grid below 9,000 nodes (at most
         * 7.2 above 0: inside num_expf_to_88's range). The exp without its
         * range tests. */
        real_t u = num_mul(x - centre[ks], g->inv_width);
        r = num_expf_to_88(num_mul(u, g->d) - g->half_d2);
    } else {
        /* A NaN x fails the test above too: tested here only, off the
         * common path between the outer nodes. */
        if (!(x == x)) {
            for (uint32_t k = 0u; k < n; k++)
                v_out[k] = x;
            *wv = x;
            return x;
        }
        ks = t > R(0.0) ? n - 1u : 0u;
        /* Beyond the outer nodes u is not bounded: clamped so that u d stays
         * finite; x is not NaN here and u is bounded, so the argument is not
         * NaN (g->d and g->half_d2 are finite by rbfn_grid_derive): the exp
         * without its NaN test. */
        real_t u = num_limit(num_mul(x - centre[ks], g->inv_width), R(1e15));
        r = num_expf_not_nan(num_mul(u, g->d) - g->half_d2);
    }
    const real_t q = g->q; /* held in a register: the stores into v_out could alias it */
    real_t rho = num_div(q, r);
    real_t sum = R(1.0);
    v_out[ks] = R(1.0);
    real_t y = weighted ? w[ks] : R(0.0);
    /* walked with pointers: no index arithmetic per node */
    real_t v = R(1.0);
    real_t *vk = v_out + ks;
    const real_t *wk = w + ks;
    for (const real_t *end = v_out + n; ++vk < end;) {
        v = num_mul(v, r);
        r = num_mul(r, q);
        *vk = v;
        sum += v;
        if (weighted)
            y = num_mac(*++wk, v, y);
    }
    v = R(1.0);
    vk = v_out + ks;
    wk = w + ks;
    while (vk > v_out) {
        v = num_mul(v, rho);
        rho = num_mul(rho, q);
        *--vk = v;
        sum += v;
        if (weighted)
            y = num_mac(*--wk, v, y);
    }
    *wv = y;
    return sum;
}

void rbfn_basis_grid(const rbfn_grid *g, const real_t *centre, uint32_t n, real_t x, real_t *z)
{
    real_t wv;
    real_t inv = num_div(R(1.0), grid_terms(g, centre, n, x, false, z, z, &wv));
    for (uint32_t k = 0u; k < n; k++)
        z[k] = num_mul(z[k], inv);
}

real_t rbfn_grid_eval(const rbfn_grid *g, const real_t *centre, uint32_t n, real_t x, const real_t *w, real_t *v,
                      real_t *scale)
{
    real_t wv;
    real_t inv = num_div(R(1.0), grid_terms(g, centre, n, x, true, w, v, &wv));
    *scale = inv;
    return num_mul(wv, inv);
}

real_t rbfn_output(const real_t *w, const real_t *z, uint32_t n)
{
    real_t y = R(0.0);
    for (uint32_t q = 0u; q < n; q++)
        y = num_mac(w[q], z[q], y);
    return y;
}

real_t rbfn_norm(const real_t *w, uint32_t n)
{
    real_t s = R(0.0);
    for (uint32_t q = 0u; q < n; q++)
        s = num_mac(w[q], w[q], s);
    return num_sqrt_nonneg(s); /* a sum of squares */
}

/* rbfn_project with |W| = @p norm already worked out. */
static real_t project_with_norm(real_t *w, uint32_t n, real_t m_w, real_t norm)
{
    if (!(m_w > R(0.0))) {
        for (uint32_t q = 0u; q < n; q++)
            w[q] = R(0.0);
        return R(0.0);
    }
    real_t lim = m_w * (R(1.0) - RBFN_PROJ_MARGIN);
    if (norm <= lim)
        return norm;
    real_t scale = num_div(lim, norm) * (R(1.0) - RBFN_PROJ_MARGIN);
    for (uint32_t q = 0u; q < n; q++)
        w[q] = num_mul(w[q], scale);
    return rbfn_norm(w, n);
}

real_t rbfn_project(real_t *w, uint32_t n, real_t m_w)
{
    return project_with_norm(w, n, m_w, rbfn_norm(w, n));
}

real_t rbfn_update_projected(real_t *w, const real_t *z, uint32_t n, real_t e, real_t gamma_w_dt,
                             real_t m_w)
{
    /* Euler step of eq. 14. */
    real_t g = -gamma_w_dt * e;
    real_t s2 = R(0.0); /* |W|^2 of the new weights, summed as rbfn_norm does */
    for (uint32_t q = 0u; q < n; q++) {
        w[q] = num_mac(g, z[q], w[q]);
        s2 = num_mac(w[q], w[q], s2);
    }
    /* Eq. 21 in discrete time: a step that leaves the ball loses its outward
     * part, i.e. W is put back on the sphere (the Euclidean projection onto
     * the convex set |W| <= M_w; to first order in the step it is exactly the
     * tangential projection of eq. 21). An inward step is left alone. */
    return project_with_norm(w, n, m_w, num_sqrt_nonneg(s2)); /* a sum of squares */
}
