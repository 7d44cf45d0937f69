// Exhaustive checks of the STM32G474 binding's per-period NPC leg planner
// (hal/stm32g4/npc_plan.c, and its reference planner tests/oracles/npc_plan_leg.c): the programme the HRTIM runs never turns S1 and
// S4 on together, never steps a leg directly between P and N (also across
// periods), keeps the switching instant out of the sampling window and the
// second pulse above its minimum, and otherwise applies what was asked.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "npc_plan.h"
#include "npc_plan_leg.h"

namespace {

const npc_timing kTm = {34000u, 1190u, 340u}; // 200 us at 170 MHz, 7 us, 2 us
// Every state a leg's record can hold: each level, with and without NPC_LEG_HELD.
const uint8_t kPrevs[] = {NPC_N, NPC_O, NPC_P, NPC_N | NPC_LEG_HELD, NPC_O | NPC_LEG_HELD, NPC_P | NPC_LEG_HELD};

// Leg state from the output-1 levels of pair 0 (S3; S1 is its complement) and
// pair 1 (S2; S4 is its complement); -1 = S1 and S4 on.
int leg_state(bool s3, bool s2)
{
    bool s1 = !s3;
    if (s1 && s2)
        return NPC_P;
    if (!s1 && s2)
        return NPC_O;
    if (!s1 && !s2)
        return NPC_N;
    return -1;
}

bool is_pn(int a, int b) { return (a == NPC_P && b == NPC_N) || (a == NPC_N && b == NPC_P); }

// States the leg goes through in one period: [prev, after the start event, after t].
std::vector<int> simulate(uint8_t prev, const npc_leg_plan &p)
{
    bool lv[2], st[2];
    for (unsigned k = 0; k < 2; k++) {
        lv[k] = npc_pair_level(k, prev);
        EXPECT_EQ(p.set[k] & p.rst[k], 0u) << "set and reset on the same event";
        EXPECT_NE((p.set[k] | p.rst[k]) & NPC_EV_START, 0u) << "every period sets its start level";
        st[k] = (p.set[k] & NPC_EV_START) != 0;
    }
    std::vector<int> seq = {leg_state(lv[0], lv[1]), leg_state(st[0], st[1])};
    bool en[2] = {st[0], st[1]};
    for (unsigned k = 0; k < 2; k++) {
        if (p.set[k] & NPC_EV_T)
            en[k] = true;
        if (p.rst[k] & NPC_EV_T)
            en[k] = false;
    }
    seq.push_back(leg_state(en[0], en[1]));
    return seq;
}

// The planning rules written out step by step (the planner's first version,
// before its table): an independent reference for the table-driven planner.
void reference_plan(const npc_timing &tm, uint8_t prev, uint8_t v0, uint8_t v1, uint32_t t0, npc_leg_plan &out)
{
    out.fixups = 0u;
    if (is_pn(prev, v0)) {
        v0 = NPC_O;
        out.fixups++;
    }
    if (is_pn(v0, v1)) {
        v1 = NPC_O;
        out.fixups++;
    }
    uint32_t t = t0 > tm.per ? tm.per : t0;
    if (t < tm.keepout)
        t = (t < tm.keepout / 2u && !is_pn(prev, v1)) ? 0u : tm.keepout;
    if (t + tm.min_pulse > tm.per)
        t = tm.per;
    if (v0 == v1)
        t = tm.per;
    for (unsigned k = 0u; k < 2u; k++) {
        // output 1: S3 (pair 0) on in O and N, S2 (pair 1) on in P and O
        auto level = [k](uint8_t leg) { return k == 0u ? leg != NPC_P : leg != NPC_N; };
        bool l_start = level(t == 0u ? v1 : v0);
        bool l_end = level(v1);
        uint32_t set = 0u, rst = 0u;
        (l_start ? set : rst) |= NPC_EV_START;
        if (t != 0u && t != tm.per && l_end != l_start)
            (l_end ? set : rst) |= NPC_EV_T;
        out.set[k] = set;
        out.rst[k] = rst;
    }
    out.t = t;
    out.v0 = v0;
    out.v1 = v1;
    out.end = t == tm.per ? v0 : v1;
}

// The case's name in a failure message.
std::string case_of(uint8_t prev, uint8_t v0, uint8_t v1, uint32_t t0)
{
    return "prev " + std::to_string(int(prev)) + " v0 " + std::to_string(int(v0)) + " v1 " + std::to_string(int(v1)) +
           " t0 " + std::to_string(t0) + ": ";
}

// npc_plan_leg's plan equals the rules' (reference_plan) field by field.
::testing::AssertionResult same_as_reference(const npc_timing &tm, uint8_t prev, uint8_t v0, uint8_t v1, uint32_t t0)
{
    npc_leg_plan p, r;
    npc_plan_leg(&tm, prev, v0, v1, t0, &p);
    reference_plan(tm, prev, v0, v1, t0, r);
    const std::string at = case_of(prev, v0, v1, t0);
    for (unsigned k = 0; k < 2; k++) {
        if (p.set[k] != r.set[k] || p.rst[k] != r.rst[k])
            return ::testing::AssertionFailure() << at << "pair " << k << " set/rst " << int(p.set[k]) << "/"
                                                 << int(p.rst[k]) << ", the rules " << int(r.set[k]) << "/"
                                                 << int(r.rst[k]);
    }
    if (p.t != r.t || p.v0 != r.v0 || p.v1 != r.v1 || p.end != r.end || p.fixups != r.fixups)
        return ::testing::AssertionFailure() << at << "t " << p.t << " v0 " << int(p.v0) << " v1 " << int(p.v1)
                                             << " end " << int(p.end) << " fixups " << p.fixups << ", the rules t "
                                             << r.t << " v0 " << int(r.v0) << " v1 " << int(r.v1) << " end "
                                             << int(r.end) << " fixups " << r.fixups;
    return ::testing::AssertionSuccess();
}

// The plan for one case is safe on the simulated leg (no S1 and S4 together, no
// P<->N step), switches outside the keep-outs, and applies what was asked
// unless that was a P<->N step (then it says it fixed it up).
::testing::AssertionResult plan_is_safe(uint8_t prev, uint8_t v0, uint8_t v1, uint32_t t0)
{
    npc_leg_plan p;
    npc_plan_leg(&kTm, prev, v0, v1, t0, &p);
    std::vector<int> seq = simulate(prev, p);
    const std::string at = case_of(prev, v0, v1, t0);
    auto fail = [&at](const char *what) { return ::testing::AssertionFailure() << at << what; };
    for (int st : seq)
        if (st == -1)
            return fail("S1 and S4 on together");
    if (is_pn(seq[0], seq[1]))
        return fail("P<->N at the period start");
    if (is_pn(seq[1], seq[2]))
        return fail("P<->N at the switching instant");
    if (seq[2] != p.end)
        return fail("the leg does not end where the plan says");
    bool has_t = ((p.set[0] | p.rst[0] | p.set[1] | p.rst[1]) & NPC_EV_T) != 0;
    if (has_t && p.t < kTm.keepout)
        return fail("switching inside the sampling window");
    if (has_t && p.t + kTm.min_pulse > kTm.per)
        return fail("second pulse too short");
    bool asked_pn = is_pn(prev, v0) || is_pn(v0, v1);
    if (asked_pn)
        return p.fixups > 0u ? ::testing::AssertionSuccess() : fail("a P<->N request not fixed up");
    // What was asked is applied, with the instant moved by at most the keep-out or the minimum pulse.
    if (p.v0 != v0 || p.v1 != v1)
        return fail("the states asked for are not applied");
    if (v0 != v1) {
        uint32_t err = p.t > t0 ? p.t - t0 : t0 - p.t;
        if (err > (kTm.keepout > kTm.min_pulse ? kTm.keepout : kTm.min_pulse))
            return fail("the instant moved by more than the keep-out or the minimum pulse");
        if (t0 >= kTm.keepout && t0 + kTm.min_pulse <= kTm.per && p.t != t0)
            return fail("an instant outside the keep-outs is moved");
        if (seq[2] != (p.t == kTm.per ? v0 : v1))
            return fail("the leg ends on the wrong state");
    }
    return ::testing::AssertionSuccess();
}

TEST(NpcPlan, EveryStateTripleAndInstant)
{
    for (uint8_t prev = 0; prev <= NPC_P; prev++)
        for (uint8_t v0 = 0; v0 <= NPC_P; v0++)
            for (uint8_t v1 = 0; v1 <= NPC_P; v1++) {
                for (uint32_t t0 = 0; t0 <= kTm.per; t0 += 17)
                    ASSERT_TRUE(plan_is_safe(prev, v0, v1, t0));
                for (uint32_t t0 : {1u, 594u, 595u, 596u, 1189u, 1190u, 1191u, 33659u, 33660u, 33661u, 33999u})
                    ASSERT_TRUE(plan_is_safe(prev, v0, v1, t0));
            }
}

TEST(NpcPlan, TableEqualsTheRulesForEveryTripleAndInstant)
{
    // The board's timing and a small one where the keep-out and minimum pulse cover most of the period.
    const npc_timing tms[] = {kTm, {100u, 40u, 30u}, {34000u, 0u, 0u}};
    for (const npc_timing &tm : tms)
        for (uint8_t prev = 0; prev <= NPC_P; prev++)
            for (uint8_t v0 = 0; v0 <= NPC_P; v0++)
                for (uint8_t v1 = 0; v1 <= NPC_P; v1++) {
                    for (uint32_t t0 = 0; t0 <= tm.per + 2u; t0 += (tm.per > 1000u ? 7u : 1u))
                        ASSERT_TRUE(same_as_reference(tm, prev, v0, v1, t0));
                    for (uint32_t t0 : {tm.keepout / 2u - 1u, tm.keepout / 2u, tm.keepout - 1u, tm.keepout,
                                        tm.per - tm.min_pulse, tm.per - tm.min_pulse + 1u, tm.per, 0xFFFFFFFFu})
                        ASSERT_TRUE(same_as_reference(tm, prev, v0, v1, t0));
                }
}

// The actuation's fast path (npc_leg_words_table, the period's classes, CMP1 = the keep instant) writes
// exactly what the planner's plan says, for every triple and every instant of three timings.
TEST(NpcPlan, RegisterWordsEqualThePlanForEveryTripleAndInstant)
{
    const npc_timing tms[] = {kTm, {100u, 40u, 30u}, {34000u, 0u, 0u}};
    for (const npc_timing &tm : tms)
        for (uint32_t t0 = 0; t0 <= tm.per + 2u; t0++) {
            npc_instants in;
            npc_instants_of(&tm, t0, &in);
            const uint32_t classes = npc_period_classes(&tm, &in);
            for (uint8_t prev = 0; prev <= NPC_P; prev++)
                for (uint8_t v0 = 0; v0 <= NPC_P; v0++)
                    for (uint8_t v1 = 0; v1 <= NPC_P; v1++) {
                        npc_leg_plan p;
                        npc_plan_leg(&tm, prev, v0, v1, t0, &p);
                        const npc_leg_words *w = npc_leg_words_of(prev, v0, v1);
                        const uint32_t c = npc_leg_class(w, classes);
                        ASSERT_LE(c, 2u);
                        const uint32_t *reg = w->reg[c];
                        const std::string m = "per " + std::to_string(tm.per) + " t0 " + std::to_string(t0) +
                                              " prev " + std::to_string(prev) + " v0 " + std::to_string(v0) +
                                              " v1 " + std::to_string(v1);
                        for (unsigned k = 0; k < 2u; k++) {
                            ASSERT_EQ(reg[2u * k], p.set[k]) << m << " pair " << k;
                            ASSERT_EQ(reg[2u * k + 1u], p.rst[k] | (1u << 26)) << m << " pair " << k; // EXTEVNT6
                        }
                        // CMP1 is written exactly when the plan's instant is inside the period, and then it is keep
                        ASSERT_EQ(c == NPC_AT_T, p.t != 0u && p.t != tm.per) << m;
                        if (c == NPC_AT_T) {
                            ASSERT_EQ(in.keep, p.t) << m;
                        }
                        ASSERT_EQ(w->end[c] & NPC_LEG_STATE, p.end) << m;
                        // the held flag exactly after a period of one state
                        ASSERT_EQ((w->end[c] & NPC_LEG_HELD) != 0u, p.v0 == p.v1) << m;
                        ASSERT_EQ(w->fixups, p.fixups) << m;
                        // a leg without two states has the same class whatever the instants
                        ASSERT_EQ(w->timed != 0u, p.v0 != p.v1) << m;
                        if (w->timed == 0u) {
                            ASSERT_EQ(npc_leg_class(w, NPC_UNTIMED_CLASSES), c) << m;
                        }
                        // the same row with the held flag on prev: the same words, but for the leg that
                        // stays in its held state alone, which writes nothing
                        const npc_leg_words *h = npc_leg_words_of(uint8_t(prev | NPC_LEG_HELD), v0, v1);
                        const uint32_t hc = npc_leg_class(h, classes);
                        if (v0 == prev && v1 == prev) {
                            ASSERT_EQ(hc, NPC_HELD) << m;
                            ASSERT_EQ(h->timed, 0u) << m;
                            ASSERT_EQ(npc_leg_class(h, NPC_UNTIMED_CLASSES), uint32_t(NPC_HELD)) << m;
                            continue;
                        }
                        ASSERT_EQ(hc, c) << m;
                        ASSERT_EQ(h->timed, w->timed) << m;
                        for (unsigned k = 0; k < 4u; k++)
                            ASSERT_EQ(h->reg[hc][k], reg[k]) << m << " word " << k;
                        ASSERT_EQ(h->end[hc], w->end[c]) << m;
                        ASSERT_EQ(h->fixups, w->fixups) << m;
                    }
        }
}

// Writing nothing for a leg that stays in its held state is right: after any period of one state s
// (whatever the leg came from and whatever the instant), its timers hold exactly the words that
// (s, s, s) would write, and that period's end carries the held flag.
TEST(NpcPlan, HeldWordsAreTheOneStateWordsOfTheHeldState)
{
    const npc_timing tms[] = {kTm, {100u, 40u, 30u}, {34000u, 0u, 0u}};
    for (const npc_timing &tm : tms)
        for (uint32_t t0 = 0; t0 <= tm.per + 2u; t0++) {
            npc_instants in;
            npc_instants_of(&tm, t0, &in);
            const uint32_t classes = npc_period_classes(&tm, &in);
            for (uint8_t prev = 0; prev <= (NPC_P | NPC_LEG_HELD); prev++) {
                if ((prev & NPC_LEG_STATE) > NPC_P)
                    continue;
                for (uint8_t v0 = 0; v0 <= NPC_P; v0++)
                    for (uint8_t v1 = 0; v1 <= NPC_P; v1++) {
                        const npc_leg_words *w = npc_leg_words_of(prev, v0, v1);
                        const uint32_t c = npc_leg_class(w, classes);
                        if (c == NPC_HELD || (w->end[c] & NPC_LEG_HELD) == 0u)
                            continue;
                        const uint8_t st = uint8_t(w->end[c] & NPC_LEG_STATE);
                        npc_leg_plan ref;
                        npc_plan_leg(&tm, st, st, st, t0, &ref);
                        const std::string m = "per " + std::to_string(tm.per) + " t0 " + std::to_string(t0) +
                                              " prev " + std::to_string(prev) + " v0 " + std::to_string(v0) +
                                              " v1 " + std::to_string(v1);
                        for (unsigned k = 0; k < 2u; k++) {
                            ASSERT_EQ(w->reg[c][2u * k], ref.set[k]) << m << " pair " << k;
                            ASSERT_EQ(w->reg[c][2u * k + 1u], ref.rst[k] | (1u << 26)) << m << " pair " << k;
                        }
                        ASSERT_NE(c, uint32_t(NPC_AT_T)) << m; // and no CMP1 to hold
                    }
            }
        }
}

TEST(NpcPlan, LongRandomSequencesStayContinuous)
{
    std::mt19937 rng(12345);
    uint8_t prev = NPC_O;
    for (int i = 0; i < 200000; i++) {
        uint8_t v0 = uint8_t(rng() % 3), v1 = uint8_t(rng() % 3);
        uint32_t t0 = rng() % (kTm.per + 1);
        npc_leg_plan p;
        npc_plan_leg(&kTm, prev, v0, v1, t0, &p);
        std::vector<int> seq = simulate(prev, p);
        for (size_t k = 0; k + 1 < seq.size(); k++) {
            ASSERT_NE(seq[k + 1], -1);
            ASSERT_FALSE(is_pn(seq[k], seq[k + 1])) << "step " << i;
        }
        prev = p.end;
    }
}

TEST(NpcPlan, PairLevels)
{
    // Output 1 is the inner switch: S3 (pair 0) on in O and N, S2 (pair 1) on in P and O.
    EXPECT_FALSE(npc_pair_level(0, NPC_P));
    EXPECT_TRUE(npc_pair_level(0, NPC_O));
    EXPECT_TRUE(npc_pair_level(0, NPC_N));
    EXPECT_TRUE(npc_pair_level(1, NPC_P));
    EXPECT_TRUE(npc_pair_level(1, NPC_O));
    EXPECT_FALSE(npc_pair_level(1, NPC_N));
}

} // namespace

