// The scope: triggered capture in the interrupt (scope_sample) and read-out
// through a segmented SDO upload of the domain object 0x2601.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "co_test_util.hpp"

extern "C" {
#include "dtc/scope.h"
}

using namespace cotest;

namespace {

constexpr double kRpmPerRadS = 60.0 / (2.0 * M_PI);

// One interrupt's worth of scope work on the drive's snapshot, with a known
// signal: estimated speed = tick (rad/s), torque command = -tick / 10.
void isr_tick(Bench &b, float ref_rad_s, uint32_t faults = 0)
{
    drive_snapshot &s = b.d->snap;
    s.tick++;
    s.tel.omega_est_rad_s = float(s.tick);
    s.tel.te_ref_Nm = -float(s.tick) / 10.0f;
    s.tel.faults = faults;
    s.tel.state = uint8_t(s.tick % 4);
    scope_sample(&b.d->scope, &b.d->snap, ref_rad_s, faults, s.tick);
}

std::vector<float> as_floats(const std::vector<uint8_t> &v)
{
    std::vector<float> out(v.size() / 4);
    for (size_t i = 0; i < out.size(); i++)
        std::memcpy(&out[i], &v[4 * i], 4);
    return out;
}

void set_channels(Bench &b, std::vector<uint8_t> ch)
{
    for (uint8_t i = 0; i < 4; i++)
        ASSERT_FALSE(b.download(0x2600, uint8_t(i + 1), {i < ch.size() ? ch[i] : uint8_t(0)}).aborted());
}

TEST(DriveCoScope, EmptyDomainBeforeACapture)
{
    Bench b;
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_IDLE));
    SdoReply r = b.upload(0x2601, 0);
    ASSERT_TRUE(r.got);
    EXPECT_EQ(r.f.data[0], 0x41u); // segmented, size indicated
    EXPECT_EQ(le32(&r.f.data[4]), 0u);
    SdoReply s = b.sdo({0x60, 0, 0, 0, 0, 0, 0, 0});
    EXPECT_EQ(s.f.data[0], 0x0Fu); // t = 0, n = 7, c = 1: no data, last
}

TEST(DriveCoScope, ReferenceTriggerWithPretrigger)
{
    Bench b;
    set_channels(b, {2, 5}); // speed estimate (rpm), torque command (N m)
    ASSERT_FALSE(b.download(0x2600, 5, {1}).aborted());          // trigger: reference change
    ASSERT_FALSE(b.download(0x2600, 6, {100, 0}).aborted());     // 100 samples before
    ASSERT_FALSE(b.download(0x2600, 8, {1}).aborted());          // arm
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_ARMED));
    for (int i = 0; i < 50; i++)
        isr_tick(b, 0.0f);
    isr_tick(b, 1.0f); // a change before the pretrigger part is full: ignored
    for (int i = 0; i < 100; i++)
        isr_tick(b, 1.0f);
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_ARMED));
    isr_tick(b, 2.0f); // the trigger
    uint32_t trig_tick = b.d->snap.tick;
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_TRIGGERED));
    for (int i = 0; i < 1022 - 100; i++)
        isr_tick(b, 2.0f);
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_TRIGGERED));
    isr_tick(b, 2.0f);
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_DONE));
    EXPECT_EQ(b.read_u32(0x2600, 11), trig_tick);
    for (int i = 0; i < 10; i++)
        isr_tick(b, 3.0f); // frozen
    uint32_t abort = 1;
    auto data = as_floats(b.upload_segmented(0x2601, 0, &abort));
    ASSERT_EQ(abort, 0u);
    ASSERT_EQ(data.size(), 2u * 1024u);
    for (uint32_t j = 0; j < 1024; j++) {
        double tick = double(trig_tick) - 100.0 + j;
        EXPECT_NEAR(data[j], tick * kRpmPerRadS, 1e-3 * tick) << j;         // channel 1 in rpm
        EXPECT_NEAR(data[1024 + j], -tick / 10.0, 1e-4 * tick) << j;        // channel 2 in N m
    }
}

