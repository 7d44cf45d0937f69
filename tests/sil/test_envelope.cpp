// The drive over its whole operating envelope, with the firmware DEFAULTS:
// the scenario files set only the operating point. One test per requirement
// of the envelope, each with its threshold, so the test fails when the
// requirement fails. Design: docs/envelope.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sim_test_util.hpp"

extern "C" {
#include "dtc/drive.h"
}

namespace {

struct SimRun {
    int status = -1;
    std::string error;
    sim_metrics m{};
};

using TickHook = std::function<void(double t_s, struct drive *d)>;

void call_hook(void *user, double t_s, struct drive *d) { (*static_cast<TickHook *>(user))(t_s, d); }

// Run host_sim/scenarios/@p file with @p controller and the overrides @p sets
// ("section.key=value"), calling @p hook every tick when given.
SimRun run_sim(const std::string &file, int controller, const std::vector<std::string> &sets = {},
        TickHook hook = nullptr)
{
    SimRun r;
    simtest::Loaded l = simtest::load_scenario(simtest::source_path("host_sim/scenarios/" + file), sets);
    EXPECT_EQ(l.rc, 0) << l.error;
    if (l.rc != 0)
        return r;
    sim_options opt;
    sim_options_default(&opt);
    opt.controller = controller;
    if (hook) {
        opt.on_tick = &call_hook;
        opt.user = &hook;
    }
    auto res = std::make_unique<sim_result>();
    r.status = sim_run(l.sc.get(), &opt, res.get());
    r.error = res->error;
    r.m = res->metrics;
    const sim_metrics &m = r.m;
    std::printf("[envelope] %-22s ctl %d: final %.1f rpm %.1f N m, steady %.2f rpm, recovery %.4f s (%s), "
                "dip %.1f rpm, eps_hat %.1f / %.1f, |W|max %.0f / %.0f, np %.2f / %.2f V, fsw %.0f Hz, "
                "faults 0x%x\n",
                file.c_str(), controller, m.speed_final_rpm, m.te_final_nm, m.steady_error_rpm,
                m.has_disturbance ? m.recovery_time_s : -1.0, m.recovered ? "recovered" : "not recovered",
                m.has_disturbance ? m.max_dip_rpm : -1.0, m.eps_hat_final, m.eps_true, m.w_norm_max, m.m_w,
                m.np_dev_max_v, m.np_dev_limit_v, m.switching_freq_hz, (unsigned)m.faults);
    return r;
}

} // namespace

// ---------------------------------------------------------------- RBFN sizing

// A rated (41 N m) load step at 500 rpm: the RBFN recovers within 0.3 s and
// has learned the uncertainty (-T_L / J = -911 rad/s^2).
TEST(RatedStep500, RbfnRecoversWithinPointThreeSeconds)
{
    SimRun r = run_sim("rated_step_500.ini", SCENARIO_CTL_RBFN);
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    const sim_metrics &m = r.m;
    EXPECT_EQ(m.faults, 0u);
    ASSERT_TRUE(m.has_disturbance);
    EXPECT_TRUE(m.recovered);
    EXPECT_LE(m.recovery_time_s, 0.3);
    EXPECT_LE(m.steady_error_rpm, 2.0);
    EXPECT_NEAR(m.eps_true, -911.0, 20.0);
    EXPECT_NEAR(m.eps_hat_final, m.eps_true, 0.05 * std::abs(m.eps_true));
    EXPECT_LE(m.w_norm_max, m.m_w);
}

// The representable uncertainty follows the torque limit: a load close to
// the 80 N m limit (70 N m) is learned too, with the weights off the
// projection bound; and a rated generating load (-41 N m). (A -70 N m
// generating load still trips on the neutral point: docs/envelope.md.)
TEST(RatedStep500, AnyLoadUpToTheTorqueLimitIsLearnable)
{
    for (double load : {70.0, -41.0}) {
        SCOPED_TRACE(load);
        SimRun r = run_sim("rated_step_500.ini", SCENARIO_CTL_RBFN, {"load.step=2.5 " + std::to_string(load)});
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        const sim_metrics &m = r.m;
        EXPECT_EQ(m.faults, 0u);
        EXPECT_TRUE(m.recovered);
        EXPECT_LE(m.steady_error_rpm, 2.0);
        EXPECT_NEAR(m.eps_hat_final, m.eps_true, 0.05 * std::abs(m.eps_true));
        EXPECT_LT(m.w_norm_max, 0.95 * m.m_w) << "the weights sit on the projection bound";
    }
}

