// Telemetry TPDOs (rate, layout, scaling), the command RPDO, the CiA 402
// state machine and EMCY, on raw frames. Scalings are derived by hand here
// (rpm = rad/s * 60 / 2 pi; raw = physical / resolution).
#include <gtest/gtest.h>

#include <cmath>

#include "co_test_util.hpp"

using namespace cotest;

namespace {

constexpr double kRpmPerRadS = 60.0 / (2.0 * M_PI);

int16_t s16(const uint8_t *b) { return int16_t(uint16_t(b[0] | (b[1] << 8))); }
uint16_t u16(const uint8_t *b) { return uint16_t(b[0] | (b[1] << 8)); }

void start(Bench &b)
{
    b.inject(frame(0x000, {0x01, kNode}));
    b.pass();
}

// Run n control ticks with one background pass each.
void run_ticks(Bench &b, int n)
{
    for (int i = 0; i < n; i++) {
        b.tick();
        b.pass();
    }
}

TEST(DriveCoPdo, NoTelemetryOutsideOperational)
{
    Bench b;
    ASSERT_FALSE(b.download(0x2500, 3, {0xE8, 0x03}).aborted()); // 1000 Hz
    b.frames.clear();
    run_ticks(b, 500);
    EXPECT_TRUE(with_id(b.frames, 0x181).empty());
    start(b);
    run_ticks(b, 500);
    EXPECT_FALSE(with_id(b.frames, 0x181).empty());
    b.inject(frame(0x000, {0x02, kNode})); // stopped
    b.pass();
    b.frames.clear();
    run_ticks(b, 500);
    EXPECT_TRUE(with_id(b.frames, 0x181).empty());
}

class DriveCoPdoRate : public ::testing::TestWithParam<int> {};

TEST_P(DriveCoPdoRate, CyclesPerSecondEqualTheRate)
{
    int hz = GetParam();
    Bench b;
    ASSERT_FALSE(b.download(0x2500, 3, {uint8_t(hz), uint8_t(hz >> 8)}).aborted());
    start(b);
    b.frames.clear();
    run_ticks(b, 5000); // one second at the 200 us tick
    auto t1 = with_id(b.frames, 0x181), t2 = with_id(b.frames, 0x281), t3 = with_id(b.frames, 0x381);
    EXPECT_NEAR(double(t1.size()), double(hz), 1.0);
    EXPECT_EQ(t1.size(), t2.size());
    EXPECT_EQ(t1.size(), t3.size());
    // The sequence counter (TPDO3 bytes 6..7) counts cycles without gaps.
    for (size_t i = 1; i < t3.size(); i++)
        EXPECT_EQ(uint16_t(u16(&t3[i].data[6]) - u16(&t3[i - 1].data[6])), 1u) << i;
    for (const auto &f : t1)
        EXPECT_EQ(f.dlc, 8u);
}

INSTANTIATE_TEST_SUITE_P(Rates, DriveCoPdoRate, ::testing::Values(1, 10, 100, 1000, 3000, 5000));

TEST(DriveCoPdo, SlowBackgroundDropsCyclesInsteadOfBursting)
{
    Bench b;
    ASSERT_FALSE(b.download(0x2500, 3, {0xE8, 0x03}).aborted()); // 1000 Hz
    start(b);
    b.frames.clear();
    for (int i = 0; i < 100; i++) { // one pass every 10 ticks (2 ms)
        b.tick(10);
        b.pass();
    }
    EXPECT_EQ(with_id(b.frames, 0x181).size(), 100u);
}

TEST(DriveCoPdo, LayoutAndScalingMatchTheDbc)
{
    Bench b;
    start(b);
    drive_snapshot &s = b.d->snap;
    s.tel.speed_ref_rad_s = float(500.0 / kRpmPerRadS);  // 500 rpm
    s.tel.omega_est_rad_s = float(498.27 / kRpmPerRadS); // 498.27 rpm
    s.omega_meas_rad_s = float(-12.34 / kRpmPerRadS);
    s.tel.te_ref_Nm = 8.126f;
    s.tel.psi_s_est_Wb = 0.4499f;
    // speed_err_rad_s and vdc_diff_V are derived from the raw fields in the
    // background's copy (drive_read_snapshot): 500 - 498.27 = 1.73 rpm, 300 - 301.234 V
    s.tel.eps_hat = -180.26f;
    s.tel.w_norm = 412.0f;
    s.tel.zeta_bar = 3.33f;
    s.vc1_V = 300.0f;
    s.vc2_V = 301.234f;
    s.tel.faults = 0x21u;
    s.tel.te_est_Nm = 100000.0f; // not mapped
    b.frames.clear();
    run_ticks(b, 50); // 100 Hz default: one cycle in 50 ticks
    auto t1 = with_id(b.frames, 0x181), t2 = with_id(b.frames, 0x281), t3 = with_id(b.frames, 0x381);
    ASSERT_EQ(t1.size(), 1u);
    ASSERT_EQ(t2.size(), 1u);
    ASSERT_EQ(t3.size(), 1u);
    EXPECT_EQ(s16(&t1[0].data[0]), 5000);   // 0.1 rpm
    EXPECT_EQ(s16(&t1[0].data[2]), 4983);   // 498.27 rounds to 498.3
    EXPECT_EQ(s16(&t1[0].data[4]), -123);
    EXPECT_EQ(s16(&t1[0].data[6]), 813);    // 0.01 N m
    EXPECT_EQ(s16(&t2[0].data[0]), 4499);   // 0.1 mWb
    EXPECT_EQ(s16(&t2[0].data[2]), 173);    // 0.01 rpm
    EXPECT_EQ(s16(&t2[0].data[4]), -1803);  // 0.1 rad/s^2
    EXPECT_EQ(s16(&t2[0].data[6]), 4120);
    EXPECT_EQ(s16(&t3[0].data[0]), 33);
    EXPECT_EQ(s16(&t3[0].data[2]), -123);   // 0.01 V
    EXPECT_EQ(u16(&t3[0].data[4]), 0x21u);
    // Saturation instead of wrap-around.
    s.tel.omega_est_rad_s = float(-500.0 / kRpmPerRadS); // speed error 1000 rpm > 327.67
    s.tel.eps_hat = -5000.0f;
    b.frames.clear();
    run_ticks(b, 50);
    t2 = with_id(b.frames, 0x281);
    ASSERT_EQ(t2.size(), 1u);
    EXPECT_EQ(s16(&t2[0].data[2]), 32767);
    EXPECT_EQ(s16(&t2[0].data[4]), -32768);
}

TEST(DriveCoRpdo, TargetVelocityAndControlword)
{
    Bench b;
    start(b);
    // controlword 0x0006 (shutdown), target 500 rpm
    auto rpdo = [&](uint16_t cw, int32_t rpm) {
        auto v = bytes_u32(uint32_t(rpm));
        b.inject(frame(0x201, {uint8_t(cw), uint8_t(cw >> 8), v[0], v[1], v[2], v[3]}));
        b.pass();
    };
    rpdo(0x0006, 500);
    EXPECT_NEAR(b.d->speed_ref_rad_s, 500.0 / kRpmPerRadS, 1e-3);
    EXPECT_FALSE(b.d->run);
    rpdo(0x000F, 500);
    EXPECT_TRUE(b.d->run);
    rpdo(0x0007, -300);
    EXPECT_FALSE(b.d->run);
    EXPECT_NEAR(b.d->speed_ref_rad_s, -300.0 / kRpmPerRadS, 1e-3);
    // Out of range: that value is skipped, the rest applies.
    rpdo(0x000F, 5000);
    EXPECT_NEAR(b.d->speed_ref_rad_s, -300.0 / kRpmPerRadS, 1e-3);
    EXPECT_TRUE(b.d->run);
}

TEST(DriveCoRpdo, ShortFrameIsIgnoredAndReported)
{
    Bench b;
    start(b);
    b.frames.clear();
    b.inject(frame(0x201, {0x0F, 0x00, 0xF4, 0x01, 0x00}));
    b.pass();
    EXPECT_FALSE(b.d->run);
    EXPECT_EQ(b.d->speed_ref_rad_s, 0.0f);
    auto emcy = with_id(b.frames, 0x081);
    ASSERT_EQ(emcy.size(), 1u);
    EXPECT_EQ(u16(&emcy[0].data[0]), 0x8210u);
}

TEST(DriveCoRpdo, IgnoredOutsideOperational)
{
    Bench b;
    b.inject(frame(0x201, {0x0F, 0x00, 0xF4, 0x01, 0x00, 0x00}));
    b.pass();
    EXPECT_FALSE(b.d->run);
    EXPECT_EQ(b.d->speed_ref_rad_s, 0.0f);
}

TEST(DriveCoCia402, StateMachineAndStatusword)
{
    Bench b;
    auto cw = [&](uint16_t v) { return b.download(0x6040, 0, {uint8_t(v), uint8_t(v >> 8)}); };
    auto sw = [&] { return b.read_u32(0x6041, 0) & 0x006Fu; }; // state bits
    EXPECT_EQ(sw(), 0x0040u);                                 // switch on disabled
    EXPECT_EQ(b.read_u32(0x6041, 0) & 0x0200u, 0x0200u);      // remote
    ASSERT_FALSE(cw(0x000F).aborted());
    EXPECT_FALSE(b.d->run) << "enable operation from switch on disabled is ignored";
    cw(0x0006);
    EXPECT_EQ(sw(), 0x0021u);
    cw(0x0007);
    EXPECT_EQ(sw(), 0x0023u);
    cw(0x000F);
    EXPECT_EQ(sw(), 0x0027u);
    EXPECT_TRUE(b.d->run);
    cw(0x0007); // disable operation
    EXPECT_EQ(sw(), 0x0023u);
    EXPECT_FALSE(b.d->run);
    cw(0x000F);
    EXPECT_TRUE(b.d->run);
    cw(0x000B); // quick stop (bit 2 low): quick stop active while the ramp runs
    EXPECT_EQ(sw(), 0x0007u);
    EXPECT_TRUE(b.d->run);
    EXPECT_TRUE(b.d->quick_stop_req);
    cw(0x000F); // enable operation does not interrupt it
    EXPECT_EQ(sw(), 0x0007u);
    b.d->snap.quick_stop_done = true; // the interrupt's ramp has ended
    b.pass();
    EXPECT_EQ(sw(), 0x0040u);
    EXPECT_FALSE(b.d->run);
    EXPECT_FALSE(b.d->quick_stop_req);
    b.d->snap.quick_stop_done = false;
    // Quick stop option 0: coast at once.
    ASSERT_FALSE(b.download(0x605A, 0, {0, 0}).aborted());
    cw(0x0006);
    cw(0x000F);
    cw(0x000B);
    EXPECT_FALSE(b.d->run);
    EXPECT_EQ(sw(), 0x0040u);
    cw(0x0006);
    cw(0x000F);
    EXPECT_TRUE(b.d->run);
    cw(0x0000); // disable voltage
    EXPECT_FALSE(b.d->run);
    EXPECT_EQ(sw(), 0x0040u);
    EXPECT_EQ(b.read_u32(0x6040, 0), 0u);
}

TEST(DriveCoCia402, FaultAndFaultReset)
{
    Bench b;
    b.download(0x6040, 0, {0x06, 0});
    b.download(0x6040, 0, {0x0F, 0});
    ASSERT_TRUE(b.d->run);
    // The control core latched a fault.
    b.d->snap.tel.state = CTL_FAULTED;
    b.d->snap.tel.faults = CTL_FAULT_OVERCURRENT;
    b.pass();
    EXPECT_EQ(b.read_u32(0x6041, 0) & 0x004Fu, 0x0008u);
    b.download(0x6040, 0, {0x0F, 0}); // ignored in fault
    EXPECT_EQ(b.read_u32(0x6041, 0) & 0x004Fu, 0x0008u);
    b.download(0x6040, 0, {0x80, 0}); // fault reset (rising edge of bit 7)
    EXPECT_TRUE(b.d->clear_faults_req);
    EXPECT_FALSE(b.d->run);
    b.d->snap.tel.state = CTL_STOPPED;
    b.d->snap.tel.faults = 0;
    b.pass();
    EXPECT_EQ(b.read_u32(0x6041, 0) & 0x004Fu, 0x0040u);
}

TEST(DriveCoCia402, FollowsADriveStartedElsewhere)
{
    Bench b;
    drive_set_run(b.d.get(), true);
    b.pass();
    EXPECT_EQ(b.read_u32(0x6041, 0) & 0x006Fu, 0x0027u);
    drive_set_run(b.d.get(), false);
    b.pass();
    EXPECT_EQ(b.read_u32(0x6041, 0) & 0x006Fu, 0x0023u);
}

TEST(DriveCoCia402, TargetReached)
{
    Bench b;
    drive_set_run(b.d.get(), true);
    drive_set_speed_ref(b.d.get(), float(500.0 / kRpmPerRadS));
    b.d->snap.tel.omega_est_rad_s = float(480.0 / kRpmPerRadS);
    b.pass();
    EXPECT_EQ(b.read_u32(0x6041, 0) & 0x0400u, 0u);
    b.d->snap.tel.omega_est_rad_s = float(497.0 / kRpmPerRadS); // within 1 % (5 rpm)
    b.pass();
    EXPECT_EQ(b.read_u32(0x6041, 0) & 0x0400u, 0x0400u);
    EXPECT_EQ(int32_t(b.read_u32(0x606C, 0)), 497);
}

TEST(DriveCoEmcy, OneMessagePerNewFaultAndResetWhenCleared)
{
    Bench b;
    b.frames.clear();
    b.d->snap.tel.faults = CTL_FAULT_OVERCURRENT;
    b.pass();
    auto e = with_id(b.frames, 0x081);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(e[0].dlc, 8u);
    EXPECT_EQ(u16(&e[0].data[0]), 0x2310u);
    EXPECT_EQ(e[0].data[2], 0x03u); // generic + current
    EXPECT_EQ(le32(&e[0].data[3]), uint32_t(CTL_FAULT_OVERCURRENT));
    EXPECT_EQ(b.read_u32(0x1001, 0), 0x03u);
    // Still latched: no repeat. A second fault: one more message, after the
    // inhibit time (0x1015, default 100 ms) since the first.
    b.frames.clear();
    b.pass();
    EXPECT_TRUE(with_id(b.frames, 0x081).empty());
    b.d->snap.tel.faults = CTL_FAULT_OVERCURRENT | CTL_FAULT_DC_OVERVOLT;
    b.advance_ms(99);
    b.pass();
    EXPECT_TRUE(with_id(b.frames, 0x081).empty()) << "within the inhibit time";
    b.advance_ms(1);
    b.pass();
    e = with_id(b.frames, 0x081);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(u16(&e[0].data[0]), 0x3210u);
    EXPECT_EQ(e[0].data[2], 0x07u); // generic + current + voltage
    // All cleared: error reset.
    b.frames.clear();
    b.d->snap.tel.faults = 0;
    b.advance_ms(100);
    b.pass();
    e = with_id(b.frames, 0x081);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(u16(&e[0].data[0]), 0x0000u);
    EXPECT_EQ(e[0].data[2], 0x00u);
    EXPECT_EQ(b.read_u32(0x1001, 0), 0x00u);
}

TEST(DriveCoEmcy, NotSentInStoppedButAfterwards)
{
    Bench b;
    b.inject(frame(0x000, {0x02, kNode}));
    b.pass();
    b.frames.clear();
    b.d->snap.tel.faults = CTL_FAULT_NP_IMBALANCE;
    b.pass();
    EXPECT_TRUE(with_id(b.frames, 0x081).empty());
    b.inject(frame(0x000, {0x80, kNode}));
    b.pass();
    auto e = with_id(b.frames, 0x081);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(u16(&e[0].data[0]), 0xFF01u);
    EXPECT_EQ(e[0].data[2], 0x81u); // generic + manufacturer
}

} // namespace