TEST(DriveCoScope, ManualTriggerDecimationAndIntegerSignals)
{
    Bench b;
    set_channels(b, {21, 0, 23}); // run state (UNSIGNED8), off, tick (UNSIGNED32)
    ASSERT_FALSE(b.download(0x2600, 5, {0}).aborted());       // manual
    ASSERT_FALSE(b.download(0x2600, 6, {0, 0}).aborted());    // no pretrigger
    ASSERT_FALSE(b.download(0x2600, 7, {3, 0}).aborted());    // every 3rd tick
    EXPECT_EQ(b.download(0x2600, 8, {2}).abort_code(), kAbortState) << "trigger needs an armed scope";
    ASSERT_FALSE(b.download(0x2600, 8, {1}).aborted());
    for (int i = 0; i < 10; i++)
        isr_tick(b, 0.0f);
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_ARMED));
    ASSERT_FALSE(b.download(0x2600, 8, {2}).aborted());
    int n = 0;
    while (b.read_u32(0x2600, 9) != SCOPE_DONE && n < 4000) {
        isr_tick(b, 0.0f);
        n++;
    }
    EXPECT_NEAR(n, 3 * 1024, 3);
    auto data = as_floats(b.upload_segmented(0x2601, 0));
    ASSERT_EQ(data.size(), 2u * 1024u);
    for (uint32_t j = 1; j < 1024; j++) {
        EXPECT_EQ(data[1024 + j] - data[1024 + j - 1], 3.0f) << j; // the tick, every 3rd
        EXPECT_EQ(data[j], float(uint32_t(data[1024 + j]) % 4)) << j;
    }
}

// Every kind in one capture: two byte signals sharing a word (the vector at
// byte 0, the run state at byte 1), two 32-bit ones. The interrupt stores each
// channel's word as it is; the reader must pick each byte out of its word.
TEST(DriveCoScope, EveryKindInOneCaptureEachValueItsOwn)
{
    Bench b;
    set_channels(b, {20, 21, 23, 22}); // vector, run state (UNSIGNED8), tick, faults (UNSIGNED32)
    ASSERT_FALSE(b.download(0x2600, 5, {0}).aborted());    // manual
    ASSERT_FALSE(b.download(0x2600, 6, {0, 0}).aborted()); // no pretrigger
    ASSERT_FALSE(b.download(0x2600, 8, {1}).aborted());
    ASSERT_FALSE(b.download(0x2600, 8, {2}).aborted()); // trigger now
    drive_snapshot &s = b.d->snap;
    for (int i = 0; i < 1100 && b.read_u32(0x2600, 9) != SCOPE_DONE; i++) {
        s.tick++;
        s.tel.vector_index = uint8_t((s.tick * 7u) % 27u);
        s.tel.state = uint8_t(s.tick % 4u);
        s.tel.faults = (1u << 20) | s.tick; // exact as a float (below 2^24)
        scope_sample(&b.d->scope, &b.d->snap, 0.0f, 0u, s.tick);
    }
    ASSERT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_DONE));
    auto data = as_floats(b.upload_segmented(0x2601, 0));
    ASSERT_EQ(data.size(), 4u * 1024u);
    for (uint32_t j = 0; j < 1024; j++) {
        uint32_t tick = uint32_t(data[2048 + j]);
        EXPECT_EQ(data[j], float((tick * 7u) % 27u)) << j;
        EXPECT_EQ(data[1024 + j], float(tick % 4u)) << j;
        EXPECT_EQ(data[3072 + j], float((1u << 20) | tick)) << j;
        if (j > 0) {
            EXPECT_EQ(data[2048 + j] - data[2048 + j - 1], 1.0f) << j;
        }
    }
}

// Every telemetry signal the scope can capture: the word the interrupt copies
// is an aligned one inside the snapshot, and holds the signal (a byte signal
// at its place in it), against the object dictionary's offset.
TEST(DriveCoScope, EverySignalsWordIsAlignedAndInsideTheSnapshot)
{
    int armed = 0;
    for (uint8_t sig = 1; sig <= CO_TEL_COUNT; sig++) {
        SCOPED_TRACE(int(sig));
        Bench b;
        set_channels(b, {sig});
        const co_param *p = co_od_find(&drive_od, uint16_t(CO_TEL_INDEX), sig, nullptr);
        ASSERT_NE(p, nullptr);
        if (p->bind != DRIVE_BIND_SNAP) {
            EXPECT_TRUE(b.download(0x2600, 8, {1}).aborted()) << "a signal not in the snapshot cannot be armed";
            continue;
        }
        ASSERT_FALSE(b.download(0x2600, 8, {1}).aborted());
        const scope &sc = b.d->scope;
        EXPECT_EQ(sc.word_at[0] % 4u, 0u);
        EXPECT_LE(sc.word_at[0] + 4u, sizeof(drive_snapshot));
        EXPECT_EQ(uint32_t(sc.word_at[0]) + sc.byte_in_word[0], uint32_t(p->offset));
        EXPECT_EQ(sc.byte_in_word[0] != 0u, p->csize == 1u && p->offset % 4u != 0u);
        armed++;
    }
    EXPECT_GE(armed, 20);
}

