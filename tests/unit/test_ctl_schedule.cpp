// The slots of the control step's slow tasks (dtc/ctl_schedule.h): every
// predicate against the table of the header's documentation written out
// here, the tasks' rates against their own modules' windows, no tick with two
// heavy tasks, and, through ctl_step, the one place the slot advances: once
// per tick that judges a sample.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "dtc/ctl.h"
#include "dtc/ctl_guard.h"
#include "dtc/ctl_schedule.h"
#include "dtc/plausibility.h"

namespace {

// The documented cycle, slot by slot: which slow tasks step there.
//   slot   0      1        2        3           4      5        6        7
//          guard  speed    plaus    RBFN learn  guard  speed    plaus    RBFN learn
//                 command  + stall  + supervise        command  + stall  + FSW + level
//                                                                        + speed dev
const char *const kTable[8] = {
    "guard", "speed", "plaus stall", "learn supervise", "guard", "speed", "plaus stall", "learn fsw level dev",
};

// The tasks the predicates give slot @p slot, in the table's order.
std::string tasks_of(uint8_t slot)
{
    std::string t;
    auto add = [&t](bool on, const char *name) {
        if (on)
            t += (t.empty() ? "" : " ") + std::string(name);
    };
    add(ctl_slot_guard(slot), "guard");
    add(ctl_slot_speed_command(slot), "speed");
    add(ctl_slot_plaus(slot), "plaus");
    add(ctl_slot_stall(slot), "stall");
    add(ctl_slot_rbfn_learn(slot), "learn");
    add(ctl_slot_supervise(slot), "supervise");
    add(ctl_slot_fsw(slot), "fsw");
    add(ctl_slot_level(slot), "level");
    add(ctl_slot_speed_dev(slot), "dev");
    return t;
}

TEST(CtlSchedule, EverySlotRunsTheDocumentedTasks)
{
    ASSERT_EQ(CTL_SLOW_SLOTS, 8u);
    for (uint8_t slot = 0; slot < CTL_SLOW_SLOTS; ++slot)
        EXPECT_EQ(tasks_of(slot), kTable[slot]) << "slot " << int(slot);
}

TEST(CtlSchedule, NextSlotCountsAroundTheCycle)
{
    for (uint8_t slot = 0; slot < CTL_SLOW_SLOTS; ++slot)
        EXPECT_EQ(ctl_schedule_next(slot), (slot + 1) % 8) << "slot " << int(slot);
}

// Each task's rate is its module's: the loss-of-control monitor's window, the
// plausibility checks' period, one speed-loop step per CTL_RBFN_TICKS ticks
// for its command, the RBFN's learning and the stall windows; once per cycle
// for the supervision, the regulation and the level. No tick carries two of
// the heavy ones (a monitor and the speed command).
TEST(CtlSchedule, RatesAreTheTasksOwnAndHeavyTasksNeverMeet)
{
    int guard = 0, plaus = 0, speed = 0, learn = 0, stall = 0, sup = 0, fsw = 0, level = 0, dev = 0;
    for (uint8_t slot = 0; slot < CTL_SLOW_SLOTS; ++slot) {
        guard += ctl_slot_guard(slot);
        plaus += ctl_slot_plaus(slot);
        speed += ctl_slot_speed_command(slot);
        learn += ctl_slot_rbfn_learn(slot);
        stall += ctl_slot_stall(slot);
        sup += ctl_slot_supervise(slot);
        fsw += ctl_slot_fsw(slot);
        level += ctl_slot_level(slot);
        dev += ctl_slot_speed_dev(slot);
        const int heavy = int(ctl_slot_guard(slot)) + int(ctl_slot_plaus(slot)) + int(ctl_slot_speed_command(slot));
        EXPECT_LE(heavy, 1) << "slot " << int(slot);
        // the supervision beside neither a monitor nor the command
        if (ctl_slot_supervise(slot)) {
            EXPECT_EQ(heavy, 0) << "slot " << int(slot);
        }
        // the speed-deviation step neither beside a heavy task nor the stall windows
        if (ctl_slot_speed_dev(slot)) {
            EXPECT_EQ(heavy, 0) << "slot " << int(slot);
            EXPECT_FALSE(ctl_slot_stall(slot)) << "slot " << int(slot);
        }
    }
    EXPECT_EQ(guard, int(CTL_SLOW_SLOTS / CTL_GUARD_WINDOW_MAX));
    EXPECT_EQ(plaus, int(CTL_SLOW_SLOTS / PLAUS_CHECK_TICKS));
    EXPECT_EQ(speed, int(CTL_SLOW_SLOTS / CTL_RBFN_TICKS));
    EXPECT_EQ(learn, speed);
    EXPECT_EQ(stall, speed);
    EXPECT_EQ(sup, 1);
    EXPECT_EQ(fsw, 1);
    EXPECT_EQ(level, 1);
    EXPECT_EQ(dev, 1);
    // the RBFN learns from a command before the next one: one learning slot between two commands
    for (uint8_t slot = 0; slot < CTL_SLOW_SLOTS; ++slot) {
        if (!ctl_slot_speed_command(slot))
            continue;
        int learned = 0;
        uint8_t k = ctl_schedule_next(slot);
        for (; !ctl_slot_speed_command(k); k = ctl_schedule_next(k))
            learned += ctl_slot_rbfn_learn(k);
        EXPECT_EQ(learned, 1) << "after the command in slot " << int(slot);
    }
}

struct Core {
    ctl_cfg cfg;
    ctl_state s;
    ctl_out out;
    Core()
    {
        ctl_cfg_default(&cfg);
        ctl_init(&s, &cfg);
        std::memset(&out, 0, sizeof out);
    }
    static ctl_in nominal(bool run = true)
    {
        ctl_in in;
        std::memset(&in, 0, sizeof in);
        in.sample.vc1_V = 155.5f;
        in.sample.vc2_V = 155.5f;
        in.sample_fresh = true;
        in.run = run;
        return in;
    }
    // The slot after one ctl_step with @p in.
    uint8_t step(const ctl_in &in)
    {
        ctl_step(&s, &cfg, &in, &out);
        return s.slow_slot;
    }
};

// The slot advances once per tick that judges a sample, whatever the tick
// then does (stopped, running, faulted, tripping on a limit), and stands still
// when the sample is stale or a value in it is not a number.
TEST(CtlSchedule, SlotAdvancesOncePerTickThatJudgesASample)
{
    Core c;
    uint8_t slot = c.s.slow_slot;
    ctl_in stopped = Core::nominal(false);
    for (int k = 0; k < 11; ++k) { // stopped ticks judge their samples too
        slot = ctl_schedule_next(slot);
        ASSERT_EQ(c.step(stopped), slot) << "stopped tick " << k;
    }
    ctl_in running = Core::nominal();
    for (int k = 0; k < 13; ++k) {
        slot = ctl_schedule_next(slot);
        ASSERT_EQ(c.step(running), slot) << "running tick " << k;
    }
    ASSERT_EQ(c.s.run_state, CTL_MAGNETISING);

    ctl_in stale = running;
    stale.sample_fresh = false;
    EXPECT_EQ(c.step(stale), slot) << "a stale sample is not judged";
    EXPECT_EQ(c.s.run_state, CTL_FAULTED);
    ctl_in nan = running;
    nan.sample.ib_A = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(c.step(nan), slot) << "a value that is not a number is not judged";
    ctl_in inf = running;
    inf.sample.vc1_V = std::numeric_limits<float>::infinity();
    EXPECT_EQ(c.step(inf), slot) << "an infinite value is not judged";
    ctl_in over = running;
    over.sample.ia_A = 2.0f * c.cfg.i_trip_A;
    over.sample.ib_A = -over.sample.ia_A;
    slot = ctl_schedule_next(slot);
    EXPECT_EQ(c.step(over), slot) << "a sample beyond a limit is judged";
    EXPECT_NE(c.s.faults & CTL_FAULT_OVERCURRENT, 0u);
    slot = ctl_schedule_next(slot);
    EXPECT_EQ(c.step(running), slot) << "a faulted core judges its samples";
    ctl_in hw = running;
    hw.fault_input = true;
    hw.overrun = true;
    slot = ctl_schedule_next(slot);
    EXPECT_EQ(c.step(hw), slot) << "the hardware fault input and an overrun leave the sample judged";
}

} // namespace
