// The three speed controllers on an ideal mechanical plant simulated here in
// double, against the paper's closed forms: eq. 3 (IP gains), eq. 1-2 (IP
// step response), eq. 7 (nominal error decay), eq. 5 (the uncertainty the
// RBFN must learn), plus anti-windup, adaptation limits and mode switching.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

extern "C" {
#include "dtc/speed_ctl.h"
}

namespace {

constexpr double kJ = 0.045, kB = 0.005, kT = 2e-4;

motor_model nominal_motor()
{
    motor_model m{};
    m.J_kgm2 = (float)kJ;
    m.B_Nms = (float)kB;
    m.pole_pairs = 2.0f;
    return m;
}

// Ideal first-order mechanics dw/dt = (Te - B w - TL)/J + eps_extra, Te held
// over the period (the DTC is taken as perfect, K_T = 1).
struct Plant {
    double J = kJ, B = kB, TL = 0.0, eps_extra = 0.0, w = 0.0;
    void advance(double te)
    {
        const int sub = 20;
        const double h = kT / sub;
        for (int i = 0; i < sub; ++i)
            w += h * ((te - B * w - TL) / J + eps_extra);
    }
};

// Closed loop: controller + plant, reference r (rad/s), constant.
struct Loop {
    motor_model m = nominal_motor();
    speed_cfg cfg{};
    speed_ctl s{};
    Plant p;
    speed_out out{};
    explicit Loop(speed_mode mode)
    {
        speed_cfg_default(&cfg, &m);
        cfg.mode = mode;
        speed_cfg_derive(&cfg, &m);
        speed_ctl_init(&s, &cfg);
        speed_ctl_reset(&s, 0.0f);
    }
    void restart_at(double w0)
    {
        p.w = w0;
        speed_ctl_set_ref(&s, (float)w0);
    }
    void step(double r, double dr = 0.0)
    {
        speed_in in{};
        in.omega_ref_rad_s = (float)r;
        in.domega_ref_rad_s2 = (float)dr;
        in.omega_est_rad_s = (float)p.w;
        speed_ctl_step(&s, &cfg, &m, (float)kT, &in, &out);
        p.advance(out.te_ref_Nm);
    }
};

// Unit step response of eq. 2: wn^2 / (s (s^2 + 2 zeta wn s + wn^2)).
double eq2_step(double wn, double zeta, double t)
{
    if (std::abs(zeta - 1.0) < 1e-9)
        return 1.0 - std::exp(-wn * t) * (1.0 + wn * t);
    if (zeta < 1.0) {
        const double wd = wn * std::sqrt(1.0 - zeta * zeta);
        return 1.0 - std::exp(-zeta * wn * t) *
                         (std::cos(wd * t) + zeta / std::sqrt(1.0 - zeta * zeta) * std::sin(wd * t));
    }
    const double r = std::sqrt(zeta * zeta - 1.0);
    const double p1 = -wn * (zeta - r), p2 = -wn * (zeta + r);
    return 1.0 + (p2 * std::exp(p1 * t) - p1 * std::exp(p2 * t)) / (p1 - p2);
}

} // namespace

TEST(SpeedIp, GainsFollowEq3)
{
    motor_model m = nominal_motor();
    speed_cfg cfg;
    speed_cfg_default(&cfg, &m);
    const double cases[][4] = {{10, 1.0, 0.045, 0.005}, {25, 0.7, 0.045, 0.005}, {7, 1.3, 0.2, 0.02}};
    for (const auto &c : cases) {
        cfg.ip.wn_rad_s = (float)c[0];
        cfg.ip.zeta = (float)c[1];
        m.J_kgm2 = (float)c[2];
        m.B_Nms = (float)c[3];
        speed_cfg_derive(&cfg, &m);
        // K_I = wn^2 J / K_T, K_P = (2 zeta wn J - B) / K_T with K_T = 1.
        EXPECT_NEAR(cfg.ip.ki, c[0] * c[0] * c[2], 1e-5 * c[0] * c[0] * c[2]);
        EXPECT_NEAR(cfg.ip.kp, 2 * c[1] * c[0] * c[2] - c[3], 1e-5);
    }
    // Hand values for the default motor at wn = 10, zeta = 1: 4.5 and 0.895.
    m = nominal_motor();
    cfg.ip.wn_rad_s = 10.0f;
    cfg.ip.zeta = 1.0f;
    speed_cfg_derive(&cfg, &m);
    EXPECT_NEAR(cfg.ip.ki, 4.5, 1e-5);
    EXPECT_NEAR(cfg.ip.kp, 0.895, 1e-5);
}

