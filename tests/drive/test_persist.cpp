// Persistence: two NVM slots, sequence numbers, CRC-32. A save cut at every
// byte (hal_host_board.nvm_write_budget) must leave a loadable set, old or
// new, never a mix; both slots corrupt boots with defaults and reports it.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "co_test_util.hpp"

extern "C" {
#include "dtc/persist.h"
}

using namespace cotest;

namespace {

constexpr uint32_t kSave = 0x65766173u; // "save"
constexpr uint32_t kLoad = 0x64616F6Cu; // "load"

// Reference CRC-32 (IEEE 802.3, reflected, init and final xor 0xFFFFFFFF),
// written here independently of the firmware's.
uint32_t ref_crc32(const uint8_t *p, size_t n)
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c & 1u) ? (c >> 1) ^ 0xEDB88320u : c >> 1;
    }
    return c ^ 0xFFFFFFFFu;
}

// A set of parameter values used to tell two saved sets apart.
struct Set {
    float rbfn_k, ip_wn, psi_ref;
    uint16_t tel_hz;
    uint8_t mode;
};

void apply(Bench &b, const Set &s)
{
    ASSERT_FALSE(b.download_f32(0x2100, 1, s.rbfn_k).aborted());
    ASSERT_FALSE(b.download_f32(0x2010, 1, s.ip_wn).aborted());
    ASSERT_FALSE(b.download_f32(0x2200, 1, s.psi_ref).aborted());
    ASSERT_FALSE(b.download(0x2500, 3, {uint8_t(s.tel_hz), uint8_t(s.tel_hz >> 8)}).aborted());
    ASSERT_FALSE(b.download(0x2000, 2, {s.mode}).aborted());
}

// Read the set a freshly booted drive has (direct reads, no CAN).
Set read_set(drive *d)
{
    const ctl_cfg *c = drive_cfg(d);
    return Set{c->speed.rbfn.k, c->speed.ip.wn_rad_s, c->dtc.psi_ref_Wb, d->co.comm.telemetry_hz,
               uint8_t(c->speed.mode)};
}

bool same(const Set &a, const Set &b)
{
    return a.rbfn_k == b.rbfn_k && a.ip_wn == b.ip_wn && a.psi_ref == b.psi_ref && a.tel_hz == b.tel_hz &&
           a.mode == b.mode;
}

const Set kA{11.0f, 15.0f, 0.40f, 200, 0};
const Set kB{22.0f, 25.0f, 0.42f, 300, 1};
const Set kC{33.0f, 35.0f, 0.44f, 400, 2};

// A save of the drive's parameters as 0x1010:1 makes it, the slot image in a
// buffer the size the table gives.
int save(drive *d)
{
    std::vector<uint8_t> work(PERSIST_HEADER_SIZE + CO_PERSIST_BYTES);
    return persist_save(&d->persist, PERSIST_SAVE_VALUES, work.data(), work.size());
}

std::unique_ptr<drive> boot_fresh()
{
    std::unique_ptr<drive> d(new drive);
    drive_init(d.get());
    return d;
}

TEST(Persist, Crc32CheckValue)
{
    const char *s = "123456789";
    EXPECT_EQ(persist_crc32(0, s, 9), 0xCBF43926u); // the CRC-32 check value
    EXPECT_EQ(persist_crc32(persist_crc32(0, s, 4), s + 4, 5), 0xCBF43926u);
    uint8_t buf[300];
    for (int i = 0; i < 300; i++)
        buf[i] = uint8_t(i * 37 + 11);
    EXPECT_EQ(persist_crc32(0, buf, sizeof buf), ref_crc32(buf, sizeof buf));
}

TEST(Persist, ErasedNvmBootsWithDefaultsWithoutError)
{
    Bench b;
    EXPECT_EQ(b.read_u32(0x2510, 1), uint32_t(PERSIST_EMPTY));
    EXPECT_EQ(b.read_u32(0x1001, 0), 0u);
}

