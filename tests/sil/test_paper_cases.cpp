// The paper's CASE1 / CASE2 and the small-step bandwidth check, run through the
// SIL engine's library API with the firmware DEFAULT gains (the scenario files
// set only the case conditions). Thresholds: docs/speed_control.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sim_test_util.hpp"

extern "C" {
#include "dtc/drive.h"
}

namespace {

const char *const kNames[] = {"ip", "nominal", "rbfn"};

// Each (scenario, controller) runs once; the tests share the results.
const sim_metrics &run(const std::string &file, int controller)
{
    static std::map<std::string, sim_metrics> cache;
    const std::string key = file + "/" + kNames[controller];
    auto it = cache.find(key);
    if (it != cache.end())
        return it->second;

    simtest::Loaded l = simtest::load_scenario(simtest::source_path("host_sim/scenarios/" + file));
    EXPECT_EQ(l.rc, 0) << l.error;
    sim_options opt;
    sim_options_default(&opt);
    opt.controller = controller;
    auto res = std::make_unique<sim_result>(); // large: keep it off the stack
    EXPECT_EQ(sim_run(l.sc.get(), &opt, res.get()), SIM_OK) << key << ": " << res->error;
    const sim_metrics &m = res->metrics;
    std::printf("[metrics] %-16s %-7s steady %.3f rpm, est_err %.3f rpm, rise %.4f s, recovery %.4f s, "
                "dip %.2f rpm, eps_hat %.1f / eps %.1f, |W|max %.1f / %.1f, np %.2f / %.2f V, fsw %.0f Hz, "
                "faults %u, wall %.3f s\n",
                file.c_str(), kNames[controller], m.steady_error_rpm, m.speed_est_error_rpm,
                m.has_rise ? m.rise_time_s : -1.0, m.has_disturbance ? m.recovery_time_s : -1.0,
                m.has_disturbance ? m.max_dip_rpm : -1.0, m.eps_hat_final, m.eps_true, m.w_norm_max, m.m_w,
                m.np_dev_max_v, m.np_dev_limit_v, m.switching_freq_hz, (unsigned)m.faults, m.wall_seconds);
    return cache.emplace(key, m).first->second;
}

void expect_inverter_healthy(const sim_metrics &m, const char *what)
{
    EXPECT_EQ(m.faults, 0u) << what;
    ASSERT_TRUE(m.has_steady_window) << what;
    EXPECT_LT(m.np_dev_max_v, m.np_dev_limit_v) << what << ": neutral-point deviation";
    EXPECT_GE(m.switching_freq_hz, 300.0) << what;
    EXPECT_LE(m.switching_freq_hz, 1500.0) << what;
}

} // namespace

class Case1 : public ::testing::TestWithParam<int> {};

TEST_P(Case1, EveryControllerHoldsFiveHundredRpm)
{
    const sim_metrics &m = run("case1.ini", GetParam());
    EXPECT_LE(m.steady_error_rpm, 2.0);
    EXPECT_NEAR(m.speed_final_rpm, 500.0, 2.0);
    expect_inverter_healthy(m, kNames[GetParam()]);
}

INSTANTIATE_TEST_SUITE_P(Controllers, Case1, ::testing::Values(0, 1, 2),
                         [](const ::testing::TestParamInfo<int> &i) { return std::string(kNames[i.param]); });

TEST(Case2, RbfnLearnsTheUncertaintyAndRecoversFast)
{
    const sim_metrics &m = run("case2.ini", SCENARIO_CTL_RBFN);
    ASSERT_TRUE(m.has_disturbance);
    EXPECT_TRUE(m.recovered);
    EXPECT_LE(m.recovery_time_s, 0.10); // within 0.1 s (0.076 s with the sized RBFN)
    EXPECT_LE(m.steady_error_rpm, 2.0);
    EXPECT_LE(m.speed_est_error_rpm, 5.0);
    // eps_true is the plant's own eq.-5 uncertainty, about -180 rad/s^2.
    EXPECT_NEAR(m.eps_true, -180.0, 10.0);
    EXPECT_NEAR(m.eps_hat_final, m.eps_true, 0.15 * std::abs(m.eps_true));
    EXPECT_LE(m.w_norm_max, m.m_w);
    expect_inverter_healthy(m, "rbfn case2");
}

TEST(Case2, IpRecoversAtLeastThreeTimesSlower)
{
    const sim_metrics &ip = run("case2.ini", SCENARIO_CTL_IP);
    const sim_metrics &rbfn = run("case2.ini", SCENARIO_CTL_RBFN);
    ASSERT_TRUE(ip.has_disturbance);
    EXPECT_TRUE(ip.recovered);
    EXPECT_GE(ip.recovery_time_s, 3.0 * rbfn.recovery_time_s);
    EXPECT_LE(ip.steady_error_rpm, 2.0); // slower, but it gets there (integral action)
    expect_inverter_healthy(ip, "ip case2");
}

