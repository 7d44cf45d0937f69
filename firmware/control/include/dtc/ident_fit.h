/**
 * @file ident_fit.h
 * @brief The estimators of the identification run: pure functions that turn
 *        the sums the interrupt collected into parameters (background), and
 *        the sums themselves (interrupt). The method, its sources and why each
 *        step is insensitive to the inverter's errors: docs/commissioning.md,
 *        "Identification".
 *
 * Machine model: the inverse-Gamma equivalent circuit (Slemon, "Modelling
 * of induction machines for electric drives", IEEE TIA 1989), which is what a
 * standstill test can see without assuming how the leakage splits:
 *
 *   v = Rs i + Lsig di/dt + (L_M / Tr) (i - i_f),   Tr di_f/dt = i - i_f
 *
 * with Lsig = sigma Ls, L_M = Lm^2 / Lr, R_R = Rr (Lm / Lr)^2 = L_M / Tr and
 * Tr = Lr / Rr (the rotor at rest; i_f is the current the rotor flux has
 * followed, psi_r = Lm i_f). The T-model parameters follow with an assumed
 * leakage split (ident_t_model: Lls = Llr, the usual assumption of IEEE 112
 * for design A/B motors).
 *
 * Every function here is bounded (no loop beyond its documented size),
 * uses no heap and no static mutable state.
 */
#ifndef DTC_IDENT_FIT_H
#define DTC_IDENT_FIT_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ least squares */

#define IDENT_LSQ_MAX 5u /**< most unknowns of one least-squares problem */

/**
 * A least-squares problem solved row by row with Givens rotations (Golub and
 * Van Loan, "Matrix Computations", 5.1.8): the rows are never stored, only
 * the triangular factor R of the design matrix, Q^T y and the residual sum of
 * squares. Float is enough: the rotations are orthogonal, so the rounding
 * errors stay of the order of the data's (normal equations would square the
 * condition number).
 */
typedef struct {
    real_t r[IDENT_LSQ_MAX][IDENT_LSQ_MAX]; /**< upper triangular factor */
    real_t qty[IDENT_LSQ_MAX];              /**< Q^T y */
    real_t rss;                             /**< residual sum of squares so far */
    uint32_t n;                             /**< unknowns, 1..IDENT_LSQ_MAX */
    uint32_t rows;                          /**< rows added */
} ident_lsq;

/** Start a problem with @p n unknowns (clamped to 1..IDENT_LSQ_MAX). Context: any. */
void ident_lsq_init(ident_lsq *q, uint32_t n);

/** Add the row @p x (n values; overwritten) with the target @p y. O(n^2). Context: any. */
void ident_lsq_add(ident_lsq *q, real_t x[], real_t y);

/**
 * The solution into @p coef (n values). @return 0, or -1 when the problem is
 * rank deficient (a diagonal of R below 1e-6 of the largest). Context: any.
 */
int ident_lsq_solve(const ident_lsq *q, real_t coef[]);

/* ------------------------------------------------------------------ standstill DC steps */

/** One bin of the DC part: sums over its control periods (written by the interrupt). */
typedef struct {
    real_t v_sum_V;  /**< sum of the periods' mean alpha voltages, V */
    real_t i_sum_A;  /**< sum of the periods' mean alpha currents (trapezoid of the samples), A */
    real_t ib_sum_A; /**< the same of the beta current, A */
    uint16_t n_v;    /**< periods whose voltage is summed */
    uint16_t n_i;    /**< periods whose current is summed */
    uint8_t use;     /**< 1: the fit uses the bin (settled, the regular pulse pattern only) */
} ident_bin;