// The word-wide leg check against the byte-by-byte rule: every value 0..255 at
// every one of the six positions, the others valid (0..2), and every
// combination of valid and 3 (the value the bit test must catch from its two
// low bits) over the six.
TEST(NpcPlan, LegsValidEqualsTheByteRule)
{
    for (int pos = 0; pos < 6; ++pos) {
        for (int v = 0; v < 256; ++v) {
            for (int fill = 0; fill <= 2; ++fill) {
                uint8_t legs[6];
                for (int k = 0; k < 6; ++k)
                    legs[k] = uint8_t((k + fill) % 3);
                legs[pos] = uint8_t(v);
                EXPECT_EQ(npc_legs_valid(legs), v <= 2) << "pos " << pos << " value " << v;
            }
        }
    }
    for (int m = 0; m < 4096; ++m) { // base 4 over six positions, digits 0..3
        uint8_t legs[6];
        bool valid = true;
        for (int k = 0, x = m; k < 6; ++k, x /= 4) {
            legs[k] = uint8_t(x % 4);
            valid = valid && legs[k] <= 2;
        }
        EXPECT_EQ(npc_legs_valid(legs), valid) << m;
    }
}

// The gates-off repeat (hal_actuate) skips writing when the request is the
// held one: the comparison must see every leg code and every bit of the duty,
// and nothing else (the padding after the six codes).
TEST(NpcPlan, DutyValidEqualsTheFloatRule)
{
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<float> v = {0.0f, -0.0f, 1.0f, 0.5f, std::nextafter(1.0f, 2.0f), std::nextafter(0.0f, -1.0f),
                            std::nextafter(0.0f, 1.0f), -1.0f, 2.0f, inf, -inf, nan, -nan, 1e-38f, -1e-38f};
    std::mt19937 rng(7);
    for (int i = 0; i < 200000; i++) { // every kind of bit pattern: sign, exponent and mantissa at random
        uint32_t b = uint32_t(rng());
        float f;
        std::memcpy(&f, &b, sizeof f);
        v.push_back(f);
    }
    for (float f : v)
        ASSERT_EQ(npc_duty_valid(f), f >= 0.0f && f <= 1.0f) << f;
}

