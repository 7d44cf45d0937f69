// The drive under a failing or hostile master, judged from the plant's TRUE
// speed (the sample's speed_meas is the plant's shaft speed in the SIL):
// heartbeat lost, NMT stop, NMT reset while running, and the abort connection
// option 0x6007 (0 none, 1 fault, 3 quick stop). The motor runs at 500 rpm;
// the quick stop ramp is the default 0x6049 = 900 rpm per 1 s. Last, the
// master's own set point against the scenario's reference profile.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <vector>

extern "C" {
#include "dtc/drive.h"
#include "hal_host/hal_host.h"
#include "sim/sim.h"
}
#include "sim_test_util.hpp"

namespace {

constexpr uint8_t kNode = 1;
constexpr double kRpmPerRadS = 60.0 / (2.0 * M_PI);
constexpr double kDecelRpmS = 900.0;
// The speed loop follows the ramped reference with the lag of its reference
// model (2 zeta / wn = 0.2 s for zeta 1, wn 10 rad/s; docs/speed_control.md).
// Stopped (the estimate below 20 rpm) by the ramp time plus that lag plus the
// final approach: at most 0.56 + 0.2 + 0.4 s after the reaction starts.
constexpr double kStopWithinS = 500.0 / kDecelRpmS + 0.2 + 0.4;
// A coasting motor (no load, viscous friction only) loses a few rpm in 0.5 s;
// the ramp takes it below 350 rpm (900 x (0.5 - 0.2) = 270 rpm down).
constexpr double kRampedBelowRpm = 350.0;

struct Bus {
    hal_host_can_loopback loop{};
    hal_host_can_backend backend{};
    std::function<void(Bus &, double)> script; // frames to send at t
    double t = 0.0;
    // What the drive did, sampled each tick.
    std::vector<double> t_s, true_rpm;
    std::vector<double> ref_rpm; // the drive's speed reference (before its ramp limiter)
    std::vector<bool> gates;
    double t_gates_off = -1.0;  // first tick with the gates off after they were on
    double t_bootup = -1.0;     // a boot-up message after the first
    int bootups = 0;
    std::vector<uint16_t> emcy;
    std::vector<double> emcy_t; // when each EMCY left the drive
    int frames_out = 0;         // every frame the drive sent
    uint16_t statusword = 0;
    bool sdo_answered_after_stop = false;
    bool was_on = false;

    void send(uint16_t id, std::vector<uint8_t> data)
    {
        hal_can_frame f;
        std::memset(&f, 0, sizeof f);
        f.id = id;
        f.dlc = uint8_t(data.size());
        for (size_t i = 0; i < data.size(); i++)
            f.data[i] = data[i];
        ASSERT_EQ(hal_host_can_loopback_inject(&loop, &f), HAL_OK);
    }
    void sdo_write(uint16_t index, uint8_t sub, uint32_t v, uint8_t len)
    {
        send(0x600 + kNode, {uint8_t(0x23 | ((4 - len) << 2)), uint8_t(index), uint8_t(index >> 8), sub, uint8_t(v),
                             uint8_t(v >> 8), uint8_t(v >> 16), uint8_t(v >> 24)});
    }
    double rpm_at(double when) const { return at(true_rpm, when); }
    double at(const std::vector<double> &v, double when) const
    {
        for (size_t i = 0; i < t_s.size(); i++)
            if (t_s[i] >= when)
                return v[i];
        return v.back();
    }
};

void on_tick(void *user, double t_s, drive *d)
{
    Bus &b = *static_cast<Bus *>(user);
    b.t = t_s;
    if (b.script)
        b.script(b, t_s);
    hal_can_frame f;
    while (hal_host_can_loopback_take(&b.loop, &f) == HAL_OK) {
        b.frames_out++;
        if (f.id == 0x700 + kNode && f.dlc == 1 && f.data[0] == 0x00) {
            if (++b.bootups > 1 && b.t_bootup < 0)
                b.t_bootup = t_s;
        } else if (f.id == 0x080 + kNode) {
            b.emcy.push_back(uint16_t(f.data[0] | (f.data[1] << 8)));
            b.emcy_t.push_back(t_s);
        } else if (f.id == 0x580 + kNode && t_s > 1.6) {
            b.sdo_answered_after_stop = true;
        }
    }
    double rpm = d->snap.omega_meas_rad_s * kRpmPerRadS;
    b.t_s.push_back(t_s);
    b.true_rpm.push_back(rpm);
    b.ref_rpm.push_back(d->speed_ref_rad_s * kRpmPerRadS);
    bool on = d->out.gate_enable;
    if (on)
        b.was_on = true;
    if (b.was_on && !on && b.t_gates_off < 0)
        b.t_gates_off = t_s;
    b.statusword = uint16_t(d->co.cia402.state);
}

sim_result run(Bus &b, double duration_s = 3.0)
{
    auto l = simtest::parse_text("[sim]\nduration_s = " + std::to_string(duration_s) +
                                 "\n[controller]\nname = ip\n[reference]\nramp = 0.3 0.8 500\n");
    EXPECT_EQ(l.rc, 0) << l.error;
    hal_host_can_loopback_init(&b.loop, &b.backend);
    sim_options o;
    sim_options_default(&o);
    o.can = &b.backend;
    o.on_tick = on_tick;
    o.user = &b;
    sim_result res;
    std::memset(&res, 0, sizeof res);
    sim_run(l.sc.get(), &o, &res);
    return res;
}

// Operational at t = 0 with the master's heartbeat watched (300 ms), beats
// every 100 ms until @p t_last.
void master_until(Bus &b, double t, double t_last)
{
    if (t == 0.0) {
        b.send(0x000, {0x01, kNode});
        b.sdo_write(0x1016, 1, (0x7Fu << 16) | 300u, 4);
    }
    long tick = std::lround(t / 200e-6);
    if (t > 0.0 && t <= t_last && tick % 500 == 0)
        b.send(0x77F, {0x05});
}

double first_time(const Bus &b, uint16_t code)
{
    for (size_t i = 0; i < b.emcy.size(); i++)
        if (b.emcy[i] == code)
            return b.emcy_t[i];
    return -1.0;
}

bool has(const std::vector<uint16_t> &v, uint16_t code)
{
    for (uint16_t c : v)
        if (c == code)
            return true;
    return false;
}

} // namespace

