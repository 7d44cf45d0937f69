// The recording library alone (recording/: the recorded-tick format and the [control] key
// registry), linked without the SIL, the plant or the drive. The expected bytes are the offsets
// the format states in recording/tick_record.h (and tests/pil/test_pil_equiv.py reads), written
// out here by hand, not produced by the library's own encoder.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "recording/control_keys.h"
#include "recording/tick_record.h"

namespace {

uint32_t u32_at(const std::vector<uint8_t> &b, size_t at)
{
    return static_cast<uint32_t>(b[at]) | (static_cast<uint32_t>(b[at + 1]) << 8) |
           (static_cast<uint32_t>(b[at + 2]) << 16) | (static_cast<uint32_t>(b[at + 3]) << 24);
}

uint32_t bits(float f)
{
    uint32_t v;
    std::memcpy(&v, &f, sizeof v);
    return v;
}

float next_up(float f)
{
    uint32_t v = bits(f) + 1u;
    std::memcpy(&f, &v, sizeof f);
    return f;
}

tick_rec_header valid_header()
{
    tick_rec_header h;
    std::memset(&h, 0, sizeof h);
    h.version = 1;
    h.header_bytes = 96;
    h.record_bytes = 124;
    h.cfg_words = tick_rec_cfg_words();
    h.speed_mode = 2;
    h.period_us = 200;
    std::strcpy(h.name, "case2.ini");
    return h;
}

// Every field a different value, so a field written at another's offset shows.
tick_rec full_record()
{
    tick_rec r;
    std::memset(&r, 0, sizeof r);
    r.tick = 0x01020304u;
    r.flags = TICK_REC_SAMPLE_NEW | TICK_REC_SPEED_VALID | TICK_REC_RUN;
    r.sample = {1.5f, -2.25f, 0.75f, 280.0f, 281.5f, 150.0f, true, 77u};
    r.speed_ref_rad_s = 157.0f;
    r.qs_decel_rad_s2 = 300.0f;
    r.act.vector[0] = {{HAL_LEG_P, HAL_LEG_O, HAL_LEG_N}};
    r.act.vector[1] = {{HAL_LEG_O, HAL_LEG_P, HAL_LEG_P}};
    r.act.duty0 = 0.625f;
    r.gate_enable = 1;
    r.state = 3;
    r.vector_index = 19;
    r.faults = 0x00010020u;
    r.te_ref_Nm = 10.5f;
    r.te_est_Nm = 10.25f;
    r.psi_s_est_Wb = 0.71f;
    r.psi_ref_Wb = 0.72f;
    r.omega_est_rad_s = 156.5f;
    r.speed_ref_out_rad_s = 156.75f;
    r.eps_hat = -0.125f;
    r.w_norm = 3.5f;
    r.psi_r_Wb[0] = 0.61f;
    r.psi_r_Wb[1] = -0.62f;
    r.is_hat_A[0] = 4.5f;
    r.is_hat_A[1] = -4.75f;
    r.omega_e_rad_s = 310.0f;
    r.omega_int_rad_s = 311.0f;
    r.rs_ohm = 1.405f;
    return r;
}

} // namespace

TEST(RecordingFormat, HeaderAtTheStatedOffsets)
{
    tick_rec_header h = valid_header();
    std::vector<uint8_t> b(96, 0xAA);
    tick_rec_encode_header(&h, b.data());
    EXPECT_EQ(std::string(b.begin(), b.begin() + 8), "DTCTREC1");
    EXPECT_EQ(u32_at(b, 8), 1u);
    EXPECT_EQ(u32_at(b, 12), 96u);
    EXPECT_EQ(u32_at(b, 16), 124u);
    EXPECT_EQ(u32_at(b, 20), tick_rec_cfg_words());
    EXPECT_EQ(u32_at(b, 24), 2u);
    EXPECT_EQ(u32_at(b, 28), 200u);
    EXPECT_EQ(u32_at(b, 32), 0u);
    EXPECT_EQ(std::string(reinterpret_cast<const char *>(&b[36])), "case2.ini");
    for (size_t i = 36 + 9; i < 96; ++i)
        ASSERT_EQ(b[i], 0u) << "name padding at " << i;

    tick_rec_header back;
    const char *why = nullptr;
    ASSERT_EQ(tick_rec_decode_header(b.data(), &back, &why), 0) << why;
    EXPECT_EQ(back.cfg_words, h.cfg_words);
    EXPECT_EQ(back.speed_mode, 2u);
    EXPECT_EQ(back.period_us, 200u);
    EXPECT_STREQ(back.name, "case2.ini");
}

