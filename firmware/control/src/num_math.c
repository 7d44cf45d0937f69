/**
 * @file num_math.c
 * @brief Deterministic exp, sin, cos (dtc/num_math.h): Cody-Waite range
 *        reduction, then a Taylor polynomial in Horner form.
 */
#include "dtc/num_math.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

/* ln 2 split so that k * LN2_HI is exact for |k| <= 256 (LN2_HI has 15
 * significant bits), and the rest. */
#define LN2_HI 0.693145751953125f
#define LN2_LO 1.428606765330187e-06f
#define LOG2_E 1.4426950216293335f
#define EXP_X_MAX 88.7228f  /* ln(FLT_MAX): above, +inf */
#define EXP_X_MIN -87.33f   /* ln(FLT_MIN): below, 0 (no denormals) */

/* 2 pi in three parts of 10, 10 and 24 bits: k * C1 and k * C2 are exact for
 * |k| <= 2^14, i.e. |x| <= 1e5. */
#define TWO_PI_C1 6.28125f
#define TWO_PI_C2 0.0019359588623046875f
#define TWO_PI_C3 (-6.516827397717861e-07f)
#define INV_TWO_PI 0.15915493667125702f
#define PI_HI 3.1415927410125732f
#define PI_LO (-8.742277657347586e-08f)
#define PI_2_HI 1.5707963705062866f
#define PI_2_LO (-4.371138828673793e-08f)
#define TRIG_X_MAX 1e5f

typedef union {
    float f;
    uint32_t u;
} float_bits;

/* 2^k for k in -126..127, built from the exponent field (exact). */
static float pow2i(int32_t k)
{
    float_bits b;
    b.u = (uint32_t)(k + 127) << 23;
    return b.f;
}

/* Round to the nearest integer, halves away from zero; |t| < 2^30. */
static int32_t round_i32(float t) { return (int32_t)(t >= 0.0f ? t + 0.5f : t - 0.5f); }

float num_expf(float x)
{
    if (x != x)
        return x + x; /* NaN */
    return num_expf_not_nan(x);
}

static float exp_in_range(float x);

float num_expf_not_nan(float x)
{
    if (x > EXP_X_MAX)
        return INFINITY;
    if (x < EXP_X_MIN)
        return 0.0f;
    return exp_in_range(x);
}

/* e^x's Cody-Waite reduction and polynomial: e^x = p 2^k, k into *k_out. */
static inline float exp_reduced(float x, int32_t *k_out)
{
    int32_t k = round_i32(x * LOG2_E); /* -126..128 */
    *k_out = k;
    float kf = (float)k;
    float r = fmaf(-kf, LN2_LO, fmaf(-kf, LN2_HI, x)); /* |r| <= ln2/2 + a little */
    /* e^r = 1 + r + r^2/2! + ... + r^7/7!: truncation below 6e-9 relative; Horner
     * with fused multiply-adds (one VFMA each on the target, exact fmaf on the host). */
    float p = 1.9841270113829523e-04f;
    p = fmaf(p, r, 1.3888889225199819e-03f);
    p = fmaf(p, r, 8.333333767950535e-03f);
    p = fmaf(p, r, 4.16666679084301e-02f);
    p = fmaf(p, r, 0.1666666716337204f);
    p = fmaf(p, r, 0.5f);
    p = fmaf(p, r, 1.0f);
    return fmaf(p, r, 1.0f);
}

/* num_expf for x in [EXP_X_MIN, EXP_X_MAX]: no NaN nor range test. */
static float exp_in_range(float x)
{
    int32_t k;
    float p = exp_reduced(x, &k);
    if (k > 127)
        return (p * pow2i(k - 1)) * 2.0f;
    return p * pow2i(k);
}

float num_expf_to_88(float x)
{
    int32_t k;
    float p = exp_reduced(x, &k); /* x <= 88 gives k <= 127 (x log2 e < 127.5) */
    return p * pow2i(k);
}

/* sin(r) for |r| <= pi/2 + a little: odd Taylor polynomial to r^13
 * (truncation below 7e-10). */
static float sin_poly(float r)
{
    float r2 = r * r;
    float p = 1.6059044372074283e-10f;
    p = p * r2 - 2.5052107943679403e-08f;
    p = p * r2 + 2.7557318844628753e-06f;
    p = p * r2 - 1.9841270113829523e-04f;
    p = p * r2 + 8.333333767950535e-03f;
    p = p * r2 - 0.1666666716337204f;
    return r + (r * r2) * p;
}

/* sin(a) for a in [-pi, 3 pi / 2]: fold onto [-pi/2, pi/2] by sin(a) = sin(pi - a). */
static float sin_folded(float a)
{
    if (a > PI_2_HI)
        a = (PI_HI - a) + PI_LO;
    else if (a < -PI_2_HI)
        a = (-PI_HI - a) - PI_LO;
    return sin_poly(a);
}

/* x - k 2 pi in [-pi, pi] (|x| <= TRIG_X_MAX). */
static float reduce_two_pi(float x)
{
    int32_t k = round_i32(x * INV_TWO_PI);
    float kf = (float)k;
    return ((x - kf * TWO_PI_C1) - kf * TWO_PI_C2) - kf * TWO_PI_C3;
}

float num_sinf(float x)
{
    if (x != x)
        return x + x;
    if (!(x <= TRIG_X_MAX && x >= -TRIG_X_MAX))
        return 0.0f; /* documented: not reduced */
    return sin_folded(reduce_two_pi(x));
}

float num_cosf(float x)
{
    if (x != x)
        return x + x;
    if (!(x <= TRIG_X_MAX && x >= -TRIG_X_MAX))
        return 0.0f;
    /* cos(r) = sin(pi/2 - r), pi/2 - r in [-pi/2, 3 pi/2]. */
    float r = reduce_two_pi(x);
    return sin_folded((PI_2_HI - r) + PI_2_LO);
}

/* atan(t) for |t| <= tan(pi/12) + a little: odd Taylor polynomial to t^11
 * (truncation below 3e-9). */
static float atan_poly(float t)
{
    float t2 = t * t;
    float p = -0.09090909361839294f;
    p = p * t2 + 0.1111111119389534f;
    p = p * t2 - 0.1428571492433548f;
    p = p * t2 + 0.20000000298023224f;
    p = p * t2 - 0.3333333432674408f;
    return t + (t * t2) * p;
}

#define TAN_PI_12 0.2679491937160492f
#define SQRT3 1.7320507764816284f
#define PI_6 0.5235987901687622f

float num_atan2f(float y, float x)
{
    if (x != x || y != y)
        return x + y; /* NaN */
    float ax = x < 0.0f ? -x : x;
    float ay = y < 0.0f ? -y : y;
    if (ax == 0.0f && ay == 0.0f)
        return 0.0f;
    if (ax > 3.4e38f || ay > 3.4e38f) {
        /* an infinity: only the direction counts */
        ax = ax > 3.4e38f ? 1.0f : 0.0f;
        ay = ay > 3.4e38f ? 1.0f : 0.0f;
    }
    bool steep = ay > ax;
    float a = steep ? ax / ay : ay / ax; /* 0..1 */
    float r;
    if (a > TAN_PI_12) /* atan(a) = pi/6 + atan((sqrt3 a - 1) / (a + sqrt3)) */
        r = PI_6 + atan_poly((SQRT3 * a - 1.0f) / (a + SQRT3));
    else
        r = atan_poly(a);
    if (steep)
        r = (PI_2_HI - r) + PI_2_LO;
    if (x < 0.0f)
        r = (PI_HI - r) + PI_LO;
    return y < 0.0f ? -r : r;
}