/** Result of ident_rotor_fit. */
typedef struct {
    real_t rs_ohm;      /**< stator resistance, ohm */
    real_t rr_ref_ohm;  /**< R_R = Rr (Lm/Lr)^2, ohm */
    real_t tr_s;        /**< rotor time constant, s */
    real_t lm_ref_H;    /**< L_M = R_R Tr, H */
    real_t u_off_V;     /**< constant voltage error (inverter, sensors), V */
    real_t psi0_V;      /**< initial-flux term's amplitude, V */
    real_t resid_V;     /**< rms residual over the bins used, V */
    real_t v_span_V;    /**< rms of the fitted excess voltage R_R (i - i_f) over the bins used, V */
    uint32_t used;      /**< bins used */
    int status;         /**< 0; 1: no rotor transient (Rs and u_off from the two levels alone, the
                             rotor's values 0); -1: too few bins or rank deficient */
} ident_rotor_fit_out;

/**
 * Fit the DC part: bin b (duration @p bin_s, starting at b x bin_s from a
 * rotor at rest, demagnetised up to the psi0 term) has the mean voltage V_b
 * and current I_b; the model
 *
 *   V_b = Rs I_b + R_R (I_b - F_b) + u_off + psi0 G_b
 *
 * where F_b is the bin mean of i_f (the current, taken constant over each
 * bin, through the first-order lag Tr) and G_b the bin mean of exp(-t/Tr)
 * (a rotor flux already present at the start decays so), is linear in
 * Rs, R_R, u_off and psi0 for a given Tr: solved by least squares over the
 * bins with use set, Tr by minimising the residual (a log grid of 24 points
 * over @p tr_lo_s .. @p tr_hi_s, then 30 golden-section steps). A Tr found
 * beyond the record's length means no transient (a load without a rotor):
 * then R_R (I - F) would be nearly R_R I and take a share of Rs, so Rs and
 * u_off come from the two levels alone (status 1); so they do when R_R is
 * not > 0 or the transient's rms is not above three times the residual's.
 * Work: about 54 x n_bins rows of 4 unknowns. Context: BG.
 */
void ident_rotor_fit(const ident_bin bins[], uint32_t n_bins, real_t bin_s, real_t tr_lo_s, real_t tr_hi_s,
                     ident_rotor_fit_out *out);

/* ------------------------------------------------------------------ transient inductance */

/**
 * Sums of the transient-inductance regression: per control period of the
 * high-frequency pulses, y = the volt-seconds applied (alpha), x1 = the change
 * of the current over the period, x2 = its mean less the bias (A):
 *
 *   y = Lsig x1 + R_hf T x2 + c T
 *
 * (R_hf = Rs + R_R: the rotor flux does not follow at this frequency; c the
 * slow voltage of the bias: Rs I, the rotor's back-emf, the inverter's
 * constant error).
 */
typedef struct {
    real_t s11, s12, s22, s1, s2, n; /**< sums of x1 x1, x1 x2, x2 x2, x1, x2 and of 1 */
    real_t sy1, sy2, sy, syy;        /**< sums of y x1, y x2, y and y y */
} ident_hf_sums;

/** Zero @p s. Context: any. */
void ident_hf_reset(ident_hf_sums *s);

/** One period into @p s: @p y V s, @p x1 A, @p x2 A (ten multiply-adds). Context: ISR. */
static inline void ident_hf_add(ident_hf_sums *s, real_t y, real_t x1, real_t x2)
{
    s->s11 = num_mac(x1, x1, s->s11);
    s->s12 = num_mac(x1, x2, s->s12);
    s->s22 = num_mac(x2, x2, s->s22);
    s->s1 += x1;
    s->s2 += x2;
    s->n += R(1.0);
    s->sy1 = num_mac(y, x1, s->sy1);
    s->sy2 = num_mac(y, x2, s->sy2);
    s->sy += y;
    s->syy = num_mac(y, y, s->syy);
}

/**
 * Solve the regression of @p s (period @p period_s): Lsig (H) into
 * @p lsig_H, R_hf (ohm) into @p r_hf_ohm, the rms residual over the mean
 * |x1| (a relative misfit, 0 for a perfect fit) into @p misfit. @return 0,
 * or -1 when too few periods or the excitation is degenerate. Context: BG.
 */
int ident_hf_solve(const ident_hf_sums *s, real_t period_s, real_t *lsig_H, real_t *r_hf_ohm, real_t *misfit);

/* ------------------------------------------------------------------ rotating */