TEST(SpeedIp, StepResponseMatchesSecondOrderClosedForm)
{
    for (double wn : {8.0, 20.0}) {
        for (double zeta : {0.6, 1.0, 1.5}) {
            Loop L(SPEED_MODE_IP);
            L.cfg.ip.wn_rad_s = (float)wn;
            L.cfg.ip.zeta = (float)zeta;
            speed_cfg_derive(&L.cfg, &L.m);
            L.restart_at(50.0);
            speed_ip_bumpless(&L.s.ip, &L.cfg.ip, (float)(kB * 50.0), 50.0f); // steady at 50
            const double step = 5.0; // 5 rad/s: far from the torque limit
            double worst = 0.0;
            for (int k = 0; k < (int)(1.5 / kT); ++k) {
                L.step(50.0 + step);
                const double t = (k + 1) * kT;
                worst = std::max(worst, std::abs((L.p.w - 50.0) / step - eq2_step(wn, zeta, t)));
            }
            EXPECT_LT(worst, 0.01) << "wn " << wn << " zeta " << zeta;
        }
    }
}

TEST(SpeedIp, RejectsLoadWithZeroSteadyError)
{
    Loop L(SPEED_MODE_IP);
    L.restart_at(50.0);
    L.p.TL = 8.0;
    for (int k = 0; k < (int)(4.0 / kT); ++k)
        L.step(50.0);
    EXPECT_NEAR(L.p.w, 50.0, 1e-3);
    EXPECT_NEAR(L.out.te_ref_Nm, 8.0 + kB * 50.0, 1e-2);
}

TEST(SpeedIp, AntiWindupKeepsOvershootSmallAfterLongSaturation)
{
    // 0 -> 150 rad/s with a 10 N m limit: about 0.7 s at the limit.
    auto run = [](bool naive) {
        Loop L(SPEED_MODE_IP);
        L.cfg.te_max_Nm = 10.0f;
        double integ = 0.0, peak = 0.0; // naive IP written here, for contrast
        for (int k = 0; k < (int)(4.0 / kT); ++k) {
            if (naive) {
                integ += L.cfg.ip.ki * (150.0 - L.p.w) * kT;
                double te = std::clamp(integ - L.cfg.ip.kp * L.p.w, -10.0, 10.0);
                L.p.advance(te);
            } else {
                L.step(150.0);
                EXPECT_LE(std::abs(L.out.te_ref_Nm), 10.0f);
            }
            peak = std::max(peak, L.p.w);
        }
        return std::make_pair(peak, L.p.w);
    };
    auto [peak, final_w] = run(false);
    auto [naive_peak, naive_final] = run(true);
    (void)naive_final;
    EXPECT_LT(peak, 150.0 * 1.05) << "overshoot after saturation";
    EXPECT_NEAR(final_w, 150.0, 0.05);
    EXPECT_GT(naive_peak, 150.0 * 1.15) << "the scenario must be one that winds a plain integrator up";
}

TEST(SpeedNominal, ErrorDecaysAsExpMinusKxT)
{
    for (double kx : {10.0, 30.0}) {
        Loop L(SPEED_MODE_NOMINAL);
        L.cfg.nominal.k_x = (float)kx;
        L.cfg.ref_wn_rad_s = 0.0f; // X_d straight from the input: eq. 6 literally
        L.restart_at(40.0);
        const double e0 = 10.0;
        double worst = 0.0;
        for (int k = 0; k < (int)(0.5 / kT); ++k) {
            const double t = k * kT;
            worst = std::max(worst, std::abs((50.0 - L.p.w) - e0 * std::exp(-kx * t)));
            L.step(50.0);
        }
        EXPECT_LT(worst, 0.01 * e0) << "K_x " << kx;
    }
}

