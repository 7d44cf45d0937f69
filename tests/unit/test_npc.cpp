// The NPC inverter's geometry (dtc/npc.h): the leg rule, the 27 states and
// their leg codes, the 19 space vectors, the NP current of each state, and per
// pair of states the commutations, the P<->N steps and the P<->N-safe state,
// checked against the PLANT's inverter model (plant_inverter_output), the
// states' names written out by hand and base-3 digits worked out here.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <cstring>
#include <random>

#include "dtc/npc.h"
#include "im_ref.hpp"
#include "plant/plant.h"

namespace {

using cd = std::complex<double>;
constexpr double kPi = 3.14159265358979323846;

// Leg codes of a state number, written out independently: state = a*9 + b*3 + c.
void legs_of(int state, uint8_t legs[3])
{
    legs[0] = uint8_t(state / 9);
    legs[1] = uint8_t((state / 3) % 3);
    legs[2] = uint8_t(state % 3);
}

int state_of(const hal_vector &v) { return v.leg[0] * 9 + v.leg[1] * 3 + v.leg[2]; }

// Stator voltage of a state from the plant (isolated star), alpha-beta.
cd plant_voltage(int state, double vc1, double vc2, const double i_abc[3] = nullptr, double *i_np = nullptr)
{
    uint8_t legs[3];
    legs_of(state, legs);
    double zero[3] = {0, 0, 0}, v[3], inp = 0;
    plant_inverter_output(legs, vc1, vc2, i_abc ? i_abc : zero, v, &inp);
    if (i_np)
        *i_np = inp;
    Eigen::Vector2d ab = imref::clarke(v);
    return {ab[0], ab[1]};
}

// One leg: the leg codes are hal_leg_state's, a step between P and N is the
// only forbidden one, and the safe code holds such a step at O, every other
// one as asked (written out case by case).
TEST(Npc, LegRule)
{
    EXPECT_EQ(NPC_N, unsigned(HAL_LEG_N));
    EXPECT_EQ(NPC_O, unsigned(HAL_LEG_O));
    EXPECT_EQ(NPC_P, unsigned(HAL_LEG_P));
    const unsigned codes[3] = {NPC_N, NPC_O, NPC_P};
    for (unsigned a : codes)
        for (unsigned b : codes) {
            const bool pn = (a == 0u && b == 2u) || (a == 2u && b == 0u);
            EXPECT_EQ(bool(NPC_LEG_PN(a, b)), pn) << a << " -> " << b;
            EXPECT_EQ(unsigned(NPC_LEG_SAFE(a, b)), pn ? 1u : b) << a << " -> " << b;
        }
}

TEST(Npc, VoltagesAndNpCurrentMatchThePlant)
{
    const double vc1 = 161.0, vc2 = 149.0; // deliberately unbalanced
    const double i_abc[3] = {12.5, -3.0, -9.5};
    for (int st = 0; st < 27; ++st) {
        double inp_plant;
        cd vp = plant_voltage(st, vc1, vc2, i_abc, &inp_plant);
        float vf[2];
        npc_state_voltage(uint8_t(st), float(vc1), float(vc2), vf);
        float iabc_f[3] = {12.5f, -3.0f, -9.5f};
        SCOPED_TRACE(st);
        EXPECT_NEAR(vf[0], vp.real(), 1e-3);
        EXPECT_NEAR(vf[1], vp.imag(), 1e-3);
        EXPECT_NEAR(npc_np_current(uint8_t(st), iabc_f), inp_plant, 1e-5);
        hal_vector hv;
        npc_legs(uint8_t(st), &hv);
        EXPECT_EQ(state_of(hv), st);
        EXPECT_EQ(npc_state_of(&hv), st);
    }
}

// The 27 states written out by hand from the NPC topology (leg a, b, c; N, O, P),
// in the documented numbering a*9 + b*3 + c.
const char *const kStateNames[27] = {
    "NNN", "NNO", "NNP", "NON", "NOO", "NOP", "NPN", "NPO", "NPP",
    "ONN", "ONO", "ONP", "OON", "OOO", "OOP", "OPN", "OPO", "OPP",
    "PNN", "PNO", "PNP", "PON", "POO", "POP", "PPN", "PPO", "PPP",
};

int level_of(char c) { return c == 'N' ? 0 : (c == 'O' ? 1 : 2); }

// The precomputed state tables (legs, voltage per capacitor, NP current,
// P<->N steps, commutations, P<->N-safe target) for every state and every
// pair, against the hand-written names and the plant's inverter model,
// with out-of-range indices handled as documented.
TEST(Npc, StateTablesMatchTheTopologyForEveryPair)
{
    const double vc1 = 157.0, vc2 = 151.5;
    const double i_abc[3] = {-7.25, 11.0, -3.75};
    const float i_abc_f[3] = {-7.25f, 11.0f, -3.75f};
    for (int from = 0; from < 27; ++from) {
        SCOPED_TRACE(kStateNames[from]);
        hal_vector hv;
        npc_legs(uint8_t(from), &hv);
        for (int k = 0; k < 3; ++k)
            EXPECT_EQ(int(hv.leg[k]), level_of(kStateNames[from][k]));
        double inp_plant;
        cd vp = plant_voltage(from, vc1, vc2, i_abc, &inp_plant);
        float v[2];
        npc_state_voltage(uint8_t(from), float(vc1), float(vc2), v);
        EXPECT_NEAR(v[0], vp.real(), 1e-4);
        EXPECT_NEAR(v[1], vp.imag(), 1e-4);
        EXPECT_NEAR(npc_np_current(uint8_t(from), i_abc_f), inp_plant, 1e-6);
        for (int to = 0; to < 27; ++to) {
            SCOPED_TRACE(kStateNames[to]);
            int changes = 0;
            bool pn = false;
            char safe[4] = {0, 0, 0, 0};
            for (int k = 0; k < 3; ++k) {
                int a = level_of(kStateNames[from][k]), b = level_of(kStateNames[to][k]);
                changes += std::abs(a - b);
                pn |= std::abs(a - b) == 2;
                safe[k] = std::abs(a - b) == 2 ? 'O' : kStateNames[to][k];
            }
            EXPECT_EQ(int(npc_leg_changes(uint8_t(from), uint8_t(to))), changes);
            EXPECT_EQ(npc_pn_step(uint8_t(from), uint8_t(to)), pn);
            EXPECT_STREQ(kStateNames[npc_pn_safe(uint8_t(from), uint8_t(to))], safe);
        }
        EXPECT_EQ(npc_leg_changes(uint8_t(from), 27u), 0u);
        EXPECT_FALSE(npc_pn_step(0xFFu, uint8_t(from)));
        EXPECT_EQ(npc_pn_safe(uint8_t(from), 0xFFu), NPC_STATE_OOO);
    }
    hal_vector hv;
    npc_legs(0xFFu, &hv);
    EXPECT_EQ(state_of(hv), int(NPC_STATE_OOO));
    EXPECT_EQ(npc_np_current(27u, i_abc_f), 0.0f);
    float v[2];
    npc_state_voltage(200u, float(vc1), float(vc2), v);
    EXPECT_EQ(v[0], 0.0f);
    EXPECT_EQ(v[1], 0.0f);
}

// npc_legs_voltage (leg voltages looked up by leg code) gives the very bits
// of npc_state_voltage (selections) for every state, balanced or not (the
// control step's observer input relies on it: tools/sil_identical.sh).
TEST(Npc, LegsVoltageEqualsStateVoltageBitForBit)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.f, 400.f);
    for (int k = 0; k < 200; ++k) {
        float vc1 = u(rng), vc2 = u(rng);
        const float leg_V[3] = {-vc2, 0.0f, vc1};
        for (int st = 0; st < 27; ++st) {
            float a[2], b[2];
            hal_vector hv;
            npc_legs(uint8_t(st), &hv);
            npc_state_voltage(uint8_t(st), vc1, vc2, a);
            npc_legs_voltage(&hv, leg_V, b);
            ASSERT_EQ(std::memcmp(a, b, sizeof a), 0) << kStateNames[st] << " " << vc1 << " " << vc2;
        }
    }
}

