// The speed reference's one rule (dtc/speed_ref.h), through every object that
// asks for a speed: SDO 0x2000:1 (REAL32 rpm), 0x60FF (INTEGER32 rpm), 0x6042
// (INTEGER16 rpm), the RPDO's target velocity, and a board's own command.
// The expected values are worked out here from the rule's statement, in rpm:
// a bus target's magnitude at least vl_velocity_min (if non-zero), then at
// most vl_velocity_max; then every reference within speed_ref_rpm's declared
// range and the envelope's top speed overspeed_rad_s / 1.1.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "co_test_util.hpp"

using namespace cotest;

namespace {

constexpr double kRpmPerRadS = 60.0 / (2.0 * M_PI);
constexpr uint32_t kAbortMaxBelowMin = 0x06090036u; // CiA 301: maximum value is less than minimum value

// The declared range of speed_ref_rpm (0x2000:1), bus rpm, from the table.
double declared_max_rpm()
{
    const co_param *p = co_od_find_name(&drive_od, "speed_ref_rpm");
    EXPECT_NE(p, nullptr);
    return p != nullptr ? double(p->max.f) : 0.0;
}

// The envelope's top speed, rpm: the default overspeed trip (docs/faults.md: 310 rad/s) / 1.1.
constexpr double kTopRpm = 310.0 / 1.1 * kRpmPerRadS; // 2691.2 rpm

std::vector<uint8_t> i16(int v) { return {uint8_t(v), uint8_t(v >> 8)}; }

double ref_rpm(Bench &b) { return double(b.read_f32(0x2000, 1)); }

// Every object that shows the speed reference or a request within its declared range.
::testing::AssertionResult references_in_declared_ranges(Bench &b)
{
    for (const char *name : {"speed_ref_rpm", "target_velocity", "vl_target_velocity", "vl_velocity_min",
                             "vl_velocity_max"}) {
        const co_param *p = b.param(name);
        co_num v;
        v.u = 0;
        if (co_od_read_num(&b.d->co, p, &v) != CO_ABORT_NONE)
            return ::testing::AssertionFailure() << name << ": unreadable";
        double x = p->dtype == CO_DT_REAL32 ? double(v.f)
                   : (p->dtype == CO_DT_UNSIGNED32) ? double(v.u)
                                                     : double(int32_t(v.i));
        double lo = p->dtype == CO_DT_REAL32 ? double(p->min.f)
                    : (p->dtype == CO_DT_UNSIGNED32) ? double(p->min.u)
                                                      : double(p->min.i);
        double hi = p->dtype == CO_DT_REAL32 ? double(p->max.f)
                    : (p->dtype == CO_DT_UNSIGNED32) ? double(p->max.u)
                                                      : double(p->max.i);
        if (!(x >= lo && x <= hi))
            return ::testing::AssertionFailure() << name << " = " << x << " outside " << lo << ".." << hi;
    }
    return ::testing::AssertionSuccess();
}

} // namespace