TEST(NpcPlan, RequestSameSeesEveryLegAndDutyBit)
{
    const uint8_t base[8] = {1, 1, 1, 1, 1, 1, 0xAA, 0x55};
    const npc_request a = npc_request_of(base, 1.0f);
    uint8_t padded[8] = {1, 1, 1, 1, 1, 1, 0x00, 0xFF};
    const npc_request b = npc_request_of(padded, 1.0f);
    EXPECT_TRUE(npc_request_same(&a, &b)); // padding ignored
    for (int pos = 0; pos < 6; ++pos) {
        for (uint8_t v : {uint8_t(0), uint8_t(2)}) {
            uint8_t legs[8] = {1, 1, 1, 1, 1, 1, 0, 0};
            legs[pos] = v;
            const npc_request c = npc_request_of(legs, 1.0f);
            EXPECT_FALSE(npc_request_same(&a, &c)) << "pos " << pos << " value " << int(v);
        }
    }
    for (int bit = 0; bit < 32; ++bit) {
        uint32_t u = 0x3F800000u ^ (1u << bit); // 1.0f with one bit flipped
        float d;
        std::memcpy(&d, &u, sizeof d);
        const npc_request c = npc_request_of(base, d);
        EXPECT_FALSE(npc_request_same(&a, &c)) << "duty bit " << bit;
    }
    const npc_request zero = npc_request_of(base, 0.0f);
    EXPECT_FALSE(npc_request_same(&a, &zero));
}

