// RBFN building blocks (firmware/src/rbfn.c) against an independent
// double-precision Eigen implementation of eq. 8, 9, 14 and 21 written here.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <limits>
#include <algorithm>
#include <random>

extern "C" {
#include "dtc/rbfn.h"
#include "dtc/speed_ctl.h"
}

namespace {

using Vec = Eigen::VectorXd;

// Eq. 8 taken literally (no shift of the exponents): fine in double for the
// moderate inputs the comparison uses.
Vec ref_basis(const Vec &m, const Vec &s, double x)
{
    Vec phi = (-(x - m.array()).square() / (2.0 * s.array().square())).exp();
    return phi / phi.sum();
}

// Euclidean projection onto the ball |W| <= M (the discrete form of eq. 21).
Vec ref_project(const Vec &w, double M)
{
    double n = w.norm();
    return n > M ? Vec(w * (M / n)) : w;
}

// Eq. 21 integrated literally over one tick with many small Euler substeps:
// dW/dt = -g e Z, minus the radial part when on the sphere and moving out.
Vec ref_eq21_continuous(Vec w, const Vec &z, double e, double g, double dt, double M, int sub)
{
    double h = dt / sub;
    for (int i = 0; i < sub; ++i) {
        Vec d = -g * e * z;
        double n = w.norm();
        if (n >= M * (1.0 - 1e-12) && e * w.dot(z) < 0.0)
            d += g * e * w * w.dot(z) / (n * n);
        w += h * d;
    }
    return w;
}

struct Rng {
    std::mt19937 gen{12345u};
    double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(gen); }
    int uint(int a, int b) { return std::uniform_int_distribution<int>(a, b)(gen); }
};

} // namespace

TEST(RbfnBasis, MatchesEigenReferenceOnRandomInputs)
{
    Rng r;
    for (int trial = 0; trial < 2000; ++trial) {
        const int n = r.uint(1, RBFN_NODES_MAX);
        float c[RBFN_NODES_MAX], s[RBFN_NODES_MAX], z[RBFN_NODES_MAX];
        Vec mc(n), ms(n);
        for (int q = 0; q < n; ++q) {
            c[q] = (float)r.uni(-20.0, 20.0);
            s[q] = (float)r.uni(1.0, 8.0);
            mc[q] = c[q];
            ms[q] = s[q];
        }
        const float x = (float)r.uni(-30.0, 30.0);
        rbfn_basis(c, s, (uint32_t)n, x, z);
        Vec zr = ref_basis(mc, ms, x);
        double sum = 0.0;
        for (int q = 0; q < n; ++q) {
            ASSERT_NEAR(z[q], zr[q], 2e-6) << "trial " << trial << " node " << q;
            sum += z[q];
        }
        EXPECT_NEAR(sum, 1.0, 1e-6);
    }
}

TEST(RbfnBasis, FarInputsStayFiniteAndPickTheNearestNode)
{
    const float c[3] = {-10.0f, 0.0f, 10.0f};
    const float s[3] = {1.0f, 1.0f, 1.0f};
    float z[3];
    // Plain eq. 8 would give 0/0 here: every exp() underflows.
    for (float x : {1e3f, -1e3f, 1e30f, -1e30f, 3e38f}) {
        rbfn_basis(c, s, 3u, x, z);
        for (float v : z)
            ASSERT_TRUE(std::isfinite(v)) << x;
        EXPECT_NEAR(z[0] + z[1] + z[2], 1.0f, 1e-6f) << x;
        if (std::abs(x) < 1e6f) { // beyond that float cannot tell the centres apart
            EXPECT_NEAR(x > 0 ? z[2] : z[0], 1.0f, 1e-6f) << x;
        }
    }
    // A zero or negative width must not divide by zero.
    const float bad_s[3] = {0.0f, -1.0f, 1.0f};
    rbfn_basis(c, bad_s, 3u, 0.3f, z);
    EXPECT_TRUE(std::isfinite(z[0]) && std::isfinite(z[1]) && std::isfinite(z[2]));
}