/**
 * The magnetising inductance L_M = Ls - sigma Ls from a steady state at
 * speed: the window means @p p_VsA of psi_s . i_s, @p q_VsA of psi_s x i_s
 * (the stator flux from the voltage model, Wb, times the current, A),
 * @p i2_A2 of |i_s|^2 and @p psi2_Wb2 of |psi_s|^2, with @p lsig_H from the
 * standstill part. In the rotor flux frame psi_s = Ls i_d + j Lsig i_q at
 * steady state, so
 *
 *   A = P - Lsig |i|^2 = L_M i_d^2,   Q = L_M i_d i_q,
 *   |psi|^2 = (L_M + Lsig)^2 i_d^2 + Lsig^2 i_q^2,
 *
 * whence, with r = Q / A and k = |psi|^2 / A,
 * L_M^2 + (2 Lsig - k) L_M + Lsig^2 (1 + r^2) = 0 (the larger root): exact at
 * any slip. The switching ripple of the current (at no load as large as the
 * magnetising current itself) cancels from A, as its flux ripple is Lsig
 * times it; in |psi|^2 that flux ripple's square, Lsig^2 (|i|^2 - i0^2), is
 * taken out by two fixed-point passes. The fundamental's current
 * i0 = sqrt(i_d^2 + i_q^2) into @p i0_A (may be NULL). @return L_M, H, or 0
 * when A <= 0 or there is no real root. Context: BG.
 */
real_t ident_lm_from_no_load(real_t p_VsA, real_t q_VsA, real_t i2_A2, real_t psi2_Wb2, real_t lsig_H, real_t *i0_A);

/** One speed change at a constant torque command (ident_inertia). */
typedef struct {
    real_t t_s;        /**< duration of the window, s */
    real_t dw_rad_s;   /**< speed at its end less at its start, rad/s (mechanical) */
    real_t te_int_Nms; /**< integral of the electromagnetic torque over it, N m s */
} ident_speed_window;

/**
 * Inertia from an acceleration @p a and a deceleration @p d over the same
 * speed range: J dw = integral(Te) - Fbar t in each, with Fbar the
 * time-averaged friction and load torque, equal in both when the speed
 * changes at a constant rate through the same range (viscous and Coulomb
 * friction), so it drops out:
 *
 *   J = (Ia td - Id ta) / (dwa td - dwd ta).
 *
 * @return J, kg m^2, or 0 when the windows are degenerate. Context: BG.
 */
real_t ident_inertia(const ident_speed_window *a, const ident_speed_window *d);

/**
 * Viscous friction from the mean torque @p te1_Nm, @p te2_Nm at two steady
 * speeds @p w1_rad_s, @p w2_rad_s (mechanical): B = dTe / dw (a constant,
 * Coulomb, part drops out). @return B, N m s/rad (0 when the speeds are
 * equal). Context: BG.
 */
real_t ident_friction(real_t te1_Nm, real_t w1_rad_s, real_t te2_Nm, real_t w2_rad_s);

/* ------------------------------------------------------------------ T model */

/** The T-equivalent parameters of an inverse-Gamma model with Lls = Llr. */
typedef struct {
    real_t lm_H; /**< magnetising inductance Lm, H */
    real_t ls_H; /**< stator inductance Ls = L_M + Lsig, H */
    real_t lr_H; /**< rotor inductance Lr = Ls (equal leakages), H */
    real_t rr_ohm; /**< rotor resistance Rr = R_R (Lr / Lm)^2, ohm */
} ident_t_params;

/**
 * From Lsig, L_M and R_R with equal stator and rotor leakage: Ls = Lr =
 * L_M + Lsig, Lm = sqrt(L_M Ls), Rr = R_R Ls / L_M. @return 0, or -1 when
 * a value is not > 0 (@p t is then zeroed). Context: BG.
 */
int ident_t_model(real_t lsig_H, real_t lm_ref_H, real_t rr_ref_ohm, ident_t_params *t);

#ifdef __cplusplus
}
#endif

#endif /* DTC_IDENT_FIT_H */