TEST(BusLoss, HeartbeatLostQuickStopsOnTheRampThenGatesOff)
{
    Bus b;
    b.script = [](Bus &bb, double t) { master_until(bb, t, 1.5); };
    sim_result r = run(b);
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_NEAR(b.rpm_at(1.5), 500.0, 10.0);
    EXPECT_TRUE(has(b.emcy, 0x8130));
    // Detected 300 ms after the last beat (1.5 s), then a controlled ramp.
    double t_detect = 1.8;
    EXPECT_NEAR(b.rpm_at(t_detect - 0.01), 500.0, 15.0) << "no reaction before the timeout";
    EXPECT_LT(b.rpm_at(t_detect + 0.5), kRampedBelowRpm) << "ramped down, not coasting";
    ASSERT_GT(b.t_gates_off, t_detect + 0.2);
    EXPECT_LT(b.t_gates_off, t_detect + kStopWithinS);
    EXPECT_LT(std::fabs(b.rpm_at(b.t_gates_off)), 40.0);
    EXPECT_LT(std::fabs(b.true_rpm.back()), 40.0);
    EXPECT_EQ(b.statusword, CO_CIA402_SWITCH_ON_DISABLED);
    std::printf("heartbeat lost at 1.8 s: true speed %.0f rpm at +0.5 s, gates off at %.3f s (%.1f rpm), "
                "%.1f rpm at the end\n",
                b.rpm_at(t_detect + 0.5), b.t_gates_off, b.rpm_at(b.t_gates_off), b.true_rpm.back());
}

TEST(BusLoss, NmtStopWhileRunningQuickStopsAndSdoIsIgnored)
{
    Bus b;
    b.script = [](Bus &bb, double t) {
        if (t == 0.0)
            bb.send(0x000, {0x01, kNode});
        if (std::fabs(t - 1.5) < 1e-9)
            bb.send(0x000, {0x02, kNode});
        if (std::fabs(t - 1.7) < 1e-9) // nothing on the bus can help: SDO ignored in stopped
            bb.send(0x600 + kNode, {0x40, 0x41, 0x60, 0x00, 0, 0, 0, 0});
    };
    sim_result r = run(b);
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_NEAR(b.rpm_at(1.49), 500.0, 10.0);
    EXPECT_LT(b.rpm_at(2.0), kRampedBelowRpm);
    ASSERT_GT(b.t_gates_off, 1.7);
    EXPECT_LT(b.t_gates_off, 1.5 + kStopWithinS);
    EXPECT_LT(std::fabs(b.true_rpm.back()), 40.0);
    EXPECT_FALSE(b.sdo_answered_after_stop);
}