// The one-exp() recurrence on a uniform grid against eq. 8 in double, over
// random grids and inputs inside and well outside the centres.
TEST(RbfnBasisGrid, MatchesEigenReferenceOnUniformGrids)
{
    Rng r;
    for (int trial = 0; trial < 3000; ++trial) {
        const int n = r.uint(1, RBFN_NODES_MAX);
        const double c0 = r.uni(-20.0, 0.0), h = r.uni(0.5, 6.0), w = h * r.uni(0.5, 1.5);
        float c[RBFN_NODES_MAX], s[RBFN_NODES_MAX], z[RBFN_NODES_MAX];
        Vec mc(n), ms(n);
        for (int q = 0; q < n; ++q) {
            c[q] = float(c0 + q * h);
            s[q] = float(w);
            mc[q] = c[q];
            ms[q] = s[q];
        }
        rbfn_grid g;
        rbfn_grid_derive(&g, c, s, uint32_t(n));
        ASSERT_EQ(g.n, uint32_t(n));
        const double span = c0 + (n - 1) * h;
        const float x = float(r.uni(c0 - 2.0 * h, span + 2.0 * h));
        rbfn_basis_grid(&g, c, uint32_t(n), x, z);
        Vec zr = ref_basis(mc, ms, x);
        double sum = 0.0;
        for (int q = 0; q < n; ++q) {
            ASSERT_NEAR(z[q], zr[q], 2e-5 * std::max(1.0, zr[q] * n)) << "trial " << trial << " node " << q;
            sum += z[q];
        }
        EXPECT_NEAR(sum, 1.0, 2e-6);
    }
}

// The command tick's one pass (rbfn_grid_eval): the unnormalised basis times the scale is the
// reference basis of eq. 8, and the output is eq. 9 with random weights.
TEST(RbfnGridEval, BasisTimesScaleAndOutputMatchTheReference)
{
    Rng r;
    for (int trial = 0; trial < 3000; ++trial) {
        const int n = r.uint(1, RBFN_NODES_MAX);
        const double c0 = r.uni(-20.0, 0.0), h = r.uni(0.5, 6.0), w = h * r.uni(0.5, 1.5);
        float c[RBFN_NODES_MAX], s[RBFN_NODES_MAX], v[RBFN_NODES_MAX], wt[RBFN_NODES_MAX];
        Vec mc(n), ms(n), mw(n);
        for (int q = 0; q < n; ++q) {
            c[q] = float(c0 + q * h);
            s[q] = float(w);
            wt[q] = float(r.uni(-500.0, 500.0));
            mc[q] = c[q];
            ms[q] = s[q];
            mw[q] = wt[q];
        }
        rbfn_grid g;
        rbfn_grid_derive(&g, c, s, uint32_t(n));
        ASSERT_EQ(g.n, uint32_t(n));
        const double span = c0 + (n - 1) * h;
        const float x = float(r.uni(c0 - 2.0 * h, span + 2.0 * h));
        float scale = 0.0f;
        const float y = rbfn_grid_eval(&g, c, uint32_t(n), x, wt, v, &scale);
        Vec zr = ref_basis(mc, ms, x);
        for (int q = 0; q < n; ++q)
            ASSERT_NEAR(double(v[q]) * scale, zr[q], 2e-5 * std::max(1.0, zr[q] * n)) << "trial " << trial << " node " << q;
        EXPECT_NEAR(y, mw.dot(zr), 1e-5 * mw.cwiseAbs().sum()) << "trial " << trial;
    }
    const float c[3] = {-10.0f, 0.0f, 10.0f}, s[3] = {1.0f, 1.0f, 1.0f}, wt[3] = {1.0f, 2.0f, 3.0f};
    rbfn_grid g;
    rbfn_grid_derive(&g, c, s, 3u);
    float v[3], scale = 0.0f;
    EXPECT_TRUE(std::isnan(rbfn_grid_eval(&g, c, 3u, std::numeric_limits<float>::quiet_NaN(), wt, v, &scale)));
    EXPECT_TRUE(std::isnan(scale) && std::isnan(v[0]) && std::isnan(v[1]) && std::isnan(v[2]));
}