TEST(SpeedRef, ATargetOf2500ThroughEachObjectStaysInTheDeclaredRange)
{
    for (int via = 0; via < 4; via++) {
        SCOPED_TRACE(via);
        Bench b;
        switch (via) {
        case 0:
            ASSERT_FALSE(b.download(0x60FF, 0, bytes_u32(2500u)).aborted());
            break;
        case 1:
            ASSERT_FALSE(b.download(0x6042, 0, i16(2500)).aborted());
            break;
        case 2:
            ASSERT_FALSE(b.download_f32(0x2000, 1, 2500.0f).aborted());
            break;
        default:
            b.inject(frame(0x000, {0x01, kNode})); // operational: RPDOs are applied
            b.pass();
            b.inject(frame(0x200 + kNode, {0x00, 0x00, 0xC4, 0x09, 0x00, 0x00})); // controlword 0, 2500 rpm
            b.pass();
            break;
        }
        double ref = ref_rpm(b);
        EXPECT_LE(ref, declared_max_rpm());
        EXPECT_LE(ref, kTopRpm);
        EXPECT_NEAR(ref, std::min({2500.0, 2610.0, declared_max_rpm(), kTopRpm}), 0.01);
        EXPECT_TRUE(references_in_declared_ranges(b));
        // The same request with the vl maximum at 1000 rpm: limited to it.
        ASSERT_FALSE(b.download_u32(0x6046, 2, 1000u).aborted());
        EXPECT_NEAR(ref_rpm(b), 1000.0, 0.01) << "a bus reference follows a lowered vl maximum";
        EXPECT_EQ(int32_t(b.read_u32(0x60FF, 0)), 1000);
        ASSERT_FALSE(b.download_u32(0x6046, 2, 3000u).aborted());
        EXPECT_NEAR(ref_rpm(b), std::min(2500.0, kTopRpm), 0.01) << "and the target again once it is raised";
        EXPECT_TRUE(references_in_declared_ranges(b));
    }
}

TEST(SpeedRef, NoObjectAsksForMoreThanTheEnvelope)
{
    Bench b;
    ASSERT_FALSE(b.download_u32(0x6046, 2, 3000u).aborted());
    for (int rpm : {3000, -3000}) {
        ASSERT_FALSE(b.download(0x60FF, 0, bytes_u32(uint32_t(rpm))).aborted());
        EXPECT_NEAR(ref_rpm(b), rpm > 0 ? kTopRpm : -kTopRpm, 0.01);
        EXPECT_EQ(int32_t(b.read_u32(0x60FF, 0)), rpm > 0 ? 2691 : -2691);
        EXPECT_EQ(int16_t(b.read_u32(0x6042, 0)), rpm) << "0x6042 shows the target as written";
    }
    // A lower overspeed trip lowers the top speed: 100 rad/s / 1.1 = 868.1 rpm.
    ASSERT_FALSE(b.download_f32(0x2400, 5, 100.0f).aborted());
    EXPECT_NEAR(ref_rpm(b), -100.0 / 1.1 * kRpmPerRadS, 0.01) << "the reference in force is read";
    ASSERT_FALSE(b.download(0x6042, 0, i16(2000)).aborted());
    EXPECT_NEAR(ref_rpm(b), 100.0 / 1.1 * kRpmPerRadS, 0.01);
    // A board's own command (the SIL's scenario) goes through the same limits:
    // the declared range when it is set, the top speed where it is used.
    drive_set_speed_ref(b.d.get(), float(5000.0 / kRpmPerRadS));
    EXPECT_NEAR(b.d->speed_ref_rad_s * kRpmPerRadS, declared_max_rpm(), 0.01);
    EXPECT_NEAR(ref_rpm(b), 100.0 / 1.1 * kRpmPerRadS, 0.01);
    drive_set_speed_ref(b.d.get(), float(-300.0 / kRpmPerRadS));
    EXPECT_NEAR(b.d->speed_ref_rad_s, -300.0 / kRpmPerRadS, 1e-4) << "inside the limits: as asked";
    EXPECT_NEAR(ref_rpm(b), -300.0, 0.01);
    drive_set_speed_ref(b.d.get(), std::nanf(""));
    EXPECT_NEAR(b.d->speed_ref_rad_s, -300.0 / kRpmPerRadS, 1e-4) << "not a number: unchanged";
    ASSERT_FALSE(b.download_f32(0x2400, 5, 500.0f).aborted()); // top 454.5 rad/s = 4340 rpm
    drive_set_speed_ref(b.d.get(), float(5000.0 / kRpmPerRadS));
    EXPECT_NEAR(ref_rpm(b), declared_max_rpm(), 0.01) << "then the declared range limits";
    // The top speed lowered under a bus reference, then a vl maximum below it:
    // the reference follows the maximum (the stored value is the bus's).
    ASSERT_FALSE(b.download_f32(0x2400, 5, 310.0f).aborted());
    ASSERT_FALSE(b.download(0x60FF, 0, bytes_u32(2500u)).aborted());
    ASSERT_FALSE(b.download_f32(0x2400, 5, 100.0f).aborted());
    EXPECT_NEAR(ref_rpm(b), 100.0 / 1.1 * kRpmPerRadS, 0.01);
    ASSERT_FALSE(b.download_u32(0x6046, 2, 500u).aborted());
    EXPECT_NEAR(ref_rpm(b), 500.0, 0.01);
}