TEST(BusLoss, NmtResetWhileRunningStopsTheMotorBeforeResetting)
{
    Bus b;
    b.script = [](Bus &bb, double t) {
        if (t == 0.0)
            bb.send(0x000, {0x01, kNode});
        if (std::fabs(t - 1.5) < 1e-9)
            bb.send(0x000, {0x81, 0}); // reset node, broadcast
    };
    sim_result r = run(b);
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    ASSERT_GT(b.t_bootup, 0.0) << "the reset happened";
    EXPECT_GT(b.t_bootup, 1.5 + 0.2);
    EXPECT_LT(std::fabs(b.rpm_at(b.t_bootup)), 40.0) << "stopped before the reset";
    EXPECT_LT(b.rpm_at(2.0), kRampedBelowRpm);
    EXPECT_LT(b.t_bootup, 1.5 + kStopWithinS + 0.01);
    std::printf("NMT reset at 1.5 s: boot-up at %.3f s with the motor at %.1f rpm\n", b.t_bootup,
                b.rpm_at(b.t_bootup));
}

TEST(BusLoss, OptionNoneKeepsRunningOptionFaultCoastsIntoTheFaultState)
{
    Bus none;
    none.script = [](Bus &bb, double t) {
        master_until(bb, t, 1.5);
        if (t == 0.0)
            bb.sdo_write(0x6007, 0, 0, 2);
    };
    sim_result r = run(none);
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_TRUE(has(none.emcy, 0x8130));
    EXPECT_NEAR(none.true_rpm.back(), 500.0, 10.0) << "0x6007 = 0: no action";

    Bus fault;
    fault.script = [](Bus &bb, double t) {
        master_until(bb, t, 1.5);
        if (t == 0.0)
            bb.sdo_write(0x6007, 0, 1, 2);
    };
    r = run(fault);
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_NEAR(fault.t_gates_off, 1.8, 0.01) << "gates off at the detection";
    EXPECT_GT(fault.rpm_at(1.95), 450.0) << "coasting, not ramped";
    EXPECT_TRUE(has(fault.emcy, 0x8100));
    EXPECT_EQ(fault.statusword, CO_CIA402_FAULT);
}

// A CAN bus-off while running (the loopback backend's injected bus-off: the
// controller leaves the bus for 100 ms, then is back) gets the 0x6007
// reaction, quick stop by default, seen in the plant's true speed; nothing
// leaves the drive while off the bus, and EMCY 0x8140 (recovered from
// bus-off) follows the recovery. A second bus-off during the quick stop does
// not restart the reaction, and one while stopped only reports.
TEST(BusLoss, BusOffWhileRunningQuickStopsAndReportsTheRecovery)
{
    Bus b;
    int frames_at_off = -1, frames_at_on = -1;
    b.script = [&](Bus &bb, double t) {
        if (t == 0.0)
            bb.send(0x000, {0x01, kNode});
        long tick = std::lround(t / 200e-6);
        if (tick == 7500) { // 1.5 s
            hal_host_can_loopback_set_bus_off(&bb.loop, true);
            frames_at_off = bb.frames_out;
        }
        if (tick == 8000) { // 1.6 s: recovered
            frames_at_on = bb.frames_out;
            hal_host_can_loopback_set_bus_off(&bb.loop, false);
        }
        if (tick == 9000) // 1.8 s, during the quick stop
            hal_host_can_loopback_set_bus_off(&bb.loop, true);
        if (tick == 9050)
            hal_host_can_loopback_set_bus_off(&bb.loop, false);
    };
    sim_result r = run(b);
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_NEAR(b.rpm_at(1.49), 500.0, 10.0);
    EXPECT_EQ(frames_at_on, frames_at_off) << "nothing sent while bus-off";
    EXPECT_LT(b.rpm_at(2.0), kRampedBelowRpm) << "ramped down (quick stop), not running on";
    EXPECT_GT(b.rpm_at(1.7), 400.0) << "a ramp, not a coast to a standstill or a trip";
    ASSERT_GT(b.t_gates_off, 1.5 + 0.2);
    EXPECT_LT(b.t_gates_off, 1.5 + kStopWithinS);
    EXPECT_LT(std::fabs(b.true_rpm.back()), 40.0);
    EXPECT_EQ(b.statusword, CO_CIA402_SWITCH_ON_DISABLED);
    double t_emcy = first_time(b, 0x8140);
    EXPECT_GE(t_emcy, 1.6) << "EMCY 0x8140 only once back on the bus";
    EXPECT_LT(t_emcy, 1.61);
    int n8140 = 0;
    for (uint16_t c : b.emcy)
        n8140 += c == 0x8140;
    EXPECT_EQ(n8140, 2) << "one per bus-off";
    std::printf("bus-off at 1.5 s: true speed %.0f rpm at 2.0 s, gates off at %.3f s, EMCY 0x8140 at %.3f s\n",
                b.rpm_at(2.0), b.t_gates_off, t_emcy);
}