TEST(NpcPlan, LegsWordIsOneToOne)
{
    for (int x = 0; x < 27; ++x) {
        for (int y = 0; y < 27; ++y) {
            const uint8_t a[3] = {uint8_t(x % 3), uint8_t(x / 3 % 3), uint8_t(x / 9)};
            const uint8_t b[3] = {uint8_t(y % 3), uint8_t(y / 3 % 3), uint8_t(y / 9)};
            EXPECT_EQ(npc_legs_word(a) == npc_legs_word(b), x == y) << x << " " << y;
        }
    }
}

// The three legs' table indices at once equal npc_leg_words_of's, leg by leg,
// for every recorded state (with and without NPC_LEG_HELD) and every pair of
// valid vectors; the fourth byte of the word is 0.
TEST(NpcPlan, LegWordsIndex3EqualsTheIndexOfEachLeg)
{
    int checked = 0;
    for (uint8_t p0 : kPrevs)
        for (uint8_t p1 : kPrevs)
            for (uint8_t p2 : kPrevs) {
                const uint8_t prev4[4] = {p0, p1, p2, 0u};
                for (int v = 0; v < 729; ++v) { // six leg codes 0..2
                    uint8_t legs[6];
                    for (int k = 0, r = v; k < 6; ++k, r /= 3)
                        legs[k] = uint8_t(r % 3);
                    ASSERT_TRUE(npc_legs_valid(legs));
                    const uint32_t i3 = npc_leg_words_index3(legs, prev4);
                    ASSERT_EQ(i3 >> 24, 0u);
                    for (unsigned leg = 0u; leg < 3u; ++leg) {
                        const npc_leg_words *want = npc_leg_words_of(prev4[leg], legs[leg], legs[3u + leg]);
                        const uint32_t idx = (i3 >> (8u * leg)) & 0xFFu;
                        ASSERT_LT(idx, NPC_LEG_WORDS_ENTRIES);
                        ASSERT_EQ(&npc_leg_words_table[idx], want)
                            << "prev " << int(prev4[leg]) << " v0 " << int(legs[leg]) << " v1 " << int(legs[3u + leg]);
                    }
                    ++checked;
                }
            }
    EXPECT_EQ(checked, 216 * 729);
}

