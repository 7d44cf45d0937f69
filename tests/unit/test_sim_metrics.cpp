// The engine's metric accumulators fed with synthetic tick records whose
// metrics are worked out by hand (recovery, dip, rise time, steady means,
// neutral-point deviation, switching frequency, windows).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "../../host_sim/src/metrics.h"
#include "sim_test_util.hpp"

namespace {

const double T = 1e-3; // 1 ms ticks keep the arithmetic readable

struct Feed {
    simtest::Loaded scen;
    metrics_acc acc{};
    sim_metrics out{};
};

// Run ticks 0..n through the accumulator with samples from @p make.
void feed(Feed &f, int n, const std::function<metrics_sample(double)> &make)
{
    ASSERT_EQ(f.scen.rc, 0) << f.scen.error;
    ASSERT_EQ(metrics_acc_init(&f.acc, f.scen.sc.get(), T), 0);
    for (int k = 0; k <= n; ++k) {
        metrics_sample s = make(k * T);
        s.t_s = k * T;
        metrics_acc_add(&f.acc, &s);
    }
    metrics_acc_finish(&f.acc, &f.out);
    metrics_acc_free(&f.acc);
}

} // namespace

TEST(SimMetrics, RecoveryDipAndSteadyMeans)
{
    Feed f;
    f.scen = simtest::parse_text("[sim]\nduration_s = 3\nperiod_s = 1e-3\n[reference]\nstep = 0 500\n"
                                 "[load]\nstep = 1.0 8\n");
    // Speed at 500 until 1.0 s, then a dip: 500 - 40 at 1.0 s recovering linearly
    // to 500 at 1.4 s; the error exceeds 1 % (5 rpm) until 500 - 40 (1 - x/0.4) > 5,
    // i.e. the last tick with |e| > 5 is x < 0.35 -> t = 1.349 s.
    feed(f, 3000, [](double t) {
        metrics_sample s{};
        s.ref_rpm = 500.0;
        double x = t - 1.0;
        s.speed_rpm = (x >= 0.0 && x < 0.4) ? 500.0 - 40.0 * (1.0 - x / 0.4) : 500.0;
        s.est_rpm = s.speed_rpm + 2.0;
        s.te_nm = t < 1.0 ? 1.0 : 8.0;
        s.is_sq = 3.0 * 49.0; // 7 A rms per phase
        s.eps_hat = -170.0;
        s.eps_true = -180.0;
        return s;
    });
    const sim_metrics &m = f.out;
    ASSERT_TRUE(m.has_disturbance);
    EXPECT_DOUBLE_EQ(m.disturbance_t_s, 1.0);
    EXPECT_NEAR(m.recovery_time_s, 0.349, 1e-9);
    EXPECT_TRUE(m.recovered);
    EXPECT_NEAR(m.max_dip_rpm, 40.0, 1e-9);
    EXPECT_NEAR(m.steady_error_rpm, 0.0, 1e-12);
    EXPECT_NEAR(m.speed_est_error_rpm, 2.0, 1e-9);
    EXPECT_NEAR(m.eps_hat_final, -170.0, 1e-9);
    EXPECT_NEAR(m.eps_true, -180.0, 1e-9);
    EXPECT_NEAR(m.speed_final_rpm, 500.0, 1e-9);
    EXPECT_NEAR(m.speed_final_rad_s, 500.0 * 2.0 * M_PI / 60.0, 1e-9);
    EXPECT_NEAR(m.te_final_nm, 8.0, 1e-12);
    EXPECT_NEAR(m.is_rms_final_a, 7.0, 1e-12);
    // The only reference change is 0 -> 500 at t = 0 and the speed is already there.
    ASSERT_TRUE(m.has_rise);
    EXPECT_DOUBLE_EQ(m.rise_time_s, 0.0);
}

TEST(SimMetrics, NotRecoveredAtTheEnd)
{
    Feed f;
    f.scen = simtest::parse_text("[sim]\nduration_s = 2\nperiod_s = 1e-3\n[reference]\nstep = 0 1000\n"
                                 "[events]\nJ_scale = 1.5 2\n");
    feed(f, 2000, [](double t) {
        metrics_sample s{};
        s.ref_rpm = 1000.0;
        s.speed_rpm = t < 1.5 ? 1000.0 : 980.0; // 2 % low from 1.5 s on
        return s;
    });
    EXPECT_TRUE(f.out.has_disturbance);
    EXPECT_FALSE(f.out.recovered);
    EXPECT_NEAR(f.out.recovery_time_s, 0.5, 1e-9); // to the last tick (2.0 s)
    EXPECT_NEAR(f.out.max_dip_rpm, 20.0, 1e-9);
    EXPECT_NEAR(f.out.steady_error_rpm, 20.0, 1e-9);
}

TEST(SimMetrics, RiseTimeOfTheLastChange)
{
    Feed f;
    f.scen = simtest::parse_text("[sim]\nduration_s = 2\nperiod_s = 1e-3\n[reference]\nstep = 0.1 200\n"
                                 "ramp = 0.5 0.7 700\n");
    // The last change is the ramp 200 -> 700 starting at 0.5 s. The speed
    // follows 200 + 500 (t - 0.5) / 0.4 from 0.5 to 0.9 s: 10 % (250) at
    // 0.54 s, 90 % (650) at 0.86 s -> 0.32 s.
    feed(f, 2000, [](double t) {
        metrics_sample s{};
        double x = std::min(std::max(t - 0.5, 0.0), 0.4);
        s.speed_rpm = t < 0.1 ? 0.0 : (t < 0.5 ? 200.0 : 200.0 + 500.0 * x / 0.4);
        return s;
    });
    ASSERT_TRUE(f.out.has_rise);
    EXPECT_NEAR(f.out.rise_time_s, 0.32, 1.01e-3);
    EXPECT_FALSE(f.out.has_disturbance);
}