TEST(SpeedNominal, FeedforwardTracksARampWithoutError)
{
    Loop L(SPEED_MODE_NOMINAL);
    L.cfg.ref_wn_rad_s = 0.0f;
    double r = 0.0, worst = 0.0;
    const double slope = 100.0; // rad/s^2
    for (int k = 0; k < (int)(0.5 / kT); ++k) {
        L.step(r, slope);
        r += slope * kT;
        worst = std::max(worst, std::abs(r - L.p.w));
    }
    EXPECT_LT(worst, 0.05);
}

TEST(SpeedRefModel, NominalAndRbfnReproduceTheIpResponseOfEq2)
{
    // With the reference model the nominal and RBFN controllers ask for the
    // IP's own closed loop (eq. 1-2): same step response on the nominal plant.
    for (speed_mode mode : {SPEED_MODE_NOMINAL, SPEED_MODE_RBFN}) {
        Loop L(mode);
        const double wn = L.cfg.ref_wn_rad_s, zeta = L.cfg.ref_zeta;
        ASSERT_GT(wn, 0.0);
        L.restart_at(50.0);
        L.p.w = 50.0;
        double worst = 0.0;
        for (int k = 0; k < (int)(1.5 / kT); ++k) {
            L.step(55.0);
            worst = std::max(worst, std::abs((L.p.w - 50.0) / 5.0 - eq2_step(wn, zeta, (k + 1) * kT)));
        }
        EXPECT_LT(worst, 0.02) << "mode " << mode;
    }
}

TEST(SpeedRbfn, LearnsAConstantDisturbance)
{
    Loop L(SPEED_MODE_RBFN);
    L.restart_at(50.0);
    for (int k = 0; k < (int)(0.5 / kT); ++k)
        L.step(50.0);
    const double eps = -150.0; // rad/s^2, unknown to the controller
    L.p.eps_extra = eps;
    for (int k = 0; k < (int)(3.0 / kT); ++k)
        L.step(50.0);
    EXPECT_LT(std::abs(50.0 - L.p.w), 0.01);
    EXPECT_NEAR(L.out.eps_hat, eps, 0.01 * std::abs(eps));
    EXPECT_LE(L.out.w_norm, L.cfg.rbfn.m_w);
}

TEST(SpeedRbfn, LearnsTheCase2UncertaintyOfEq5)
{
    Loop L(SPEED_MODE_RBFN);
    const double w_ref = 500.0 * 2.0 * M_PI / 60.0;
    L.restart_at(w_ref);
    for (int k = 0; k < (int)(0.5 / kT); ++k)
        L.step(w_ref);
    // CASE2: J and B times 1.4 and 8 N m of load, all at once.
    L.p.J = 1.4 * kJ;
    L.p.B = 1.4 * kB;
    L.p.TL = 8.0;
    double peak_err = 0.0;
    for (int k = 0; k < (int)(3.0 / kT); ++k) {
        L.step(w_ref);
        peak_err = std::max(peak_err, w_ref - L.p.w);
    }
    // Eq. 5 at steady state (dw/dt = 0): eps = -(A_n w + B_n Te) with
    // Te = B' w + TL, A_n = -B/J, B_n = 1/J.
    const double te = 1.4 * kB * w_ref + 8.0;
    const double eps = -((-kB / kJ) * w_ref + te / kJ);
    EXPECT_NEAR(eps, -180.1, 0.1);
    EXPECT_NEAR(L.out.eps_hat, eps, 0.01 * std::abs(eps));
    EXPECT_LT(std::abs(w_ref - L.p.w), 0.01);
    EXPECT_GT(peak_err, 0.5) << "the disturbance must actually have disturbed";
    // Sign convention: load -> speed drops (e > 0) -> eps_hat < 0 -> more torque.
    EXPECT_GT(L.out.te_ref_Nm, 8.0f);
}

