/**
 * @file rbfn.c
 * @brief Normalised Gaussian RBF network: basis, output, projected update.
 */
#include "dtc/rbfn.h"

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
    return num_sqrt(s);
}

real_t rbfn_project(real_t *w, uint32_t n, real_t m_w)
{
    real_t norm = rbfn_norm(w, n);
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

real_t rbfn_update_projected(real_t *w, const real_t *z, uint32_t n, real_t e, real_t gamma_w_dt,
                             real_t m_w)
{
    /* Euler step of eq. 14. */
    real_t g = -gamma_w_dt * e;
    for (uint32_t q = 0u; q < n; q++)
        w[q] = num_mac(g, z[q], w[q]);
    /* Eq. 21 in discrete time: a step that leaves the ball loses its outward
     * part, i.e. W is put back on the sphere (the Euclidean projection onto
     * the convex set |W| <= M_w; to first order in the step it is exactly the
     * tangential projection of eq. 21). An inward step is left alone. */
    return rbfn_project(w, n, m_w);
}