TEST(DriveCoScope, FaultTriggerOnTheRisingEdge)
{
    Bench b;
    set_channels(b, {22});
    ASSERT_FALSE(b.download(0x2600, 5, {2}).aborted());
    ASSERT_FALSE(b.download(0x2600, 6, {10, 0}).aborted());
    ASSERT_FALSE(b.download(0x2600, 8, {1}).aborted());
    for (int i = 0; i < 20; i++)
        isr_tick(b, 5.0f);
    isr_tick(b, 5.0f, CTL_FAULT_OVERSPEED);
    for (int i = 0; i < 1100; i++)
        isr_tick(b, 5.0f, CTL_FAULT_OVERSPEED);
    ASSERT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_DONE));
    auto data = as_floats(b.upload_segmented(0x2601, 0));
    ASSERT_EQ(data.size(), 1024u);
    for (int j = 0; j < 10; j++)
        EXPECT_EQ(data[j], 0.0f);
    EXPECT_EQ(data[10], float(CTL_FAULT_OVERSPEED));
}

TEST(DriveCoScope, StopAndRearm)
{
    Bench b;
    ASSERT_FALSE(b.download(0x2600, 8, {1}).aborted());
    ASSERT_FALSE(b.download(0x2600, 8, {0}).aborted());
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_IDLE));
    for (int i = 0; i < 2000; i++)
        isr_tick(b, float(i));
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_IDLE));
    // Out-of-range channel settings are refused at the write, not at arming.
    EXPECT_EQ(b.download(0x2600, 1, {uint8_t(CO_TEL_COUNT + 1)}).abort_code(), kAbortHigh);
    EXPECT_EQ(b.download(0x2600, 7, {0, 0}).abort_code(), kAbortLow);
}

// The real interrupt drives the scope: a reference step while the drive is
// stopped (no control action needed) triggers a capture.
TEST(DriveCoScope, SampledByDriveIsr)
{
    Bench b;
    hal_tick_start(drive_isr, b.d.get(), 200);
    ASSERT_FALSE(b.download(0x2600, 8, {1}).aborted()); // defaults: reference trigger, 128 before
    hal_sample s{};
    s.vc1_V = 155.5f;
    s.vc2_V = 155.5f;
    for (uint32_t i = 0; i < 1200; i++) {
        s.seq = i + 1;
        hal_host_set_sample(&b.board, &s);
        if (i == 300)
            drive_set_speed_ref(b.d.get(), 10.0f);
        hal_host_run_tick(&b.board);
    }
    b.pass();
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_DONE));
    EXPECT_EQ(b.read_u32(0x2600, 11), 301u);
    hal_tick_stop();
}