// ------------------------------------------------------- loss-of-control trip

namespace {

// Forces a divergence at @p t_s: the observer's speed adaptation is switched
// off (kp = ki = 0 through the background configuration path) and its speed
// estimate is scaled by @p factor and frozen there. Records the first tick
// at which CTL_FAULT_LOSS_OF_CONTROL is latched.
struct Diverger {
    double t_s;
    float factor;
    bool done = false;
    double t_trip = -1.0;
    void operator()(double t, struct drive *d)
    {
        if (!done && t >= t_s) {
            ctl_cfg *c = drive_cfg_edit(d);
            c->obs.kp_speed = 0.0f;
            c->obs.ki_speed = 0.0f;
            drive_cfg_commit(d);
            d->ctl.obs.omega_int_rad_s *= factor;
            d->ctl.obs.omega_e_rad_s = d->ctl.obs.omega_int_rad_s;
            done = true;
        }
        if (t_trip < 0.0 && (d->ctl.faults & CTL_FAULT_LOSS_OF_CONTROL) != 0u)
            t_trip = t;
    }
};

} // namespace

// A speed estimate that is frozen at a wrong value (the observer has lost
// the machine) is caught by the voltage-model flux check within 50 ms, the
// overspeed trip being blind to it (the estimate stays in range).
TEST(LossOfControl, ForcedDivergenceTripsWithinFiftyMilliseconds)
{
    for (float factor : {0.5f, 0.0f, -1.0f}) {
        SCOPED_TRACE(factor);
        Diverger dv{3.0, factor};
        SimRun r = run_sim("rated_step_500.ini", SCENARIO_CTL_RBFN, {},
                           [&dv](double t, struct drive *d) { dv(t, d); });
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        std::printf("[envelope] forced divergence x%.1f: trip %.4f s after\n", factor, dv.t_trip - dv.t_s);
        EXPECT_NE(r.m.faults & CTL_FAULT_LOSS_OF_CONTROL, 0u);
        ASSERT_GE(dv.t_trip, dv.t_s);
        EXPECT_LE(dv.t_trip - dv.t_s, 0.05);
    }
}

// The same forcing with the estimate frozen at the right value is not a
// loss of control: no trip, and the drive still holds the speed.
TEST(LossOfControl, FrozenButRightEstimateDoesNotTrip)
{
    Diverger dv{3.0, 1.0f};
    SimRun r = run_sim("rated_step_500.ini", SCENARIO_CTL_RBFN, {}, [&dv](double t, struct drive *d) { dv(t, d); });
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_EQ(r.m.faults, 0u);
    EXPECT_NEAR(r.m.speed_final_rpm, 500.0, 10.0);
}

// The sensorless runaway (30 rpm, 40 N m, IP): with the observer's
// regenerating-mode stabilisation switched off it still diverges (the dip
// takes the speed through zero, where the load drives the motor), and that
// natural divergence ends in a loss-of-control trip instead of an unfaulted
// run to -24,000 rpm.
TEST(LossOfControl, SensorlessRunawayTrips)
{
    double t_trip = -1.0;
    SimRun r = run_sim("runaway_trip.ini", SCENARIO_CTL_IP, {"control.obs_regen_angle_rad=0"},
                       [&t_trip](double t, struct drive *d) {
        if (t_trip < 0.0 && (d->ctl.faults & CTL_FAULT_LOSS_OF_CONTROL) != 0u)
            t_trip = t;
    });
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    std::printf("[envelope] runaway: loss-of-control trip at %.4f s (load at 2.0 s)\n", t_trip);
    EXPECT_NE(r.m.faults & CTL_FAULT_LOSS_OF_CONTROL, 0u);
    EXPECT_GE(t_trip, 2.0);
    EXPECT_LE(t_trip, 2.5);
}