TEST(SpeedRbfn, BoundDoesNotGrowOnNoiseInsideTheDeadZone)
{
    motor_model m = nominal_motor();
    speed_cfg cfg;
    speed_cfg_default(&cfg, &m);
    cfg.te_max_Nm = 1e6f;
    cfg.rbfn.zeta_leak = 0.0f;
    rbfn_state st{};
    std::mt19937 gen(7);
    const double dz = cfg.rbfn.zeta_dead_zone_rad_s;
    std::uniform_real_distribution<double> noise(-0.99 * dz, 0.99 * dz);
    speed_out out{};
    for (int k = 0; k < 1000000; ++k) { // 200 s
        speed_in in{50.0f, 0.0f, (float)(50.0 + noise(gen)), 0.0f};
        speed_rbfn_step(&st, &cfg.rbfn, &m, cfg.te_max_Nm, (float)kT, &in, &out);
        ASSERT_EQ(st.zeta_bar, 0.0f) << k;
    }
}

TEST(SpeedRbfn, BoundStaysBoundedOnLargeNoise)
{
    motor_model m = nominal_motor();
    speed_cfg cfg;
    speed_cfg_default(&cfg, &m);
    cfg.te_max_Nm = 1e6f;
    const double dz = cfg.rbfn.zeta_dead_zone_rad_s, a = 3.0 * dz;
    std::uniform_real_distribution<double> noise(-a, a);

    // Without leakage only the ceiling holds it: it must reach and keep it.
    {
        cfg.rbfn.zeta_leak = 0.0f;
        rbfn_state st{};
        std::mt19937 gen(8);
        speed_out out{};
        for (int k = 0; k < 1000000; ++k) {
            speed_in in{50.0f, 0.0f, (float)(50.0 + noise(gen)), 0.0f};
            speed_rbfn_step(&st, &cfg.rbfn, &m, cfg.te_max_Nm, (float)kT, &in, &out);
            ASSERT_LE(st.zeta_bar, cfg.rbfn.zeta_max);
            ASSERT_GE(st.zeta_bar, 0.0f);
        }
        EXPECT_EQ(st.zeta_bar, cfg.rbfn.zeta_max);
    }
    // With leakage it settles where growth and leak balance:
    // gamma E[(|n| - dz)+] = leak zeta, and for uniform noise on [-a, a]
    // E[(|n| - dz)+] = (a - dz)^2 / (2 a).
    {
        cfg.rbfn.zeta_leak = 2.0f;
        cfg.rbfn.zeta_max = 1e6f;
        rbfn_state st{};
        std::mt19937 gen(9);
        speed_out out{};
        double mean = 0.0;
        int n = 0;
        for (int k = 0; k < 1000000; ++k) {
            speed_in in{50.0f, 0.0f, (float)(50.0 + noise(gen)), 0.0f};
            speed_rbfn_step(&st, &cfg.rbfn, &m, cfg.te_max_Nm, (float)kT, &in, &out);
            if (k > 100000) {
                mean += st.zeta_bar;
                ++n;
            }
        }
        mean /= n;
        const double expect = cfg.rbfn.gamma_zeta * (a - dz) * (a - dz) / (2.0 * a) / cfg.rbfn.zeta_leak;
        EXPECT_NEAR(mean, expect, 0.05 * expect);
    }
}

TEST(SpeedRbfn, AdaptationFreezesOnlyInTheWindUpDirection)
{
    motor_model m = nominal_motor();
    speed_cfg cfg;
    speed_cfg_default(&cfg, &m);
    cfg.te_max_Nm = 1.0f;
    // e > 0 and the command at +limit: both laws would raise U: frozen.
    rbfn_state st{};
    speed_out out{};
    speed_in in{60.0f, 0.0f, 40.0f, 0.0f};
    speed_rbfn_step(&st, &cfg.rbfn, &m, cfg.te_max_Nm, (float)kT, &in, &out);
    EXPECT_EQ(out.te_ref_Nm, 1.0f);
    for (uint32_t q = 0; q < cfg.rbfn.n_nodes; ++q)
        EXPECT_EQ(st.w[q], 0.0f);
    EXPECT_EQ(st.zeta_bar, 0.0f);
    // e < 0 while at +limit (a large feedforward): adaptation lowers U: runs.
    speed_in in2{40.0f, 5000.0f, 45.0f, 0.0f};
    speed_rbfn_step(&st, &cfg.rbfn, &m, cfg.te_max_Nm, (float)kT, &in2, &out);
    EXPECT_EQ(out.te_ref_Nm, 1.0f);
    double sum = 0.0;
    for (uint32_t q = 0; q < cfg.rbfn.n_nodes; ++q)
        sum += st.w[q];
    EXPECT_GT(sum, 0.0); // -gamma e Z with e < 0 raises W, so eps_hat rises, U falls
    EXPECT_GT(st.zeta_bar, 0.0f);
}