TEST(RbfnBasisGrid, RefusesGridsThatAreNotUniformAndHandlesFarInputs)
{
    const float c[3] = {-10.0f, 0.0f, 10.0f};
    const float s[3] = {1.25f, 1.25f, 1.25f}; // 8 widths apart: the sparsest grid the recurrence takes
    rbfn_grid g;
    rbfn_grid_derive(&g, c, s, 3u);
    ASSERT_EQ(g.n, 3u);
    float z[3];
    for (float x : {1e3f, -1e3f, 1e30f, -1e30f, 3e38f, -3e38f}) {
        rbfn_basis_grid(&g, c, 3u, x, z);
        EXPECT_EQ(x > 0 ? z[2] : z[0], 1.0f) << x;
        EXPECT_EQ(z[1], 0.0f) << x;
    }
    rbfn_basis_grid(&g, c, 3u, std::numeric_limits<float>::quiet_NaN(), z);
    EXPECT_TRUE(std::isnan(z[0]) && std::isnan(z[1]) && std::isnan(z[2]));

    const float uneven[3] = {-10.0f, 0.0f, 11.0f};
    rbfn_grid_derive(&g, uneven, s, 3u);
    EXPECT_EQ(g.n, 0u);
    const float widths[3] = {1.0f, 1.0f, 2.0f};
    rbfn_grid_derive(&g, c, widths, 3u);
    EXPECT_EQ(g.n, 0u);
    const float down[3] = {10.0f, 0.0f, -10.0f};
    rbfn_grid_derive(&g, down, s, 3u);
    EXPECT_EQ(g.n, 0u);
    const float zero_w[3] = {0.0f, 0.0f, 0.0f};
    rbfn_grid_derive(&g, c, zero_w, 3u);
    EXPECT_EQ(g.n, 0u);
}

// The recurrence's ratio q = exp(-d^2) must stay a normal float: with nodes
// d = 10 widths apart it is 0 and the downward ratio q / r is 0 / 0 = NaN
// for every node at x = -5 (midway). Such a grid is refused (the caller then
// takes rbfn_basis); the sparsest accepted ones, d^2 up to RBFN_GRID_D2_MAX,
// match eq. 8 in double, midway between nodes too. d = 1e16 (whose exp
// argument could have been inf - inf) is refused as well.
TEST(RbfnBasisGrid, RefusesGridsTooSparseForTheRecurrence)
{
    const float c[3] = {-10.0f, 0.0f, 10.0f};
    rbfn_grid g;
    const float w10[3] = {1.0f, 1.0f, 1.0f};
    rbfn_grid_derive(&g, c, w10, 3u);
    EXPECT_EQ(g.n, 0u) << "d = 10";
    float z[3];
    rbfn_basis(c, w10, 3u, -5.0f, z); // what the controller takes instead: finite, the two nodes equal
    EXPECT_TRUE(std::isfinite(z[0]) && std::isfinite(z[1]) && std::isfinite(z[2]));
    EXPECT_NEAR(z[0], 0.5f, 1e-6f);
    EXPECT_NEAR(z[1], 0.5f, 1e-6f);
    const float w16[3] = {1e-5f, 1e-5f, 1e-5f};
    const float c16[3] = {-1e11f, 0.0f, 1e11f};
    rbfn_grid_derive(&g, c16, w16, 3u);
    EXPECT_EQ(g.n, 0u) << "d = 1e16";

    const float c5[5] = {-20.0f, -10.0f, 0.0f, 10.0f, 20.0f};
    Vec mc(5), ms(5);
    for (double d : {4.0, 7.0, 8.9}) {
        float w[5];
        for (int q = 0; q < 5; ++q) {
            w[q] = float(10.0 / d);
            mc[q] = c5[q];
            ms[q] = w[q];
        }
        rbfn_grid_derive(&g, c5, w, 5u);
        ASSERT_EQ(g.n, 5u) << "d = " << d;
        for (float x : {-25.0f, -15.0f, -5.0f, -0.1f, 0.0f, 4.9f, 5.0f, 5.1f, 15.0f, 25.0f}) {
            float zg[5];
            rbfn_basis_grid(&g, c5, 5u, x, zg);
            Vec zr = ref_basis(mc, ms, x);
            for (int q = 0; q < 5; ++q)
                EXPECT_NEAR(zg[q], zr[q], 2e-5 * std::max(1.0, zr[q] * 5)) << "d = " << d << ", x = " << x << ", node " << q;
        }
    }
}

