// A duty that uses the new plant features together (host_sim/scenarios/
// pump_duty.ini: real inverter, Coulomb + fan load, heating ramps of Rs and
// Rr, a supply sag, a load step): it must run to the end without a fault or
// a runaway, and the speed-controlled runs must end near the reference.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

extern "C" {
#include "dtc/ctl.h"
}
#include "sim_test_util.hpp"

TEST(Duty, PumpDutyRunsWithoutFaultOrRunaway)
{
    auto l = simtest::load_scenario(simtest::source_path("host_sim/scenarios/pump_duty.ini"));
    ASSERT_EQ(l.rc, 0) << l.error;
    // The file relies on the [inverter] defaults: the real inverter.
    EXPECT_DOUBLE_EQ(l.sc->plant.inverter.dead_time_s, 2e-6);
    EXPECT_DOUBLE_EQ(l.sc->plant.inverter.v_on_V, 1.0);
    for (int ctl : { SCENARIO_CTL_IP, SCENARIO_CTL_NOMINAL, SCENARIO_CTL_RBFN }) {
        sim_options o;
        sim_options_default(&o);
        o.controller = ctl;
        sim_result res;
        ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
        const sim_metrics &m = res.metrics;
        // the nominal controller (no integral action) leaves a lasting error under the duty's
        // load, which the speed-deviation supervision trips on; the others hold the speed
        EXPECT_EQ(m.faults, ctl == SCENARIO_CTL_NOMINAL ? (uint32_t)CTL_FAULT_SPEED_DEV : 0u) << ctl;
        EXPECT_FALSE(m.runaway) << ctl;
        EXPECT_LT(m.speed_true_max_abs_rpm, 1100.0) << ctl;
        if (ctl != SCENARIO_CTL_NOMINAL) {
            EXPECT_NEAR(m.speed_true_end_rpm, 1000.0, 20.0) << ctl;
            EXPECT_LT(m.steady_error_rpm, 20.0) << ctl;
            // The fan load is there: the final torque is well above the 4 N m step alone
            // (the nominal controller's gates are off by then).
            EXPECT_GT(m.te_final_nm, 10.0) << ctl;
        }
    }
}

// An overhauling load beyond the torque limit drives the motor away while
// the firmware reports no fault: the metrics must say so.
TEST(Duty, OverhaulingLoadIsFlaggedAsRunaway)
{
    // With the stall trip off, the drive reports no fault while the load runs the motor away:
    // what makes the flag necessary.
    auto l = simtest::parse_text("[sim]\nduration_s = 2\n[reference]\nramp = 0.2 0.4 300\n"
                                 "[load]\nstep = 0.5 -30\n[control]\nte_max_Nm = 20\nstall_time_s = 0\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    sim_result res;
    ASSERT_EQ(sim_run(l.sc.get(), nullptr, &res), SIM_OK) << res.error;
    EXPECT_NEAR(res.metrics.runaway_limit_rpm, 750.0, 1e-9);
    EXPECT_TRUE(res.metrics.runaway);
    EXPECT_GT(res.metrics.speed_true_end_rpm, 750.0);
    EXPECT_EQ(res.metrics.faults, 0u);

    // With the default stall trip the drive reacts: the torque command pinned at the limit
    // for 1 s trips STALL (gates off; the active load still turns the unbraked motor).
    auto st = simtest::parse_text("[sim]\nduration_s = 2\n[reference]\nramp = 0.2 0.4 300\n"
                                  "[load]\nstep = 0.5 -30\n[control]\nte_max_Nm = 20\n");
    ASSERT_EQ(st.rc, 0) << st.error;
    ASSERT_EQ(sim_run(st.sc.get(), nullptr, &res), SIM_OK) << res.error;
    EXPECT_EQ(res.metrics.faults, uint32_t(CTL_FAULT_STALL));

    auto ok = simtest::parse_text("[sim]\nduration_s = 2\n[reference]\nramp = 0.2 0.4 300\n"
                                  "[load]\nstep = 0.5 -10\n[control]\nte_max_Nm = 20\n");
    ASSERT_EQ(ok.rc, 0) << ok.error;
    ASSERT_EQ(sim_run(ok.sc.get(), nullptr, &res), SIM_OK) << res.error;
    EXPECT_FALSE(res.metrics.runaway); // held within the torque limit
    EXPECT_NEAR(res.metrics.speed_true_end_rpm, 300.0, 15.0);
}

// The capability sweep's silent runaway (tools/run-envelope.sh, real inverter): 30 rpm with a
// 20.5 N m driving load. The sensorless estimate stays near 125 rpm while the shaft runs away,
// so neither the overspeed trip (on the estimate) nor the loss-of-control monitor (not judged at
// low stator frequency) sees it; the stall trip does, from the torque command pinned at the limit.
// The firmware's low-speed measures (regenerating-mode stabilisation, lowered flux near zero
// stator frequency, dead-time compensation) hold this point; they are switched off here to
// keep the runaway that the stall trip must catch.
// Whether and when the runaway starts is chaotic: a one-ulp change in the RBFN basis moved the
// first escape that is not caught from about 2 s to 4.4 s (7 s covers both), and over 1 % changes
// of an unrelated filter (the speed estimate's low-pass, 49..51 Hz) the same point runs away in 3 to
// 5 of 5 runs, depending on the code's rounding (a run may also leave the band for 0.1 s and be braked
// back by the drive itself, which the stall rule rightly does not trip). So the rule is checked over
// those five draws: every run ends either with exactly the STALL trip or holding the point with no
// fault (never a silent runaway), and at least one of them trips, so that the trip itself is
// exercised. Without the stall trip every runaway run fails the second check.
TEST(Duty, SilentLowSpeedGeneratingRunawayTripsStall)
{
    int tripped = 0;
    for (const char *lpf_hz : {"49", "49.5", "50", "50.5", "51"}) {
        SCOPED_TRACE(std::string("obs_speed_lpf_hz = ") + lpf_hz);
        auto l = simtest::parse_text(std::string("[sim]\nduration_s = 7\n[controller]\nname = rbfn\n"
                                                 "[reference]\nramp = 0.3 0.5 30\n[load]\nstep = 1.2 -20.5\n"
                                                 "[control]\nobs_regen_angle_rad = 0\nregen_flux_min_frac = 1\n"
                                                 "dead_time_comp_s = 0\nobs_speed_lpf_hz = ") +
                                     lpf_hz + "\n");
        ASSERT_EQ(l.rc, 0) << l.error;
        sim_result res;
        ASSERT_EQ(sim_run(l.sc.get(), nullptr, &res), SIM_OK) << res.error;
        if (res.metrics.faults != 0u) {
            EXPECT_EQ(res.metrics.faults, uint32_t(CTL_FAULT_STALL));
            tripped++;
        } else { // no trip: the drive must hold the point (an excursion it brakes back itself is allowed)
            EXPECT_NEAR(res.metrics.speed_true_end_rpm, 30.0, 15.0);
        }
    }
    EXPECT_GE(tripped, 1) << "no draw ran away: the stall trip was not exercised";
}
