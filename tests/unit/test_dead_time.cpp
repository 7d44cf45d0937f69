// Dead-time volt-seconds per leg (the reference tests/oracles/dead_time_leg_error.c) against
// cases worked out by hand from the NPC leg's commutation: an edge a -> b is
// late by the dead time when the current flows the way of the step, on time
// otherwise; a late edge costs (v_b - v_a) Td over the period T.
#include <gtest/gtest.h>

#include "dead_time_leg_error.h"
#include "dtc/inverter_model.h"

namespace {

constexpr float kVc1 = 160.0f, kVc2 = 150.0f;
constexpr float kDtPerT = 2e-6f / 2e-4f; // 2 us of 200 us
constexpr float kBand = 1.0f;

hal_vector vec(uint8_t a, uint8_t b, uint8_t c) { return hal_vector{{a, b, c}}; }

hal_actuation act(hal_vector v0, hal_vector v1, float duty0) { return hal_actuation{{v0, v1}, duty0}; }

enum : uint8_t { N = HAL_LEG_N, O = HAL_LEG_O, P = HAL_LEG_P };

struct Out {
    float dv[3];
};

Out run(const hal_actuation &prev, const hal_actuation &now, float ia, float ib, float ic)
{
    Out o{};
    const float i[3] = {ia, ib, ic};
    dead_time_leg_error(&prev, &now, i, kVc1, kVc2, kDtPerT, kBand, o.dv);
    return o;
}

} // namespace

// O -> P on leg a: current into the motor keeps the leg at O for Td (late,
// loses vc1 Td / T = 1.6 V); current out of the motor takes P through D1 D2 at
// once (on time).
TEST(DeadTime, RisingEdgeIsLateOnlyWithCurrentIntoTheMotor)
{
    hal_actuation prev = act(vec(O, O, O), vec(O, O, O), 0.5f);
    hal_actuation now = act(vec(P, O, O), vec(P, O, O), 1.0f);
    Out in = run(prev, now, 10.0f, -5.0f, -5.0f);
    EXPECT_FLOAT_EQ(in.dv[0], -kVc1 * kDtPerT); // -1.6 V
    EXPECT_FLOAT_EQ(in.dv[1], 0.0f);
    EXPECT_FLOAT_EQ(in.dv[2], 0.0f);
    Out out = run(prev, now, -10.0f, 5.0f, 5.0f);
    EXPECT_FLOAT_EQ(out.dv[0], 0.0f);
}

// P -> O: late (stays at P, gains vc1 Td / T) only with current out of the
// motor; N -> O with current into the motor is late (stays at N: O - N = vc2).
TEST(DeadTime, FallingAndLowerEdges)
{
    hal_actuation prev = act(vec(P, N, O), vec(P, N, O), 1.0f);
    hal_actuation now = act(vec(O, O, O), vec(O, O, O), 1.0f);
    Out o = run(prev, now, -10.0f, 10.0f, 0.0f);
    EXPECT_FLOAT_EQ(o.dv[0], kVc1 * kDtPerT);  // P -> O, i < 0: +1.6 V
    EXPECT_FLOAT_EQ(o.dv[1], -kVc2 * kDtPerT); // N -> O, i > 0: -1.5 V
    EXPECT_FLOAT_EQ(o.dv[2], 0.0f);            // no edge
    Out on_time = run(prev, now, 10.0f, -10.0f, 0.0f);
    EXPECT_FLOAT_EQ(on_time.dv[0], 0.0f);
    EXPECT_FLOAT_EQ(on_time.dv[1], 0.0f);
}

// Two edges in one period: the previous period's last vector -> vector[0] at
// the start, vector[0] -> vector[1] at the split. Leg a: O -> P (late, i > 0)
// then P -> O (on time, i > 0): -1.6 V. A vector applied for no time has no
// edge: with duty0 = 1, vector[1] is never applied.
TEST(DeadTime, EdgesAtThePeriodStartAndAtTheSplit)
{
    hal_actuation prev = act(vec(P, P, P), vec(O, O, O), 0.3f); // ended on OOO
    hal_actuation now = act(vec(P, O, N), vec(O, O, O), 0.4f);
    Out o = run(prev, now, 10.0f, 0.0f, -10.0f);
    EXPECT_FLOAT_EQ(o.dv[0], -kVc1 * kDtPerT);
    // leg c: O -> N (falling, i < 0: late, keeps O: gains vc2 Td) then N -> O
    // (rising, i < 0: on time)
    EXPECT_FLOAT_EQ(o.dv[2], kVc2 * kDtPerT);
    hal_actuation only0 = act(vec(P, O, N), vec(O, O, O), 1.0f);
    Out one = run(prev, only0, 10.0f, 0.0f, -10.0f);
    EXPECT_FLOAT_EQ(one.dv[0], -kVc1 * kDtPerT);
    EXPECT_FLOAT_EQ(one.dv[2], kVc2 * kDtPerT);
    hal_actuation prev_only0 = act(vec(P, P, P), vec(O, O, O), 1.0f); // ended on PPP
    Out from_p = run(prev_only0, only0, 10.0f, 0.0f, -10.0f);
    EXPECT_FLOAT_EQ(from_p.dv[0], 0.0f);                      // P -> P: no edge
    // leg c P -> N is a direct step the firmware never commands; it counts as
    // one step of vc1 + vc2 (i < 0: late, stays at P)
    EXPECT_FLOAT_EQ(from_p.dv[2], (kVc1 + kVc2) * kDtPerT);
}