// With the defaults the same case is held: no trip, no runaway, on speed.
// Judged 2.5 s after the load, over the last 0.5 s: the IP's recovery from
// its dip through zero (about -290 rpm) still swings by +-5 rpm 1 s after the
// load (the scenario's 3 s end falls on a 34-35.5 rpm crest of it) and is on
// 30 rpm within 1 rpm from about 4.3 s.
TEST(LossOfControl, RunawayCaseIsHeldWithTheDefaults)
{
    SimRun r = run_sim("runaway_trip.ini", SCENARIO_CTL_IP, {"sim.duration_s=4.5"});
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_EQ(r.m.faults, 0u);
    EXPECT_FALSE(r.m.runaway);
    EXPECT_NEAR(r.m.speed_true_end_rpm, 30.0, 5.0);
    EXPECT_LE(r.m.steady_error_rpm, 5.0); // mean |error| over 4.0-4.5 s
}

// No false trip on healthy runs: rated load at 500 rpm (both controllers),
// torque steps motoring and generating at 500 and 1000 rpm, 1700 rpm.
TEST(LossOfControl, NoFalseTripOnHealthyRuns)
{
    struct Case {
        const char *file;
        int controller;
        std::vector<std::string> sets;
    };
    const std::vector<Case> cases = {
        {"rated_step_500.ini", SCENARIO_CTL_RBFN, {}},
        {"rated_step_500.ini", SCENARIO_CTL_IP, {}},
        {"torque_step.ini", SCENARIO_CTL_RBFN, {}},
        {"torque_step.ini", SCENARIO_CTL_IP, {"reference.ramp=0.3 1.3 1000"}},
        {"case1.ini", SCENARIO_CTL_RBFN, {"reference.ramp=0.3 2.3 1700"}},
    };
    for (const Case &c : cases) {
        SCOPED_TRACE(std::string(c.file) + (c.sets.empty() ? "" : " " + c.sets[0]));
        SimRun r = run_sim(c.file, c.controller, c.sets);
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        EXPECT_EQ(r.m.faults & CTL_FAULT_LOSS_OF_CONTROL, 0u);
    }
}

// ------------------------------------- nameplate and field weakening

namespace {

double window_speed(const sim_metrics &m, const char *name)
{
    for (int i = 0; i < m.n_windows; ++i)
        if (std::string(m.windows[i].name) == name && m.windows[i].valid)
            return m.windows[i].speed_rpm;
    ADD_FAILURE() << "no window " << name;
    return 0.0;
}

} // namespace

// 1740 rpm with the rated 41 N m, both controllers with integral action.
TEST(Nameplate, ReachesAndHolds1740RpmWithRatedTorque)
{
    for (int c : {SCENARIO_CTL_RBFN, SCENARIO_CTL_IP}) {
        SCOPED_TRACE(c);
        SimRun r = run_sim("nameplate.ini", c);
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        const sim_metrics &m = r.m;
        EXPECT_EQ(m.faults, 0u);
        EXPECT_NEAR(window_speed(m, "loaded"), 1740.0, 2.0);
        EXPECT_GE(m.te_final_nm, 41.0);
        EXPECT_LE(m.np_dev_max_v, 6.22); // at the voltage limit too (2 % of Vdc)
        if (c == SCENARIO_CTL_RBFN) {
            // mean |error| over the last 0.5 s: the speed ripple at the voltage limit.
            // It is chaotic: a 1 % change of a gain moves it anywhere in 1.9-3.6 rpm
            // since the neutral point is held within 2 % of Vdc there (1.4-2.2 rpm
            // before; docs/envelope.md sections 3 and 5), so one run decides nothing:
            // the median of this run and four with obs_speed_lpf_hz 1 % and 2 % off.
            // The bullet's "within 2 rpm" is the loaded mean above (2 s: the IP's speed
            // swings +-3 rpm over about 2 s at the voltage limit).
            std::vector<double> ripple = {m.steady_error_rpm};
            for (const char *f : {"49", "49.5", "50.5", "51"}) {
                SimRun p = run_sim("nameplate.ini", c, {std::string("control.obs_speed_lpf_hz=") + f});
                ASSERT_EQ(p.status, SIM_OK) << p.error;
                EXPECT_EQ(p.m.faults, 0u) << "obs_speed_lpf_hz " << f;
                ripple.push_back(p.m.steady_error_rpm);
            }
            std::sort(ripple.begin(), ripple.end());
            std::printf("[envelope] nameplate ripple (rbfn, 5 runs): %.2f %.2f %.2f %.2f %.2f rpm\n", ripple[0],
                        ripple[1], ripple[2], ripple[3], ripple[4]);
            EXPECT_LE(ripple[2], 3.5);
        }
    }
}