TEST(Case2, NominalControllerKeepsAnErrorItCannotLearn)
{
    // Eq. 6 with eps = 0 has no integral action: the error settles near
    // eps / K_x. Shows the RBFN's gain comes from learning, not from its K.
    const sim_metrics &nom = run("case2.ini", SCENARIO_CTL_NOMINAL);
    const sim_metrics &rbfn = run("case2.ini", SCENARIO_CTL_RBFN);
    EXPECT_GT(nom.steady_error_rpm, 10.0 * std::max(rbfn.steady_error_rpm, 0.1));
    expect_inverter_healthy(nom, "nominal case2");
}

TEST(SmallStep, IpAndRbfnHaveTheSameSmallSignalBandwidth)
{
    const sim_metrics &ip = run("small_step.ini", SCENARIO_CTL_IP);
    const sim_metrics &rbfn = run("small_step.ini", SCENARIO_CTL_RBFN);
    ASSERT_TRUE(ip.has_rise);
    ASSERT_TRUE(rbfn.has_rise);
    EXPECT_GT(ip.rise_time_s, 0.0);
    // "Within 20 % of each other": relative to the faster of the two.
    EXPECT_LE(std::abs(ip.rise_time_s - rbfn.rise_time_s), 0.2 * std::min(ip.rise_time_s, rbfn.rise_time_s));
    expect_inverter_healthy(ip, "ip small_step");
    expect_inverter_healthy(rbfn, "rbfn small_step");
}

namespace {

// Switches the controller mode at given times through the background
// configuration path (edit the inactive copy, commit) and records the torque
// command of every tick around the switches.
struct Switcher {
    struct At {
        double t_s;
        speed_mode mode;
        bool done;
    };
    std::vector<At> plan;
    std::vector<std::pair<double, float>> te; // (t, te_ref) near the switches
    static void on_tick(void *user, double t_s, struct drive *d)
    {
        auto *self = static_cast<Switcher *>(user);
        for (At &a : self->plan) {
            if (!a.done && t_s >= a.t_s) {
                ctl_cfg *c = drive_cfg_edit(d);
                c->speed.mode = a.mode;
                drive_cfg_commit(d);
                a.done = true;
            }
            if (std::abs(t_s - a.t_s) < 0.05) {
                drive_snapshot snap;
                drive_read_snapshot(d, &snap);
                self->te.emplace_back(t_s, snap.tel.te_ref_Nm);
            }
        }
    }
};

} // namespace

TEST(ModeSwitch, IpToRbfnAndBackUnderLoadIsBumpless)
{
    simtest::Loaded l = simtest::load_scenario(simtest::source_path("host_sim/scenarios/case2.ini"));
    ASSERT_EQ(l.rc, 0) << l.error;
    Switcher sw;
    sw.plan = {{3.0, SPEED_MODE_RBFN, false}, {3.6, SPEED_MODE_IP, false}, {4.2, SPEED_MODE_RBFN, false}};
    sim_options opt;
    sim_options_default(&opt);
    opt.controller = SCENARIO_CTL_IP;
    opt.on_tick = &Switcher::on_tick;
    opt.user = &sw;
    auto res = std::make_unique<sim_result>();
    ASSERT_EQ(sim_run(l.sc.get(), &opt, res.get()), SIM_OK) << res->error;

    // The largest tick-to-tick change of the torque command next to each
    // switch must look like the ordinary ripple around it, not a step.
    for (const auto &a : sw.plan) {
        double at_switch = 0.0, elsewhere = 0.0;
        for (size_t i = 1; i < sw.te.size(); ++i) {
            const double t = sw.te[i].first;
            const bool consecutive = t - sw.te[i - 1].first > 0.0 && t - sw.te[i - 1].first < 3e-4;
            if (std::abs(t - a.t_s) >= 0.05 || !consecutive)
                continue;
            const double d = std::abs(sw.te[i].second - sw.te[i - 1].second);
            double &slot = std::abs(t - a.t_s) < 2e-3 ? at_switch : elsewhere;
            slot = std::max(slot, d);
        }
        std::printf("[switch] t %.1f -> mode %d: largest te_ref change at the switch %.3f N m, elsewhere %.3f N m\n",
                    a.t_s, (int)a.mode, at_switch, elsewhere);
        EXPECT_LE(at_switch, std::max(0.2, 2.0 * elsewhere)) << "switch at " << a.t_s;
    }
    EXPECT_LE(res->metrics.steady_error_rpm, 2.0);
    EXPECT_EQ(res->metrics.faults, 0u);
}
