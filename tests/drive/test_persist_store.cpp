// The parameter store on its own: its narrow interface (persist_params) fed by
// a small owner of made-up values, on the host board's NVM. Nothing of the
// drive, the CANopen binding or the dictionary is used: what the store needs of
// its owner is what persist.h says. Slots are read back byte by byte against
// the layout written out in persist.h.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

extern "C" {
#include "dtc/persist.h"
#include "hal/hal.h"
#include "hal_host/hal_host.h"
}

namespace {

using Key = std::pair<uint16_t, uint8_t>;
using Values = std::map<Key, std::vector<uint8_t>>;

// The owner: values in a map; a load starts from `defaults`, takes the keys it
// has with the length it has, and reports what its finish drops.
struct Owner {
    Values values, defaults;
    std::vector<std::string> calls; // hook order
    int fail_at = -1;               // next() fails at this record (-1: never)
    uint32_t finish_drops = 0;

    static Owner &of(void *ctx) { return *static_cast<Owner *>(ctx); }
    std::vector<uint8_t> at(uint16_t index, uint8_t sub) { return values[{index, sub}]; }

    static int hook_next(void *ctx, uint32_t *cursor, persist_record *rec)
    {
        Owner &o = of(ctx);
        o.calls.push_back("next");
        if (int(*cursor) == o.fail_at)
            return HAL_EIO;
        auto it = o.values.begin();
        std::advance(it, std::min<size_t>(*cursor, o.values.size()));
        if (it == o.values.end())
            return 0;
        rec->index = it->first.first;
        rec->sub = it->first.second;
        rec->len = uint8_t(it->second.size());
        std::memcpy(rec->value, it->second.data(), it->second.size());
        ++*cursor;
        return 1;
    }
    static void hook_defaults(void *ctx)
    {
        Owner &o = of(ctx);
        o.calls.push_back("defaults");
        o.values = o.defaults;
    }
    static bool hook_take(void *ctx, const persist_record *rec)
    {
        Owner &o = of(ctx);
        o.calls.push_back("take");
        auto it = o.values.find({rec->index, rec->sub});
        if (it == o.values.end() || it->second.size() != rec->len)
            return false;
        it->second.assign(rec->value, rec->value + rec->len);
        return true;
    }
    static uint32_t hook_finish(void *ctx)
    {
        Owner &o = of(ctx);
        o.calls.push_back("finish");
        return o.finish_drops;
    }
};

const persist_params kParams = {Owner::hook_next, Owner::hook_defaults, Owner::hook_take, Owner::hook_finish};

uint32_t le(const uint8_t *b, int n)
{
    uint32_t v = 0;
    for (int i = 0; i < n; i++)
        v |= uint32_t(b[i]) << (8 * i);
    return v;
}

class Store : public ::testing::Test {
protected:
    void SetUp() override
    {
        hal_host_board_init(&board);
        hal_host_bind(&board);
        owner.defaults = {{{0x2000, 1}, {0, 0, 0, 0}}, {{0x2000, 2}, {7}}, {{0x2100, 3}, {1, 2}}};
        owner.values = owner.defaults;
        persist_init(&st, &kParams, &owner);
    }
    void TearDown() override { hal_host_bind(nullptr); }

    int save(persist_save_kind kind = PERSIST_SAVE_VALUES, size_t work_size = 64)
    {
        std::vector<uint8_t> work(work_size);
        return persist_save(&st, kind, work.data(), work.size());
    }
    const uint8_t *slot(int i) const { return &board.nvm[i * (HAL_HOST_NVM_SIZE / 2)]; }

