// The loss-of-control monitor's configuration edges (dtc/ctl_guard.h):
// guard_time_s = 0 (trip at the first check above the level, never below
// it) and guard_flux_err_frac = 0 (off: never a trip, not even on a NaN).
// Same synthetic machine as test_ctl_guard.cpp: a flux rotating at omega_s
// with the voltage that makes it, the observer's flux turning at another
// frequency from t_div on; summed every tick, checked every
// CTL_GUARD_WINDOW_MAX-th tick as the control step schedules it
// (dtc/ctl_schedule.h).
#include <gtest/gtest.h>

#include <cmath>

extern "C" {
#include "dtc/ctl.h"
#include "dtc/ctl_guard.h"
}

namespace {

constexpr double kT = 200e-6;
constexpr double kPi = 3.14159265358979;

// the time of the first trip, or -1; judged from 0.5 s on
double first_trip(const ctl_cfg &c, double w, double w_obs, double t_div, double t_end, bool nan_voltage = false)
{
    ctl_guard g;
    ctl_guard_reset(&g);
    const double psi0 = 0.45, i0 = 30.0, rs = 0.288;
    double th_obs = 0.0;
    for (int k = 0; k * kT < t_end; ++k) {
        const double t = k * kT;
        const double th = w * t, th1 = w * (t + kT);
        float v[2] = {float(psi0 * (std::cos(th1) - std::cos(th)) / kT + rs * i0 * std::cos(th + 1.0)),
                      float(psi0 * (std::sin(th1) - std::sin(th)) / kT + rs * i0 * std::sin(th + 1.0))};
        if (nan_voltage)
            v[0] = std::nanf("");
        float is[2] = {float(i0 * std::cos(th + 1.0)), float(i0 * std::sin(th + 1.0))};
        th_obs = t < t_div ? th : th_obs + w_obs * kT;
        float po[2] = {float(psi0 * std::cos(th_obs)), float(psi0 * std::sin(th_obs))};
        if (k % CTL_GUARD_WINDOW_MAX == 0 &&
            ctl_guard_check(&g, &c.guard, float(kT), is, float(rs), po, 0.45f, t > 0.5))
            return t;
        ctl_guard_accumulate(&g, v, is);
    }
    return -1.0;
}

} // namespace

TEST(CtlGuardCfg, ZeroTripTimeTripsAtTheFirstCheckAboveTheLevelAndNeverBelowIt)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    c.guard.time_s = 0.0f;
    ctl_cfg_derive(&c);
    for (double f_hz : {-60.0, 5.0, 17.0, 60.0}) {
        const double w = 2 * kPi * f_hz;
        EXPECT_LT(first_trip(c, w, w, 10.0, 1.5), 0.0) << f_hz << " Hz, healthy";
    }
    // 17 Hz, the observer's flux stops at 1 s: with the default 10 ms the
    // trip comes at least 9.6 ms (12 more windows) after the first check
    // above the level; with 0 at that check
    const double w = 2 * kPi * 17.0;
    const double t0 = first_trip(c, w, 0.0, 1.0, 1.5);
    ctl_cfg_default(&c);
    const double t10 = first_trip(c, w, 0.0, 1.0, 1.5);
    ASSERT_GE(t0, 1.0);
    ASSERT_GE(t10, 1.0);
    EXPECT_LE(t0 - 1.0, 0.05);
    EXPECT_NEAR(t10 - t0, 12 * CTL_GUARD_WINDOW_MAX * kT, 1e-6);
}

TEST(CtlGuardCfg, OffNeverTripsNotEvenOnANaN)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    c.guard.flux_err_frac = 0.0f;
    ctl_cfg_derive(&c);
    const double w = 2 * kPi * 17.0;
    EXPECT_LT(first_trip(c, w, -w, 1.0, 1.5), 0.0) << "diverged";
    EXPECT_LT(first_trip(c, w, w, 10.0, 1.5, true), 0.0) << "NaN voltage";
    // the same runs with the monitor on do trip (the test can fail)
    ctl_cfg_default(&c);
    EXPECT_GE(first_trip(c, w, -w, 1.0, 1.5), 1.0) << "diverged, on";
    EXPECT_GE(first_trip(c, w, w, 10.0, 1.5, true), 0.5) << "NaN voltage, on";
}