// The derived snapshot fields (vc1 - vc2, the current magnitude, the DC link)
// are worked out in the interrupt only for the scope that reads them
// (drive_scope_arm): captured through the real drive_isr, each sample is that
// tick's value, against the closed forms in double.
TEST(DriveCoScope, DerivedSignalsAreThisTicksValues)
{
    Bench b;
    auto sub_of = [](const char *name) {
        const co_param *p = co_od_find_name(&drive_od, name);
        return p != nullptr ? p->sub : uint8_t(0);
    };
    const uint8_t diff = sub_of("tel_vdc_diff_V"), peak = sub_of("tel_i_peak_A"), vdc = sub_of("tel_vdc_V"),
                  vc1 = sub_of("tel_vc1_V");
    ASSERT_NE(diff * peak * vdc * vc1, 0);
    set_channels(b, {diff, peak, vdc, vc1});
    ASSERT_FALSE(b.download(0x2600, 5, {0}).aborted());    // manual
    ASSERT_FALSE(b.download(0x2600, 6, {0, 0}).aborted()); // no pretrigger
    ASSERT_FALSE(b.download(0x2600, 8, {1}).aborted());
    EXPECT_EQ(b.d->snap_derived, DRIVE_SNAP_VDC_DIFF | DRIVE_SNAP_I_PEAK | DRIVE_SNAP_VDC);
    hal_tick_start(drive_isr, b.d.get(), 200);
    ASSERT_FALSE(b.download(0x2600, 8, {2}).aborted()); // trigger now
    auto sample_of = [](uint32_t i) {
        hal_sample s{};
        s.seq = i + 1;
        s.vc1_V = 150.0f + 0.25f * float(i % 40);
        s.vc2_V = 160.0f - 0.5f * float(i % 30);
        s.ia_A = 3.0f * float(i % 7) - 9.0f;
        s.ib_A = 2.0f - 0.5f * float(i % 11);
        s.ic_A = -s.ia_A - s.ib_A;
        return s;
    };
    uint32_t first = 0;
    for (uint32_t i = 0; i < 1100 && b.read_u32(0x2600, 9) != SCOPE_DONE; i++) {
        hal_sample s = sample_of(i);
        hal_host_set_sample(&b.board, &s);
        hal_host_run_tick(&b.board);
        if (i == 0)
            first = b.d->snap.tick - 1u; // the trigger's sample is the first stored one
        b.pass();
    }
    hal_tick_stop();
    ASSERT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_DONE));
    uint32_t abort = 1;
    auto data = as_floats(b.upload_segmented(0x2601, 0, &abort));
    ASSERT_EQ(abort, 0u);
    ASSERT_EQ(data.size(), 4u * 1024u);
    for (uint32_t j = 0; j < 1024; j++) {
        const hal_sample s = sample_of(first + j);
        const double ia = s.ia_A, ib = s.ib_A, ic = s.ic_A;
        EXPECT_NEAR(data[j], double(s.vc1_V) - double(s.vc2_V), 1e-4) << j;
        EXPECT_NEAR(data[1024 + j], std::sqrt(2.0 / 3.0 * (ia * ia + ib * ib + ic * ic)), 1e-4) << j;
        EXPECT_NEAR(data[2048 + j], double(s.vc1_V) + double(s.vc2_V), 1e-4) << j;
        EXPECT_EQ(data[3072 + j], s.vc1_V) << j;
    }
    // The background's copy has every derived field, whatever the scope reads.
    b.pass();
    const drive_snapshot &g = b.d->bg_snap;
    EXPECT_EQ(g.vdc_diff_V, g.vc1_V - g.vc2_V);
    EXPECT_EQ(g.vdc_V, g.vc1_V + g.vc2_V);
    EXPECT_EQ(g.speed_err_rad_s, g.tel.speed_ref_rad_s - g.tel.omega_est_rad_s);
    EXPECT_NEAR(g.i_peak_A,
                std::sqrt(2.0 / 3.0 * (double(g.ia_A) * g.ia_A + double(g.ib_A) * g.ib_A + double(g.ic_A) * g.ic_A)),
                1e-4);
}

} // namespace

// A manual trigger asked for while the pretrigger part is still filling waits
// for it and is taken with the first sample after it: exactly pretrigger
// samples before the trigger sample.
TEST(DriveCoScope, ManualTriggerDuringThePretriggerWaitsForIt)
{
    Bench b;
    set_channels(b, {2});
    ASSERT_FALSE(b.download(0x2600, 5, {0}).aborted());    // manual
    ASSERT_FALSE(b.download(0x2600, 6, {100, 0}).aborted()); // 100 samples before
    ASSERT_FALSE(b.download(0x2600, 8, {1}).aborted());
    for (int i = 0; i < 10; i++)
        isr_tick(b, 0.0f);
    ASSERT_FALSE(b.download(0x2600, 8, {2}).aborted()); // trigger now: 90 pretrigger samples still to come
    for (int i = 0; i < 90; i++)
        isr_tick(b, 0.0f);
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_ARMED));
    isr_tick(b, 0.0f);
    const uint32_t trig_tick = b.d->snap.tick;
    EXPECT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_TRIGGERED));
    for (int i = 0; i < 1024 - 100 - 1; i++)
        isr_tick(b, 0.0f);
    ASSERT_EQ(b.read_u32(0x2600, 9), uint32_t(SCOPE_DONE));
    auto data = as_floats(b.upload_segmented(0x2601, 0));
    ASSERT_EQ(data.size(), 1024u);
    EXPECT_FLOAT_EQ(data[100], float(trig_tick) * float(kRpmPerRadS)); // the speed estimate is the tick, in rpm
    EXPECT_FLOAT_EQ(data[0], float(trig_tick - 100u) * float(kRpmPerRadS));
}