    hal_host_board board{};
    Owner owner;
    persist_state st{};
};

TEST_F(Store, SavesTheOwnersRecordsInTheDocumentedLayout)
{
    owner.values[{0x2000, 1}] = {0x11, 0x22, 0x33, 0x44};
    ASSERT_EQ(save(), HAL_OK);
    const uint8_t *h = slot(0);
    EXPECT_EQ(le(h, 4), PERSIST_MAGIC);
    EXPECT_EQ(le(h + 4, 2), PERSIST_FORMAT);
    EXPECT_EQ(le(h + 6, 2), 3u);      // records
    EXPECT_EQ(le(h + 8, 4), 1u);      // the first sequence number
    EXPECT_EQ(le(h + 12, 4), 4u * 3u + 4u + 1u + 2u); // three record headers and their values
    const std::vector<uint8_t> payload = {0x00, 0x20, 1, 4, 0x11, 0x22, 0x33, 0x44, // 0x2000:1
                                          0x00, 0x20, 2, 1, 7,                      // 0x2000:2
                                          0x00, 0x21, 3, 2, 1, 2};                  // 0x2100:3
    EXPECT_EQ(std::vector<uint8_t>(h + PERSIST_HEADER_SIZE, h + PERSIST_HEADER_SIZE + payload.size()), payload);
    std::vector<uint8_t> covered(h, h + 16);
    covered.insert(covered.end(), payload.begin(), payload.end());
    EXPECT_EQ(le(h + 16, 4), persist_crc32(0, covered.data(), covered.size()));
    EXPECT_EQ(st.status, uint8_t(PERSIST_LOADED));
    EXPECT_EQ(st.saves, 1u);
}

TEST_F(Store, ALoadStartsFromTheDefaultsTakesEveryRecordThenFinishes)
{
    owner.values[{0x2000, 2}] = {9};
    ASSERT_EQ(save(), HAL_OK);
    owner.values[{0x2000, 2}] = {5};
    owner.calls.clear();
    EXPECT_EQ(persist_load(&st), uint8_t(PERSIST_LOADED));
    EXPECT_EQ(owner.at(0x2000, 2), std::vector<uint8_t>{9});
    EXPECT_EQ(owner.calls, (std::vector<std::string>{"defaults", "take", "take", "take", "finish"}));
}

TEST_F(Store, NothingStoredStillGivesDefaultsAndAFinish)
{
    owner.values[{0x2000, 2}] = {5};
    EXPECT_EQ(persist_load(&st), uint8_t(PERSIST_EMPTY));
    EXPECT_EQ(owner.values, owner.defaults);
    EXPECT_EQ(owner.calls, (std::vector<std::string>{"defaults", "finish"}));
}

TEST_F(Store, RecordsTheOwnerRefusesAndWhatItsFinishDropsMakeAPartialSet)
{
    ASSERT_EQ(save(), HAL_OK);
    owner.defaults.erase({0x2100, 3}); // the next firmware has no 0x2100:3
    EXPECT_EQ(persist_load(&st), uint8_t(PERSIST_PARTIAL));
    owner.defaults[{0x2100, 3}] = {1, 2};
    EXPECT_EQ(persist_load(&st), uint8_t(PERSIST_LOADED));
    owner.finish_drops = 1; // e.g. a configuration refused as a whole
    EXPECT_EQ(persist_load(&st), uint8_t(PERSIST_PARTIAL));
}

TEST_F(Store, ARecordLongerThanAnyValueIsSkippedWithoutTheOwnerSeeingIt)
{
    owner.values = {{{0x2000, 1}, {1, 2, 3, 4}}};
    ASSERT_EQ(save(), HAL_OK);
    // Rewrite the slot by hand: a 6-byte record first, then the 4-byte one.
    std::vector<uint8_t> payload = {0x00, 0x30, 9, 6, 1, 2, 3, 4, 5, 6, 0x00, 0x20, 1, 4, 9, 8, 7, 6};
    uint8_t h[PERSIST_HEADER_SIZE];
    std::memcpy(h, slot(0), sizeof h);
    h[6] = 2;
    h[12] = uint8_t(payload.size());
    std::vector<uint8_t> covered(h, h + 16);
    covered.insert(covered.end(), payload.begin(), payload.end());
    uint32_t crc = persist_crc32(0, covered.data(), covered.size());
    for (int i = 0; i < 4; i++)
        h[16 + i] = uint8_t(crc >> (8 * i));
    std::memcpy(board.nvm, h, sizeof h);
    std::memcpy(board.nvm + PERSIST_HEADER_SIZE, payload.data(), payload.size());
    owner.calls.clear();
    EXPECT_EQ(persist_load(&st), uint8_t(PERSIST_PARTIAL));
    EXPECT_EQ(owner.at(0x2000, 1), (std::vector<uint8_t>{9, 8, 7, 6}));
    EXPECT_EQ(owner.calls, (std::vector<std::string>{"defaults", "take", "finish"}));
}

TEST_F(Store, AnOwnersErrorOrATooSmallBufferRefusesTheSaveAndWritesNothing)
{
    ASSERT_EQ(save(), HAL_OK);
    std::vector<uint8_t> before(board.nvm, board.nvm + HAL_HOST_NVM_SIZE);
    owner.values[{0x2000, 2}] = {8};
    owner.fail_at = 1;
    EXPECT_EQ(save(), HAL_EIO);
    owner.fail_at = -1;
    EXPECT_EQ(save(PERSIST_SAVE_VALUES, PERSIST_HEADER_SIZE + 4 + 4 + 4 + 1), HAL_ENOSPC); // one value short
    EXPECT_EQ(save(PERSIST_SAVE_VALUES, PERSIST_HEADER_SIZE - 1), HAL_ENOSPC);
    EXPECT_EQ(std::vector<uint8_t>(board.nvm, board.nvm + HAL_HOST_NVM_SIZE), before);
    EXPECT_EQ(st.saves, 1u);
    EXPECT_EQ(persist_load(&st), uint8_t(PERSIST_LOADED));
    EXPECT_EQ(owner.at(0x2000, 2), std::vector<uint8_t>{7});
}

TEST_F(Store, AnEmptySetAsksTheOwnerNothingAndLoadsAsDefaults)
{
    owner.values[{0x2000, 2}] = {9};
    ASSERT_EQ(save(), HAL_OK);
    owner.calls.clear();
    ASSERT_EQ(save(PERSIST_SAVE_EMPTY, PERSIST_HEADER_SIZE), HAL_OK);
    EXPECT_TRUE(owner.calls.empty());
    const uint8_t *h = slot(1); // the slot not holding the newest set
    EXPECT_EQ(le(h + 6, 2), 0u);
    EXPECT_EQ(le(h + 8, 4), 2u);
    EXPECT_EQ(le(h + 12, 4), 0u);
    EXPECT_EQ(persist_load(&st), uint8_t(PERSIST_LOADED));
    EXPECT_EQ(owner.values, owner.defaults);
}

} // namespace