TEST(RecordingFormat, LongNameIsCutToItsField)
{
    tick_rec_header h = valid_header();
    std::string long_name(70, 'n');
    std::strcpy(h.name, long_name.substr(0, 60).c_str());
    std::vector<uint8_t> b(96, 0);
    tick_rec_encode_header(&h, b.data());
    tick_rec_header back;
    const char *why = nullptr;
    ASSERT_EQ(tick_rec_decode_header(b.data(), &back, &why), 0) << why;
    EXPECT_EQ(std::string(back.name), long_name.substr(0, 60));
}

TEST(RecordingFormat, BadHeadersAreRefusedWithAReason)
{
    struct Case {
        size_t at;
        uint32_t value;
        const char *why;
    };
    const Case cases[] = {
        {8, 2u, "version"},
        {12, 100u, "size"},
        {16, 120u, "size"},
        {20, tick_rec_cfg_words() + 1u, "configuration word count"},
        {24, 3u, "speed mode"},
        {28, 49u, "period"},
        {28, 1001u, "period"},
    };
    tick_rec_header h = valid_header();
    for (const Case &c : cases) {
        std::vector<uint8_t> b(96, 0);
        tick_rec_encode_header(&h, b.data());
        for (size_t i = 0; i < 4; ++i)
            b[c.at + i] = static_cast<uint8_t>(c.value >> (8 * i));
        tick_rec_header back;
        const char *why = nullptr;
        EXPECT_EQ(tick_rec_decode_header(b.data(), &back, &why), -1) << c.at << " = " << c.value;
        ASSERT_NE(why, nullptr);
        EXPECT_NE(std::string(why).find(c.why), std::string::npos) << why;
    }
    std::vector<uint8_t> b(96, 0);
    tick_rec_encode_header(&h, b.data());
    b[7] = '2';
    tick_rec_header back;
    const char *why = nullptr;
    EXPECT_EQ(tick_rec_decode_header(b.data(), &back, &why), -1);
    ASSERT_NE(why, nullptr);
    EXPECT_NE(std::string(why).find("magic"), std::string::npos) << why;
}

TEST(RecordingFormat, RecordAtTheStatedOffsets)
{
    const tick_rec r = full_record();
    std::vector<uint8_t> b(124, 0xAA);
    tick_rec_encode(&r, b.data());
    EXPECT_EQ(u32_at(b, 0), 0x01020304u);
    EXPECT_EQ(u32_at(b, 4), r.flags);
    EXPECT_EQ(u32_at(b, 8), bits(1.5f));
    EXPECT_EQ(u32_at(b, 12), bits(-2.25f));
    EXPECT_EQ(u32_at(b, 16), bits(0.75f));
    EXPECT_EQ(u32_at(b, 20), bits(280.0f));
    EXPECT_EQ(u32_at(b, 24), bits(281.5f));
    EXPECT_EQ(u32_at(b, 28), bits(150.0f));
    EXPECT_EQ(u32_at(b, 32), 77u);
    EXPECT_EQ(u32_at(b, 36), bits(157.0f));
    EXPECT_EQ(u32_at(b, 40), bits(300.0f));
    const uint8_t legs[6] = {HAL_LEG_P, HAL_LEG_O, HAL_LEG_N, HAL_LEG_O, HAL_LEG_P, HAL_LEG_P};
    for (size_t i = 0; i < 6; ++i)
        EXPECT_EQ(b[44 + i], legs[i]) << i;
    EXPECT_EQ(b[50], 1u);  // gate enable
    EXPECT_EQ(b[51], 3u);  // run state
    EXPECT_EQ(b[52], 19u); // vector index
    EXPECT_EQ(b[53], 0u);
    EXPECT_EQ(b[54], 0u);
    EXPECT_EQ(b[55], 0u);
    EXPECT_EQ(u32_at(b, 56), 0x00010020u);
    const float floats[] = {0.625f, 10.5f, 10.25f, 0.71f, 0.72f, 156.5f, 156.75f, -0.125f,
                            3.5f,   0.61f, -0.62f, 4.5f,  -4.75f, 310.0f, 311.0f, 1.405f};
    for (size_t i = 0; i < sizeof floats / sizeof floats[0]; ++i)
        EXPECT_EQ(u32_at(b, 60 + 4 * i), bits(floats[i])) << "offset " << 60 + 4 * i;
    EXPECT_EQ(60 + 4 * (sizeof floats / sizeof floats[0]), 124u);
}