// 2610 rpm (1.5 x base) with 27 N m: constant power in field weakening.
TEST(FieldWeakening, HoldsRatedPowerAtOnePointFiveTimesBaseSpeed)
{
    for (int c : {SCENARIO_CTL_RBFN, SCENARIO_CTL_IP}) {
        SCOPED_TRACE(c);
        SimRun r = run_sim("field_weakening.ini", c);
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        const sim_metrics &m = r.m;
        EXPECT_EQ(m.faults, 0u);
        EXPECT_NEAR(window_speed(m, "loaded"), 2610.0, 2.0);
        EXPECT_GE(m.te_final_nm, 27.0);
        EXPECT_LE(m.np_dev_max_v, 6.22);
        // mean |error| includes the speed ripple at this speed: 1.5-3 rpm with the RBFN;
        // the IP's is chaotic, 2.5-6.9 rpm for 1 % changes of a gain (docs/envelope.md
        // section 3); the bullet's "hold" is the loaded mean above
        EXPECT_LE(m.steady_error_rpm, c == SCENARIO_CTL_RBFN ? 5.0 : 7.0);
    }
}

// The overspeed trip follows the speed range: it sits above the reference
// limit, which covers 1.5 x base speed; a reference beyond the range is
// limited instead of tripping.
TEST(FieldWeakening, OverspeedLevelFollowsTheSpeedRange)
{
    ctl_cfg cfg;
    ctl_cfg_default(&cfg);
    const double rpm_per_rad_s = 60.0 / (2.0 * M_PI);
    EXPECT_GE(cfg.speed_max_rad_s * rpm_per_rad_s, 2610.0);
    EXPECT_GT(cfg.overspeed_rad_s, 1.05 * cfg.speed_max_rad_s);

    SimRun r = run_sim("field_weakening.ini", SCENARIO_CTL_RBFN,
                       {"reference.ramp=0.3 4.5 3500", "load.step=5.0 10"});
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_EQ(r.m.faults, 0u);
    EXPECT_NEAR(r.m.speed_final_rpm, cfg.speed_max_rad_s * rpm_per_rad_s, 10.0);
}

// ------------------------------------------------- switching frequency

namespace {

double fsw_at(double rpm, double load_Nm)
{
    SimRun r = run_sim("operating_point.ini", SCENARIO_CTL_RBFN,
                       {"reference.ramp=0.3 2.3 " + std::to_string(rpm), "load.step=2.5 " + std::to_string(load_Nm)});
    EXPECT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_EQ(r.m.faults, 0u) << rpm << " rpm, " << load_Nm << " N m";
    EXPECT_NEAR(window_speed(r.m, "point"), rpm, 5.0) << load_Nm << " N m";
    std::printf("[envelope] %6.0f rpm %4.0f N m: switching %.0f Hz, np %.2f V\n", rpm, load_Nm,
                r.m.switching_freq_hz, r.m.np_dev_max_v);
    return r.m.switching_freq_hz;
}

} // namespace

// Device switching frequency <= 1.5 kHz over the speed range (before the
// adaptive bands: 2.2-2.5 kHz at 700-1300 rpm).
TEST(SwitchingFrequency, AtMostOnePointFiveKilohertzEverywhere)
{
    for (double rpm : {100.0, 700.0, 1000.0, 1300.0, 1740.0})
        for (double load : {0.0, 20.0, 41.0})
            EXPECT_LE(fsw_at(rpm, load), 1500.0) << rpm << " rpm, " << load << " N m";
}

// 0.5-1 kHz at the paper's 500 rpm point, from no load to rated.
TEST(SwitchingFrequency, HalfToOneKilohertzAtFiveHundredRpm)
{
    for (double load : {0.0, 8.0, 20.0, 41.0}) {
        const double f = fsw_at(500.0, load);
        EXPECT_GE(f, 500.0) << load << " N m";
        EXPECT_LE(f, 1000.0) << load << " N m";
    }
}

// ------------------------------------------------------- torque response

