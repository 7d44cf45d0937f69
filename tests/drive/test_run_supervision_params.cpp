// The run-supervision block 0x2A00 over SDO: hostile values get their abort
// code and leave every parameter as it was; a rising warning sends its EMCY
// once (not latched: the error register stays clear).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "co_test_util.hpp"

using namespace cotest;

TEST(RunSupervisionParams, SpeedDeviationHostileWritesRefused)
{
    Bench b;
    EXPECT_FLOAT_EQ(b.read_f32(0x2A00, 1), 5.86f);
    EXPECT_FLOAT_EQ(b.read_f32(0x2A00, 2), 1.0f);
    auto before = b.dump();
    EXPECT_EQ(b.download_f32(0x2A00, 1, -0.5f).abort_code(), kAbortLow);
    EXPECT_EQ(b.download_f32(0x2A00, 1, 500.5f).abort_code(), kAbortHigh);
    EXPECT_EQ(b.download_f32(0x2A00, 1, std::numeric_limits<float>::quiet_NaN()).abort_code(), kAbortInvalid);
    EXPECT_EQ(b.download_f32(0x2A00, 2, -1.0f).abort_code(), kAbortLow);
    EXPECT_EQ(b.download_f32(0x2A00, 2, 61.0f).abort_code(), kAbortHigh);
    EXPECT_EQ(b.download_f32(0x2A00, 2, std::numeric_limits<float>::infinity()).abort_code(), kAbortInvalid);
    EXPECT_EQ(b.download(0x2A00, 2, {0x00, 0x00}).abort_code(), kAbortLength);
    EXPECT_TRUE(changed(before, b.dump()).empty());
    // in range: taken, and the derived recovery rate follows
    EXPECT_FALSE(b.download_f32(0x2A00, 1, 8.0f).aborted());
    EXPECT_FALSE(b.download_f32(0x2A00, 2, 2.0f).aborted());
    EXPECT_FLOAT_EQ(drive_cfg(b.d.get())->speed_dev_band_rad_s, 8.0f);
    EXPECT_FLOAT_EQ(drive_cfg(b.d.get())->speed_dev_shrink_rad_s_per_s, 4.0f);
}

TEST(RunSupervisionParams, RisingWarningSendsItsEmcyOnce)
{
    Bench b;
    auto set_warnings = [&b](uint32_t w) {
        b.d->snap.seq++;
        b.d->snap.tel.warnings = w;
        b.d->snap.seq++;
    };
    auto emcy_codes = [&b]() {
        std::vector<uint16_t> codes;
        for (const auto &f : b.frames)
            if (f.id == 0x80u + kNode)
                codes.push_back(uint16_t(f.data[0] | (f.data[1] << 8)));
        return codes;
    };
    b.frames.clear();
    set_warnings(CTL_WARN_SPEED_DEV);
    b.pass();
    EXPECT_EQ(emcy_codes(), std::vector<uint16_t>{0xFF17});
    EXPECT_EQ(b.read_u32(0x3000, 26), (uint32_t)CTL_WARN_SPEED_DEV);
    EXPECT_EQ(b.read_u32(0x1001, 0) & 0xFFu, 0u); // not latched into the error register
    b.frames.clear();
    b.advance_ms(100.0);
    b.pass(); // still present: nothing new
    EXPECT_TRUE(emcy_codes().empty());
    set_warnings(0u);
    b.advance_ms(100.0);
    b.pass();
    set_warnings(CTL_WARN_SPEED_DEV);
    b.frames.clear();
    b.advance_ms(100.0);
    b.pass(); // risen again: sent again
    EXPECT_EQ(emcy_codes(), std::vector<uint16_t>{0xFF17});
}