TEST(RecordingFormat, RecordDecodesToWhatWasEncoded)
{
    const tick_rec r = full_record();
    std::vector<uint8_t> b(124, 0);
    tick_rec_encode(&r, b.data());
    tick_rec back;
    std::memset(&back, 0x55, sizeof back);
    tick_rec_decode(b.data(), &back);
    EXPECT_EQ(back.tick, r.tick);
    EXPECT_EQ(back.flags, r.flags);
    EXPECT_EQ(bits(back.sample.ib_A), bits(r.sample.ib_A));
    EXPECT_EQ(back.sample.seq, 77u);
    EXPECT_TRUE(back.sample.speed_meas_valid); // from TICK_REC_SPEED_VALID
    EXPECT_EQ(bits(back.qs_decel_rad_s2), bits(r.qs_decel_rad_s2));
    EXPECT_EQ(tick_rec_diff(&back, &r), nullptr);

    tick_rec no_speed = r;
    no_speed.flags &= ~TICK_REC_SPEED_VALID;
    tick_rec_encode(&no_speed, b.data());
    tick_rec_decode(b.data(), &back);
    EXPECT_FALSE(back.sample.speed_meas_valid);
}

TEST(RecordingFormat, DiffNamesTheFirstDifferingOutput)
{
    const tick_rec want = full_record();
    EXPECT_EQ(tick_rec_diff(&want, &want), nullptr);

    // The inputs are not compared: they are what the replay fed in.
    tick_rec got = want;
    got.sample.ia_A = next_up(got.sample.ia_A);
    got.flags ^= TICK_REC_RUN;
    EXPECT_EQ(tick_rec_diff(&got, &want), nullptr);

    struct Case {
        void (*change)(tick_rec &);
        const char *name;
    };
    const Case cases[] = {
        {[](tick_rec &x) { x.act.vector[0].leg[2] = HAL_LEG_O; }, "act.vector[0]"},
        {[](tick_rec &x) { x.act.vector[1].leg[0] = HAL_LEG_N; }, "act.vector[1]"},
        {[](tick_rec &x) { x.act.duty0 = next_up(x.act.duty0); }, "duty0"},
        {[](tick_rec &x) { x.gate_enable = 0; }, "gate_enable"},
        {[](tick_rec &x) { x.state = 1; }, "run state"},
        {[](tick_rec &x) { x.vector_index = 20; }, "vector_index"},
        {[](tick_rec &x) { x.faults = 0; }, "faults"},
        {[](tick_rec &x) { x.te_ref_Nm = next_up(x.te_ref_Nm); }, "te_ref_Nm"},
        {[](tick_rec &x) { x.te_est_Nm = next_up(x.te_est_Nm); }, "te_est_Nm"},
        {[](tick_rec &x) { x.psi_s_est_Wb = next_up(x.psi_s_est_Wb); }, "psi_s_est_Wb"},
        {[](tick_rec &x) { x.psi_ref_Wb = next_up(x.psi_ref_Wb); }, "psi_ref_Wb"},
        {[](tick_rec &x) { x.omega_est_rad_s = next_up(x.omega_est_rad_s); }, "omega_est_rad_s"},
        {[](tick_rec &x) { x.speed_ref_out_rad_s = next_up(x.speed_ref_out_rad_s); }, "speed_ref_rad_s"},
        {[](tick_rec &x) { x.eps_hat = next_up(x.eps_hat); }, "eps_hat"},
        {[](tick_rec &x) { x.w_norm = next_up(x.w_norm); }, "w_norm"},
        {[](tick_rec &x) { x.psi_r_Wb[0] = next_up(x.psi_r_Wb[0]); }, "psi_r_Wb[0]"},
        {[](tick_rec &x) { x.psi_r_Wb[1] = next_up(x.psi_r_Wb[1]); }, "psi_r_Wb[1]"},
        {[](tick_rec &x) { x.is_hat_A[0] = next_up(x.is_hat_A[0]); }, "is_A[0]"},
        {[](tick_rec &x) { x.is_hat_A[1] = next_up(x.is_hat_A[1]); }, "is_A[1]"},
        {[](tick_rec &x) { x.omega_e_rad_s = next_up(x.omega_e_rad_s); }, "omega_e_rad_s"},
        {[](tick_rec &x) { x.omega_int_rad_s = next_up(x.omega_int_rad_s); }, "omega_int_rad_s"},
        {[](tick_rec &x) { x.rs_ohm = next_up(x.rs_ohm); }, "rs_ohm"},
    };
    for (const Case &c : cases) {
        got = want;
        c.change(got);
        const char *d = tick_rec_diff(&got, &want);
        ASSERT_NE(d, nullptr) << c.name;
        EXPECT_NE(std::string(d).find(c.name), std::string::npos) << c.name << " -> " << d;
    }
}