// The packed leg codes (the DTC's and the actuation's output) against the base-3 digits of the
// state number, and the step's vectors against its states.
TEST(Npc, PackedLegsAreTheBase3Digits)
{
    for (int st = 0; st < 27; ++st) {
        uint32_t want = uint32_t(st / 9) | uint32_t(st / 3 % 3) << 8 | uint32_t(st % 3) << 16;
        EXPECT_EQ(npc_state_legs_packed[st], want) << kStateNames[st];
    }
}

// Both vectors of an actuation written at once: for every pair of states the
// six leg bytes are each state's base-3 digits (leg a, b, c), and the duty
// after them is left as it was.
TEST(Npc, LegsPairWritesBothStatesBase3Digits)
{
    for (int s0 = 0; s0 < 27; ++s0)
        for (int s1 = 0; s1 < 27; ++s1) {
            hal_actuation a;
            std::memset(&a, 0xA5, sizeof a);
            a.duty0 = 0.25f;
            npc_legs_pair_unchecked(uint8_t(s0), uint8_t(s1), &a);
            const int st[2] = {s0, s1};
            for (int v = 0; v < 2; ++v) {
                EXPECT_EQ(int(a.vector[v].leg[0]), st[v] / 9) << kStateNames[s0] << " " << kStateNames[s1];
                EXPECT_EQ(int(a.vector[v].leg[1]), st[v] / 3 % 3) << kStateNames[s0] << " " << kStateNames[s1];
                EXPECT_EQ(int(a.vector[v].leg[2]), st[v] % 3) << kStateNames[s0] << " " << kStateNames[s1];
            }
            EXPECT_EQ(a.duty0, 0.25f);
        }
}