TEST(SimMetrics, NeutralPointAndSwitchingAfterStartup)
{
    Feed f;
    f.scen = simtest::parse_text("[sim]\nduration_s = 3\nperiod_s = 1e-3\n[metrics]\nstartup_end_s = 1.0\n"
                                 "window = w 2.0 2.5\n");
    // 600 leg transitions per second in total: 200 per leg -> 100 Hz device switching.
    // NP deviation 9 V before 1.0 s (ignored), then at most 4 V.
    feed(f, 3000, [](double t) {
        metrics_sample s{};
        s.switch_count = (unsigned long)std::lround(t * 600.0);
        s.np_dev_v = t < 0.9995 ? 9.0 : 4.0 * std::fabs(std::sin(t * 10.0));
        bool odd = std::lround(t / T) % 2 == 1;
        s.speed_rpm = t >= 2.0 && t < 2.5 ? 1000.0 + (odd ? 10.0 : -10.0) : 0.0;
        s.is_sq = t >= 2.0 && t < 2.5 ? 3.0 * 25.0 : 0.0;
        return s;
    });
    const sim_metrics &m = f.out;
    ASSERT_TRUE(m.has_steady_window);
    EXPECT_NEAR(m.np_dev_max_v, 4.0, 1e-3);
    EXPECT_NEAR(m.switching_freq_hz, 100.0, 1e-9);
    ASSERT_EQ(m.n_windows, 1);
    ASSERT_TRUE(m.windows[0].valid);
    EXPECT_NEAR(m.windows[0].speed_rpm, 1000.0, 1e-9); // alternating +-10 over 500 ticks
    EXPECT_NEAR(m.windows[0].is_rms_a, 5.0, 1e-12);
}

TEST(SimMetrics, ShortRunHasNoSteadyWindow)
{
    Feed f;
    f.scen = simtest::parse_text("[sim]\nduration_s = 0.5\nperiod_s = 1e-3\n[metrics]\nwindow = late 0.8 0.9\n");
    feed(f, 500, [](double) { return metrics_sample{}; });
    EXPECT_FALSE(f.out.has_steady_window); // startup_end defaults to 1.0 s
    ASSERT_EQ(f.out.n_windows, 1);
    EXPECT_FALSE(f.out.windows[0].valid);
}

// Runaway: |true speed| > 1.5 x the largest |reference| of the run + 300 rpm
// at any tick. 500 rpm reference -> limit 1050 rpm; a speed that passes it
// for a single tick and comes back still flags the run.
TEST(SimMetrics, RunawayFlaggedEvenWhenTheEndLooksFine)
{
    Feed f;
    f.scen = simtest::parse_text("[sim]\nduration_s = 2\nperiod_s = 1e-3\n[reference]\nstep = 0 500\n");
    feed(f, 2000, [](double t) {
        metrics_sample s{};
        s.ref_rpm = 500.0;
        s.speed_rpm = std::fabs(t - 1.0) < 0.5e-3 ? -1051.0 : 500.0; // one tick beyond, negative
        return s;
    });
    EXPECT_NEAR(f.out.runaway_limit_rpm, 1050.0, 1e-12);
    EXPECT_TRUE(f.out.runaway);
    EXPECT_DOUBLE_EQ(f.out.speed_true_max_abs_rpm, 1051.0);
    EXPECT_DOUBLE_EQ(f.out.speed_true_end_rpm, 500.0);
    EXPECT_NEAR(f.out.steady_error_rpm, 0.0, 1e-12); // the run would otherwise look perfect

    Feed g; // exactly at the limit is not a runaway; the limit follows the largest |reference|
    g.scen = simtest::parse_text("[sim]\nduration_s = 2\nperiod_s = 1e-3\n[reference]\nstep = 0 -200\nstep = 1 100\n");
    feed(g, 2000, [](double t) {
        metrics_sample s{};
        s.ref_rpm = t < 1.0 ? -200.0 : 100.0;
        s.speed_rpm = t < 1.0 ? -600.0 : 600.0; // 1.5 x 200 + 300 = 600
        return s;
    });
    EXPECT_FALSE(g.out.runaway);
    EXPECT_NEAR(g.out.runaway_limit_rpm, 600.0, 1e-12);
    EXPECT_DOUBLE_EQ(g.out.speed_true_end_rpm, 600.0);

    Feed h; // the limit comes from the largest |reference| of the whole run
    h.scen = simtest::parse_text("[sim]\nduration_s = 1\nperiod_s = 1e-3\n[reference]\nstep = 0.5 2000\n");
    feed(h, 1000, [](double t) {
        metrics_sample s{};
        s.ref_rpm = t < 0.5 ? 0.0 : 2000.0;
        s.speed_rpm = t < 0.1 ? 0.0 : (t < 0.2 ? 3300.0 : 2000.0); // at the limit, not beyond
        return s;
    });
    EXPECT_FALSE(h.out.runaway);
    EXPECT_NEAR(h.out.runaway_limit_rpm, 3300.0, 1e-12);

    Feed n; // no reference at all: 300 rpm; a NaN speed is a runaway
    n.scen = simtest::parse_text("[sim]\nduration_s = 1\nperiod_s = 1e-3\n");
    feed(n, 1000, [](double t) {
        metrics_sample s{};
        s.speed_rpm = std::fabs(t - 0.5) < 0.5e-3 ? std::nan("") : 100.0;
        return s;
    });
    EXPECT_TRUE(n.out.runaway);
    EXPECT_NEAR(n.out.runaway_limit_rpm, 300.0, 1e-12);
}