TEST(RecordingFormat, OutputsAreTakenFromTheInterruptAndTheObserver)
{
    ctl_out out;
    std::memset(&out, 0, sizeof out);
    observer obs;
    std::memset(&obs, 0, sizeof obs);
    out.act.vector[0] = {{HAL_LEG_N, HAL_LEG_N, HAL_LEG_P}};
    out.act.duty0 = 0.25f;
    out.gate_enable = true;
    out.tel.faults = 0x40u;
    out.tel.te_ref_Nm = 7.0f;
    out.tel.speed_ref_rad_s = 99.0f;
    obs.psi_r_Wb[1] = 0.5f;
    obs.is_A[0] = -3.0f;
    obs.rs_ohm = 1.25f;
    tick_rec r;
    std::memset(&r, 0, sizeof r);
    r.tick = 5;
    tick_rec_set_outputs(&r, &out, &obs);
    EXPECT_EQ(r.tick, 5u); // the inputs stay
    EXPECT_EQ(r.act.vector[0].leg[2], HAL_LEG_P);
    EXPECT_EQ(r.act.duty0, 0.25f);
    EXPECT_EQ(r.gate_enable, 1u);
    EXPECT_EQ(r.faults, 0x40u);
    EXPECT_EQ(r.te_ref_Nm, 7.0f);
    EXPECT_EQ(r.speed_ref_out_rad_s, 99.0f);
    EXPECT_EQ(r.psi_r_Wb[1], 0.5f);
    EXPECT_EQ(r.is_hat_A[0], -3.0f);
    EXPECT_EQ(r.rs_ohm, 1.25f);
}

TEST(RecordingControlKeys, RegistryNamesFieldsOfCtlCfg)
{
    size_t n = 0;
    const control_key *k = control_keys(&n);
    ASSERT_GT(n, 10u);
    std::set<std::string> names;
    for (size_t i = 0; i < n; ++i) {
        EXPECT_TRUE(names.insert(k[i].name).second) << "duplicate " << k[i].name;
        size_t width = k[i].type == CONTROL_KEY_BOOL ? sizeof(bool) : 4u;
        EXPECT_LE(k[i].offset + width, sizeof(ctl_cfg)) << k[i].name;
        EXPECT_EQ(control_key_find(k[i].name), static_cast<int>(i));
    }
    EXPECT_EQ(control_key_find("no_such_key"), -1);
    EXPECT_EQ(control_key_find(""), -1);
    // Spot checks against the ctl_cfg layout, written by hand.
    struct Spot {
        const char *name;
        size_t offset;
        control_key_type type;
    };
    const Spot spots[] = {
        {"te_max_Nm", offsetof(ctl_cfg, speed.te_max_Nm), CONTROL_KEY_REAL},
        {"ip_zeta", offsetof(ctl_cfg, speed.ip.zeta), CONTROL_KEY_REAL},
        {"rbfn_n_nodes", offsetof(ctl_cfg, speed.rbfn.n_nodes), CONTROL_KEY_U32},
        {"rbfn_width_8_rad_s", offsetof(ctl_cfg, speed.rbfn.width) + 8 * sizeof(float), CONTROL_KEY_REAL},
        {"ripple_reduction", offsetof(ctl_cfg, dtc.ripple_reduction), CONTROL_KEY_BOOL},
        {"bringup_level", offsetof(ctl_cfg, bringup_level), CONTROL_KEY_U32},
        {"bringup_te_Nm", offsetof(ctl_cfg, bringup_te_Nm), CONTROL_KEY_REAL},
        {"speed_dev_time_s", offsetof(ctl_cfg, speed_dev_time_s), CONTROL_KEY_REAL},
    };
    for (const Spot &s : spots) {
        int i = control_key_find(s.name);
        ASSERT_GE(i, 0) << s.name;
        EXPECT_EQ(k[i].offset, s.offset) << s.name;
        EXPECT_EQ(k[i].type, s.type) << s.name;
    }
    // The first and last keys of the list fix the order a recording's words follow.
    EXPECT_STREQ(k[0].name, "te_max_Nm");
    EXPECT_STREQ(k[n - 1].name, "speed_dev_time_s");
}

