// NMT slave and heartbeat producer on raw frames (CiA 301 layouts by hand).
#include <gtest/gtest.h>

#include "co_test_util.hpp"

using namespace cotest;

namespace {

void nmt(Bench &b, uint8_t cmd, uint8_t node)
{
    b.inject(frame(0x000, {cmd, node}));
    b.pass();
}

// Heartbeat byte of the next beat (advances one period).
int next_beat(Bench &b)
{
    b.frames.clear();
    b.advance_ms(1000);
    b.pass();
    auto hb = with_id(b.frames, 0x701);
    if (hb.size() != 1 || hb[0].dlc != 1)
        return -1;
    return hb[0].data[0];
}

TEST(DriveCoNmt, BootUpMessageThenPreOperational)
{
    Bench b(false);
    b.pass();
    auto boot = with_id(b.frames, 0x701);
    ASSERT_EQ(boot.size(), 1u);
    EXPECT_EQ(boot[0].dlc, 1u);
    EXPECT_EQ(boot[0].data[0], 0x00u);
    EXPECT_EQ(b.board.can_bitrate, 500000u); // default bit rate
    EXPECT_EQ(next_beat(b), 0x7F);
}

TEST(DriveCoNmt, HeartbeatPeriodFollows0x1017)
{
    Bench b;
    // Default 1000 ms: nothing at 999 ms, a beat at 1000 ms.
    b.advance_ms(999);
    b.pass();
    EXPECT_TRUE(with_id(b.frames, 0x701).empty());
    b.advance_ms(1);
    b.pass();
    EXPECT_EQ(with_id(b.frames, 0x701).size(), 1u);
    // 100 ms: ten beats in one second of 10 ms passes.
    ASSERT_FALSE(b.download(0x1017, 0, {100, 0}).aborted());
    b.frames.clear();
    for (int i = 0; i < 100; i++) {
        b.advance_ms(10);
        b.pass();
    }
    EXPECT_NEAR(double(with_id(b.frames, 0x701).size()), 10.0, 1.0);
    // 0 switches it off.
    ASSERT_FALSE(b.download(0x1017, 0, {0, 0}).aborted());
    b.frames.clear();
    for (int i = 0; i < 50; i++) {
        b.advance_ms(100);
        b.pass();
    }
    EXPECT_TRUE(with_id(b.frames, 0x701).empty());
}

TEST(DriveCoNmt, StateCommands)
{
    Bench b;
    nmt(b, 0x01, kNode); // start
    EXPECT_EQ(next_beat(b), 0x05);
    nmt(b, 0x02, kNode); // stop
    EXPECT_EQ(next_beat(b), 0x04);
    // SDO is not served in stopped.
    EXPECT_FALSE(b.upload(0x1000, 0).got);
    nmt(b, 0x80, 0); // pre-operational, to all nodes
    EXPECT_EQ(next_beat(b), 0x7F);
    EXPECT_TRUE(b.upload(0x1000, 0).got);
    nmt(b, 0x01, 0); // start, to all nodes
    EXPECT_EQ(next_beat(b), 0x05);
}

TEST(DriveCoNmt, OtherNodesUnknownCommandsAndMalformedFramesAreIgnored)
{
    Bench b;
    nmt(b, 0x01, 2); // start node 2
    EXPECT_EQ(next_beat(b), 0x7F);
    nmt(b, 0x55, kNode); // unknown command
    EXPECT_EQ(next_beat(b), 0x7F);
    b.inject(frame(0x000, {0x01})); // too short
    b.inject(frame(0x000, {0x01, kNode, 0})); // too long
    b.inject(frame(0x000, {0x01, kNode}, true)); // remote frame
    b.pass();
    EXPECT_EQ(next_beat(b), 0x7F);
}

TEST(DriveCoNmt, ResetCommunicationAppliesANewNodeId)
{
    Bench b;
    ASSERT_FALSE(b.download(0x2500, 1, {5}).aborted());
    EXPECT_EQ(b.read_u32(0x2500, 1), 5u);
    EXPECT_EQ(b.read_u32(0x1800, 1), 0x40000181u) << "the node id changes only at a reset";
    b.frames.clear();
    nmt(b, 0x82, kNode);
    auto boot = with_id(b.frames, 0x705);
    ASSERT_EQ(boot.size(), 1u);
    EXPECT_EQ(boot[0].data[0], 0x00u);
    EXPECT_FALSE(b.upload(0x1000, 0).got); // node 1 is gone
    SdoReply r = b.sdo(Bench::req(0x40, 0x1800, 1), 5);
    ASSERT_TRUE(r.got);
    EXPECT_EQ(r.f.id, 0x585u);
    EXPECT_EQ(le32(&r.f.data[4]), 0x40000185u);
}

TEST(DriveCoNmt, ResetNodeStopsTheDriveAndReloadsStoredParameters)
{
    Bench b;
    ASSERT_FALSE(b.download_f32(0x2100, 1, 12.0f).aborted()); // rbfn_k
    ASSERT_FALSE(b.download_u32(0x1010, 1, 0x65766173u).aborted()); // save
    ASSERT_FALSE(b.download_f32(0x2100, 1, 30.0f).aborted()); // not saved
    drive_set_run(b.d.get(), true);
    b.frames.clear();
    nmt(b, 0x81, 0);
    // Running: the abort connection option (default 3, quick stop) comes first;
    // the reset waits for the ramp to end.
    EXPECT_TRUE(b.d->quick_stop_req);
    EXPECT_TRUE(b.d->run);
    EXPECT_TRUE(with_id(b.frames, 0x701).empty());
    b.pass();
    EXPECT_TRUE(with_id(b.frames, 0x701).empty());
    b.d->snap.quick_stop_done = true; // as the interrupt reports the end of the ramp
    b.pass();
    EXPECT_FALSE(b.d->run);
    EXPECT_FALSE(b.d->quick_stop_req);
    EXPECT_EQ(with_id(b.frames, 0x701).size(), 1u); // boot-up again
    EXPECT_EQ(b.read_f32(0x2100, 1), 12.0f);
    EXPECT_EQ(next_beat(b), 0x7F);
}

TEST(DriveCoNmt, AutostartEntersOperationalAfterBootUp)
{
    Bench b;
    ASSERT_FALSE(b.download(0x2500, 4, {1}).aborted());
    ASSERT_FALSE(b.download_u32(0x1010, 1, 0x65766173u).aborted());
    b.power_cycle(false);
    b.pass();
    ASSERT_EQ(with_id(b.frames, 0x701).size(), 1u);
    EXPECT_EQ(next_beat(b), 0x05);
}

TEST(DriveCoNmt, BitRateTakesEffectAtTheNextBoot)
{
    Bench b;
    ASSERT_FALSE(b.download(0x2500, 2, {0xE8, 0x03}).aborted()); // 1000 kbit/s
    EXPECT_EQ(b.board.can_bitrate, 500000u);
    ASSERT_FALSE(b.download_u32(0x1010, 1, 0x65766173u).aborted());
    b.power_cycle();
    EXPECT_EQ(b.board.can_bitrate, 1000000u);
}

} // namespace
