// Inverter non-idealities of the plant against hand-derived volt-seconds:
// dead time (the leg's level during blanking follows the current through the
// NPC diodes; mean error -sgn(i) (Vdc/2) t_dead per commutation pair) and the
// on-state voltage (2 devices per path, drop follows the sign of the current).
//
// Method: with Rs ~ 0 the stator flux integrates the applied phase voltage,
// dpsi_s/dt = v_s, so the difference of psi_s between a run with the
// non-ideality and the same run with the ideal inverter IS the volt-second
// error, which is compared with the hand-derived value. Huge capacitors keep
// vc1 = vc2 = Vdc/2 and a huge inertia keeps the rotor still.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "plant/plant.h"

namespace {

constexpr uint8_t N = 0, O = 1, P = 2;
const double kT = 200e-6;
const double kTd = 2e-6;
const double kVdc = 311.0;

plant_config base_cfg()
{
    plant_config c;
    plant_default_config(&c);
    c.motor.Rs_ohm = 1e-9;
    c.motor.J_kgm2 = 1e4;
    c.dc.c1_F = 1e3;
    c.dc.c2_F = 1e3;
    c.dc.vdc_V = kVdc;
    return c;
}

// Phase currents (zero sum) with zero rotor current: psi_s = Ls i, psi_r = Lm i.
void set_currents(plant_state &s, double ia, double ib, double ic)
{
    const plant_motor_params &m = s.cfg.motor;
    double a = ia, b = (ib - ic) / std::sqrt(3.0);
    s.psi_s[0] = (m.Lls_H + m.Lm_H) * a;
    s.psi_s[1] = (m.Lls_H + m.Lm_H) * b;
    s.psi_r[0] = m.Lm_H * a;
    s.psi_r[1] = m.Lm_H * b;
}

struct Pair {
    plant_state ideal, real;
};

// Two plants from the same state, the second with the non-idealities given.
Pair make_pair(double td, double v_on, double ia, double ib, double ic)
{
    Pair p;
    plant_config c = base_cfg();
    EXPECT_EQ(plant_init(&p.ideal, &c), 0);
    c.inverter.dead_time_s = td;
    c.inverter.v_on_V = v_on;
    EXPECT_EQ(plant_init(&p.real, &c), 0);
    set_currents(p.ideal, ia, ib, ic);
    set_currents(p.real, ia, ib, ic);
    return p;
}

void both(Pair &p, const uint8_t v0[3], const uint8_t v1[3], double duty0)
{
    plant_advance(&p.ideal, v0, v1, duty0, kT);
    plant_advance(&p.real, v0, v1, duty0, kT);
}

// Volt-second error of the real inverter, alpha and beta, V s.
double d_alpha(const Pair &p) { return p.real.psi_s[0] - p.ideal.psi_s[0]; }
double d_beta(const Pair &p) { return p.real.psi_s[1] - p.ideal.psi_s[1]; }

} // namespace

// One commutation pair of leg a per period (O -> X at the period start, X -> O
// at mid-period) for X = P and N and both current directions. Hand
// derivation: while blanked the leg sits at the lower of the two levels when
// i_a > 0 and at the upper one when i_a < 0; so for i_a > 0 the edge to the
// higher level (O->P, N->O) comes t_d late and the other is on time, and for
// i_a < 0 the reverse. Either way the leg loses sgn(i_a) (Vdc/2) t_d per pair,
// and the phase (amplitude-invariant alpha) sees 2/3 of a leg-a error.
TEST(PlantDeadTime, VoltSecondErrorPerCommutationPairIsSignOfCurrentTimesHalfVdcTimesDeadTime)
{
    const uint8_t ooo[3] = {O, O, O};
    for (uint8_t x : {P, N}) {
        for (double sgn : {1.0, -1.0}) {
            Pair p = make_pair(kTd, 0.0, 20.0 * sgn, -10.0 * sgn, -10.0 * sgn);
            both(p, ooo, ooo, 1.0); // a previous vector, so the next edge is a commutation
            const uint8_t xoo[3] = {x, O, O};
            const int periods = 2;
            for (int k = 0; k < periods; ++k)
                both(p, xoo, ooo, 0.5);
            double expect = periods * (2.0 / 3.0) * (-sgn) * (kVdc / 2.0) * kTd;
            EXPECT_NEAR(d_alpha(p), expect, 2e-3 * std::fabs(expect)) << "level " << int(x) << " sgn " << sgn;
            EXPECT_NEAR(d_beta(p), 0.0, 1e-9);
            // The currents kept their sign throughout (the premise of the hand derivation).
            plant_truth tr;
            plant_get_truth(&p.real, &tr);
            EXPECT_GT(tr.ia_A * sgn, 5.0);
            // As a mean voltage over the two periods: -sgn (Vdc/2) t_d / T per pair and period.
            double mean_leg_V = d_alpha(p) * 1.5 / (periods * kT);
            EXPECT_NEAR(mean_leg_V, -sgn * kVdc / 2.0 * kTd / kT, 2e-3 * kVdc / 2.0 * kTd / kT);
        }
    }
}

