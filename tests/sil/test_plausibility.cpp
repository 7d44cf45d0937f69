// Sensor plausibility: a 10 A current offset, a current gain of 0.5, a
// capacitor voltage reading 10 % high and a lost phase. Each fault injected
// from a scenario trips exactly its own bit, in a bounded time; the healthy
// run trips nothing.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

extern "C" {
#include "dtc/ctl.h"
#include "dtc/drive.h"
#include "sim/sim.h"
}
#include "sim_test_util.hpp"

namespace {

struct Trip {
    uint32_t faults = 0;
    double t_trip = -1.0;
};

Trip run(const std::string &extra, double duration_s = 1.2)
{
    // Towards 300 rpm with 20 N m of load from 0.6 s: current flows in all phases
    // (at 0.8 s the IP is still accelerating, about 135 rpm; at 300 rpm from 1.4 s).
    auto l = simtest::parse_text("[sim]\nduration_s = " + std::to_string(duration_s) +
                                 "\n[controller]\nname = ip\n[reference]\nramp = 0.2 0.4 300\n"
                                 "[load]\nstep = 0.6 20\n" + extra);
    EXPECT_EQ(l.rc, 0) << l.error;
    Trip t;
    sim_options o;
    sim_options_default(&o);
    o.user = &t;
    o.on_tick = [](void *user, double t_s, struct drive *d) {
        auto *tr = static_cast<Trip *>(user);
        if (tr->t_trip < 0 && d->snap.tel.faults != 0)
            tr->t_trip = t_s;
        tr->faults = d->snap.tel.faults;
    };
    sim_result res;
    EXPECT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    std::printf("[plausibility] faults 0x%x, first at %.4f s\n", (unsigned)t.faults, t.t_trip);
    return t;
}

} // namespace

TEST(Plausibility, HealthyRunTripsNothing)
{
    EXPECT_EQ(run("").faults, 0u);
    // Sensor noise (1 A and 1 V rms on every channel) is no fault either.
    EXPECT_EQ(run("[sensors]\ni_noise_A = 1.0\nv_noise_V = 1.0\n").faults, 0u);
}

TEST(Plausibility, CurrentOffsetOnOnePhase)
{
    Trip t = run("[faults]\noffset = 0.8 a 10\n"); // a 10 A offset on phase a
    EXPECT_EQ(t.faults, uint32_t(CTL_FAULT_CURRENT_SENSOR));
    EXPECT_GE(t.t_trip, 0.8);
    EXPECT_LT(t.t_trip, 0.8 + 0.005) << "10 ticks of an implausible sum";
}

TEST(Plausibility, CurrentGainHalfOnOnePhase)
{
    Trip t = run("[faults]\ngain = 0.8 b 0.5\n"); // a gain of 0.5 on phase b
    EXPECT_EQ(t.faults, uint32_t(CTL_FAULT_CURRENT_SENSOR));
    EXPECT_LT(t.t_trip, 0.8 + 0.05) << "within a quarter of an electrical period at 10 Hz";
}

TEST(Plausibility, StuckCurrentReading)
{
    Trip t = run("[faults]\nstuck = 0.8 c\n");
    EXPECT_EQ(t.faults, uint32_t(CTL_FAULT_CURRENT_SENSOR));
    EXPECT_LT(t.t_trip, 0.8 + 0.05);
}

TEST(Plausibility, CapacitorVoltageReadingTenPercentHighIsRefusedAtStart)
{
    Trip t = run("[faults]\ngain = 0 vc1 1.1\n");
    EXPECT_EQ(t.faults, uint32_t(CTL_FAULT_DC_DIVIDER));
    EXPECT_LT(t.t_trip, 0.001) << "judged while stopped, before the first switching";
}

TEST(Plausibility, OpenMotorPhaseIsPhaseLoss)
{
    // At 300 rpm with the load (2 pole pairs: 10 Hz, half a period 50 ms): the
    // phase-loss check trips before the loss-of-control monitor; never a sensor
    // fault: the current sum stays 0.
    Trip t = run("[faults]\nopen_phase = 1.5 a\n", 1.9);
    EXPECT_EQ(t.faults & uint32_t(CTL_FAULT_PHASE_LOSS), uint32_t(CTL_FAULT_PHASE_LOSS)) << t.faults;
    EXPECT_EQ(t.faults & uint32_t(CTL_FAULT_CURRENT_SENSOR), 0u);
    // half a period (the first check counts its 4 ticks, so up to 0.8 ms early)
    // plus the time to fall below 0.5 A and the check's rate (measured 53 ms)
    EXPECT_GE(t.t_trip, 1.5 + 0.05 - 0.0008);
    EXPECT_LT(t.t_trip, 1.5 + 0.06);
    // During the acceleration (about 135 rpm, 4.5 Hz when the phase opens: half a
    // period is 111 ms, and the lost phase drags the speed estimate towards the
    // check's 2 Hz floor) the loss-of-control monitor sees it first (measured
    // 100 ms): either, within 0.12 s.
    Trip a = run("[faults]\nopen_phase = 0.8 a\n");
    EXPECT_NE(a.faults & uint32_t(CTL_FAULT_PHASE_LOSS | CTL_FAULT_LOSS_OF_CONTROL), 0u) << a.faults;
    EXPECT_EQ(a.faults & uint32_t(CTL_FAULT_CURRENT_SENSOR), 0u);
    EXPECT_LT(a.t_trip, 0.8 + 0.12);
}

TEST(Plausibility, LostCurrentSensorIsASensorFaultNotPhaseLoss)
{
    Trip t = run("[faults]\nlost = 0.8 a\n");
    EXPECT_EQ(t.faults, uint32_t(CTL_FAULT_CURRENT_SENSOR));
}