TEST(SpeedCtl, ModeSwitchIsBumpless)
{
    Loop L(SPEED_MODE_IP);
    L.restart_at(50.0);
    L.p.TL = 8.0;
    for (int k = 0; k < (int)(3.0 / kT); ++k)
        L.step(50.0);
    const speed_mode seq[] = {SPEED_MODE_RBFN, SPEED_MODE_IP, SPEED_MODE_RBFN};
    for (speed_mode next : seq) {
        const float te_before = L.out.te_ref_Nm;
        L.cfg.mode = next;
        L.step(50.0);
        EXPECT_NEAR(L.out.te_ref_Nm, te_before, 0.02) << "switch to " << next;
        double worst = 0.0;
        for (int k = 0; k < (int)(1.0 / kT); ++k) {
            L.step(50.0);
            worst = std::max(worst, std::abs(50.0 - L.p.w));
        }
        EXPECT_LT(worst, 0.05) << "after switching to " << next;
    }
}

TEST(SpeedCtl, NonFiniteInputGivesZeroTorqueAndKeepsState)
{
    Loop L(SPEED_MODE_RBFN);
    L.restart_at(50.0);
    L.p.TL = 5.0;
    for (int k = 0; k < 5000; ++k)
        L.step(50.0);
    speed_ctl before = L.s;
    const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()};
    for (float b : bad) {
        for (int which = 0; which < 3; ++which) {
            speed_in in{50.0f, 0.0f, 50.0f, 0.0f};
            (which == 0 ? in.omega_ref_rad_s : which == 1 ? in.domega_ref_rad_s2 : in.omega_est_rad_s) = b;
            speed_out out{};
            speed_ctl_step(&L.s, &L.cfg, &L.m, (float)kT, &in, &out);
            EXPECT_EQ(out.te_ref_Nm, 0.0f);
            EXPECT_EQ(std::memcmp(&before.rbfn, &L.s.rbfn, sizeof before.rbfn), 0);
            EXPECT_EQ(std::memcmp(&before.ip, &L.s.ip, sizeof before.ip), 0);
            EXPECT_EQ(before.ref_x_rad_s, L.s.ref_x_rad_s);
        }
    }
}

TEST(SpeedCtl, RampLimiter)
{
    EXPECT_FLOAT_EQ(speed_ref_ramp(0.0f, 10.0f, 1.0f), 1.0f);
    EXPECT_FLOAT_EQ(speed_ref_ramp(0.0f, -10.0f, 1.0f), -1.0f);
    EXPECT_FLOAT_EQ(speed_ref_ramp(3.0f, 3.5f, 1.0f), 3.5f);
    EXPECT_FLOAT_EQ(speed_ref_ramp(3.0f, 2.5f, 1.0f), 2.5f);
    EXPECT_FLOAT_EQ(speed_ref_ramp(0.0f, 10.0f, 0.0f), 10.0f);  // 0: no limit
    EXPECT_FLOAT_EQ(speed_ref_ramp(0.0f, 10.0f, -1.0f), 10.0f); // negative: no limit
    // 500 rpm at the default ramp, 200 us steps: reaches the target exactly.
    float r = 0.0f;
    int k = 0;
    const float target = 52.3598775f, step = 100.0f * 2e-4f;
    while (r != target && k < 100000) {
        r = speed_ref_ramp(r, target, step);
        ++k;
    }
    EXPECT_EQ(r, target);
    EXPECT_NEAR(k * 2e-4, 52.36 / 100.0, 1e-3);
}