TEST(RecordingControlKeys, ConfigurationWordsFollowTheRegistry)
{
    size_t n = 0;
    const control_key *k = control_keys(&n);
    ASSERT_EQ(tick_rec_cfg_words(), 11u + n);

    ctl_cfg cfg;
    ctl_cfg_default(&cfg);
    cfg.motor.Rs_ohm = 1.5f;
    cfg.motor.B_Nms = 0.002f;
    cfg.period_s = 250e-6f;
    cfg.vdc_nom_V = 540.0f;
    cfg.speed.mode = SPEED_MODE_NOMINAL;
    cfg.speed.ip.zeta = 0.9f;
    cfg.speed.rbfn.n_nodes = 5u;
    cfg.dtc.ripple_reduction = true;
    std::vector<uint32_t> w(tick_rec_cfg_words(), 0xDEADBEEFu);
    tick_rec_cfg_encode(&cfg, w.data());
    EXPECT_EQ(w[0], bits(1.5f));    // motor.Rs_ohm first
    EXPECT_EQ(w[7], bits(0.002f));  // motor.B_Nms last of the motor's eight
    EXPECT_EQ(w[8], bits(250e-6f)); // period_s
    EXPECT_EQ(w[9], bits(540.0f));  // vdc_nom_V
    EXPECT_EQ(w[10], 1u);           // speed.mode
    EXPECT_EQ(w[11 + control_key_find("ip_zeta")], bits(0.9f));
    EXPECT_EQ(w[11 + control_key_find("rbfn_n_nodes")], 5u);
    EXPECT_EQ(w[11 + control_key_find("ripple_reduction")], 1u);
    cfg.dtc.ripple_reduction = false;
    tick_rec_cfg_encode(&cfg, w.data());
    EXPECT_EQ(w[11 + control_key_find("ripple_reduction")], 0u);
    for (size_t i = 0; i < w.size(); ++i)
        EXPECT_NE(w[i], 0xDEADBEEFu) << "word " << i << " not written";

    // Applied to a blank configuration: the settable fields come back, nothing else is written
    // (the derived fields are the reader's ctl_cfg_derive's).
    ctl_cfg back;
    std::memset(&back, 0x5A, sizeof back);
    tick_rec_cfg_apply(&back, w.data());
    std::vector<bool> settable(sizeof(ctl_cfg), false);
    auto mark = [&](size_t off, size_t width) {
        for (size_t i = off; i < off + width; ++i)
            settable[i] = true;
    };
    const size_t fixed[] = {offsetof(ctl_cfg, motor.Rs_ohm), offsetof(ctl_cfg, motor.Rr_ohm),
                            offsetof(ctl_cfg, motor.Ls_H),   offsetof(ctl_cfg, motor.Lr_H),
                            offsetof(ctl_cfg, motor.Lm_H),   offsetof(ctl_cfg, motor.pole_pairs),
                            offsetof(ctl_cfg, motor.J_kgm2), offsetof(ctl_cfg, motor.B_Nms),
                            offsetof(ctl_cfg, period_s),     offsetof(ctl_cfg, vdc_nom_V)};
    for (size_t off : fixed)
        mark(off, sizeof(float));
    mark(offsetof(ctl_cfg, speed.mode), sizeof cfg.speed.mode);
    for (size_t j = 0; j < n; ++j)
        mark(k[j].offset, k[j].type == CONTROL_KEY_BOOL ? sizeof(bool) : 4u);
    const uint8_t *raw = reinterpret_cast<const uint8_t *>(&back);
    for (size_t i = 0; i < sizeof(ctl_cfg); ++i) {
        if (!settable[i]) {
            ASSERT_EQ(raw[i], 0x5Au) << "byte " << i << " of ctl_cfg written";
        }
    }
    EXPECT_EQ(back.motor.Rs_ohm, 1.5f);
    EXPECT_EQ(back.period_s, 250e-6f);
    EXPECT_EQ(back.speed.mode, SPEED_MODE_NOMINAL);
    EXPECT_EQ(back.speed.ip.zeta, 0.9f);
    EXPECT_EQ(back.speed.rbfn.n_nodes, 5u);
    EXPECT_FALSE(back.dtc.ripple_reduction);
    for (size_t j = 0; j < n; ++j) {
        size_t width = k[j].type == CONTROL_KEY_BOOL ? sizeof(bool) : 4u;
        EXPECT_EQ(std::memcmp(reinterpret_cast<const uint8_t *>(&back) + k[j].offset,
                              reinterpret_cast<const uint8_t *>(&cfg) + k[j].offset, width),
                  0)
            << k[j].name;
    }
    std::vector<uint32_t> again(w.size(), 0u);
    tick_rec_cfg_encode(&back, again.data());
    EXPECT_EQ(again, w);
}