// The period's classes and change instant taken straight from a usual instant
// equal npc_period_classes of npc_instants_of (and its keep instant) for every
// requested instant, in timings with and without a keep-out and a minimum
// pulse, and with a period too short for both.
TEST(NpcPlan, PeriodClassesAtEqualTheInstantsWay)
{
    const npc_timing tms[] = {kTm, {100u, 40u, 30u}, {34000u, 0u, 0u}, {100u, 0u, 30u},
                              {100u, 40u, 0u}, {50u, 40u, 30u}, {1u, 0u, 0u}, {8500u, 1190u, 340u}};
    for (const npc_timing &tm : tms)
        for (uint32_t t0 = 0; t0 <= tm.per + 2u; t0++) {
            npc_instants in;
            npc_instants_of(&tm, t0, &in);
            uint32_t t = 12345u;
            const uint32_t classes = npc_period_classes_at(&tm, t0, &t);
            ASSERT_EQ(classes, npc_period_classes(&tm, &in)) << "per " << tm.per << " t0 " << t0;
            ASSERT_EQ(t, in.keep) << "per " << tm.per << " t0 " << t0;
        }
}

// The last two leg codes (the halfword npc_legs_valid adds the word's constant
// to) for every pair of byte values, and the first four for every pair too.
TEST(NpcPlan, LegsValidSeesEveryPairOfCodes)
{
    for (int a = 0; a < 256; ++a)
        for (int b = 0; b < 256; ++b) {
            const uint8_t tail[6] = {2, 1, 0, 2, uint8_t(a), uint8_t(b)};
            ASSERT_EQ(npc_legs_valid(tail), a <= 2 && b <= 2) << a << " " << b;
            const uint8_t head[6] = {uint8_t(a), 1, 0, uint8_t(b), 2, 2};
            ASSERT_EQ(npc_legs_valid(head), a <= 2 && b <= 2) << a << " " << b;
            const uint8_t mid[6] = {0, 2, uint8_t(a), 1, uint8_t(b), 0};
            ASSERT_EQ(npc_legs_valid(mid), a <= 2 && b <= 2) << a << " " << b;
        }
}

