// The stator voltage the inverter model gives the observer and the
// loss-of-control monitor with a real inverter (dtc/inverter_model.h,
// inverter_voltage: the legs' levels, the device drops and the dead-time
// edges worked out on packed leg codes) against a reference built here from
// the parts the unit tests check on their own: the commanded leg voltages
// mixed by the duty, the drop 2 v_drop sat(i / 0.5 A) against the current,
// dead_time_leg_error (tests/oracles; hand-derived cases in
// test_dead_time.cpp), then the Clarke transform, in double. The model's
// constants are the configuration's own (ctl_cfg_derive).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "dead_time_leg_error.h"
#include "dtc/ctl_cfg.h"
#include "dtc/inverter_model.h"
#include "dtc/npc.h"

namespace {

constexpr double kBandA = 0.5; // the drop's and the dead time's softened sign (INVERTER_DROP_BAND_A)

struct Case {
    uint8_t end, st0, st1; // state the last period ended on, this period's two states
    float duty0;           // share of st0, 0..1
    float i[3];            // phase currents, A (sum 0)
    float vc1, vc2;        // capacitor voltages, V
};

double sat(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }

// The reference stator voltage (alpha, beta), V.
void reference(const Case &c, double v_drop_V, double dt_per_T, double v_ab[2])
{
    hal_actuation prev{}, act{};
    npc_legs(c.end, &prev.vector[0]);
    npc_legs(c.end, &prev.vector[1]);
    prev.duty0 = 0.5f; // both vectors the end state: it ends there
    npc_legs(c.st0, &act.vector[0]);
    npc_legs(c.st1, &act.vector[1]);
    act.duty0 = c.duty0;
    float dv[3];
    dead_time_leg_error(&prev, &act, c.i, c.vc1, c.vc2, float(dt_per_T), float(kBandA), dv);
    const double level[3] = {-double(c.vc2), 0.0, double(c.vc1)}; // N, O, P
    double leg[3];
    for (int k = 0; k < 3; ++k) {
        double cmd = c.duty0 * level[act.vector[0].leg[k]] + (1.0 - c.duty0) * level[act.vector[1].leg[k]];
        leg[k] = cmd - 2.0 * v_drop_V * sat(c.i[k] / kBandA, -1.0, 1.0) + dv[k];
    }
    v_ab[0] = (2.0 * leg[0] - leg[1] - leg[2]) / 3.0;
    v_ab[1] = (leg[1] - leg[2]) / std::sqrt(3.0);
}

struct Model {
    ctl_cfg cfg;
    uint8_t end = 0; // the state the last period asked for ended on
    explicit Model(float dead_time_s, float v_drop_V)
    {
        ctl_cfg_default(&cfg);
        cfg.dead_time_comp_s = dead_time_s;
        cfg.v_drop_V = v_drop_V;
        ctl_cfg_derive(&cfg);
    }
    // inverter_voltage for @p c: the period applying c's states after one
    // that ended on c.end, at c's capacitor voltages and currents. end is then
    // the state that period ended on.
    void voltage(const Case &c, double v_ab[2])
    {
        inverter_period p;
        std::memset(&p, 0, sizeof p);
        npc_legs(c.st0, &p.act.vector[0]);
        npc_legs(c.st1, &p.act.vector[1]);
        p.act.duty0 = c.duty0;
        p.state[0] = c.st0;
        p.state[1] = c.st1;
        p.end_state = c.end;
        const float level_V[3] = {-c.vc2, 0.0f, c.vc1}; // N, O, P
        float v[2];
        end = inverter_voltage(&p, level_V, c.i, &cfg.inv, v);
        v_ab[0] = v[0];
        v_ab[1] = v[1];
    }
};

// Random periods: every pair of states, duty 0, 1 or between, currents of
// either sign and inside the softened band, unequal capacitors.
std::vector<Case> cases(unsigned n)
{
    std::mt19937 rng(20261128u);
    std::uniform_int_distribution<int> state(0, 26);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f), amp(-40.0f, 40.0f), small(-0.6f, 0.6f),
        vc(140.0f, 170.0f);
    std::vector<Case> out;
    for (unsigned k = 0; k < n; ++k) {
        Case c{};
        c.end = uint8_t(state(rng));
        c.st0 = uint8_t(state(rng));
        c.st1 = k % 5 == 0 ? c.st0 : uint8_t(state(rng)); // one vector only, now and then
        float pick = u01(rng);
        c.duty0 = pick < 0.15f ? 0.0f : (pick < 0.3f ? 1.0f : u01(rng));
        c.i[0] = k % 3 == 0 ? small(rng) : amp(rng);
        c.i[1] = k % 4 == 0 ? small(rng) : amp(rng);
        c.i[2] = -c.i[0] - c.i[1];
        c.vc1 = vc(rng);
        c.vc2 = vc(rng);
        out.push_back(c);
    }
    return out;
}