TEST(Persist, SavedValuesSurviveAPowerCycle)
{
    Bench b;
    apply(b, kA);
    ASSERT_FALSE(b.download_f32(0x2000, 1, 250.0f).aborted()); // speed reference: not persistent
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    apply(b, kB); // not saved
    b.power_cycle();
    EXPECT_TRUE(same(read_set(b.d.get()), kA));
    EXPECT_EQ(b.d->speed_ref_rad_s, 0.0f);
    EXPECT_EQ(b.read_u32(0x2510, 1), uint32_t(PERSIST_LOADED));
    // Save again (the other slot); the newest wins.
    apply(b, kB);
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    b.power_cycle();
    EXPECT_TRUE(same(read_set(b.d.get()), kB));
    apply(b, kC);
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    b.power_cycle();
    EXPECT_TRUE(same(read_set(b.d.get()), kC));
}

// Cut a save after every possible number of bytes, from two starting points:
// one valid slot, and two valid slots (the save then overwrites the older).
// Each cut's boot is checked here; the tally is the test's to judge.
struct CutTally {
    long total = 0;      // bytes a complete save writes
    long last_diff = -1; // the last of them that differs from what the slot held
    int n_old = 0, n_new = 0;
};

void cut_everywhere(int saves_before, CutTally &t)
{
    Bench b;
    const Set sets[3] = {kA, kB, kC};
    for (int i = 0; i < saves_before; i++) {
        apply(b, sets[i]);
        ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    }
    const Set &old_set = sets[saves_before - 1];
    const Set &new_set = sets[saves_before];
    apply(b, new_set);
    std::array<uint8_t, HAL_HOST_NVM_SIZE> image;
    std::memcpy(image.data(), b.board.nvm, image.size());

    // How many bytes a complete save writes, and the last of them that differs
    // from what the slot held (one write from the slot's start: header, payload).
    b.board.nvm_write_budget = 1000000;
    ASSERT_EQ(save(b.d.get()), HAL_OK);
    long total = 1000000 - b.board.nvm_write_budget;
    t.total = total;
    ASSERT_GT(total, long(PERSIST_HEADER_SIZE));
    const uint32_t base = saves_before == 1 ? HAL_HOST_NVM_SIZE / 2 : 0u; // the slot not holding the newest
    long last_diff = -1;
    for (long i = 0; i < total; i++)
        if (b.board.nvm[base + i] != image[base + i])
            last_diff = i;
    ASSERT_GE(last_diff, long(PERSIST_HEADER_SIZE)) << "the payload changes";
    t.last_diff = last_diff;

    for (long cut = 0; cut <= total; cut++) {
        std::memcpy(b.board.nvm, image.data(), image.size());
        b.board.nvm_write_budget = cut;
        int rc = save(b.d.get());
        b.board.nvm_write_budget = -1;
        EXPECT_EQ(rc == HAL_OK, cut == total) << "cut after " << cut << " bytes";
        auto d2 = boot_fresh();
        Set got = read_set(d2.get());
        bool is_old = same(got, old_set), is_new = same(got, new_set);
        EXPECT_TRUE(is_old || is_new) << "cut after " << cut << " bytes: a mixed or default set";
        EXPECT_NE(d2->persist.status, uint8_t(PERSIST_CORRUPT)) << cut;
        t.n_old += is_old;
        t.n_new += is_new;
        // Header and payload go in one write, the header's CRC covering the
        // payload: while a byte of the slot still differs from its final value
        // the slot does not validate and the old set is the one; once the last
        // differing byte is written the slot is the new set exactly (the host's
        // NVM keeps the old bytes beyond the cut; the flash would read them erased
        // and validate only at the end).
        if (cut <= last_diff) {
            EXPECT_TRUE(is_old) << cut;
        } else {
            EXPECT_TRUE(is_new) << cut;
        }
    }
}

TEST(Persist, SaveCutAtEveryByteFromOneValidSlot)
{
    CutTally t;
    cut_everywhere(1, t);
    ASSERT_GT(t.total, long(PERSIST_HEADER_SIZE));
    EXPECT_EQ(t.n_new, t.total - t.last_diff) << "the new set from the last differing byte on";
    EXPECT_EQ(t.n_old, t.last_diff + 1) << "the old set before it";
}

TEST(Persist, SaveCutAtEveryByteFromTwoValidSlots)
{
    CutTally t;
    cut_everywhere(2, t);
    ASSERT_GT(t.total, long(PERSIST_HEADER_SIZE));
    EXPECT_EQ(t.n_new, t.total - t.last_diff) << "the new set from the last differing byte on";
    EXPECT_EQ(t.n_old, t.last_diff + 1) << "the old set before it";
}