// A period without a two-state leg needs no class word: every entry without
// npc_leg_words.timed has class NPC_HELD exactly when npc_leg_held says so
// (then it is the held state alone again) and NPC_AT_PER otherwise; an entry
// with two states is never held.
TEST(NpcPlan, UntimedEntriesAreHeldOrTheWholePeriod)
{
    for (uint8_t prev : kPrevs)
        for (uint8_t v0 = 0; v0 <= NPC_P; v0++)
            for (uint8_t v1 = 0; v1 <= NPC_P; v1++) {
                const npc_leg_words *w = npc_leg_words_of(prev, v0, v1);
                const bool alone_again = (prev & NPC_LEG_HELD) != 0u && v0 == (prev & NPC_LEG_STATE) && v1 == v0;
                EXPECT_EQ(npc_leg_held(w), alone_again) << int(prev) << " " << int(v0) << " " << int(v1);
                if (w->timed != 0u) {
                    EXPECT_FALSE(npc_leg_held(w));
                    continue;
                }
                EXPECT_EQ(npc_leg_class(w, NPC_UNTIMED_CLASSES),
                          npc_leg_held(w) ? uint32_t(NPC_HELD) : uint32_t(NPC_AT_PER))
                    << int(prev) << " " << int(v0) << " " << int(v1);
            }
}

