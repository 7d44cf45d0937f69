// dtc-sim's tick recording (--record-samples, recording/tick_record.h): what the PIL bench and the
// equivalence tests replay. The file is read here byte by byte at the offsets the format states
// and compared with what the drive held at each tick (seen through the engine's on_tick hook),
// not with the recorder's own encoder.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "dtc/drive.h"
#include "sim_test_util.hpp"

namespace {

constexpr size_t kHeader = 96, kRecord = 124; // docs: recording/tick_record.h

struct Seen {
    std::vector<ctl_out> out;
    std::vector<float> psi_r_alpha;
    std::vector<bool> run;
};

void grab(void *user, double, struct drive *d)
{
    auto *s = static_cast<Seen *>(user);
    s->out.push_back(d->out);
    s->psi_r_alpha.push_back(d->ctl.obs.psi_r_Wb[0]);
    s->run.push_back(d->run);
}

uint32_t u32_at(const std::string &b, size_t at)
{
    uint32_t v = 0;
    for (int i = 3; i >= 0; --i)
        v = (v << 8) | static_cast<uint8_t>(b[at + static_cast<size_t>(i)]);
    return v;
}

float f32_at(const std::string &b, size_t at)
{
    uint32_t v = u32_at(b, at);
    float f;
    std::memcpy(&f, &v, sizeof f);
    return f;
}

uint32_t bits(float f)
{
    uint32_t v;
    std::memcpy(&v, &f, sizeof v);
    return v;
}

} // namespace

TEST(TickRecord, EveryTickInputsAndOutputsAtTheStatedOffsets)
{
    simtest::TempDir d;
    auto l = simtest::load_scenario(simtest::source_path("host_sim/scenarios/case2.ini"), {"sim.duration_s=0.4"});
    ASSERT_EQ(l.rc, 0) << l.error;
    std::string rec = d.file("c.rec");
    Seen seen;
    sim_options o;
    sim_options_default(&o);
    o.record_path = rec.c_str();
    o.on_tick = grab;
    o.user = &seen;
    o.start_delay_s = 0.1;
    sim_result res;
    ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    ASSERT_FALSE(simtest::file_exists(rec + ".partial"));

    std::string b = simtest::read_file(rec);
    ASSERT_GE(b.size(), kHeader);
    EXPECT_EQ(b.substr(0, 8), "DTCTREC1");
    EXPECT_EQ(u32_at(b, 8), 1u);
    EXPECT_EQ(u32_at(b, 12), kHeader);
    EXPECT_EQ(u32_at(b, 16), kRecord);
    EXPECT_EQ(u32_at(b, 24), 2u);   // case2.ini: rbfn
    EXPECT_EQ(u32_at(b, 28), 200u); // period, us
    size_t cfg_words = u32_at(b, 20);
    size_t body = kHeader + 4 * cfg_words;
    ASSERT_EQ(res.ticks, 2001u);
    ASSERT_EQ(b.size(), body + res.ticks * kRecord);
    ASSERT_EQ(seen.out.size(), res.ticks);
    // The first configuration words: the scenario motor's Rs and the period.
    EXPECT_EQ(bits(f32_at(b, kHeader)), bits(static_cast<float>(l.sc->plant.motor.Rs_ohm)));
    EXPECT_FLOAT_EQ(f32_at(b, kHeader + 8 * 4), 200e-6f);

    int stopped = 0;
    for (size_t k = 0; k < res.ticks; ++k) {
        size_t r = body + k * kRecord;
        ASSERT_EQ(u32_at(b, r), k);
        uint32_t flags = u32_at(b, r + 4);
        EXPECT_EQ((flags >> 4) & 1u, seen.run[k] ? 1u : 0u) << k; // run, as the interrupt found it
        EXPECT_EQ(u32_at(b, r + 32), k + 1u) << k;                  // sample seq
        const ctl_out &o_k = seen.out[k];
        for (size_t v = 0; v < 2; ++v)
            for (size_t leg = 0; leg < 3; ++leg)
                ASSERT_EQ(static_cast<uint8_t>(b[r + 44 + 3 * v + leg]), o_k.act.vector[v].leg[leg]) << k;
        ASSERT_EQ(static_cast<uint8_t>(b[r + 51]), o_k.tel.state) << k;
        ASSERT_EQ(u32_at(b, r + 56), o_k.tel.faults) << k;
        ASSERT_EQ(u32_at(b, r + 60), bits(o_k.act.duty0)) << k;
        ASSERT_EQ(u32_at(b, r + 64), bits(o_k.tel.te_ref_Nm)) << k;
        ASSERT_EQ(u32_at(b, r + 80), bits(o_k.tel.omega_est_rad_s)) << k;
        ASSERT_EQ(u32_at(b, r + 96), bits(seen.psi_r_alpha[k])) << k;
        stopped += o_k.tel.state == CTL_STOPPED;
    }
    // --start-delay 0.1: the first 500 ticks run without the run command: stopped.
    EXPECT_EQ(stopped, 500);
    EXPECT_FALSE(seen.run[499]);
    EXPECT_TRUE(seen.run[500]);
}

TEST(TickRecord, BadOptionsAreInputErrorsAndLeaveNothing)
{
    simtest::TempDir d;
    auto l = simtest::load_scenario(simtest::source_path("host_sim/scenarios/case2.ini"), {"sim.duration_s=0.01"});
    ASSERT_EQ(l.rc, 0) << l.error;
    sim_options o;
    sim_options_default(&o);
    std::string bad = d.file("no/such/dir/x.rec");
    o.record_path = bad.c_str();
    sim_result res;
    EXPECT_EQ(sim_run(l.sc.get(), &o, &res), SIM_EINPUT);
    EXPECT_NE(std::string(res.error).find("cannot create"), std::string::npos) << res.error;

    sim_options_default(&o);
    o.start_delay_s = -1.0;
    EXPECT_EQ(sim_run(l.sc.get(), &o, &res), SIM_EINPUT);
    EXPECT_NE(std::string(res.error).find("start delay"), std::string::npos) << res.error;

    // Sine supply: no firmware, nothing to record.
    auto s = simtest::parse_text("[sim]\nduration_s = 0.01\n[supply]\nmode = sine\n");
    ASSERT_EQ(s.rc, 0) << s.error;
    sim_options_default(&o);
    std::string rec = d.file("s.rec");
    o.record_path = rec.c_str();
    EXPECT_EQ(sim_run(s.sc.get(), &o, &res), SIM_EINPUT);
    EXPECT_FALSE(simtest::file_exists(rec));
    EXPECT_FALSE(simtest::file_exists(rec + ".partial"));
}
