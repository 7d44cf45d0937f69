// 10,000 random and malformed CAN frames during a closed-loop run (case2)
// must leave the control metrics exactly as in the same run without them,
// and no parameter changed.
//
// Choice of frames (documented in the test name and here): anything goes,
// EXCEPT frames that are valid state-changing requests to our node, because
// those are supposed to change things:
//   - an SDO request to 0x601 of length 8 whose command is a download
//     (ccs 0 or 1) is turned into an upload request (ccs 2), so no random
//     download can ever succeed;
//   - an NMT command (id 0, length 2) with a known command for node 0 or 1
//     is re-addressed to another node;
//   - an RPDO (0x201) is cut below its mapped length (6 bytes) -- the drive
//     must ignore it (and report EMCY 0x8210).
// On top of the random frames, a share of the frames are crafted downloads
// that are well-formed but must be REFUSED: to read-only objects, with the
// wrong length, out of range, NaN, to missing objects and subindexes. The
// drive must answer every one with an abort and change nothing; the test
// also checks that no download was ever confirmed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <string>
#include <vector>

extern "C" {
#include "dtc/drive.h"
#include "dtc/drive_co.h"
#include "dtc/param_table.h"
#include "hal_host/hal_host.h"
}
#include "sim_test_util.hpp"

namespace {

constexpr uint8_t kNode = 1;
constexpr int kFrames = 10000;

using Dump = std::vector<std::pair<std::string, uint32_t>>;

// Every parameter (writable entries and the configuration) as a bus value.
Dump dump(drive *d)
{
    Dump out;
    for (uint32_t i = 0; i < CO_PARAM_COUNT; i++) {
        const co_param *p = &co_params[i];
        if (co_dtype_size(p->dtype) == 0 || !((p->flags & CO_F_WRITE) != 0 || p->bind == DRIVE_BIND_CFG))
            continue;
        if (p->bind == DRIVE_BIND_FN && (p->flags & CO_F_PERSIST) == 0 && p->index != 0x2000 && p->index != 0x60FF)
            continue; // commands (store, restore, controlword, scope command) read constants
        if (p->bind == CO_BIND_ERRHIST)
            continue; // the error history 0x1003 records the fuzz's EMCYs (short RPDOs): diagnostics, not a parameter
        co_num v;
        v.u = 0;
        co_od_read_num(&d->co, p, &v);
        out.emplace_back(p->name, v.u);
    }
    return out;
}

struct FuzzRun {
    bool fuzz = false;
    std::mt19937 rng{12345};
    hal_host_can_loopback loop{};
    hal_host_can_backend backend{};
    long tick = 0;
    long injected = 0, refused_inject = 0;
    long crafted = 0;
    std::map<uint32_t, long> aborts;    // abort code -> count
    long download_confirms = 0;         // download responses (must stay 0 after the preamble)
    long sdo_responses = 0, tpdos = 0, emcys = 0;
    bool preamble_done = false;
    Dump end_dump;
    uint32_t end_run = 0;
};

uint32_t rnd(FuzzRun &r, uint32_t n) { return std::uniform_int_distribution<uint32_t>(0, n - 1)(r.rng); }

hal_can_frame random_frame(FuzzRun &r)
{
    hal_can_frame f;
    std::memset(&f, 0, sizeof f);
    uint32_t kind = rnd(r, 100);
    if (kind < 40)
        f.id = uint16_t(rnd(r, 0x800));
    else if (kind < 75)
        f.id = 0x600 + kNode;
    else if (kind < 82)
        f.id = 0x000;
    else if (kind < 92)
        f.id = 0x200 + kNode;
    else
        f.id = uint16_t(0x600 + rnd(r, 128)); // SDO requests to any node
    f.dlc = uint8_t(rnd(r, 100) < 70 && f.id == 0x600 + kNode ? 8 : rnd(r, 9));
    f.rtr = rnd(r, 20) == 0;
    for (auto &b : f.data)
        b = uint8_t(rnd(r, 256));
    if (f.id == 0x000 && rnd(r, 2) == 0) { // plausible NMT commands
        const uint8_t cmds[] = {0x01, 0x02, 0x80, 0x81, 0x82};
        f.data[0] = cmds[rnd(r, 5)];
        f.data[1] = uint8_t(rnd(r, 3));
    }
    // Mask the valid state-changing requests to our node (see the file comment).
    if (f.id == 0x600 + kNode && f.dlc == 8 && !f.rtr && (f.data[0] >> 5) <= 1)
        f.data[0] = uint8_t((f.data[0] & 0x1F) | (2 << 5));
    if (f.id == 0x000 && f.dlc == 2 && !f.rtr && (f.data[1] == 0 || f.data[1] == kNode)) {
        uint8_t c = f.data[0];
        if (c == 0x01 || c == 0x02 || c == 0x80 || c == 0x81 || c == 0x82)
            f.data[1] = uint8_t(2 + rnd(r, 126));
    }
    if (f.id == 0x200 + kNode && f.dlc >= 6)
        f.dlc = uint8_t(rnd(r, 6));
    return f;
}

// A well-formed expedited download the drive must refuse.
hal_can_frame crafted_bad_download(FuzzRun &r)
{
    hal_can_frame f;
    std::memset(&f, 0, sizeof f);
    f.id = 0x600 + kNode;
    f.dlc = 8;
    for (int guard = 0; guard < 1000; guard++) {
        const co_param *p = &co_params[rnd(r, CO_PARAM_COUNT)];
        size_t size = co_dtype_size(p->dtype);
        uint16_t index = p->index;
        uint8_t sub = p->sub;
        uint32_t value = r.rng();
        size_t len = size == 0 ? 4 : size;
        switch (rnd(r, 6)) {
        case 0: // read-only object, right length
            if (p->flags & CO_F_WRITE)
                continue;
            break;
        case 1: // wrong length
            if (size == 0)
                continue;
            do
                len = 1 + rnd(r, 4);
            while (len == size);
            break;
        case 2: { // out of range
            if (!(p->flags & CO_F_LIMITS) || !(p->flags & CO_F_WRITE))
                continue;
            bool high = rnd(r, 2) == 0;
            if (p->dtype == CO_DT_REAL32) {
                float x = high ? p->max.f + 1.0f + std::fabs(p->max.f) * 0.5f : p->min.f - 1.0f - std::fabs(p->min.f) * 0.5f;
                std::memcpy(&value, &x, 4);
            } else if (p->dtype == CO_DT_INTEGER32 || p->dtype == CO_DT_INTEGER16 || p->dtype == CO_DT_INTEGER8) {
                value = uint32_t(high ? p->max.i + 1 : p->min.i - 1);
            } else {
                if (high && p->max.u < (size == 1 ? 0xFFu : size == 2 ? 0xFFFFu : 0xFFFFFFFFu))
                    value = p->max.u + 1;
                else if (!high && p->min.u > 0)
                    value = p->min.u - 1;
                else
                    continue;
            }
            break;
        }
        case 3: { // NaN or infinity
            if (p->dtype != CO_DT_REAL32 || !(p->flags & CO_F_WRITE))
                continue;
            float x = rnd(r, 2) ? std::nanf("") : -INFINITY;
            std::memcpy(&value, &x, 4);
            break;
        }
        case 4: // subindex that does not exist
            sub = 0xFE;
            break;
        default: // object that does not exist
            index = uint16_t(0x4000 + rnd(r, 0x1000));
            break;
        }
        f.data[0] = uint8_t(0x23 | ((4 - len) << 2));
        f.data[1] = uint8_t(index);
        f.data[2] = uint8_t(index >> 8);
        f.data[3] = sub;
        for (size_t i = 0; i < 4; i++)
            f.data[4 + i] = uint8_t(value >> (8 * i));
        r.crafted++;
        return f;
    }
    return f;
}

void on_tick(void *user, double t_s, drive *d)
{
    FuzzRun &r = *static_cast<FuzzRun *>(user);
    (void)t_s;
    // The same valid preamble in both runs: operational, telemetry at 1 kHz.
    if (r.tick == 0) {
        hal_can_frame f;
        std::memset(&f, 0, sizeof f);
        f.id = 0x000;
        f.dlc = 2;
        f.data[0] = 0x01;
        f.data[1] = kNode;
        hal_host_can_loopback_inject(&r.loop, &f);
        f.id = 0x600 + kNode;
        f.dlc = 8;
        const uint8_t req[8] = {0x2B, 0x00, 0x25, 0x03, 0xE8, 0x03, 0, 0};
        std::memcpy(f.data, req, 8);
        hal_host_can_loopback_inject(&r.loop, &f);
    } else if (r.tick == 2) {
        r.preamble_done = true;
    }
    // Two frames every fifth tick: 10,000 frames over the 25,000 ticks of case2.
    if (r.fuzz && r.tick >= 2 && r.tick % 5 == 0 && r.injected < kFrames) {
        for (int i = 0; i < 2; i++) {
            hal_can_frame f = rnd(r, 100) < 20 ? crafted_bad_download(r) : random_frame(r);
            if (hal_host_can_loopback_inject(&r.loop, &f) == HAL_OK)
                r.injected++;
            else
                r.refused_inject++;
        }
    }
    hal_can_frame f;
    while (hal_host_can_loopback_take(&r.loop, &f) == HAL_OK) {
        if (f.id == 0x580 + kNode) {
            r.sdo_responses++;
            uint8_t scs = f.data[0] >> 5;
            if (f.data[0] == 0x80)
                r.aborts[uint32_t(f.data[4]) | (uint32_t(f.data[5]) << 8) | (uint32_t(f.data[6]) << 16) |
                         (uint32_t(f.data[7]) << 24)]++;
            else if (r.preamble_done && (scs == 3 || scs == 1))
                r.download_confirms++;
        } else if (f.id == 0x181 || f.id == 0x281 || f.id == 0x381) {
            r.tpdos++;
        } else if (f.id == 0x081) {
            r.emcys++;
        }
    }
    r.tick++;
    r.end_dump = dump(d);
    r.end_run = d->run ? 1u : 0u;
}

sim_result run_case2(FuzzRun &r)
{
    auto l = simtest::load_scenario(std::string(DTC_SOURCE_DIR) + "/host_sim/scenarios/case2.ini");
    EXPECT_EQ(l.rc, 0) << l.error;
    hal_host_can_loopback_init(&r.loop, &r.backend);
    sim_options o;
    sim_options_default(&o);
    o.can = &r.backend;
    o.on_tick = on_tick;
    o.user = &r;
    sim_result res;
    std::memset(&res, 0, sizeof res);
    sim_run(l.sc.get(), &o, &res);
    return res;
}

TEST(CanFuzz, TenThousandMalformedFramesChangeNeitherControlNorParameters)
{
    FuzzRun clean, fuzzed;
    fuzzed.fuzz = true;
    sim_result a = run_case2(clean);
    sim_result b = run_case2(fuzzed);
    ASSERT_EQ(a.status, SIM_OK) << a.error;
    ASSERT_EQ(b.status, SIM_OK) << b.error;
    EXPECT_EQ(fuzzed.injected, kFrames);
    EXPECT_EQ(fuzzed.refused_inject, 0);

    // Control: bit-for-bit the same run.
    const sim_metrics &ma = a.metrics, &mb = b.metrics;
    EXPECT_EQ(a.ticks, b.ticks);
    EXPECT_EQ(ma.speed_final_rpm, mb.speed_final_rpm);
    EXPECT_EQ(ma.te_final_nm, mb.te_final_nm);
    EXPECT_EQ(ma.is_rms_final_a, mb.is_rms_final_a);
    EXPECT_EQ(ma.steady_error_rpm, mb.steady_error_rpm);
    EXPECT_EQ(ma.speed_est_error_rpm, mb.speed_est_error_rpm);
    EXPECT_EQ(ma.recovery_time_s, mb.recovery_time_s);
    EXPECT_EQ(ma.max_dip_rpm, mb.max_dip_rpm);
    EXPECT_EQ(ma.eps_hat_final, mb.eps_hat_final);
    EXPECT_EQ(ma.np_dev_max_v, mb.np_dev_max_v);
    EXPECT_EQ(ma.switching_freq_hz, mb.switching_freq_hz);
    EXPECT_EQ(ma.w_norm_max, mb.w_norm_max);
    EXPECT_EQ(ma.faults, mb.faults);
    EXPECT_EQ(fuzzed.end_run, 1u);

    // Parameters: all the same, and no download was ever confirmed.
    ASSERT_EQ(clean.end_dump.size(), fuzzed.end_dump.size());
    for (size_t i = 0; i < clean.end_dump.size(); i++)
        EXPECT_EQ(clean.end_dump[i].second, fuzzed.end_dump[i].second) << clean.end_dump[i].first;
    EXPECT_EQ(fuzzed.download_confirms, 0);

    // The fuzz reached the refusal paths, and the device kept working.
    EXPECT_GT(fuzzed.crafted, 1000);
    for (uint32_t code : {0x06020000u, 0x06090011u, 0x06010002u, 0x06070010u, 0x06090031u, 0x06090032u,
                          0x06090030u, 0x05040001u})
        EXPECT_GT(fuzzed.aborts[code], 0) << std::hex << code;
    EXPECT_GT(fuzzed.emcys, 0); // short RPDOs are reported
    EXPECT_NEAR(double(fuzzed.tpdos), double(clean.tpdos), 0.01 * double(clean.tpdos));
    EXPECT_GT(clean.tpdos, 3 * 4900); // 1 kHz x 3 TPDOs for ~5 s
    long total_aborts = 0;
    for (const auto &kv : fuzzed.aborts)
        total_aborts += kv.second;
    std::printf("case2 with %ld frames (%ld crafted bad downloads): %ld SDO responses, %ld aborts, "
                "%ld EMCY, %ld TPDO frames; speed_final %.3f rpm, steady error %.4f rpm, recovery %.4f s "
                "(identical to the run without frames)\n",
                fuzzed.injected, fuzzed.crafted, fuzzed.sdo_responses, total_aborts, fuzzed.emcys, fuzzed.tpdos,
                mb.speed_final_rpm, mb.steady_error_rpm, mb.recovery_time_s);
    for (const auto &kv : fuzzed.aborts)
        std::printf("  abort 0x%08X: %ld\n", kv.first, kv.second);
}

} // namespace
