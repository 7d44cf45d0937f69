// Direct-on-line start from the ideal 220 V, 60 Hz source, run through the
// engine's library API on host_sim/scenarios/dol_start.ini, against the
// steady-state T-equivalent circuit computed independently (tests/common/tequiv.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "sim_test_util.hpp"
#include "tequiv.hpp"

namespace {

struct DolRun {
    simtest::Loaded scen;
    sim_result res{};
};

const DolRun &dol_run()
{
    static DolRun r = [] {
        DolRun run;
        run.scen = simtest::load_scenario(simtest::source_path("host_sim/scenarios/dol_start.ini"));
        if (run.scen.rc == 0) {
            sim_options o;
            sim_options_default(&o);
            sim_run(run.scen.sc.get(), &o, &run.res);
        }
        return run;
    }();
    return r;
}

const sim_window_result *window(const sim_metrics &m, const char *name)
{
    for (int i = 0; i < m.n_windows; ++i)
        if (std::string(m.windows[i].name) == name)
            return &m.windows[i];
    return nullptr;
}

} // namespace

TEST(DolStart, ReferencePointsMatchTheMotorSheet)
{
    const DolRun &r = dol_run();
    ASSERT_EQ(r.scen.rc, 0) << r.scen.error;
    auto m = tequiv::from_params(r.scen.sc->plant.motor);
    // docs/motor-10hp.json: no load 1798.9 rpm / 7.84 A; 20 N m 1773.7 rpm / 13.70 A.
    auto p0 = tequiv::solve(m, 220.0, 60.0, 0.0);
    auto p1 = tequiv::solve(m, 220.0, 60.0, 20.0);
    EXPECT_NEAR(p0.speed_rpm, 1798.9, 0.1);
    EXPECT_NEAR(p0.is_rms_A, 7.84, 0.01);
    EXPECT_NEAR(p1.speed_rpm, 1773.7, 0.1);
    EXPECT_NEAR(p1.is_rms_A, 13.70, 0.01);
}

TEST(DolStart, WindowsMatchTheTEquivalentCircuit)
{
    const DolRun &r = dol_run();
    ASSERT_EQ(r.scen.rc, 0) << r.scen.error;
    ASSERT_EQ(r.res.status, SIM_OK) << r.res.error;
    const scenario &sc = *r.scen.sc;
    auto m = tequiv::from_params(sc.plant.motor);
    const double v = sc.plant.sine.v_ll_rms_V, f = sc.plant.sine.f_Hz;
    ASSERT_EQ(sc.n_load, 1);

    auto p0 = tequiv::solve(m, v, f, 0.0);
    auto p1 = tequiv::solve(m, v, f, sc.load[0].nm);
    const sim_metrics &met = r.res.metrics;
    const sim_window_result *w0 = window(met, "noload");
    const sim_window_result *w1 = window(met, "load");
    ASSERT_NE(w0, nullptr);
    ASSERT_NE(w1, nullptr);
    ASSERT_TRUE(w0->valid);
    ASSERT_TRUE(w1->valid);

    EXPECT_NEAR(w0->speed_rpm, p0.speed_rpm, 0.002 * p0.speed_rpm);
    EXPECT_NEAR(w0->is_rms_a, p0.is_rms_A, 0.01 * p0.is_rms_A);
    EXPECT_NEAR(w1->speed_rpm, p1.speed_rpm, 0.002 * p1.speed_rpm);
    EXPECT_NEAR(w1->is_rms_a, p1.is_rms_A, 0.01 * p1.is_rms_A);

    // The final means (last 0.1 s = 6 periods) agree with the loaded point too,
    // and the torque balances load plus friction.
    EXPECT_NEAR(met.speed_final_rpm, p1.speed_rpm, 0.002 * p1.speed_rpm);
    EXPECT_NEAR(met.speed_final_rad_s, p1.omega_m_rad_s, 0.002 * p1.omega_m_rad_s);
    EXPECT_NEAR(met.is_rms_final_a, p1.is_rms_A, 0.01 * p1.is_rms_A);
    EXPECT_NEAR(met.te_final_nm, sc.load[0].nm + sc.plant.motor.B_Nms * p1.omega_m_rad_s, 0.01 * p1.te_Nm);

    // Sine supply: the firmware did not run.
    EXPECT_FALSE(met.firmware);
    EXPECT_STREQ(met.controller, "none");
    EXPECT_NEAR(met.sim_seconds, sc.duration_s, 1e-9);
    EXPECT_EQ(r.res.ticks, 5001u);
}

// eq. 5 with the plant at its nominal values and a load: eps_true = -T_L / J
// once the load is on (0.5 s window ends at 1.0 s; the load acts from 0.6 s).
TEST(DolStart, TrueUncertaintyIsMinusLoadOverInertia)
{
    const DolRun &r = dol_run();
    ASSERT_EQ(r.res.status, SIM_OK) << r.res.error;
    const scenario &sc = *r.scen.sc;
    // ticks in the last 0.5 s: 2500 (t = 0.5002 .. 1.0); with load: t >= 0.6, 2001 of them.
    double expect = -sc.load[0].nm / sc.plant.motor.J_kgm2 * 2001.0 / 2500.0;
    EXPECT_NEAR(r.res.metrics.eps_true, expect, 1e-6 * std::fabs(expect));
}
