/**
 * @file num_math.h
 * @brief The project's own exp, sin, cos and atan2 in single precision.
 *
 * Why: libm differs between builds (glibc on the host SIL, newlib on the
 * target) by an ulp here and there, so the same input sequence would give
 * different control outputs on the two within a few thousand ticks. These use
 * only IEEE + - * / on float, a float -> int32 conversion and the exponent
 * bits of a float, all exactly specified, so every build that compiles them
 * without contraction (-ffp-contract=off) and with float evaluation
 * (FLT_EVAL_METHOD 0: SSE on x86-64, the FPv4-SP on the Cortex-M4F) returns
 * the same bits. They are also short (no calls, no tables).
 *
 * Error bounds (checked by tests/unit/test_num_math.cpp against the
 * 64-bit libm over the stated ranges):
 *  - num_expf: relative error <= 3e-7 (about 2.5 ulp) for x in [-87, 88];
 *    0 below -87.3 (no denormals), +inf above 88.72, NaN for NaN.
 *  - num_sinf, num_cosf: absolute error <= 4e-7 for |x| <= 2 pi (the V/f angle
 *    range), <= 2e-6 for |x| <= 1000. Arguments beyond 1e5 are not reduced:
 *    the result is 0.
 *  - num_atan2f: absolute error <= 4e-7 rad for every finite (x, y); an
 *    infinite component counts by its direction only.
 * All are constant-time apart from the branch on the range; any context.
 */
#ifndef DTC_NUM_MATH_H
#define DTC_NUM_MATH_H

#ifdef __cplusplus
extern "C" {
#endif

/** e^x (see the bounds above). Context: ANY. */
float num_expf(float x);

/** num_expf for an argument known not to be NaN (the same bits without the
 *  NaN test, for callers on the tick's hot path). A NaN argument
 *  is undefined here: callers that cannot rule it out call num_expf.
 *  Context: ANY. */
float num_expf_not_nan(float x);

/** num_expf for an argument known to lie in [-87.3, 88.0] (the same bits; no
 *  NaN nor range test, and none for 2^128, which only x above 88.37 needs).
 *  Outside that range the result is undefined: callers that cannot bound the
 *  argument call num_expf_not_nan or num_expf. Context: ANY. */
float num_expf_to_88(float x);

/** sin(x), x in rad (see the bounds above). Context: ANY. */
float num_sinf(float x);

/** cos(x), x in rad (see the bounds above). Context: ANY. */
float num_cosf(float x);

/** Angle of (x, y) in rad, in [-pi, pi] (see the bounds above); (0, 0) gives 0. Context: ANY. */
float num_atan2f(float y, float x);

#ifdef __cplusplus
}
#endif

#endif /* DTC_NUM_MATH_H */