TEST(BusLoss, BusOffWithOptionNoneKeepsRunningOptionFaultCoastsIntoTheFaultState)
{
    Bus none;
    none.script = [](Bus &bb, double t) {
        if (t == 0.0) {
            bb.send(0x000, {0x01, kNode});
            bb.sdo_write(0x6007, 0, 0, 2);
        }
        long tick = std::lround(t / 200e-6);
        if (tick == 7500)
            hal_host_can_loopback_set_bus_off(&bb.loop, true);
        if (tick == 8000)
            hal_host_can_loopback_set_bus_off(&bb.loop, false);
    };
    sim_result r = run(none);
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_NEAR(none.true_rpm.back(), 500.0, 10.0) << "0x6007 = 0: no action";
    EXPECT_TRUE(has(none.emcy, 0x8140));

    Bus fault;
    fault.script = [](Bus &bb, double t) {
        if (t == 0.0) {
            bb.send(0x000, {0x01, kNode});
            bb.sdo_write(0x6007, 0, 1, 2);
        }
        long tick = std::lround(t / 200e-6);
        if (tick == 7500)
            hal_host_can_loopback_set_bus_off(&bb.loop, true);
        if (tick == 8000)
            hal_host_can_loopback_set_bus_off(&bb.loop, false);
    };
    r = run(fault);
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    EXPECT_NEAR(fault.t_gates_off, 1.5, 0.01) << "0x6007 = 1: gates off at the bus-off";
    EXPECT_TRUE(has(fault.emcy, 0x8100));
    EXPECT_EQ(fault.statusword, CO_CIA402_FAULT);
}

// A tuner's `dtctune set speed_ref_rpm 200` (SDO 0x2000:1, REAL32 rpm) lands
// during the scenario's ramp (0.3 .. 0.8 s to 500 rpm): from then on the master
// owns the reference and the profile does not override it (if it did, the ramp's
// next tick would write 0..500 rpm over it and the README's session would read
// back the ramp's value).
TEST(BusLoss, ReferenceWrittenOverTheBusHoldsAgainstTheScenarioProfile)
{
    Bus b;
    b.script = [](Bus &bb, double t) {
        master_until(bb, t, 3.0);
        if (std::fabs(t - 0.5) < 1e-9) {
            float rpm = 200.0f;
            uint32_t bits;
            std::memcpy(&bits, &rpm, sizeof bits);
            bb.sdo_write(0x2000, 1, bits, 4);
        }
    };
    sim_result r = run(b);
    ASSERT_EQ(r.status, SIM_OK) << r.error;
    // The profile's ramp before the write: (0.45 - 0.3) / 0.5 x 500 rpm.
    EXPECT_NEAR(b.at(b.ref_rpm, 0.45), 150.0, 0.5);
    // The write, then nothing else: the ramp would have reached 500 rpm at 0.8 s.
    EXPECT_NEAR(b.at(b.ref_rpm, 0.52), 200.0, 1e-3);
    EXPECT_NEAR(b.at(b.ref_rpm, 1.0), 200.0, 1e-3);
    EXPECT_NEAR(b.ref_rpm.back(), 200.0, 1e-3);
    // ... and the motor follows the master's 200 rpm.
    EXPECT_NEAR(b.rpm_at(2.9), 200.0, 10.0);
    std::printf("bus write of 200 rpm at 0.5 s during the 0.3..0.8 s ramp to 500 rpm: reference %.2f rpm at "
                "1.0 s, true speed %.1f rpm at 2.9 s\n",
                b.at(b.ref_rpm, 1.0), b.rpm_at(2.9));
}