// 0 -> 41 N m command at 500 rpm (no load), answered 10-90 % within 5 ms.
// The command step: the torque limit set to the rated 41 N m and, at
// t_step, the IP's integrator put far above it, so the next command is the
// limit (the controller then stays there). The response is the observer's
// torque estimate (telemetry; the plant's torque is not visible to the
// hook), sampled every tick.
TEST(TorqueResponse, RatedTorqueStepAnsweredWithinFiveMilliseconds)
{
    const double t_step = 2.5;
    std::vector<std::pair<double, double>> te; // (t, te_est) after the step
    double t10 = -1.0, t90 = -1.0, te_before = 0.0;
    bool set = false;
    SimRun r = run_sim("operating_point.ini", SCENARIO_CTL_IP, {"load.step=2.5 0", "control.te_max_Nm=41"},
                       [&](double t, struct drive *d) {
                           if (!set && t >= t_step) {
                               te_before = d->ctl.te_ref_Nm;
                               d->ctl.speed.ip.integ_Nm = 1000.0f;
                               set = true;
                               return;
                           }
                           if (set && t < t_step + 0.05) {
                               const double x = d->ctl.obs_out.te_Nm;
                               te.emplace_back(t, x);
                               if (t10 < 0.0 && x >= 0.1 * 41.0)
                                   t10 = t;
                               if (t90 < 0.0 && x >= 0.9 * 41.0)
                                   t90 = t;
                           }
                       });
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    std::printf("[envelope] torque step %.1f -> 41 N m at 500 rpm: 10 %% at +%.2f ms, 90 %% at +%.2f ms\n", te_before,
                (t10 - t_step) * 1e3, (t90 - t_step) * 1e3);
    EXPECT_LT(std::abs(te_before), 5.0);
    ASSERT_GT(t10, 0.0);
    ASSERT_GT(t90, 0.0);
    EXPECT_LE(t90 - t10, 0.005);
}

// --------------------------------------------------------- neutral point

namespace {

double np_at(double rpm, double load_Nm, bool real_inverter)
{
    std::vector<std::string> sets = {"reference.ramp=0.3 2.3 " + std::to_string(rpm),
                                     "load.step=2.5 " + std::to_string(load_Nm)};
    if (real_inverter) // the defaults of a scenario without [inverter] keys, the drops compensated
        sets.insert(sets.end(), {"inverter.dead_time_s=2e-6", "inverter.v_on_V=1", "control.v_drop_V=1"});
    SimRun r = run_sim("operating_point.ini", SCENARIO_CTL_RBFN, sets);
    EXPECT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_EQ(r.m.faults, 0u) << rpm << " rpm, " << load_Nm << " N m";
    return r.m.np_dev_max_v;
}

} // namespace

// The NP requirement: within 2 % of Vdc (6.22 V) from 100 rpm to the nameplate
// speed, motoring and generating up to the rated torque, on the ideal and
// the real inverter (the nameplate and field-weakening runs check it too,
// and tools/run-envelope.sh over the whole grid; docs/envelope.md section 5).
TEST(NeutralPoint, WithinTwoPercentOfVdcMotoringAndGenerating)
{
    for (bool real : {false, true})
        for (double rpm : {100.0, 500.0, 700.0, 1000.0, 1300.0, 1740.0})
            for (double load : {-41.0, -20.0, 0.0, 20.0, 41.0}) {
                EXPECT_LE(np_at(rpm, load, real), 6.22)
                    << rpm << " rpm, " << load << " N m, " << (real ? "real" : "ideal") << " inverter";
            }
}

// -------------------------------------------------------------- low speed

// Rated torque at 30 rpm and 20 N m at 10 rpm, sensorless, nominal
// parameters, firmware defaults (RBFN, the default controller; at 10 rpm the
// IP too).
TEST(LowSpeed, HoldsRatedTorqueAtThirtyRpmAndTwentyNmAtTenRpm)
{
    struct Case {
        const char *file;
        int controller;
        double rpm;
    };
    for (const Case &c : {Case{"low_speed_30rpm.ini", SCENARIO_CTL_RBFN, 30.0},
                          Case{"low_speed_30rpm.ini", SCENARIO_CTL_IP, 30.0},
                          Case{"low_speed_10rpm.ini", SCENARIO_CTL_RBFN, 10.0},
                          Case{"low_speed_10rpm.ini", SCENARIO_CTL_IP, 10.0}}) {
        SCOPED_TRACE(std::string(c.file) + " ctl " + std::to_string(c.controller));
        SimRun r = run_sim(c.file, c.controller);
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        EXPECT_EQ(r.m.faults, 0u);
        EXPECT_NEAR(window_speed(r.m, "point"), c.rpm, 5.0);
        EXPECT_LE(r.m.speed_est_error_rpm, 5.0);
    }
}