// The default configuration is a uniform grid, so the controller takes the
// one-exp() path, and it gives the same basis as eq. 8.
TEST(RbfnBasisGrid, DefaultConfigurationUsesTheGrid)
{
    speed_cfg cfg;
    motor_model m{};
    m.J_kgm2 = 0.045f;
    m.B_Nms = 0.005f;
    speed_cfg_default(&cfg, &m);
    const rbfn_cfg &rc = cfg.rbfn;
    ASSERT_EQ(rc.grid.n, rc.n_nodes);
    Vec mc(rc.n_nodes), ms(rc.n_nodes);
    for (uint32_t q = 0; q < rc.n_nodes; ++q) {
        mc[q] = rc.centre[q];
        ms[q] = rc.width[q];
    }
    for (float x : {-300.0f, -31.0f, -2.5f, 0.0f, 0.7f, 12.0f, 44.0f}) {
        float z[RBFN_NODES_MAX];
        rbfn_basis_grid(&rc.grid, rc.centre, rc.n_nodes, x, z);
        Vec zr = ref_basis(mc, ms, x);
        for (uint32_t q = 0; q < rc.n_nodes; ++q)
            EXPECT_NEAR(z[q], zr[q], 1e-5) << x << " node " << q;
    }
}

TEST(RbfnOutput, IsTheDotProductOfEq9)
{
    Rng r;
    for (int trial = 0; trial < 500; ++trial) {
        const int n = r.uint(1, RBFN_NODES_MAX);
        float w[RBFN_NODES_MAX], z[RBFN_NODES_MAX];
        Vec ew(n), ez(n);
        for (int q = 0; q < n; ++q) {
            w[q] = (float)r.uni(-500.0, 500.0);
            z[q] = (float)r.uni(0.0, 1.0);
            ew[q] = w[q];
            ez[q] = z[q];
        }
        EXPECT_NEAR(rbfn_output(w, z, (uint32_t)n), ew.dot(ez), 1e-3);
        EXPECT_NEAR(rbfn_norm(w, (uint32_t)n), ew.norm(), 1e-3);
    }
}

TEST(RbfnUpdate, ManyStepsMatchEigenProjectedGradient)
{
    Rng r;
    const int n = 7;
    float c[n], s[n], w[n] = {0};
    Vec mc(n), ms(n), wr = Vec::Zero(n);
    for (int q = 0; q < n; ++q) {
        c[q] = (float)(-9.0 + 3.0 * q);
        s[q] = 2.0f;
        mc[q] = c[q];
        ms[q] = s[q];
    }
    const float M = 300.0f, g = 5000.0f, dt = 2e-4f;
    int projected = 0;
    double worst = 0.0;
    for (int k = 0; k < 20000; ++k) {
        // A drifting error with noise: spends time both inside and on the sphere.
        const float e = (float)(8.0 * std::sin(k * 1e-3) + r.uni(-2.0, 2.0));
        float z[n];
        rbfn_basis(c, s, n, e, z);
        rbfn_update_projected(w, z, n, e, g * dt, M);
        Vec zr = ref_basis(mc, ms, e);
        Vec step = wr - double(g) * double(dt) * double(e) * zr;
        if (step.norm() > M)
            ++projected;
        wr = ref_project(step, M);
        for (int q = 0; q < n; ++q)
            worst = std::max(worst, std::abs(double(w[q]) - wr[q]));
    }
    EXPECT_GT(projected, 100) << "the sequence must exercise the projection";
    EXPECT_LT(worst, 1e-3 * M) << "float update drifted from the double reference";
}