// Near zero current the sign is softened linearly over +-band: at 0 A half
// the edge is late; at +band/2, three quarters.
TEST(DeadTime, SignSoftenedAroundZeroCurrent)
{
    hal_actuation prev = act(vec(O, O, O), vec(O, O, O), 1.0f);
    hal_actuation now = act(vec(P, P, P), vec(P, P, P), 1.0f);
    Out o = run(prev, now, 0.0f, 0.5f, -2.0f);
    EXPECT_FLOAT_EQ(o.dv[0], -0.5f * kVc1 * kDtPerT);
    EXPECT_FLOAT_EQ(o.dv[1], -0.75f * kVc1 * kDtPerT);
    EXPECT_FLOAT_EQ(o.dv[2], 0.0f);
}

TEST(DeadTime, ZeroDeadTimeGivesZero)
{
    hal_actuation prev = act(vec(N, N, N), vec(O, O, O), 0.5f);
    hal_actuation now = act(vec(P, P, P), vec(O, N, P), 0.5f);
    const float i[3] = {10.0f, -20.0f, 10.0f};
    float dv[3] = {1.0f, 1.0f, 1.0f};
    dead_time_leg_error(&prev, &now, i, kVc1, kVc2, 0.0f, kBand, dv);
    for (float x : dv)
        EXPECT_EQ(x, 0.0f);
}

// Every edge between any two
// of the 27 states, at each of the three places in a period (previous vector
// -> vector[0] -> vector[1]), against the rule worked out leg by leg here.
TEST(DeadTime, EveryEdgeBetweenAnyTwoStatesLegByLeg)
{
    const float i[3] = {7.0f, -3.0f, -4.0f};
    auto code = [](int st, int leg) { return uint8_t(leg == 0 ? st / 9 : (leg == 1 ? st / 3 % 3 : st % 3)); };
    auto level = [](uint8_t c) { return c == P ? kVc1 : (c == N ? -kVc2 : 0.0f); };
    for (int a = 0; a < 27; ++a) {
        for (int b = 0; b < 27; ++b) {
            hal_vector va = vec(code(a, 0), code(a, 1), code(a, 2));
            hal_vector vb = vec(code(b, 0), code(b, 1), code(b, 2));
            // a at the end of the previous period, b the whole of this one (edge 1);
            // a then b within this period after a previous a (edge 2)
            for (int place = 0; place < 2; ++place) {
                hal_actuation prev = place == 0 ? act(vec(O, O, O), va, 0.5f) : act(va, va, 1.0f);
                hal_actuation now = place == 0 ? act(vb, vb, 1.0f) : act(va, vb, 0.5f);
                Out o = run(prev, now, i[0], i[1], i[2]);
                for (int leg = 0; leg < 3; ++leg) {
                    uint8_t la = code(a, leg), lb = code(b, leg);
                    // |i| >= band: fully late when the current flows the way of the step
                    bool late = la != lb && ((lb > la) == (i[leg] > 0.0f));
                    float want = late ? -(level(lb) - level(la)) * kDtPerT : 0.0f;
                    ASSERT_NEAR(o.dv[leg], want, 1e-5f) << a << " -> " << b << " leg " << leg << " place " << place;
                }
            }
        }
    }
}

// inverter_dead_time_edge (the firmware's edge on levels read already, without
// an a == b test: the inverter model knows the leg moves): for every pair
// of different codes and a rising, falling and softened current, the late
// part of the step worked out here: (v_b - v_a) dt_per_T x late_up (rising) or
// x (1 - late_up) (falling), subtracted from the leg voltage; bit for bit as
// the reference's edge (dead_time_edge), which adds only the test.
TEST(DeadTime, EdgeMovingIsTheLatePartOfEveryStep)
{
    const float level[3] = {-kVc2, 0.0f, kVc1};
    for (uint32_t a = 0; a < 3; ++a) {
        for (uint32_t b = 0; b < 3; ++b) {
            if (a == b)
                continue;
            for (float late_up : {0.0f, 0.25f, 1.0f}) {
                float late = b > a ? late_up : 1.0f - late_up;
                float want = 12.0f - (level[b] - level[a]) * kDtPerT * late;
                float got = inverter_dead_time_edge(b > a, late_up, level[a], level[b], kDtPerT, 12.0f);
                EXPECT_NEAR(got, want, 1e-5f) << a << " -> " << b << " late_up " << late_up;
                float checked = dead_time_edge(a, b, late_up, level, kDtPerT, 12.0f);
                EXPECT_EQ(got, checked);
            }
        }
    }
    EXPECT_EQ(dead_time_edge(1u, 1u, 0.5f, level, kDtPerT, 12.0f), 12.0f); // no step: nothing
}
