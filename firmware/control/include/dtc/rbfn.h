/**
 * @file rbfn.h
 * @brief Radial-basis-function network with one input: the normalised
 *        Gaussian basis (paper eq. 8), its output (eq. 9) and the projected
 *        weight update (eq. 14 with the projection of eq. 21).
 *
 * Pure functions on caller-owned arrays; no state, constant time for a given
 * node count. Every function may be called from any context (ISR or BG).
 */
#ifndef DTC_RBFN_H
#define DTC_RBFN_H

#include <stdint.h>

#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Normalised Gaussian basis (eq. 8):
 * z_q = exp(-(x - m_q)^2 / (2 s_q^2)) / sum_k exp(-(x - m_k)^2 / (2 s_k^2)).
 * The exponents are shifted by their smallest value before exp(), so the sum
 * is >= 1 and no input, however far from the centres, gives 0/0: far away the
 * nearest node takes all the weight. The z_q sum to 1.
 * @param centre m_q, same unit as x (n entries)
 * @param width  s_q > 0 (n entries); a width <= 0 is treated as 1e-6
 * @param n      number of nodes, >= 1
 * @param x      network input
 * @param z      out: z_q (n entries)
 */
void rbfn_basis(const real_t *centre, const real_t *width, uint32_t n, real_t x, real_t *z);

/**
 * Per-configuration data for the basis on a uniform grid (rbfn_grid_derive):
 * centres m_q = m_0 + q h and one width s. There the exponentials of
 * neighbouring nodes are in a fixed ratio: with d = h / s and u_q = (x - m_q) / s,
 * exp(-u_{q+1}^2 / 2) = exp(-u_q^2 / 2) r_q with r_q = exp(u_q d - d^2 / 2) and
 * r_{q+1} = r_q exp(-d^2). One exp() per call instead of n.
 */
typedef struct {
    uint32_t n;               /**< node count the grid was derived for (0: not uniform, use rbfn_basis) */
    real_t inv_width;         /**< 1 / s, 1 / (unit of x) */
    real_t inv_spacing;       /**< 1 / h, 1 / (unit of x) */
    real_t d;                 /**< h / s */
    real_t half_d2;           /**< d^2 / 2 */
    real_t q;                 /**< exp(-d^2): ratio of successive r_q */
    real_t last_node;         /**< n - 1 as a real: the nearest-node search's upper end */
} rbfn_grid;

/** Largest (spacing / width)^2 of a grid: exp(-d^2) stays a normal float (above exp(-87.33)). */
#define RBFN_GRID_D2_MAX R(80.0)

/**
 * Detect a uniform grid (n >= 1; for n >= 2 equally spaced increasing centres
 * within 1e-5 of the spacing, at most sqrt(RBFN_GRID_D2_MAX) = 8.9 widths
 * apart, and equal widths > 1e-6) and precompute its constants; otherwise
 * g->n = 0 (the caller uses rbfn_basis). Context: BG (calls exp).
 */
void rbfn_grid_derive(rbfn_grid *g, const real_t *centre, const real_t *width, uint32_t n);

/**
 * rbfn_basis on a uniform grid derived by rbfn_grid_derive for the same
 * @p centre and @p n: the nearest node gets exp(0) = 1, the others follow by
 * the ratio recurrence outwards (one exp(), one division, two
 * multiplications per node). Relative error of each unnormalised term at
 * most about 2 n^2 ulps (products of at most n - 1 rounded factors, each
 * from a product of at most n - 1 rounded factors): 2e-5 for n = 10.
 * A NaN input gives NaN (callers screen it out); +-inf picks the outer node.
 * Context: ANY.
 */
void rbfn_basis_grid(const rbfn_grid *g, const real_t *centre, uint32_t n, real_t x, real_t *z);

/**
 * rbfn_basis_grid and rbfn_output in one pass, the normalisation left to the
 * caller: writes the unnormalised terms v (the nearest node 1) and the scale
 * 1 / sum v, so that Z = v x scale, and returns W^T Z (eq. 9) = (W^T v) x scale.
 * A NaN input gives NaN (v, scale and the output). Context: ANY.
 * @param w      weights (n entries), in the unit of the output
 * @param v      out: unnormalised basis (n entries)
 * @param scale  out: 1 / sum of v
 */
real_t rbfn_grid_eval(const rbfn_grid *g, const real_t *centre, uint32_t n, real_t x, const real_t *w, real_t *v,
                      real_t *scale);

/** Network output y = W^T Z (eq. 9), in the unit of the weights (n entries each). */
real_t rbfn_output(const real_t *w, const real_t *z, uint32_t n);

/** Euclidean norm |W| of n weights, in the unit of the weights. */
real_t rbfn_norm(const real_t *w, uint32_t n);

/**
 * Project W onto the ball |W| <= m_w: if |W| > m_w, scale it onto the sphere
 * (with a margin of a few float ulps so that |W| <= m_w holds exactly after
 * rounding). m_w <= 0 zeroes W. Returns the norm after projection (an upper
 * bound within float rounding).
 */
real_t rbfn_project(real_t *w, uint32_t n, real_t m_w);

/**
 * One Euler step of the weight law dW/dt = -gamma_w e Z (eq. 14) with the
 * projection of eq. 21: W <- W - gamma_w_dt * e * Z, then, if |W| left the
 * ball, the outward (radial) part of the step is removed (eq. 21, second
 * line) and the result is placed on the sphere |W| = m_w. For a step that
 * moves inwards nothing is removed (eq. 21, first line).
 * @param w          weights, updated (n entries); must satisfy |W| <= m_w on entry
 *                   for eq. 21's invariance; if not, it is projected anyway
 * @param z          basis Z (n entries)
 * @param e          speed error e_x, rad/s
 * @param gamma_w_dt gamma_w times the step, >= 0
 * @param m_w        radius M_w > 0
 * @return |W| after the step (<= m_w)
 */
real_t rbfn_update_projected(real_t *w, const real_t *z, uint32_t n, real_t e, real_t gamma_w_dt,
                             real_t m_w);

#ifdef __cplusplus
}
#endif

#endif /* DTC_RBFN_H */