TEST(SpeedCtl, ConfigCheckNamesTheBrokenRule)
{
    motor_model m = nominal_motor();
    speed_cfg good;
    speed_cfg_default(&good, &m);
    EXPECT_EQ(speed_cfg_check(&good, &m), SPEED_CFG_OK);
    struct Case {
        void (*mutate)(speed_cfg *);
        int code;
    };
    const Case cases[] = {
        {[](speed_cfg *c) { c->mode = (speed_mode)7; }, SPEED_CFG_E_MODE},
        {[](speed_cfg *c) { c->te_max_Nm = 0.0f; }, SPEED_CFG_E_TE_MAX},
        {[](speed_cfg *c) { c->ramp_rad_s2 = -1.0f; }, SPEED_CFG_E_RAMP},
        {[](speed_cfg *c) { c->ip.zeta = 0.0f; }, SPEED_CFG_E_IP},
        {[](speed_cfg *c) { c->nominal.k_x = -3.0f; }, SPEED_CFG_E_NOMINAL},
        {[](speed_cfg *c) { c->rbfn.gamma_w = -1.0f; }, SPEED_CFG_E_RBFN_GAIN},
        {[](speed_cfg *c) { c->rbfn.n_nodes = 0u; }, SPEED_CFG_E_RBFN_NODES},
        {[](speed_cfg *c) { c->rbfn.n_nodes = RBFN_NODES_MAX + 1u; }, SPEED_CFG_E_RBFN_NODES},
        {[](speed_cfg *c) { c->rbfn.width[1] = 0.0f; }, SPEED_CFG_E_RBFN_NODES},
        {[](speed_cfg *c) { c->rbfn.m_w = 0.0f; }, SPEED_CFG_E_RBFN_BOUND},
        {[](speed_cfg *c) { c->ref_wn_rad_s = -1.0f; }, SPEED_CFG_E_REF_MODEL},
        {[](speed_cfg *c) { c->rbfn.k = std::numeric_limits<float>::quiet_NaN(); }, SPEED_CFG_E_RBFN_GAIN},
    };
    for (const Case &c : cases) {
        speed_cfg bad = good;
        c.mutate(&bad);
        EXPECT_EQ(speed_cfg_check(&bad, &m), c.code);
    }
    motor_model bad_m = m;
    bad_m.J_kgm2 = 0.0f;
    EXPECT_EQ(speed_cfg_check(&good, &bad_m), SPEED_CFG_E_MOTOR);
}

TEST(SpeedCtl, SurvivesAHostileConfigWithoutCrashing)
{
    // Even a configuration that fails the check must not crash the ISR.
    Loop L(SPEED_MODE_RBFN);
    L.cfg.rbfn.n_nodes = 1000u;
    L.cfg.rbfn.m_w = -5.0f;
    L.cfg.te_max_Nm = -1.0f;
    for (int k = 0; k < 100; ++k) {
        L.step(50.0);
        EXPECT_TRUE(std::isfinite(L.out.te_ref_Nm));
        EXPECT_EQ(L.out.te_ref_Nm, 0.0f); // a negative limit means no torque
    }
    // NaN gains: no torque, no NaN left in the states, and the loop works
    // again once the configuration is repaired.
    for (speed_mode mode : {SPEED_MODE_IP, SPEED_MODE_NOMINAL, SPEED_MODE_RBFN}) {
        Loop N(mode);
        N.restart_at(50.0);
        const float nan = std::numeric_limits<float>::quiet_NaN();
        N.cfg.ip.kp = nan;
        N.cfg.nominal.k_x = nan;
        N.cfg.rbfn.k = nan;
        N.cfg.ref_zeta = nan;
        for (int k = 0; k < 50; ++k) {
            N.step(50.0);
            ASSERT_EQ(N.out.te_ref_Nm, 0.0f) << "mode " << mode;
            ASSERT_TRUE(std::isfinite(N.s.ip.integ_Nm) && std::isfinite(N.s.rbfn.w[0]) &&
                        std::isfinite(N.s.ref_x_rad_s));
        }
        speed_cfg_default(&N.cfg, &N.m);
        N.cfg.mode = mode;
        N.p.TL = 2.0;
        for (int k = 0; k < (int)(3.0 / kT); ++k)
            N.step(50.0);
        EXPECT_NEAR(N.p.w, 50.0, mode == SPEED_MODE_NOMINAL ? 1.5 : 0.01) << "mode " << mode;
    }
}