// The IP cannot hold 41 N m at 30 rpm (its dip takes the speed through
// zero and the observer loses the machine): it must trip, not run away.
TEST(LowSpeed, IpAtThirtyRpmWithRatedTorqueTripsInsteadOfRunningAway)
{
    SimRun r = run_sim("low_speed_30rpm.ini", SCENARIO_CTL_IP);
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    if (r.m.faults == 0u) {
        EXPECT_NEAR(window_speed(r.m, "point"), 30.0, 5.0); // holding it is fine too
    } else {
        EXPECT_NE(r.m.faults & CTL_FAULT_LOSS_OF_CONTROL, 0u);
    }
}

// A rated load driving the motor at 100 rpm (stator frequency about 1.5 Hz):
// held since the regenerating-mode rotation keeps its full angle between 20
// and 45 rad/s electrical (observer.c; before, the estimate stayed near
// 130 rpm while the load took the shaft away). Both inverters, within the
// sweep's 5 rpm, no fault.
TEST(Regenerating, RatedLoadDrivingTheMotorAt100RpmIsHeld)
{
    for (bool real : {false, true}) {
        SCOPED_TRACE(real ? "real inverter" : "ideal inverter");
        std::vector<std::string> sets = {"reference.ramp=0.3 2.3 100", "load.step=2.5 -41", "sim.duration_s=4"};
        if (real)
            sets.insert(sets.end(), {"inverter.dead_time_s=2e-6", "inverter.v_on_V=1", "control.v_drop_V=1"});
        SimRun r = run_sim("operating_point.ini", SCENARIO_CTL_RBFN, sets);
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        std::printf("[envelope] 100 rpm, 41 N m generating, %s: %.2f rpm, faults 0x%x\n", real ? "real" : "ideal",
                    r.m.speed_final_rpm, r.m.faults);
        EXPECT_EQ(r.m.faults, 0u);
        EXPECT_FALSE(r.m.runaway);
        EXPECT_NEAR(window_speed(r.m, "point"), 100.0, 5.0); // 3-4 s
    }
}

// A load driving the motor near zero stator frequency (rotor speed minus the
// slip within about 1 Hz of zero): the speed is not observable there, and at
// rated flux the estimate drifts for seconds (80 rpm with 41 N m runs at
// 118-123 rpm). The drive lowers the flux so that the stator frequency passes
// through zero to the side opposing the rotation (ctl.c, regen_flux_factor):
// held within 5 rpm for 10 s on both inverters. With the flux kept at rated
// (regen_flux_min_frac = 1) the 80 rpm point must still drift beyond 5 rpm,
// or this test no longer tests the lowering.
TEST(Regenerating, NearZeroStatorFrequencyIsHeldWithLoweredFlux)
{
    struct Point {
        double rpm, load_Nm;
    };
    for (bool real : {false, true}) {
        for (Point p : {Point{30, -20.5}, Point{-30, 20.5}, Point{45, -20.5}, Point{60, -30.75}, Point{80, -41}}) {
            SCOPED_TRACE(std::string(real ? "real" : "ideal") + " inverter, " + std::to_string(p.rpm) + " rpm");
            char ramp[64], load[64];
            std::snprintf(ramp, sizeof ramp, "reference.ramp=0.3 0.5 %g", p.rpm);
            std::snprintf(load, sizeof load, "load.step=1.2 %g", p.load_Nm);
            std::vector<std::string> sets = {ramp, load, "sim.duration_s=12.2", "metrics.window=point 11.2 12.2"};
            if (real)
                sets.insert(sets.end(), {"inverter.dead_time_s=2e-6", "inverter.v_on_V=1", "control.v_drop_V=1"});
            SimRun r = run_sim("operating_point.ini", SCENARIO_CTL_RBFN, sets);
            ASSERT_EQ(r.status, SIM_OK) << r.error;
            double n = window_speed(r.m, "point");
            std::printf("[envelope] %g rpm, %g N m generating, %s: %.2f rpm after 10 s, faults 0x%x\n", p.rpm,
                        p.load_Nm, real ? "real" : "ideal", n, r.m.faults);
            EXPECT_EQ(r.m.faults, 0u);
            EXPECT_FALSE(r.m.runaway);
            EXPECT_NEAR(n, p.rpm, 5.0);
        }
        std::vector<std::string> rated = {"reference.ramp=0.3 0.5 80", "load.step=1.2 -41", "sim.duration_s=12.2",
                                          "metrics.window=point 11.2 12.2", "control.regen_flux_min_frac=1"};
        if (real)
            rated.insert(rated.end(), {"inverter.dead_time_s=2e-6", "inverter.v_on_V=1", "control.v_drop_V=1"});
        SimRun r = run_sim("operating_point.ini", SCENARIO_CTL_RBFN, rated);
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        std::printf("[envelope] 80 rpm, -41 N m, flux kept rated, %s: %.2f rpm\n", real ? "real" : "ideal",
                    window_speed(r.m, "point"));
        EXPECT_GT(window_speed(r.m, "point") - 80.0, 5.0);
    }
}