// The usual instants (npc_usual_of, npc_instant_usual) are exactly those
// npc_period_classes_at takes as they are (out of the keep-out, not 0, before
// the last minimum pulse), for every requested instant of timings with and
// without a keep-out and a minimum pulse and with a period too short for both;
// at such an instant both kinds of two-state leg change at it.
TEST(NpcPlan, UsualInstantsAreThoseTakenAsTheyAre)
{
    const npc_timing tms[] = {kTm, {100u, 40u, 30u}, {34000u, 0u, 0u}, {100u, 0u, 30u},
                              {100u, 40u, 0u}, {50u, 40u, 30u}, {1u, 0u, 0u}, {8500u, 1190u, 340u},
                              {70u, 40u, 30u}, {71u, 40u, 30u}, {30u, 0u, 30u}};
    const uint32_t usual_classes =
        uint32_t(NPC_AT_PER) | (uint32_t(NPC_AT_T) << 8) | (uint32_t(NPC_AT_T) << 16) | (uint32_t(NPC_HELD) << 24);
    for (const npc_timing &tm : tms) {
        const npc_usual u = npc_usual_of(&tm);
        std::vector<uint32_t> t0s;
        for (uint32_t t0 = 0; t0 <= tm.per + 2u; t0++)
            t0s.push_back(t0);
        t0s.push_back(0xFFFFFFFFu);
        t0s.push_back(0x80000000u);
        int usual_seen = 0;
        for (uint32_t t0 : t0s) {
            const std::string m = "per " + std::to_string(tm.per) + " t0 " + std::to_string(t0);
            const bool want = t0 >= tm.keepout && t0 != 0u && uint64_t(t0) + tm.min_pulse < tm.per;
            ASSERT_EQ(npc_instant_usual(&u, t0), want) << m;
            if (!want)
                continue;
            ++usual_seen;
            npc_instants in;
            npc_instants_of(&tm, t0, &in);
            ASSERT_EQ(in.keep, t0) << m;
            ASSERT_EQ(in.drop, t0) << m;
            ASSERT_EQ(npc_period_classes(&tm, &in), usual_classes) << m;
        }
        EXPECT_EQ(usual_seen, int(u.span)) << "per " << tm.per;
    }
}

// A period at a usual instant writes, for every leg that is not held, its
// NPC_AT_T row, its NPC_AT_T end and CMP1 = the instant (the actuation's
// usual path): the same words and end state as the classes' way for every
// recorded state (held or not), pair of leg states and usual instant, and
// CMP1 the same wherever the classes' way writes it (elsewhere the words use
// no CMP1 event); a leg the classes' way skips is exactly a held one.
TEST(NpcPlan, UsualPeriodWritesWhatTheClassesWayWrites)
{
    const npc_timing tms[] = {kTm, {100u, 40u, 30u}, {34000u, 0u, 0u}, {8500u, 1190u, 340u}};
    for (const npc_timing &tm : tms) {
        const npc_usual u = npc_usual_of(&tm);
        for (uint32_t t0 = 0; t0 <= tm.per + 2u; t0 += (tm.per > 1000u ? 13u : 1u)) {
            if (!npc_instant_usual(&u, t0))
                continue;
            uint32_t t = 12345u;
            const uint32_t classes = npc_period_classes_at(&tm, t0, &t);
            for (uint8_t prev : kPrevs)
                for (uint8_t v0 = 0; v0 <= NPC_P; v0++)
                    for (uint8_t v1 = 0; v1 <= NPC_P; v1++) {
                        const std::string m = "per " + std::to_string(tm.per) + " t0 " + std::to_string(t0) +
                                              " prev " + std::to_string(prev) + " v0 " + std::to_string(v0) +
                                              " v1 " + std::to_string(v1);
                        const npc_leg_words *w = npc_leg_words_of(prev, v0, v1);
                        const uint32_t c = npc_leg_class(w, classes);
                        ASSERT_EQ(c == NPC_HELD, npc_leg_held(w)) << m;
                        if (c == NPC_HELD)
                            continue;
                        for (unsigned k = 0; k < 4u; k++)
                            ASSERT_EQ(w->reg[NPC_AT_T][k], w->reg[c][k]) << m << " word " << k;
                        ASSERT_EQ(w->end[NPC_AT_T], w->end[c]) << m;
                        if (c == NPC_AT_T) {
                            ASSERT_EQ(t, t0) << m;
                        } else {
                            ASSERT_EQ(w->timed, 0u) << m;
                            for (unsigned k = 0; k < 4u; k++)
                                ASSERT_EQ(w->reg[c][k] & NPC_EV_T, 0u) << m << " word " << k; // no CMP1 event
                        }
                    }
        }
    }
}

