// The loss-of-control monitor (dtc/ctl_guard.h) on synthetic signals: a
// machine flux rotating at omega_s with the voltage that makes it, against
// an observer flux that is the same (healthy) or turns at another frequency
// (diverged). The monitor sums every tick and checks every
// CTL_GUARD_WINDOW_MAX-th tick, as the control step schedules it
// (dtc/ctl_schedule.h).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

extern "C" {
#include "dtc/ctl.h"
#include "dtc/ctl_guard.h"
}

namespace {

constexpr double kT = 200e-6;
constexpr double kPi = 3.14159265358979;

struct Result {
    bool tripped = false;
    double t_trip = -1.0;
    double max_ratio = 0.0;
};

// Machine flux psi = 0.45 e^{j w t}, current i = 30 A e^{j (w t + 1)};
// the voltage v = d psi/dt + rs_true i. The observer's flux turns at w_obs
// from t_div on (same as the machine before). Monitor with the defaults.
Result run(double w, double w_obs, double t_div, double rs_true, double rs_model, double t_end)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    ctl_guard g;
    ctl_guard_reset(&g);
    Result r;
    const double psi0 = 0.45, i0 = 30.0;
    double th_obs = 0.0;
    for (int k = 0; k * kT < t_end; ++k) {
        const double t = k * kT;
        const double th = w * t;
        // the average voltage over [t, t + T] that moves psi from t to t + T
        const double th1 = w * (t + kT);
        float v[2] = {float(psi0 * (std::cos(th1) - std::cos(th)) / kT + rs_true * i0 * std::cos(th + 1.0)),
                      float(psi0 * (std::sin(th1) - std::sin(th)) / kT + rs_true * i0 * std::sin(th + 1.0))};
        float is[2] = {float(i0 * std::cos(th + 1.0)), float(i0 * std::sin(th + 1.0))};
        th_obs = t < t_div ? th : th_obs + w_obs * kT;
        float po[2] = {float(psi0 * std::cos(th_obs)), float(psi0 * std::sin(th_obs))};
        bool trip = false;
        if (k % CTL_GUARD_WINDOW_MAX == 0) {
            trip = ctl_guard_check(&g, &c.guard, float(kT), is, float(rs_model), po, 0.45f, t > 0.5);
            if (t > 0.5)
                r.max_ratio = std::max(r.max_ratio, double(g.err_Wb / g.tol_Wb));
        }
        ctl_guard_accumulate(&g, v, is);
        if (trip && !r.tripped) {
            r.tripped = true;
            r.t_trip = t;
        }
    }
    return r;
}

} // namespace

TEST(CtlGuard, HealthyDriveDoesNotTripAtAnyFrequency)
{
    for (double f_hz : {-60.0, -5.0, 1.0, 5.0, 17.0, 60.0, 90.0}) {
        const double w = 2 * kPi * f_hz;
        Result r = run(w, w, 10.0, 0.288, 0.288, 2.0);
        EXPECT_FALSE(r.tripped) << f_hz << " Hz";
        EXPECT_LT(r.max_ratio, 0.5) << f_hz << " Hz";
    }
}

TEST(CtlGuard, StatorThirtyPercentWarmIsTolerated)
{
    for (double f_hz : {1.0, 5.0, 17.0, 60.0}) {
        const double w = 2 * kPi * f_hz;
        Result r = run(w, w, 10.0, 1.3 * 0.288, 0.288, 2.0);
        EXPECT_FALSE(r.tripped) << f_hz << " Hz";
    }
}

TEST(CtlGuard, ObserverFluxAtAWrongFrequencyTripsWithinFiftyMilliseconds)
{
    // 17 Hz (500 rpm); the observer's flux then turns at half, zero, or the
    // opposite frequency
    const double w = 2 * kPi * 17.0;
    for (double k : {0.5, 0.0, -1.0}) {
        Result r = run(w, k * w, 1.0, 0.288, 0.288, 1.5);
        ASSERT_TRUE(r.tripped) << k;
        EXPECT_GE(r.t_trip, 1.0) << k;
        EXPECT_LE(r.t_trip - 1.0, 0.05) << k;
        RecordProperty("trip_delay_ms_obs_at_" + std::to_string(k) + "_w", std::to_string((r.t_trip - 1.0) * 1e3));
    }
}

TEST(CtlGuard, NoVerdictWhileNotJudgingAndNaNCountsAsAbove)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    ctl_guard g;
    ctl_guard_reset(&g);
    const float nan = std::nanf("");
    float v[2] = {nan, 0.0f}, is[2] = {0.0f, 0.0f}, po[2] = {0.0f, 0.0f};
    for (int k = 0; k < 1000; ++k) {
        if (k % CTL_GUARD_WINDOW_MAX == 0) {
            EXPECT_FALSE(ctl_guard_check(&g, &c.guard, float(kT), is, 0.288f, po, 0.45f, false));
        }
        ctl_guard_accumulate(&g, v, is);
    }
    bool trip = false;
    for (int k = 0; k < 1000 && !trip; ++k) {
        if (k % CTL_GUARD_WINDOW_MAX == 0)
            trip = ctl_guard_check(&g, &c.guard, float(kT), is, 0.288f, po, 0.45f, true);
        ctl_guard_accumulate(&g, v, is);
    }
    EXPECT_TRUE(trip);
}