// When the estimate does lose the shaft in that region anyway (forced here:
// the regenerating-mode rotation off, as on the firmware before it held this
// point), the drive must trip, not push at its torque limit while the motor
// runs away. The loss-of-control monitor is blind below 2 Hz of stator
// frequency, and the stall timer restarted whenever the noisy estimate came
// within 29 rpm of the reference. Braking at the limit without the estimate
// falling trips STALL 0.15 s after the command reaches the limit (the shaft
// is at 860-900 rpm by then; docs/envelope.md section 2). After the trip the
// free shaft is the active load's: no inverter can stop that (a brake is the
// machine's).
TEST(Regenerating, RatedLoadDrivingTheMotorAt100RpmTripsWhenTheEstimateIsLost)
{
    for (bool real : {false, true}) {
        SCOPED_TRACE(real ? "real inverter" : "ideal inverter");
        std::vector<std::string> sets = {"reference.ramp=0.3 2.3 100", "load.step=2.5 -41", "sim.duration_s=8",
                                         "control.obs_regen_angle_rad=0"};
        if (real)
            sets.insert(sets.end(), {"inverter.dead_time_s=2e-6", "inverter.v_on_V=1", "control.v_drop_V=1"});
        double t_limit = -1.0, t_trip = -1.0;
        SimRun r = run_sim("operating_point.ini", SCENARIO_CTL_RBFN, sets, [&](double t, struct drive *d) {
            if (t_limit < 0.0 && std::abs(d->ctl.te_ref_Nm) >= 0.98f * d->ctl.te_limit_Nm)
                t_limit = t;
            if (t_trip < 0.0 && (d->ctl.faults & (CTL_FAULT_STALL | CTL_FAULT_LOSS_OF_CONTROL)) != 0u)
                t_trip = t;
        });
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        std::printf("[envelope] 100 rpm, 41 N m generating, rotation off: limit at %.4f s, trip at %.4f s, "
                    "faults 0x%x\n", t_limit, t_trip, r.m.faults);
        ASSERT_TRUE(r.m.runaway) << "the forcing no longer loses the shaft: this test needs another forcing";
        EXPECT_NE(r.m.faults & (CTL_FAULT_STALL | CTL_FAULT_LOSS_OF_CONTROL), 0u) << "faults 0x" << std::hex
                                                                                  << r.m.faults;
        // Measured: real inverter STALL 0.20 s after the command reaches its limit
        // (the braking stall: off speed, then 0.1 s windows in which the estimate does
        // not fall); ideal inverter LOSS_OF_CONTROL 0.57 s after the load, before the
        // command reached its limit (which check sees it first is chaotic: a one-ulp
        // change elsewhere can swap them). A stall timer alone (at the limit, off speed,
        // 1 s in a row) takes 1.2-1.3 s, with the shaft at 8,600-9,600 rpm by then.
        EXPECT_GE(t_trip, 0.0);
        if (t_limit >= 0.0 && t_limit < t_trip)
            EXPECT_LE(t_trip - t_limit, 0.4);
        else
            EXPECT_LE(t_trip - 2.5, 0.8); // from the load step: the monitor's 10 ms once the
                                          // estimate has left the shaft by its level
    }
}