// inverter_voltage against the reference over 4000 random periods.
struct Result {
    bool real_inverter = false; // the configuration builds the voltage leg by leg
    int edges = 0;              // periods whose dead time moved the voltage (the cases reach the edges)
    int wrong_end = 0;          // periods whose end state (the next period's edges start there) is not the last applied
    double worst_V = 0.0;       // largest |v_ctl - v_ref|
    std::string worst_case;     // ... and where
};

Result compare(float dead_time_s, float v_drop_V)
{
    Result r;
    Model model(dead_time_s, v_drop_V);
    r.real_inverter = model.cfg.inv.real;
    const double dt_per_T = model.cfg.inv.dead_time_per_T;
    for (const Case &c : cases(4000)) {
        double got[2] = {0.0, 0.0}, want[2], ideal[2];
        model.voltage(c, got);
        // the state applied last: st1 after a split or st1 alone, st0 alone at duty 1
        if (model.end != (c.duty0 < 1.0f ? c.st1 : c.st0))
            r.wrong_end++;
        reference(c, v_drop_V, dt_per_T, want);
        reference(c, v_drop_V, 0.0, ideal);
        if (std::hypot(want[0] - ideal[0], want[1] - ideal[1]) > 0.1)
            r.edges++;
        double err = std::hypot(got[0] - want[0], got[1] - want[1]);
        if (err > r.worst_V || r.worst_case.empty()) {
            r.worst_V = err;
            r.worst_case = "end " + std::to_string(c.end) + ", states " + std::to_string(c.st0) + "/" +
                           std::to_string(c.st1) + ", duty0 " + std::to_string(c.duty0) + ", i " +
                           std::to_string(c.i[0]) + " " + std::to_string(c.i[1]) + " " + std::to_string(c.i[2]) +
                           ": ctl " + std::to_string(got[0]) + " " + std::to_string(got[1]) + " V, reference " +
                           std::to_string(want[0]) + " " + std::to_string(want[1]) + " V";
        }
    }
    std::printf("dead time %.1f us, drop %.1f V: 4000 periods, %d with dead-time edges, worst |v_ctl - v_ref| "
                "%.2e V\n",
                dead_time_s * 1e6, v_drop_V, r.edges, r.worst_V);
    return r;
}

// float arithmetic on voltages of about 170 V (an ulp is 1.5e-5 V); a wrong edge costs >= 0.5 V
constexpr double kBoundV = 1e-3;

// Every period of @p r built leg by leg, each ending on the state applied last,
// its voltage within kBoundV of the reference.
::testing::AssertionResult matches_reference(const Result &r)
{
    if (!r.real_inverter)
        return ::testing::AssertionFailure() << "the configuration does not build the voltage leg by leg";
    if (r.wrong_end != 0)
        return ::testing::AssertionFailure() << r.wrong_end << " periods end on another state than the last applied";
    if (!(r.worst_V < kBoundV))
        return ::testing::AssertionFailure() << "worst |v_ctl - v_ref| " << r.worst_V << " V at " << r.worst_case;
    return ::testing::AssertionSuccess();
}

} // namespace

// The band of the softened sign is the one the reference is built on.
TEST(CtlInverterModel, SoftenedSignBand) { EXPECT_EQ(double(INVERTER_DROP_BAND_A), kBandA); }

TEST(CtlInverterModel, VoltageMatchesTheDeadTimeReferenceWithDrops)
{
    Result r = compare(2e-6f, 1.0f);
    EXPECT_TRUE(matches_reference(r));
    EXPECT_GT(r.edges, 1000) << "too few periods with dead-time edges to judge";
}

TEST(CtlInverterModel, VoltageMatchesTheDeadTimeReferenceWithoutDrops)
{
    Result r = compare(3e-6f, 0.0f);
    EXPECT_TRUE(matches_reference(r));
    EXPECT_GT(r.edges, 1000) << "too few periods with dead-time edges to judge";
}

TEST(CtlInverterModel, VoltageMatchesTheDropsWithoutDeadTime)
{
    Result r = compare(0.0f, 1.5f);
    EXPECT_TRUE(matches_reference(r));
    EXPECT_EQ(r.edges, 0) << "no dead time: no edges";
}

// A NaN duty counts as 1 (st0 applied alone), as wherever the duty is tested
// against 1: the period ends on st0, and the next one's edges start there.
TEST(CtlInverterModel, NanDutyEndsOnTheFirstState)
{
    Model model(2e-6f, 1.0f);
    Case c{};
    c.end = 13; // OOO
    c.st0 = 22; // POO
    c.st1 = 12; // OON
    c.duty0 = std::numeric_limits<float>::quiet_NaN();
    c.i[0] = 5.0f;
    c.i[1] = -2.0f;
    c.i[2] = -3.0f;
    c.vc1 = c.vc2 = 155.5f;
    double v[2];
    model.voltage(c, v); // the voltage is NaN; the end state is what is judged here
    EXPECT_EQ(model.end, c.st0);
    c.duty0 = 0.25f;
    model.voltage(c, v);
    EXPECT_EQ(model.end, c.st1);
}