// The 19 space vectors: magnitude class and direction as documented in dtc/npc.h,
// every redundant state of a vector giving the same voltage (balanced link).
TEST(Npc, SpaceVectorClassesAndDirections)
{
    const double vdc = 311.0;
    int seen[27] = {0};
    for (int sv = 0; sv < 19; ++sv) {
        uint8_t st[3];
        int n = npc_sv_states(uint8_t(sv), st);
        ASSERT_GE(n, 1);
        double mag_want, ang_want;
        if (sv == 0) {
            mag_want = 0;
            ang_want = 0;
            EXPECT_EQ(n, 3);
        } else if (sv <= 6) {
            mag_want = vdc / 3;
            ang_want = (sv - 1) * 60.0;
            EXPECT_EQ(n, 2);
            EXPECT_EQ(npc_sv_class(uint8_t(sv)), NPC_CLASS_SMALL);
        } else if (sv <= 12) {
            mag_want = vdc / std::sqrt(3.0);
            ang_want = 30.0 + (sv - 7) * 60.0;
            EXPECT_EQ(n, 1);
            EXPECT_EQ(npc_sv_class(uint8_t(sv)), NPC_CLASS_MEDIUM);
        } else {
            mag_want = 2 * vdc / 3;
            ang_want = (sv - 13) * 60.0;
            EXPECT_EQ(n, 1);
            EXPECT_EQ(npc_sv_class(uint8_t(sv)), NPC_CLASS_LARGE);
        }
        for (int i = 0; i < n; ++i) {
            SCOPED_TRACE(testing::Message() << "sv " << sv << " state " << int(st[i]));
            seen[st[i]]++;
            EXPECT_EQ(npc_state_sv(st[i]), sv);
            cd v = plant_voltage(st[i], vdc / 2, vdc / 2);
            EXPECT_NEAR(std::abs(v), mag_want, 1e-6);
            if (sv != 0) {
                cd dir = std::polar(1.0, ang_want * kPi / 180.0);
                EXPECT_NEAR(std::arg(v / dir), 0.0, 1e-9);
            }
        }
    }
    for (int s = 0; s < 27; ++s)
        EXPECT_EQ(seen[s], 1) << "state " << s << " must belong to exactly one vector";
}

// The DTC gives a zero intermediate state the shortest segment without
// working out its NP current (dtc3l.c, cut_intermediate_short): that relies on every zero state drawing
// exactly no current from three phase currents formed as the step forms them
// (ic = -ia - ib in float): NNN and PPP have no leg at O, OOO sums all three.
TEST(Npc, ZeroStatesDrawExactlyNoCurrentFromTheStepsPhaseCurrents)
{
    std::mt19937 rng(11u);
    std::uniform_real_distribution<float> mant(-1.0f, 1.0f);
    std::uniform_int_distribution<int> expo(-30, 30);
    for (int n = 0; n < 200000; n++) {
        float ia = std::ldexp(mant(rng), expo(rng));
        float ib = std::ldexp(mant(rng), expo(rng));
        const float i_abc[3] = {ia, ib, -ia - ib};
        for (int zero : {0, 13, 26}) {
            float inp = npc_np_current(uint8_t(zero), i_abc);
            ASSERT_EQ(inp, 0.0f) << "state " << zero << " ia " << ia << " ib " << ib;
        }
        // and a small state's does not vanish in general (the test can fail)
        if (n == 0) {
            EXPECT_NE(npc_np_current(22u, i_abc), 0.0f);
        }
    }
}

} // namespace