TEST(RbfnUpdate, OneTickOnTheSphereAgreesWithContinuousEq21)
{
    Rng r;
    const int n = 5;
    const double M = 100.0, dt = 2e-4;
    for (int trial = 0; trial < 300; ++trial) {
        float w[n], z[n];
        Vec wr(n), zr(n);
        for (int q = 0; q < n; ++q) {
            wr[q] = r.uni(-1.0, 1.0);
            zr[q] = r.uni(0.0, 1.0);
        }
        zr /= zr.sum();
        wr *= M / wr.norm(); // on the sphere
        for (int q = 0; q < n; ++q) {
            w[q] = (float)wr[q];
            z[q] = (float)zr[q];
        }
        const double e = r.uni(-5.0, 5.0), g = 2000.0;
        rbfn_update_projected(w, z, n, (float)e, (float)(g * dt), (float)M);
        Vec wc = ref_eq21_continuous(wr, zr, e, g, dt, M, 2000);
        // The step is g e dt |Z| <= 2 rad/s^2; the two differ at second order.
        const double step = g * std::abs(e) * dt * zr.norm();
        for (int q = 0; q < n; ++q)
            EXPECT_NEAR(w[q], wc[q], 1e-4 * M + step * step / M * 2.0) << trial;
    }
}

TEST(RbfnUpdate, InwardStepIsNotModified)
{
    float w[3] = {30.0f, -40.0f, 0.0f}; // |W| = 50 < 100
    const float z[3] = {0.2f, 0.5f, 0.3f};
    rbfn_update_projected(w, z, 3u, 2.0f, 1.0f, 100.0f);
    EXPECT_FLOAT_EQ(w[0], 30.0f - 0.4f);
    EXPECT_FLOAT_EQ(w[1], -40.0f - 1.0f);
    EXPECT_FLOAT_EQ(w[2], 0.0f - 0.6f);
}

TEST(RbfnUpdate, NormNeverExceedsBoundForAdversarialSequences)
{
    Rng r;
    const float bounds[] = {1e-3f, 0.7f, 1.0f, 180.0f, 1000.0f, 3.3e4f};
    for (float M : bounds) {
        for (int n = 1; n <= RBFN_NODES_MAX; ++n) {
            float w[RBFN_NODES_MAX] = {0}, z[RBFN_NODES_MAX], c[RBFN_NODES_MAX], s[RBFN_NODES_MAX];
            for (int q = 0; q < n; ++q) {
                c[q] = (float)r.uni(-5.0, 5.0);
                s[q] = (float)r.uni(0.1, 3.0);
            }
            for (int k = 0; k < 5000; ++k) {
                // Huge gains and errors, alternating signs and bursts.
                const float e = (float)((k % 7 == 0 ? -1.0 : 1.0) * r.uni(0.0, 1e4));
                const float gdt = (float)std::pow(10.0, r.uni(-3.0, 6.0));
                rbfn_basis(c, s, (uint32_t)n, (float)r.uni(-10.0, 10.0), z);
                const float ret = rbfn_update_projected(w, z, (uint32_t)n, e, gdt, M);
                double norm = 0.0;
                for (int q = 0; q < n; ++q)
                    norm += double(w[q]) * double(w[q]);
                norm = std::sqrt(norm);
                ASSERT_LE(norm, double(M)) << "M " << M << " n " << n << " k " << k;
                ASSERT_LE(double(ret), double(M));
            }
        }
    }
}

TEST(RbfnController, WeightNormBoundedAfterEveryStepWithHugeGains)
{
    Rng r;
    motor_model m{};
    m.J_kgm2 = 0.045f;
    m.B_Nms = 0.005f;
    speed_cfg cfg;
    speed_cfg_default(&cfg, &m);
    cfg.rbfn.gamma_w = 1e7f;
    cfg.rbfn.m_w = 250.0f;
    cfg.te_max_Nm = 1e9f; // never limited, so adaptation always runs
    rbfn_state st{};
    for (int k = 0; k < 100000; ++k) {
        speed_in in{};
        in.omega_ref_rad_s = (float)r.uni(-200.0, 200.0);
        in.omega_est_rad_s = (float)r.uni(-200.0, 200.0);
        in.domega_ref_rad_s2 = (float)r.uni(-1e3, 1e3);
        speed_out out{};
        speed_rbfn_step(&st, &cfg.rbfn, &m, cfg.te_max_Nm, 2e-4f, &in, &out);
        double norm = 0.0;
        for (uint32_t q = 0; q < cfg.rbfn.n_nodes; ++q)
            norm += double(st.w[q]) * double(st.w[q]);
        ASSERT_LE(std::sqrt(norm), double(cfg.rbfn.m_w)) << k;
        ASSERT_LE(out.w_norm, cfg.rbfn.m_w);
    }
}