TEST(Persist, FailedSaveIsReportedAndKeepsThePreviousSet)
{
    Bench b;
    apply(b, kA);
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    apply(b, kB);
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    apply(b, kC);
    b.board.nvm_write_budget = 100; // power lost inside the payload of the slot holding A
    EXPECT_EQ(b.download_u32(0x1010, 1, kSave).abort_code(), kAbortStore);
    b.board.nvm_write_budget = -1;
    b.power_cycle();
    EXPECT_TRUE(same(read_set(b.d.get()), kB));
    EXPECT_EQ(b.read_u32(0x2510, 1), uint32_t(PERSIST_RECOVERED)); // the slot it cut is corrupt
}

TEST(Persist, BothSlotsCorruptBootsWithDefaultsAndReportsIt)
{
    Bench b;
    apply(b, kA);
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    apply(b, kB);
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    uint32_t half = HAL_HOST_NVM_SIZE / 2;
    b.board.nvm[PERSIST_HEADER_SIZE + 5] ^= 0x40u;        // payload of slot 0
    b.board.nvm[half + PERSIST_HEADER_SIZE + 9] ^= 0x01u; // payload of slot 1
    b.power_cycle(false);
    ctl_cfg def;
    ctl_cfg_default(&def);
    EXPECT_EQ(drive_cfg(b.d.get())->speed.rbfn.k, def.speed.rbfn.k);
    EXPECT_EQ(drive_cfg(b.d.get())->speed.ip.wn_rad_s, def.speed.ip.wn_rad_s);
    EXPECT_EQ(b.d->persist.status, uint8_t(PERSIST_CORRUPT));
    b.pass(); // boot-up and the emergency
    std::vector<hal_can_frame> emcy;
    for (const auto &f : b.frames)
        if (f.id == 0x081)
            emcy.push_back(f);
    ASSERT_EQ(emcy.size(), 1u);
    EXPECT_EQ(emcy[0].data[0] | (emcy[0].data[1] << 8), 0x6300);
    EXPECT_EQ(emcy[0].data[2], 0x81u); // generic + manufacturer
    EXPECT_EQ(b.read_u32(0x2510, 1), uint32_t(PERSIST_CORRUPT));
    EXPECT_EQ(b.read_u32(0x1001, 0), 0x81u);
    // A save repairs it (one slot), a second one the other slot too.
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    EXPECT_EQ(b.read_u32(0x2510, 1), uint32_t(PERSIST_LOADED));
    EXPECT_EQ(b.read_u32(0x1001, 0), 0u);
    b.power_cycle();
    EXPECT_EQ(b.read_u32(0x2510, 1), uint32_t(PERSIST_RECOVERED));
    EXPECT_EQ(b.read_u32(0x1001, 0), 0u);
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    b.power_cycle();
    EXPECT_EQ(b.read_u32(0x2510, 1), uint32_t(PERSIST_LOADED));
}

TEST(Persist, CorruptHeaderOrMagicIsNotLoaded)
{
    Bench b;
    apply(b, kA);
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    apply(b, kB);
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted()); // slot 1, newest
    uint32_t half = HAL_HOST_NVM_SIZE / 2;
    b.board.nvm[half + 9] ^= 0x10u; // its sequence number: the CRC no longer matches
    b.power_cycle();
    EXPECT_TRUE(same(read_set(b.d.get()), kA));
    EXPECT_EQ(b.read_u32(0x2510, 1), uint32_t(PERSIST_RECOVERED));
}

// Slots built by hand from the documented layout (persist.h) with the test's CRC.
struct SlotWriter {
    std::vector<uint8_t> payload;
    uint16_t count = 0;
    uint32_t format = PERSIST_FORMAT;
    void rec(uint16_t index, uint8_t sub, std::vector<uint8_t> v)
    {
        payload.push_back(uint8_t(index));
        payload.push_back(uint8_t(index >> 8));
        payload.push_back(sub);
        payload.push_back(uint8_t(v.size()));
        payload.insert(payload.end(), v.begin(), v.end());
        count++;
    }
    void write(hal_host_board &board, uint32_t slot, uint32_t seq)
    {
        uint8_t h[PERSIST_HEADER_SIZE];
        auto put = [&](int at, uint32_t v, int n) {
            for (int i = 0; i < n; i++)
                h[at + i] = uint8_t(v >> (8 * i));
        };
        put(0, PERSIST_MAGIC, 4);
        put(4, format, 2);
        put(6, count, 2);
        put(8, seq, 4);
        put(12, uint32_t(payload.size()), 4);
        std::vector<uint8_t> all(h, h + 16);
        all.insert(all.end(), payload.begin(), payload.end());
        put(16, ref_crc32(all.data(), all.size()), 4);
        uint32_t base = slot * (HAL_HOST_NVM_SIZE / 2);
        std::memcpy(&board.nvm[base], h, sizeof h);
        std::memcpy(&board.nvm[base + PERSIST_HEADER_SIZE], payload.data(), payload.size());
    }
};