TEST(SpeedRef, AMinimumAboveTheMaximumIsRefusedAndChangesNothing)
{
    Bench b;
    ASSERT_FALSE(b.download(0x60FF, 0, bytes_u32(50u)).aborted());
    auto before = b.dump();
    SdoReply r = b.download_u32(0x6046, 1, 3000u); // max is 2610
    EXPECT_EQ(r.abort_code(), kAbortMaxBelowMin);
    EXPECT_TRUE(changed(before, b.dump()).empty());
    EXPECT_NEAR(ref_rpm(b), 50.0, 0.01);
    ASSERT_FALSE(b.download_u32(0x6046, 1, 200u).aborted());
    EXPECT_NEAR(ref_rpm(b), 200.0, 0.01) << "a non-zero target is raised to the minimum";
    before = b.dump();
    r = b.download_u32(0x6046, 2, 100u);
    EXPECT_EQ(r.abort_code(), kAbortMaxBelowMin);
    EXPECT_TRUE(changed(before, b.dump()).empty());
    ASSERT_FALSE(b.download_u32(0x6046, 2, 200u).aborted()) << "min = max is consistent";
    ASSERT_FALSE(b.download(0x60FF, 0, bytes_u32(0u)).aborted());
    EXPECT_EQ(ref_rpm(b), 0.0f) << "zero stays zero";
}

// A stored pair from before the check (or any inconsistent pair): the
// maximum wins, the reference never exceeds it.
TEST(SpeedRef, TheMaximumWinsOverAnInconsistentPair)
{
    Bench b;
    b.d->app.vl_min_rpm = 3000;
    b.d->app.vl_max_rpm = 100;
    ASSERT_FALSE(b.download(0x60FF, 0, bytes_u32(50u)).aborted());
    EXPECT_NEAR(ref_rpm(b), 100.0, 0.01);
    ASSERT_FALSE(b.download(0x6042, 0, i16(-50)).aborted());
    EXPECT_NEAR(ref_rpm(b), -100.0, 0.01);
}

// The generator keeps every speed object's range inside speed_ref_rpm's.
TEST(SpeedRef, TheGeneratorRefusesASpeedObjectWiderThanTheDeclaredRange)
{
    std::ifstream in(std::string(DTC_SOURCE_DIR) + "/tools/params/parameters.toml");
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string table = ss.str();
    std::string dir = std::string(DTC_BINARY_DIR) + "/test_speed_ref_gen";
    ASSERT_EQ(std::system(("rm -rf " + dir + " && mkdir -p " + dir).c_str()), 0);
    struct Case {
        std::string name, after, from, to, expect;
    } cases[] = {
        {"vl_max", "name = \"vl_velocity_max\"", "max = 3000", "max = 3500",
         "vl_velocity_max: its range (a magnitude up to 3500 rpm) exceeds speed_ref_rpm's -3000..3000 rpm"},
        {"target", "name = \"target_velocity\"", "min = -3000", "min = -3001",
         "target_velocity: its range (-3001..3000 rpm) exceeds speed_ref_rpm's -3000..3000 rpm"},
        {"declared", "name = \"speed_ref_rpm\"", "max = 3000.0", "max = 2000.0",
         "exceeds speed_ref_rpm's -3000..2000 rpm"},
    };
    for (const Case &c : cases) {
        SCOPED_TRACE(c.name);
        std::string t = table;
        size_t at = t.find(c.after);
        ASSERT_NE(at, std::string::npos);
        size_t v = t.find(c.from, at);
        ASSERT_NE(v, std::string::npos);
        t.replace(v, c.from.size(), c.to);
        std::string path = dir + "/" + c.name + ".toml", out = dir + "/" + c.name + ".h", err = path + ".err";
        std::ofstream(path) << t;
        int rc = std::system(("python3 " + std::string(DTC_SOURCE_DIR) + "/tools/params/gen_params.py --table " +
                              path + " --c-header " + out + " 2> " + err)
                                 .c_str());
        ASSERT_TRUE(WIFEXITED(rc));
        EXPECT_EQ(WEXITSTATUS(rc), 2);
        std::ifstream e(err);
        std::string msg((std::istreambuf_iterator<char>(e)), std::istreambuf_iterator<char>());
        EXPECT_NE(msg.find(c.expect), std::string::npos) << msg;
        EXPECT_FALSE(std::ifstream(out).good()) << "an output was written";
    }
}