// The other side of the stall checks: a heavy load (J x 50) reversed from
// 600 to -600 rpm with a 20 N m torque limit brakes and then accelerates at
// the limit for about 7 s. That is the drive doing its job, not a stall: the
// speed error shrinks in every window. A plain stall timer (at the limit, off
// speed, 1 s in a row) would trip STALL after 1 s of it.
TEST(Stall, ReversalOfAHeavyLoadAtTheTorqueLimitDoesNotTrip)
{
    for (int c : {SCENARIO_CTL_RBFN, SCENARIO_CTL_IP}) {
        SCOPED_TRACE(c);
        SimRun r = run_sim("operating_point.ini", c,
                           {"reference.ramp=0.3 15 600", "reference.step=16 -600", "sim.duration_s=24",
                            "events.J_scale=0 50", "control.te_max_Nm=20", "control.ramp_rad_s2=0", "load.step=0 0"});
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        EXPECT_EQ(r.m.faults, 0u);
        EXPECT_LT(r.m.speed_final_rpm, -500.0);
    }
}

// A load driving the motor at low speed (regenerating): the rated 41 N m
// pulling forward at 300 rpm on the default (real) inverter. Held by both
// controllers with integral action; without the observer's regenerating-mode
// stabilisation the speed estimate falls behind the shaft and the load pulls
// the motor away until the loss-of-control monitor trips.
TEST(Regenerating, RatedLoadDrivingTheMotorAt300RpmIsHeld)
{
    for (int c : {SCENARIO_CTL_RBFN, SCENARIO_CTL_IP}) {
        SCOPED_TRACE(c);
        SimRun r = run_sim("regen_300rpm.ini", c);
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        std::printf("[envelope] regen_300rpm ctl %d: %.2f rpm, estimate error %.2f rpm, np %.2f V, faults 0x%x\n", c,
                    window_speed(r.m, "loaded"), r.m.speed_est_error_rpm, r.m.np_dev_max_v, (unsigned)r.m.faults);
        EXPECT_EQ(r.m.faults, 0u);
        EXPECT_FALSE(r.m.runaway);
        EXPECT_NEAR(window_speed(r.m, "loaded"), 300.0, 2.0);
    }
    SimRun off = run_sim("regen_300rpm.ini", SCENARIO_CTL_RBFN, {"control.obs_regen_angle_rad=0"});
    ASSERT_EQ(off.status, SIM_OK) << off.error;
    EXPECT_NE(off.m.faults & CTL_FAULT_LOSS_OF_CONTROL, 0u);
}

// The stator 30 % warm when the drive starts: the Rs identified while
// magnetising (dtc/rs_ident.h) replaces the model's and both controllers hold
// 20 N m at 30 rpm with the defaults; without it (obs_rs_ident_tol = 1) the
// RBFN drifts to 13 rpm and the IP runs away.
TEST(LowSpeed, WarmStatorAtStartHeldWithTheDefaults)
{
    for (int c : {(int)SCENARIO_CTL_RBFN, (int)SCENARIO_CTL_IP}) {
        SimRun r = run_sim("warm_stator_start.ini", c);
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        EXPECT_EQ(r.m.faults, 0u) << c;
        EXPECT_FALSE(r.m.runaway) << c;
        EXPECT_NEAR(window_speed(r.m, "point"), 30.0, 5.0) << c;
        SimRun off = run_sim("warm_stator_start.ini", c, {"control.obs_rs_ident_tol=1"});
        ASSERT_EQ(off.status, SIM_OK) << off.error;
        EXPECT_FALSE(off.m.faults == 0u && std::fabs(window_speed(off.m, "point") - 30.0) <= 5.0) << c;
    }
}

// NOT with the defaults (the bullet asks for Rs adaptation on by default):
// with obs_ki_rs = 0.1 set, the adaptation finds the 30 % warmer stator and
// the RBFN holds 20 N m at 30 rpm. With the default (off) it drifts to
// 8 rpm (docs/envelope.md section 6).
TEST(LowSpeed, WarmStatorHeldWhenRsAdaptationIsOn)
{
    SimRun r = run_sim("warm_stator.ini", SCENARIO_CTL_RBFN, {"control.obs_ki_rs=0.1"});
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_EQ(r.m.faults, 0u);
    EXPECT_NEAR(window_speed(r.m, "point"), 30.0, 5.0);
}
