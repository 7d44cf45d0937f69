/**
 * @file num.h
 * @brief The numeric vocabulary of the control code.
 *
 * Algorithms use real_t and these helpers only, so that a fixed-point
 * (Q-format) backend for FPU-less DSPs can replace this header without
 * rewriting them. Today real_t is IEEE single precision (Cortex-M4F FPU).
 * Every function is constant-time and may be called from any context.
 */
#ifndef DTC_NUM_H
#define DTC_NUM_H

#include <math.h>

#include "dtc/num_math.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef float real_t;

/** A literal in the working type: R(0.5) */
#define R(x) ((real_t)(x##f))

#define NUM_PI R(3.14159265358979)
#define NUM_SQRT3 R(1.73205080756888)
#define NUM_INV_SQRT3 R(0.577350269189626)

/** a * b. In a Q backend: widening multiply, shift, saturate. */
static inline real_t num_mul(real_t a, real_t b) { return a * b; }

/** a * b + c with one rounding where the FPU has fused multiply-add. */
static inline real_t num_mac(real_t a, real_t b, real_t c) { return fmaf(a, b, c); }

/** a / b for b != 0; callers guarantee b is away from zero. */
static inline real_t num_div(real_t a, real_t b) { return a / b; }

/** Clamp x to [lo, hi]; requires lo <= hi. */
static inline real_t num_sat(real_t x, real_t lo, real_t hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

/** Clamp x to [-lim, lim]; requires lim >= 0. */
static inline real_t num_limit(real_t x, real_t lim) { return num_sat(x, -lim, lim); }

/** |x|. */
static inline real_t num_abs(real_t x) { return fabsf(x); }

/** sqrt(x); x <= 0 (and NaN) gives 0, so a rounding-negative argument is safe. */
static inline real_t num_sqrt(real_t x) { return sqrtf(x > R(0.0) ? x : R(0.0)); }

/** sqrt(x) of an argument that cannot be negative (a sum of squares): num_sqrt
 *  without its clamp (the same result for every x >= 0; a NaN stays NaN). */
static inline real_t num_sqrt_nonneg(real_t x) { return sqrtf(x); }

/** e^x; overflows to +inf above about 88.7. The project's own (dtc/num_math.h), so
 *  every build returns the same bits. */
static inline real_t num_exp(real_t x) { return num_expf(x); }

/** sin(x), x in rad. */
static inline real_t num_sin(real_t x) { return num_sinf(x); }

/** cos(x), x in rad. */
static inline real_t num_cos(real_t x) { return num_cosf(x); }

/** Angle of (x, y) in rad, in [-pi, pi]. */
static inline real_t num_atan2(real_t y, real_t x) { return num_atan2f(y, x); }

/** sign(x): -1, 0 or +1. */
static inline real_t num_sign(real_t x) { return x > R(0.0) ? R(1.0) : (x < R(0.0) ? R(-1.0) : R(0.0)); }

#ifdef __cplusplus
}
#endif

#endif /* DTC_NUM_H */