// Every entry's flags say whether the period writes the leg (not held),
// whether it has two states and whether it has P<->N fixups; npc_legs_words'
// OR of the three is 0 exactly when every leg is held (the period writes
// nothing), has NPC_FLAG_TIMED exactly when a leg has two states and
// NPC_FLAG_FIXUPS exactly when a written leg has fixups (npc_legs_fixups
// counts those), for every recorded state (held or not) of each leg and
// every pair of valid vectors.
TEST(NpcPlan, LegsFlagsAreHeldTimedAndFixupsOfEachLeg)
{
    for (uint8_t prev : kPrevs)
        for (uint8_t v0 = 0; v0 <= NPC_P; v0++)
            for (uint8_t v1 = 0; v1 <= NPC_P; v1++) {
                const npc_leg_words *w = npc_leg_words_of(prev, v0, v1);
                // held by its class (kind_shift), not by the flags under test
                const bool held = w->kind_shift == NPC_HELD_SHIFT;
                EXPECT_EQ(npc_leg_held(w), held) << int(prev) << " " << int(v0) << " " << int(v1);
                EXPECT_EQ(w->flags, (held ? 0u : NPC_FLAG_WRITE) | (w->timed != 0u ? NPC_FLAG_TIMED : 0u) |
                                        (w->fixups != 0u ? NPC_FLAG_FIXUPS : 0u))
                    << int(prev) << " " << int(v0) << " " << int(v1);
                if (held) {
                    EXPECT_EQ(w->fixups, 0u); // a held leg, never written, has none to count
                }
            }
    int all_held = 0;
    for (uint8_t p0 : kPrevs)
        for (uint8_t p1 : kPrevs)
            for (uint8_t p2 : kPrevs) {
                const uint8_t prev4[4] = {p0, p1, p2, 0u};
                for (int v = 0; v < 729; ++v) {
                    uint8_t legs[6];
                    for (int k = 0, r = v; k < 6; ++k, r /= 3)
                        legs[k] = uint8_t(r % 3);
                    const npc_leg_words *w3[3];
                    const uint32_t flags = npc_legs_words(legs, prev4, w3);
                    bool held = true, timed = false;
                    uint32_t fixups = 0u;
                    for (unsigned leg = 0u; leg < 3u; ++leg) {
                        const npc_leg_words *w = npc_leg_words_of(prev4[leg], legs[leg], legs[3u + leg]);
                        ASSERT_EQ(w3[leg], w);
                        const bool leg_held = w->kind_shift == NPC_HELD_SHIFT;
                        held = held && leg_held;
                        timed = timed || w->timed != 0u;
                        fixups += leg_held ? 0u : w->fixups;
                    }
                    ASSERT_EQ(flags == 0u, held) << v;
                    ASSERT_EQ((flags & NPC_FLAG_TIMED) != 0u, timed) << v;
                    ASSERT_EQ((flags & NPC_FLAG_FIXUPS) != 0u, fixups != 0u) << v;
                    ASSERT_EQ(npc_legs_fixups(w3), fixups) << v; // the written legs' fixups
                    all_held += held ? 1 : 0;
                }
            }
    EXPECT_EQ(all_held, 27); // three held states per leg, each with its own (s, s) only
}