// A stored set holds the mask of the values the user set (0x2321): the
// 10 hp motor's model (ids 0-6) and rbfn_k (id 29, RATINGS_ID_RBFN_K) set;
// without its bit a stored rbfn_k would be derived again at the load.
const uint32_t kRbfnKSet = 0x7Fu | (1u << RATINGS_ID_RBFN_K);

TEST(Persist, RecordsTheFirmwareRefusesAreSkipped)
{
    Bench b;
    SlotWriter w;
    w.rec(0x2100, 1, bytes_f32(44.0f));         // rbfn_k: applied
    w.rec(0x2321, 1, bytes_u32(kRbfnKSet));     // the set mask: rbfn_k set (kept), the rest derived
    w.rec(0x2100, 4, bytes_f32(1e9f));          // rbfn_m_w: above its maximum
    w.rec(0x2FFF, 0, {1, 2, 3, 4});             // no such object
    w.rec(0x1000, 0, {0, 0, 0, 0});             // not persistent
    w.rec(0x2010, 1, {1, 2});                   // wrong length
    w.rec(0x2200, 1, bytes_f32(std::nanf("")));  // NaN
    w.rec(0x2500, 3, {0x58, 0x02});             // telemetry_hz 600: applied
    w.rec(0x2300, 9, {1, 2, 3, 4, 5, 6, 7, 8}); // an 8-byte value from another firmware
    w.rec(0x2000, 2, {1});                      // speed_mode: applied
    w.write(b.board, 0, 7);
    b.power_cycle();
    ctl_cfg def;
    ctl_cfg_default(&def);
    const ctl_cfg *c = drive_cfg(b.d.get());
    EXPECT_EQ(c->speed.rbfn.k, 44.0f);
    EXPECT_EQ(c->speed.rbfn.m_w, def.speed.rbfn.m_w);
    EXPECT_EQ(c->speed.ip.wn_rad_s, def.speed.ip.wn_rad_s);
    EXPECT_EQ(c->dtc.psi_ref_Wb, def.dtc.psi_ref_Wb);
    EXPECT_EQ(b.d->co.comm.telemetry_hz, 600u);
    EXPECT_EQ(c->speed.mode, SPEED_MODE_NOMINAL);
    EXPECT_EQ(b.read_u32(0x2510, 1), uint32_t(PERSIST_PARTIAL));
}

// A set an older firmware stored (format 1: every derivable value absolute,
// no set mask) is not guessed at: defaults, persist_status 6, EMCY 0x6300,
// and a save stores the present format.
TEST(Persist, AnOlderFormatIsRefusedCleanly)
{
    Bench b;
    SlotWriter w;
    w.format = 1u;
    w.rec(0x2100, 1, bytes_f32(44.0f)); // rbfn_k
    w.rec(0x2400, 1, bytes_f32(50.0f)); // i_trip_A
    w.write(b.board, 0, 3);
    b.power_cycle(false);
    ctl_cfg def;
    ctl_cfg_default(&def);
    const ctl_cfg *c = drive_cfg(b.d.get());
    EXPECT_EQ(c->speed.rbfn.k, def.speed.rbfn.k);
    EXPECT_EQ(c->i_trip_A, def.i_trip_A);
    EXPECT_EQ(std::memcmp(&c->set, &def.set, sizeof def.set), 0);
    EXPECT_EQ(b.d->persist.status, uint8_t(PERSIST_OLD_FORMAT));
    b.pass(); // boot-up and the emergency
    int n_emcy = 0;
    for (const auto &f : b.frames)
        if (f.id == 0x081 && (f.data[0] | (f.data[1] << 8)) == 0x6300)
            n_emcy++;
    EXPECT_EQ(n_emcy, 1);
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    EXPECT_EQ(b.read_u32(0x2510, 1), uint32_t(PERSIST_LOADED));
    b.power_cycle();
    EXPECT_EQ(b.d->persist.status, uint8_t(PERSIST_LOADED));
}