// A blanking interval that starts 1 us before the period ends runs on into
// the next period; the total error is still one edge's worth.
TEST(PlantDeadTime, BlankingCarriesAcrossThePeriodBoundary)
{
    const uint8_t ooo[3] = {O, O, O}, poo[3] = {P, O, O};
    Pair p = make_pair(kTd, 0.0, 20.0, -10.0, -10.0);
    both(p, ooo, ooo, 1.0);
    both(p, ooo, poo, 1.0 - 1e-6 / kT); // O -> P at 199 us: blanked until 201 us
    both(p, poo, ooo, 0.5);             // P -> O at 100 us: on time (i_a > 0)
    double expect = (2.0 / 3.0) * -(kVdc / 2.0) * kTd;
    EXPECT_NEAR(d_alpha(p), expect, 2e-3 * std::fabs(expect));
}

// A commutation shorter than the dead time never turns its device on: P for
// 1 us after O, with i_a > 0, leaves the leg at O the whole time.
TEST(PlantDeadTime, CommutationShorterThanTheDeadTimeIsSwallowed)
{
    const uint8_t ooo[3] = {O, O, O}, poo[3] = {P, O, O};
    Pair p = make_pair(kTd, 0.0, 20.0, -10.0, -10.0);
    both(p, ooo, ooo, 1.0);
    both(p, poo, ooo, 1e-6 / kT);
    double expect = (2.0 / 3.0) * -(kVdc / 2.0) * 1e-6; // the ideal leg's whole P pulse is lost
    EXPECT_NEAR(d_alpha(p), expect, 2e-3 * std::fabs(expect));
    // Switch counting stays with the commands (two commutations).
    EXPECT_EQ(p.real.switch_count, p.ideal.switch_count);
}

// Dead time 0 is the ideal inverter, bit for bit.
TEST(PlantDeadTime, ZeroDeadTimeAndZeroDropAreTheIdealInverter)
{
    const uint8_t ooo[3] = {O, O, O}, poo[3] = {P, O, O}, pon[3] = {P, O, N};
    Pair p = make_pair(0.0, 0.0, 20.0, -10.0, -10.0);
    for (int k = 0; k < 5; ++k) {
        both(p, poo, pon, 0.3);
        both(p, pon, ooo, 0.6);
    }
    EXPECT_EQ(d_alpha(p), 0.0);
    EXPECT_EQ(d_beta(p), 0.0);
}

// On-state voltage: each leg is 2 v_on lower when its current flows into the
// motor and 2 v_on higher when it flows out; a leg without current has no drop.
// Legs (a, b, c) with i = (+20, -10, -10) A and v_on = 1 V: (-2, +2, +2) V ->
// phase a = -2 - 2/3 = -8/3 V, beta 0. With i = (0, +10, -10): (0, -2, +2) ->
// alpha 0, beta = (-2 - 2) / sqrt(3).
TEST(PlantOnStateVoltage, DropFollowsTheSignOfEachCurrent)
{
    const uint8_t poo[3] = {P, O, O}, ooo[3] = {O, O, O};
    for (double sgn : {1.0, -1.0}) {
        Pair p = make_pair(0.0, 1.0, 20.0 * sgn, -10.0 * sgn, -10.0 * sgn);
        both(p, poo, poo, 1.0);
        EXPECT_NEAR(d_alpha(p), -sgn * 8.0 / 3.0 * kT, 1e-6 * 8.0 / 3.0 * kT) << sgn;
        EXPECT_NEAR(d_beta(p), 0.0, 1e-12);
    }
    Pair z = make_pair(0.0, 1.0, 0.0, 10.0, -10.0);
    both(z, ooo, ooo, 1.0);
    EXPECT_NEAR(d_alpha(z), 0.0, 1e-12);
    EXPECT_NEAR(d_beta(z), -4.0 / std::sqrt(3.0) * kT, 1e-6 * 4.0 / std::sqrt(3.0) * kT);
}