// The RBFN step in two halves (command, then the learning one tick later, as
// ctl.c spreads it) gives the same commands as the whole step, bit for bit,
// through a load step, the torque limit (anti-windup: projection only) and
// a mode switch; the learning's w_norm and zeta_bar come with the learning.
TEST(SpeedCtlSplit, CommandThenLearnEqualsTheWholeStep)
{
    Loop whole(SPEED_MODE_RBFN), split(SPEED_MODE_RBFN);
    whole.restart_at(50.0);
    split.restart_at(50.0);
    int limited = 0;
    for (int k = 0; k < 20000; ++k) {
        const double r = k < 2000 ? 50.0 : 60.0;
        whole.p.TL = split.p.TL = k > 8000 ? 70.0 : 10.0; // beyond te_max: the command limits
        if (k == 15000) { // to IP and back: the switch drops a pending learning
            whole.cfg.mode = split.cfg.mode = SPEED_MODE_IP;
        } else if (k == 15100) {
            whole.cfg.mode = split.cfg.mode = SPEED_MODE_RBFN;
        }
        whole.step(r);
        speed_in in{};
        in.omega_ref_rad_s = (float)r;
        in.omega_est_rad_s = (float)split.p.w;
        speed_ctl_command(&split.s, &split.cfg, &split.m, (float)kT, &in, &split.out);
        ASSERT_EQ(split.out.te_ref_Nm, whole.out.te_ref_Nm) << "tick " << k;
        ASSERT_EQ(split.out.eps_hat, whole.out.eps_hat) << "tick " << k;
        speed_ctl_learn(&split.s, &split.cfg, (float)kT, &split.out);
        ASSERT_EQ(split.out.w_norm, whole.out.w_norm) << "tick " << k;
        ASSERT_EQ(split.out.zeta_bar, whole.out.zeta_bar) << "tick " << k;
        ASSERT_EQ(std::memcmp(split.s.rbfn.w, whole.s.rbfn.w, sizeof split.s.rbfn.w), 0) << "tick " << k;
        split.p.advance(split.out.te_ref_Nm);
        limited += std::abs(whole.out.te_ref_Nm) >= whole.cfg.te_max_Nm;
    }
    EXPECT_GT(limited, 100); // the anti-windup path was taken
    EXPECT_GT(whole.out.w_norm, 0.0f);
}

// A command whose learning never ran because the mode switched away (ctl.c
// learns in RBFN mode only) is not learned after switching back: the weights
// stay as they were until the bumpless switch sets them.
TEST(SpeedCtlSplit, APendingLearningIsDroppedAcrossAModeSwitch)
{
    Loop l(SPEED_MODE_RBFN);
    l.restart_at(50.0);
    speed_in in{};
    in.omega_ref_rad_s = 60.0f;
    in.omega_est_rad_s = 50.0f;
    speed_ctl_command(&l.s, &l.cfg, &l.m, (float)kT, &in, &l.out);
    ASSERT_NE(l.s.rbfn.learn, (uint32_t)RBFN_LEARN_NONE);
    l.cfg.mode = SPEED_MODE_IP;
    speed_ctl_command(&l.s, &l.cfg, &l.m, (float)kT, &in, &l.out); // the IP: no learning call
    l.cfg.mode = SPEED_MODE_RBFN;
    float w[RBFN_NODES_MAX];
    std::memcpy(w, l.s.rbfn.w, sizeof w);
    speed_ctl_learn(&l.s, &l.cfg, (float)kT, &l.out); // ctl.c's next tick, before the RBFN's command
    EXPECT_EQ(std::memcmp(w, l.s.rbfn.w, sizeof w), 0);
}