// A value the user set survives the power cycle as set, the derived ones as derived.
TEST(Persist, TheSetMaskIsStoredWithTheValues)
{
    Bench b;
    ASSERT_FALSE(b.download_f32(0x2400, 1, 80.0f).aborted()); // i_trip_A: set
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    b.power_cycle();
    const ctl_cfg *c = drive_cfg(b.d.get());
    EXPECT_EQ(c->i_trip_A, 80.0f);
    EXPECT_TRUE(ratings_mask_has(&c->set, RATINGS_ID_I_TRIP));
    EXPECT_FALSE(ratings_mask_has(&c->set, RATINGS_ID_TE_MAX));
    EXPECT_EQ(b.read_u32(0x2321, 1), 0x7Fu | (1u << RATINGS_ID_I_TRIP));
}

TEST(Persist, NewestSequenceWinsAcrossTheWrap)
{
    Bench b;
    SlotWriter a, z;
    a.rec(0x2100, 1, bytes_f32(50.0f));
    a.rec(0x2321, 1, bytes_u32(kRbfnKSet));
    a.write(b.board, 0, 0xFFFFFFFFu);
    z.rec(0x2100, 1, bytes_f32(60.0f));
    z.rec(0x2321, 1, bytes_u32(kRbfnKSet));
    z.write(b.board, 1, 0u); // one after 0xFFFFFFFF
    b.power_cycle();
    EXPECT_EQ(drive_cfg(b.d.get())->speed.rbfn.k, 60.0f);
    // The next save goes to slot 0 with sequence 1.
    ASSERT_FALSE(b.download_f32(0x2100, 1, 70.0f).aborted());
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    EXPECT_EQ(le32(&b.board.nvm[8]), 1u);
    b.power_cycle();
    EXPECT_EQ(drive_cfg(b.d.get())->speed.rbfn.k, 70.0f);
}

TEST(Persist, RestoreDefaultsNowAndAfterTheNextBoot)
{
    Bench b;
    apply(b, kA);
    ASSERT_FALSE(b.download(0x1017, 0, {0xF4, 0x01}).aborted()); // heartbeat 500 ms
    ASSERT_FALSE(b.download_u32(0x1010, 1, kSave).aborted());
    ctl_cfg def;
    ctl_cfg_default(&def);
    // An NVM failure refuses the restore and changes nothing.
    b.board.nvm_write_budget = 0;
    EXPECT_EQ(b.download_u32(0x1011, 1, kLoad).abort_code(), kAbortStore);
    b.board.nvm_write_budget = -1;
    EXPECT_TRUE(same(read_set(b.d.get()), kA));
    ASSERT_FALSE(b.download_u32(0x1011, 1, kLoad).aborted());
    EXPECT_EQ(drive_cfg(b.d.get())->speed.rbfn.k, def.speed.rbfn.k);
    EXPECT_EQ(b.read_u32(0x1017, 0), 1000u);
    b.power_cycle();
    EXPECT_EQ(drive_cfg(b.d.get())->speed.rbfn.k, def.speed.rbfn.k);
    EXPECT_EQ(drive_cfg(b.d.get())->speed.ip.wn_rad_s, def.speed.ip.wn_rad_s);
    EXPECT_EQ(b.read_u32(0x1017, 0), 1000u);
    EXPECT_EQ(b.read_u32(0x2510, 1), uint32_t(PERSIST_LOADED));
}

TEST(Persist, UnreadableNvmBootsWithDefaults)
{
    // No board bound: the HAL refuses every NVM access.
    hal_host_bind(nullptr);
    auto d = boot_fresh();
    EXPECT_EQ(d->persist.status, uint8_t(PERSIST_NO_NVM));
    ctl_cfg def;
    ctl_cfg_default(&def);
    EXPECT_EQ(drive_cfg(d.get())->speed.rbfn.k, def.speed.rbfn.k);
    EXPECT_NE(save(d.get()), HAL_OK);
}

} // namespace