// The vl limits can also change by an NMT reset node (the stored set) and by
// restoring the defaults: a bus reference follows them as it follows a write.
TEST(SpeedRef, AReferenceFollowsLimitsReloadedByAResetOrARestore)
{
    Bench b;
    ASSERT_FALSE(b.download_u32(0x6046, 2, 1000u).aborted());
    ASSERT_FALSE(b.download_u32(0x1010, 1, 0x65766173u).aborted()); // "save": vl maximum 1000 stored
    ASSERT_FALSE(b.download_u32(0x6046, 2, 3000u).aborted());
    ASSERT_FALSE(b.download(0x6042, 0, i16(2650)).aborted());
    EXPECT_NEAR(ref_rpm(b), 2650.0, 0.01);
    b.inject(frame(0x000, {0x81, kNode})); // reset node: the stored parameters again
    for (int i = 0; i < 5; i++)
        b.pass();
    EXPECT_EQ(b.read_u32(0x6046, 2), 1000u);
    EXPECT_NEAR(ref_rpm(b), 1000.0, 0.01);
    ASSERT_FALSE(b.download_u32(0x6046, 2, 3000u).aborted());
    EXPECT_NEAR(ref_rpm(b), 2650.0, 0.01);
    ASSERT_FALSE(b.download_u32(0x1011, 1, 0x64616F6Cu).aborted()); // "load": the defaults, 2610 rpm
    EXPECT_EQ(b.read_u32(0x6046, 2), 2610u);
    EXPECT_NEAR(ref_rpm(b), 2610.0, 0.01);
    EXPECT_TRUE(references_in_declared_ranges(b));
}

// 0x6048:1 shows ramp_rad_s2 (0x2000:4) in whole rpm/s: at the top of the
// ramp's range each reads inside its own declared range (a finding of
// tests/fuzz: 10000 rad/s^2 read as 95493 rpm/s above a maximum of 95492).
TEST(SpeedRef, TheRampsTopReadsInsideBothDeclaredRanges)
{
    Bench b;
    const co_param *accel = b.param("vl_acceleration_delta_speed");
    const co_param *ramp = b.param("ramp_rad_s2");
    ASSERT_FALSE(b.download_f32(0x2000, 4, ramp->max.f).aborted());
    EXPECT_EQ(b.read_u32(0x6048, 1), uint32_t(std::lround(double(ramp->max.f) * kRpmPerRadS)));
    EXPECT_LE(b.read_u32(0x6048, 1), accel->max.u);
    ASSERT_FALSE(b.download_u32(0x6048, 1, accel->max.u).aborted());
    EXPECT_LE(b.read_f32(0x2000, 4), ramp->max.f);
    EXPECT_NEAR(b.read_f32(0x2000, 4), ramp->max.f, 0.01);
    EXPECT_EQ(b.read_u32(0x6048, 1), accel->max.u);
}
