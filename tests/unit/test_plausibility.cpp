// The plausibility checks on synthetic samples (dtc/plausibility.h), against
// hand-derived timings: a healthy balanced set never trips; an open phase
// (ia = 0, ib = -ic) trips PHASE_LOSS after half an electrical period; one
// offset sensor trips CURRENT_SENSOR after PLAUS_SUM_TICKS; the dividers are
// judged while stopped only. The current checks run every PLAUS_CHECK_TICKS-th
// tick, as ctl.c schedules them (first at tick 0 here).
#include <gtest/gtest.h>

#include <cmath>

extern "C" {
#include "dtc/ctl.h"
#include "dtc/plausibility.h"
}

namespace {

constexpr double kT = 200e-6;

hal_sample three_phase(double t, double f_hz, double amp_A, bool open_a = false, double offset_a = 0.0)
{
    hal_sample x{};
    const double w = 2.0 * M_PI * f_hz * t;
    x.ia_A = float(open_a ? 0.0 : amp_A * std::cos(w) + offset_a);
    x.ib_A = float(amp_A * std::cos(w - 2.0 * M_PI / 3.0));
    x.ic_A = float(amp_A * std::cos(w + 2.0 * M_PI / 3.0));
    if (open_a) { // the remaining two carry the same current back and forth
        x.ib_A = float(amp_A * std::sin(w));
        x.ic_A = -x.ib_A;
    }
    x.vc1_V = 311.0f;
    x.vc2_V = 311.0f;
    return x;
}

// Ticks until the first fault bit, or -1.
int ticks_to_fault(double f_hz, bool open_a, double offset_a, uint32_t *bits, int max_ticks)
{
    plaus_state p;
    plaus_reset(&p);
    const float w_e = float(2.0 * M_PI * f_hz);
    for (int k = 0; k < max_ticks; k++) {
        hal_sample x = three_phase(k * kT, f_hz, 20.0, open_a, offset_a);
        uint32_t f = plaus_check(&p, &x, true, false, w_e, float(kT), k % PLAUS_CHECK_TICKS == 0);
        if (f != 0u) {
            *bits = f;
            return k;
        }
    }
    return -1;
}

} // namespace

TEST(Plausibility, HealthyBalancedCurrentsNeverTrip)
{
    for (double f : {0.5, 3.0, 10.0, 50.0, 90.0}) {
        uint32_t bits = 0;
        EXPECT_EQ(ticks_to_fault(f, false, 0.0, &bits, 50000), -1) << f << " Hz, bits " << bits;
    }
}

TEST(Plausibility, OpenPhaseTripsAfterHalfAnElectricalPeriod)
{
    for (double f : {5.0, 10.0, 40.0}) {
        uint32_t bits = 0;
        int k = ticks_to_fault(f, true, 0.0, &bits, 50000);
        ASSERT_GE(k, 0) << f;
        EXPECT_EQ(bits, uint32_t(CTL_FAULT_PHASE_LOSS)) << f;
        double half_period_ticks = std::max(0.5 / f / kT, double(PLAUS_OPEN_MIN_TICKS));
        // the first check past it (checks at 0, 4, 8, ... count 4 ticks each)
        EXPECT_GT(k, half_period_ticks - PLAUS_CHECK_TICKS) << f << " Hz";
        EXPECT_LE(k, half_period_ticks + PLAUS_CHECK_TICKS) << f << " Hz";
        EXPECT_EQ(k % PLAUS_CHECK_TICKS, 0) << f << " Hz";
    }
    uint32_t bits = 0;
    EXPECT_EQ(ticks_to_fault(1.0, true, 0.0, &bits, 50000), -1) << "not judged below 2 Hz";
}

TEST(Plausibility, OneOffsetSensorTripsTheSumCheck)
{
    uint32_t bits = 0;
    int k = ticks_to_fault(10.0, false, 10.0, &bits, 1000); // 10 A > 5 A + 5 % of 20 A
    // checks at ticks 0, 4, 8 count 4, 8, 12 >= PLAUS_SUM_TICKS = 10: the third trips
    EXPECT_EQ(k, 2 * int(PLAUS_CHECK_TICKS));
    EXPECT_EQ(bits, uint32_t(CTL_FAULT_CURRENT_SENSOR));
    EXPECT_EQ(ticks_to_fault(10.0, false, 5.5, &bits, 20000), -1) << "5.5 A is within 5 A + 1 A";
}

TEST(Plausibility, DividersAreJudgedWhileStoppedOnly)
{
    plaus_state p;
    plaus_reset(&p);
    hal_sample x{};
    x.vc1_V = 320.0f; // 3 % of 622 V is 18.66 V: 320 - 302 = 18 V is inside
    x.vc2_V = 302.0f;
    EXPECT_EQ(plaus_check(&p, &x, false, true, 0.0f, float(kT), false), 0u);
    x.vc1_V = 322.0f; // 20 V apart: outside
    // every tick while stopped, not only the current checks' ticks
    EXPECT_EQ(plaus_check(&p, &x, false, true, 0.0f, float(kT), false), uint32_t(CTL_FAULT_DC_DIVIDER));
    EXPECT_EQ(plaus_check(&p, &x, false, true, 0.0f, float(kT), true), uint32_t(CTL_FAULT_DC_DIVIDER));
    EXPECT_EQ(plaus_check(&p, &x, true, false, 0.0f, float(kT), true), 0u) << "not while running";
}
