// The project's own exp, sin, cos (firmware/control/include/dtc/num_math.h)
// against the double-precision libm, over the ranges the header states.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>

#include "dtc/num_math.h"

namespace {

// Every step-th float of magnitude up to max_mag, both signs (and 0), walked
// by bit pattern so that small magnitudes get as many points as large ones.
template <typename F> void walk_floats(float max_mag, uint32_t step, F f)
{
    uint32_t top;
    std::memcpy(&top, &max_mag, sizeof top);
    for (uint32_t u = 0; u <= top; u += step) {
        float x;
        std::memcpy(&x, &u, sizeof x);
        f(x);
        f(-x);
    }
}

// A variant of num_expf against num_expf itself, bit for bit, over every
// step-th float up to walk_mag that lies in [lo, hi], then the @p extra points
// (those too only inside [lo, hi]): how many were compared, how many differ,
// and the first that does.
struct SameBits {
    uint64_t n = 0, differ = 0;
    float first = 0.0f;
};
template <typename F>
SameBits compare_with_expf(F variant, float lo, float hi, float walk_mag, uint32_t step,
                           std::initializer_list<float> extra)
{
    SameBits r;
    auto check = [&](float x) {
        if (!(x >= lo && x <= hi))
            return;
        float a = num_expf(x), b = variant(x);
        if (std::memcmp(&a, &b, sizeof a) != 0 && r.differ++ == 0)
            r.first = x;
        r.n++;
    };
    walk_floats(walk_mag, step, check);
    for (float x : extra)
        check(x);
    return r;
}

TEST(NumMath, ExpRelativeErrorBound)
{
    double worst = 0.0, at = 0.0;
    uint64_t n = 0;
    walk_floats(88.0f, 499u, [&](float x) {
        if (x < -87.0f)
            return;
        double ref = std::exp(static_cast<double>(x));
        double err = std::fabs(static_cast<double>(num_expf(x)) - ref) / ref;
        if (err > worst) {
            worst = err;
            at = x;
        }
        n++;
    });
    EXPECT_GT(n, 1000000u);
    EXPECT_LE(worst, 3e-7) << "at x = " << at;
    // The bound is not slack beyond reason: a float result is at best 0.5 ulp.
    EXPECT_GE(worst, 2e-8);
}

TEST(NumMath, ExpEdges)
{
    EXPECT_EQ(num_expf(0.0f), 1.0f);
    EXPECT_EQ(num_expf(-87.5f), 0.0f);
    EXPECT_EQ(num_expf(-1e30f), 0.0f);
    EXPECT_EQ(num_expf(-std::numeric_limits<float>::infinity()), 0.0f);
    EXPECT_TRUE(std::isinf(num_expf(88.8f)));
    EXPECT_TRUE(std::isinf(num_expf(std::numeric_limits<float>::infinity())));
    EXPECT_TRUE(std::isnan(num_expf(std::numeric_limits<float>::quiet_NaN())));
    // The largest finite results (k = 128 takes the two-step scaling).
    float big = num_expf(88.72f);
    EXPECT_TRUE(std::isfinite(big));
    EXPECT_NEAR(static_cast<double>(big) / std::exp(static_cast<double>(88.72f)), 1.0, 3e-7);
}

// The NaN-free entry point is the same function without its NaN test: the
// same bits for every float that is not NaN (walked over the whole range,
// infinities and the saturating ends included).
TEST(NumMath, ExpNotNanGivesTheSameBitsAsExp)
{
    const float inf = std::numeric_limits<float>::infinity();
    SameBits r = compare_with_expf([](float x) { return num_expf_not_nan(x); }, -inf, inf, inf, 997u,
                                   {0.0f, -0.0f, 88.72f, 88.8f, -87.5f, -1e30f, 1e30f, inf, -inf,
                                    std::numeric_limits<float>::denorm_min()});
    EXPECT_GT(r.n, 4000000u);
    EXPECT_EQ(r.differ, 0u) << "first at x = " << r.first;
    EXPECT_EQ(num_expf_not_nan(0.0f), 1.0f);
    EXPECT_EQ(num_expf_not_nan(-std::numeric_limits<float>::infinity()), 0.0f);
    EXPECT_TRUE(std::isinf(num_expf_not_nan(std::numeric_limits<float>::infinity())));
}

// num_expf_not_nan inside num_expf's range (where it takes the path without
// range tests): the same bits as num_expf for every float in [-87.3, 88.7],
// walked with a smaller step than the whole-range walk above, the ends and
// zero included.
TEST(NumMath, ExpNotNanGivesTheSameBitsAsExpInItsRange)
{
    SameBits r = compare_with_expf([](float x) { return num_expf_not_nan(x); }, -87.3f, 88.7f, 88.7f, 97u,
                                   {0.0f, -0.0f, -87.3f, 88.7f, -80.0f, -1.78f, 1e-30f,
                                    std::numeric_limits<float>::denorm_min()});
    EXPECT_GT(r.n, 20000000u);
    EXPECT_EQ(r.differ, 0u) << "first at x = " << r.first;
}

// num_expf_to_88 (no NaN, range nor 2^128 test) against num_expf:
// the same bits for every float in [-87.3, 88.0], the ends and zero included.
TEST(NumMath, ExpTo88GivesTheSameBitsAsExpInItsRange)
{
    SameBits r = compare_with_expf([](float x) { return num_expf_to_88(x); }, -87.3f, 88.0f, 88.0f, 97u,
                                   {0.0f, -0.0f, -87.3f, 88.0f, -80.0f, 7.2f, 1e-30f,
                                    std::numeric_limits<float>::denorm_min()});
    EXPECT_GT(r.n, 20000000u);
    EXPECT_EQ(r.differ, 0u) << "first at x = " << r.first;
}

// The largest absolute errors of num_sinf and num_cosf against double sin and
// cos over the floats of [-max_mag, max_mag] (every step-th), and where.
struct TrigWorst {
    double sin_err = 0.0, cos_err = 0.0;
    float sin_at = 0.0f, cos_at = 0.0f;
};

TrigWorst trig_worst(float max_mag, uint32_t step)
{
    TrigWorst w;
    walk_floats(max_mag, step, [&](float x) {
        double es = std::fabs(static_cast<double>(num_sinf(x)) - std::sin(static_cast<double>(x)));
        double ec = std::fabs(static_cast<double>(num_cosf(x)) - std::cos(static_cast<double>(x)));
        if (es > w.sin_err) {
            w.sin_err = es;
            w.sin_at = x;
        }
        if (ec > w.cos_err) {
            w.cos_err = ec;
            w.cos_at = x;
        }
    });
    return w;
}

TEST(NumMath, SinCosAbsoluteErrorOverTheVfAngleRange)
{
    TrigWorst w = trig_worst(2.0f * 3.14159265f, 401u);
    EXPECT_LE(w.sin_err, 4e-7) << "sin at x = " << w.sin_at;
    EXPECT_LE(w.cos_err, 4e-7) << "cos at x = " << w.cos_at;
}

TEST(NumMath, SinCosAbsoluteErrorUpTo1000)
{
    TrigWorst w = trig_worst(1000.0f, 1499u);
    EXPECT_LE(w.sin_err, 2e-6) << "sin at x = " << w.sin_at;
    EXPECT_LE(w.cos_err, 2e-6) << "cos at x = " << w.cos_at;
}

TEST(NumMath, SinCosEdges)
{
    EXPECT_EQ(num_sinf(0.0f), 0.0f);
    EXPECT_NEAR(num_cosf(0.0f), 1.0f, 1e-7);
    EXPECT_TRUE(std::isnan(num_sinf(std::numeric_limits<float>::quiet_NaN())));
    EXPECT_TRUE(std::isnan(num_cosf(std::numeric_limits<float>::quiet_NaN())));
    EXPECT_EQ(num_sinf(1e6f), 0.0f); // documented: beyond 1e5 not reduced
    EXPECT_EQ(num_cosf(-std::numeric_limits<float>::infinity()), 0.0f);
}

TEST(NumMath, Atan2AbsoluteErrorEverywhere)
{
    // Directions all around the circle and magnitudes from 1e-30 to 1e30.
    double worst = 0.0;
    float at_y = 0.0f, at_x = 0.0f;
    for (int m = -30; m <= 30; m += 6) {
        double r = std::pow(10.0, m);
        for (int i = 0; i < 200000; ++i) {
            double th = -3.14159265358979 + 6.28318530717959 * (i + 0.5) / 200000.0;
            float x = static_cast<float>(r * std::cos(th)), y = static_cast<float>(r * std::sin(th));
            double e = std::fabs(static_cast<double>(num_atan2f(y, x)) -
                                 std::atan2(static_cast<double>(y), static_cast<double>(x)));
            if (e > worst) {
                worst = e;
                at_y = y;
                at_x = x;
            }
        }
    }
    EXPECT_LE(worst, 4e-7) << "at (" << at_x << ", " << at_y << ")";
}

TEST(NumMath, Atan2Edges)
{
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(num_atan2f(0.0f, 0.0f), 0.0f);
    EXPECT_EQ(num_atan2f(0.0f, 1.0f), 0.0f);
    EXPECT_NEAR(num_atan2f(0.0f, -1.0f), 3.14159265, 4e-7);
    EXPECT_NEAR(num_atan2f(1.0f, 0.0f), 1.57079633, 4e-7);
    EXPECT_NEAR(num_atan2f(-1.0f, 0.0f), -1.57079633, 4e-7);
    EXPECT_NEAR(num_atan2f(inf, inf), 0.78539816, 4e-7);
    EXPECT_NEAR(num_atan2f(1.0f, -inf), 3.14159265, 4e-7);
    EXPECT_TRUE(std::isnan(num_atan2f(std::numeric_limits<float>::quiet_NaN(), 1.0f)));
}

} // namespace
