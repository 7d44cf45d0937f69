// Three-level NPC inverter and DC link of the plant, against hand-derived
// tables and closed-form circuit laws.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <vector>

#include "plant/plant.h"

namespace {

constexpr uint8_t N = 0, O = 1, P = 2, OFF = 3;

struct Row {
    uint8_t a, b, c;
    int va, vb, vc; // phase-to-star voltages in units of Vdc/6 (balanced capacitors)
    double i_np;    // NP current for i_abc = (11, -4, -7) A: sum over the legs at O
};

// Derived by hand: each leg sits at +Vdc/2 (P), 0 (O) or -Vdc/2 (N) from the
// neutral point, i.e. +3, 0, -3 in units of Vdc/6; the isolated star removes
// the mean of the three. Example PON: legs +3, 0, -3, mean 0 -> (3, 0, -3).
// Example NNO: legs -3, -3, 0, mean -2 -> (-1, -1, 2).
const Row kTable[27] = {
    {N, N, N, 0, 0, 0, 0.0},    {N, N, O, -1, -1, 2, -7.0}, {N, N, P, -2, -2, 4, 0.0},
    {N, O, N, -1, 2, -1, -4.0}, {N, O, O, -2, 1, 1, -11.0}, {N, O, P, -3, 0, 3, -4.0},
    {N, P, N, -2, 4, -2, 0.0},  {N, P, O, -3, 3, 0, -7.0},  {N, P, P, -4, 2, 2, 0.0},
    {O, N, N, 2, -1, -1, 11.0}, {O, N, O, 1, -2, 1, 4.0},   {O, N, P, 0, -3, 3, 11.0},
    {O, O, N, 1, 1, -2, 7.0},   {O, O, O, 0, 0, 0, 0.0},    {O, O, P, -1, -1, 2, 7.0},
    {O, P, N, 0, 3, -3, 11.0},  {O, P, O, -1, 2, -1, 4.0},  {O, P, P, -2, 1, 1, 11.0},
    {P, N, N, 4, -2, -2, 0.0},  {P, N, O, 3, -3, 0, -7.0},  {P, N, P, 2, -4, 2, 0.0},
    {P, O, N, 3, 0, -3, -4.0},  {P, O, O, 2, -1, -1, -11.0}, {P, O, P, 1, -2, 1, -4.0},
    {P, P, N, 2, 2, -4, 0.0},   {P, P, O, 1, 1, -2, -7.0},  {P, P, P, 0, 0, 0, 0.0},
};

const double kVdc = 311.0;
const double kIabc[3] = {11.0, -4.0, -7.0};

std::complex<double> space_vector(const double v[3])
{
    // amplitude-invariant Clarke, written out independently of the plant
    return {(2.0 * v[0] - v[1] - v[2]) / 3.0, (v[1] - v[2]) / std::sqrt(3.0)};
}

TEST(PlantInverter, AllStatesMatchHandTableBalanced)
{
    for (const Row &r : kTable) {
        uint8_t legs[3] = {r.a, r.b, r.c};
        double v[3], i_np = -99.0;
        plant_inverter_output(legs, kVdc / 2, kVdc / 2, kIabc, v, &i_np);
        SCOPED_TRACE(testing::Message() << "state " << int(r.a) << int(r.b) << int(r.c));
        EXPECT_NEAR(v[0], r.va * kVdc / 6, 1e-9);
        EXPECT_NEAR(v[1], r.vb * kVdc / 6, 1e-9);
        EXPECT_NEAR(v[2], r.vc * kVdc / 6, 1e-9);
        EXPECT_NEAR(i_np, r.i_np, 1e-12);
    }
}

TEST(PlantInverter, NineteenDistinctVectorsWithTheRightMagnitudes)
{
    std::vector<std::complex<double>> distinct;
    int n_zero = 0, n_small = 0, n_medium = 0, n_large = 0;
    for (const Row &r : kTable) {
        uint8_t legs[3] = {r.a, r.b, r.c};
        double v[3], i_np;
        plant_inverter_output(legs, kVdc / 2, kVdc / 2, kIabc, v, &i_np);
        std::complex<double> sv = space_vector(v);
        double m = std::abs(sv);
        if (m < 1e-9)
            ++n_zero;
        else if (std::fabs(m - kVdc / 3) < 1e-9)
            ++n_small;
        else if (std::fabs(m - kVdc / std::sqrt(3.0)) < 1e-9)
            ++n_medium;
        else if (std::fabs(m - 2 * kVdc / 3) < 1e-9)
            ++n_large;
        else
            ADD_FAILURE() << "unexpected magnitude " << m;
        bool seen = false;
        for (auto d : distinct)
            seen = seen || std::abs(d - sv) < 1e-9;
        if (!seen)
            distinct.push_back(sv);
    }
    EXPECT_EQ(distinct.size(), 19u);
    EXPECT_EQ(n_zero, 3);
    EXPECT_EQ(n_small, 12);
    EXPECT_EQ(n_medium, 6);
    EXPECT_EQ(n_large, 6);

    // 6 distinct of each non-zero kind
    int d_small = 0, d_medium = 0, d_large = 0;
    for (auto d : distinct) {
        double m = std::abs(d);
        d_small += std::fabs(m - kVdc / 3) < 1e-9;
        d_medium += std::fabs(m - kVdc / std::sqrt(3.0)) < 1e-9;
        d_large += std::fabs(m - 2 * kVdc / 3) < 1e-9;
    }
    EXPECT_EQ(d_small, 6);
    EXPECT_EQ(d_medium, 6);
    EXPECT_EQ(d_large, 6);
}

TEST(PlantInverter, UnbalancedCapacitorsByHand)
{
    // vc1 = 200 V (P at +200), vc2 = 100 V (N at -100).
    struct Case {
        uint8_t a, b, c;
        double va, vb, vc;
    } cases[] = {
        // legs 200, 0, -100; mean 100/3
        {P, O, N, 500.0 / 3, -100.0 / 3, -400.0 / 3},
        // legs 200, -100, -100; mean 0
        {P, N, N, 200.0, -100.0, -100.0},
        // legs 0, -100, -100; mean -200/3: smaller than POO now
        {O, N, N, 200.0 / 3, -100.0 / 3, -100.0 / 3},
        // legs 200, 0, 0; mean 200/3
        {P, O, O, 400.0 / 3, -200.0 / 3, -200.0 / 3},
        // legs -100, 200, 0; mean 100/3
        {N, P, O, -400.0 / 3, 500.0 / 3, -100.0 / 3},
        {P, P, P, 0.0, 0.0, 0.0},
        {N, N, N, 0.0, 0.0, 0.0},
    };
    for (const Case &c : cases) {
        uint8_t legs[3] = {c.a, c.b, c.c};
        double v[3], i_np;
        plant_inverter_output(legs, 200.0, 100.0, kIabc, v, &i_np);
        SCOPED_TRACE(testing::Message() << "state " << int(c.a) << int(c.b) << int(c.c));
        EXPECT_NEAR(v[0], c.va, 1e-9);
        EXPECT_NEAR(v[1], c.vb, 1e-9);
        EXPECT_NEAR(v[2], c.vc, 1e-9);
    }
}

TEST(PlantInverter, GatesOffLegFollowsItsCurrentSign)
{
    // a off with current into the motor: lower diodes, leg at N (-vc2);
    // b off with current out of the motor: upper diodes, leg at P (+vc1).
    // c driven at O. Legs -100, +200, 0; mean 100/3.
    uint8_t legs[3] = {OFF, OFF, O};
    double i[3] = {5.0, -3.0, -2.0}, v[3], i_np;
    plant_inverter_output(legs, 200.0, 100.0, i, v, &i_np);
    EXPECT_NEAR(v[0], -400.0 / 3, 1e-9);
    EXPECT_NEAR(v[1], 500.0 / 3, 1e-9);
    EXPECT_NEAR(v[2], -100.0 / 3, 1e-9);
    EXPECT_NEAR(i_np, -2.0, 1e-12);
    // Codes above 3 are gates off as well.
    uint8_t legs9[3] = {9, 9, O};
    double v9[3];
    plant_inverter_output(legs9, 200.0, 100.0, i, v9, &i_np);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(v9[k], v[k], 1e-12);
}

// --- dynamic tests through plant_advance ---

plant_config inverter_cfg()
{
    plant_config c;
    plant_default_config(&c);
    c.supply = PLANT_SUPPLY_INVERTER;
    return c;
}

TEST(PlantInverter, AppliedVoltagesInTheIntegrationMatchTheHandTable)
{
    // The voltages the integration applies (reported in the truth at the end
    // of an advance) are the same table; 1 us periods keep vc1, vc2 at Vdc/2.
    for (const Row &r : kTable) {
        plant_config c = inverter_cfg();
        plant_state s;
        ASSERT_EQ(plant_init(&s, &c), 0);
        uint8_t legs[3] = {r.a, r.b, r.c};
        plant_advance(&s, legs, legs, 1.0, 1e-6);
        plant_truth tr;
        plant_get_truth(&s, &tr);
        SCOPED_TRACE(testing::Message() << "state " << int(r.a) << int(r.b) << int(r.c));
        EXPECT_NEAR(tr.va_V, r.va * kVdc / 6, 1e-3);
        EXPECT_NEAR(tr.vb_V, r.vb * kVdc / 6, 1e-3);
        EXPECT_NEAR(tr.vc_V, r.vc * kVdc / 6, 1e-3);
    }
}

// A spinning, magnetised motor with open stator (i_s = 0): psi_s = (Lm/Lr) psi_r.
void spin(plant_state &s, double w, double psi_r)
{
    const plant_motor_params &m = s.cfg.motor;
    double Lr = m.Llr_H + m.Lm_H;
    s.omega_m = w;
    s.psi_r[0] = psi_r;
    s.psi_r[1] = 0.0;
    s.psi_s[0] = m.Lm_H / Lr * psi_r;
    s.psi_s[1] = 0.0;
}

TEST(PlantInverter, GatesOffSpinningMotorRectifiesOnlyAboveTheRails)
{
    // Open stator emf: line-to-line peak = sqrt3 * p w (Lm/Lr) |psi_r|.
    const uint8_t off[3] = {OFF, OFF, OFF};
    plant_truth tr;
    {
        // 900 rpm, 0.45 Wb: about 142 V < 311 V: the diodes stay off.
        plant_config c = inverter_cfg();
        plant_state s;
        ASSERT_EQ(plant_init(&s, &c), 0);
        spin(s, 94.25, 0.45);
        double max_i = 0.0;
        for (int k = 0; k < 100; ++k) {
            plant_advance(&s, off, off, 1.0, 200e-6);
            plant_get_truth(&s, &tr);
            max_i = std::fmax(max_i, std::fabs(tr.ia_A) + std::fabs(tr.ib_A) + std::fabs(tr.ic_A));
            // the floating phases show the emf, which is below the rails
            EXPECT_LT(std::fmax(std::fabs(tr.va_V - tr.vb_V), std::fabs(tr.va_V - tr.vc_V)),
                      s.vc1 + s.vc2);
        }
        EXPECT_LT(max_i, 1e-9);
        // With leg a clamped to O the others see the line emf against one
        // capacitor (peak ~142 V < 155.5 V): still no current.
        plant_state s2;
        ASSERT_EQ(plant_init(&s2, &c), 0);
        spin(s2, 94.25, 0.45);
        const uint8_t o_off[3] = {O, OFF, OFF};
        double max_i2 = 0.0;
        for (int k = 0; k < 100; ++k) {
            plant_advance(&s2, o_off, o_off, 1.0, 200e-6);
            plant_truth t2;
            plant_get_truth(&s2, &t2);
            max_i2 = std::fmax(max_i2, std::fabs(t2.ia_A) + std::fabs(t2.ib_A) + std::fabs(t2.ic_A));
        }
        EXPECT_LT(max_i2, 1e-9);
        // line emf seen at the terminals: peak sqrt3 p w Lm/Lr |psi_r| (decaying slowly)
        const double Lr = c.motor.Llr_H + c.motor.Lm_H;
        const double psi = std::hypot(tr.psi_r_alpha_Wb, tr.psi_r_beta_Wb);
        const double e_ll = std::sqrt(3.0) * 2 * tr.omega_m_rad_s * c.motor.Lm_H / Lr * psi;
        const double v_ab = tr.va_V - tr.vb_V, v_bc = tr.vb_V - tr.vc_V;
        // for a balanced set the peak follows from two line values
        const double peak = std::sqrt((v_ab * v_ab + v_bc * v_bc + (v_ab + v_bc) * (v_ab + v_bc)) * 2.0 / 3.0);
        EXPECT_NEAR(peak, e_ll, 0.02 * e_ll);
    }
    {
        // 1800 rpm, 0.45 Wb on a 100 V link: about 284 V > 100 V, the motor
        // feeds the link through the diodes and brakes.
        plant_config c = inverter_cfg();
        c.dc.vdc_V = 100.0;
        plant_state s;
        ASSERT_EQ(plant_init(&s, &c), 0);
        spin(s, 188.5, 0.45);
        double max_i = 0.0, min_te = 0.0, max_vsum = 0.0;
        for (int k = 0; k < 50; ++k) {
            plant_advance(&s, off, off, 1.0, 200e-6);
            plant_get_truth(&s, &tr);
            max_i = std::fmax(max_i, std::fabs(tr.ia_A));
            min_te = std::fmin(min_te, tr.te_Nm);
            max_vsum = std::fmax(max_vsum, tr.vc1_V + tr.vc2_V);
        }
        EXPECT_GT(max_i, 10.0);
        EXPECT_LT(min_te, -1.0);
        EXPECT_GT(max_vsum, 100.0);
        EXPECT_LT(s.omega_m, 188.5);
    }
}

TEST(PlantDcLink, ChargesFromSourceByTheRcLaw)
{
    plant_config c = inverter_cfg();
    c.dc.c1_F = 0.0022;
    c.dc.c2_F = 0.0033; // unequal on purpose
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    EXPECT_DOUBLE_EQ(s.vc1, c.dc.vdc_V / 2);
    EXPECT_DOUBLE_EQ(s.vc2, c.dc.vdc_V / 2);
    s.vc1 = s.vc2 = 0.0; // discharged link, motor disconnected (gates off, no current)
    // Series capacitors: C = C1 C2 / (C1 + C2), tau = R C; each capacitor
    // carries the same charge, so vc1 = Vdc C2/(C1+C2) (1 - exp(-t/tau)).
    const double Cser = c.dc.c1_F * c.dc.c2_F / (c.dc.c1_F + c.dc.c2_F);
    const double tau = c.dc.r_src_ohm * Cser;
    const uint8_t off[3] = {OFF, OFF, OFF};
    const double T = 20e-6;
    double max_err = 0.0;
    for (int k = 1; k <= 50; ++k) {
        plant_advance(&s, off, off, 0.5, T);
        double t = k * T;
        double q = c.dc.vdc_V * (1.0 - std::exp(-t / tau));
        double vc1 = q * c.dc.c2_F / (c.dc.c1_F + c.dc.c2_F);
        double vc2 = q * c.dc.c1_F / (c.dc.c1_F + c.dc.c2_F);
        max_err = std::fmax(max_err, std::fabs(s.vc1 - vc1));
        max_err = std::fmax(max_err, std::fabs(s.vc2 - vc2));
    }
    EXPECT_LT(max_err, 1e-3 * c.dc.vdc_V);
    plant_truth tr;
    plant_get_truth(&s, &tr);
    EXPECT_EQ(tr.ia_A, 0.0);
    EXPECT_EQ(tr.ib_A, 0.0);
    EXPECT_EQ(tr.ic_A, 0.0);
}

// Builds a current in phase a with the small vector POO, then applies @p legs
// for 1 ms in 10 us periods and returns delta(vc1 - vc2) and the integral of
// the truth's NP current (trapezoid) over that time.
struct NpRun {
    double d_vdiff, q_np, ia_start;
};

NpRun np_run(const uint8_t legs[3])
{
    plant_config c = inverter_cfg();
    plant_state s;
    EXPECT_EQ(plant_init(&s, &c), 0);
    const uint8_t poo[3] = {P, O, O};
    for (int k = 0; k < 5; ++k) // 1 ms: ia ~ (Vdc/3) t / (sigma Ls) ~ 35 A
        plant_advance(&s, poo, poo, 1.0, 200e-6);
    // The switch to the new vector: O legs of the new vector draw from the
    // NP from this instant; equalise capacitors to see only this run.
    s.vc1 = s.vc2 = c.dc.vdc_V / 2;
    plant_truth tr;
    plant_get_truth(&s, &tr);
    NpRun r{0.0, 0.0, tr.ia_A};
    const double v0 = s.vc1 - s.vc2;
    // NP current at the start, in the new vector: the O legs' currents.
    const double i_now[3] = {tr.ia_A, tr.ib_A, tr.ic_A};
    double prev = 0.0;
    for (int k = 0; k < 3; ++k)
        prev += legs[k] == O ? i_now[k] : 0.0;
    const double T = 10e-6;
    for (int k = 0; k < 100; ++k) {
        plant_advance(&s, legs, legs, 1.0, T);
        plant_get_truth(&s, &tr);
        r.q_np += 0.5 * T * (prev + tr.i_np_A);
        prev = tr.i_np_A;
    }
    r.d_vdiff = (s.vc1 - s.vc2) - v0;
    return r;
}

TEST(PlantDcLink, NeutralPointMovesTheRightWay)
{
    // Derivation (C1 = C2 = C): C dvc1/dt = i_src - i_P, C dvc2/dt = i_src + i_N,
    // so C d(vc1 - vc2)/dt = -(i_P + i_N) = i_np (the current drawn from O).
    // POO with ia > 0: i_np = ib + ic = -ia < 0 -> vc1 - vc2 falls.
    // ONN with ia > 0: i_np = ia > 0 -> vc1 - vc2 rises.
    const double C = 0.0022;
    const uint8_t poo[3] = {P, O, O}, onn[3] = {O, N, N}, ooo[3] = {O, O, O};

    NpRun a = np_run(poo);
    EXPECT_GT(a.ia_start, 10.0);
    EXPECT_LT(a.d_vdiff, -1.0);
    EXPECT_NEAR(a.d_vdiff, a.q_np / C, 0.02 * std::fabs(a.d_vdiff));

    NpRun b = np_run(onn);
    EXPECT_GT(b.d_vdiff, 1.0);
    EXPECT_NEAR(b.d_vdiff, b.q_np / C, 0.02 * std::fabs(b.d_vdiff));

    // All legs at O: the currents freewheel through the clamps, but they sum to
    // zero in an isolated star, so no net NP current and vc1 - vc2 stays put.
    NpRun z = np_run(ooo);
    EXPECT_NEAR(z.d_vdiff, 0.0, 1e-9);
    EXPECT_NEAR(z.q_np, 0.0, 1e-12);
}

TEST(PlantInverter, GatesOffCurrentsDieAndStayZeroRotorFluxDecays)
{
    plant_config c = inverter_cfg();
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    const uint8_t poo[3] = {P, O, O}, off[3] = {OFF, OFF, OFF};
    for (int k = 0; k < 25; ++k) // 5 ms of POO: magnetise along a
        plant_advance(&s, poo, poo, 1.0, 200e-6);
    plant_truth tr;
    plant_get_truth(&s, &tr);
    ASSERT_GT(tr.ia_A, 20.0);
    const double vsum0 = s.vc1 + s.vc2;
    const double ia0 = tr.ia_A;
    // Gates off: a (i > 0) returns through N, b and c (i < 0) through P, i.e.
    // the diodes apply NPP: v_a = -2/3 Vdc. With sigma Ls = Lls + Lm Llr / Lr
    // the current falls at about (2/3 Vdc + Rs ia) / (sigma Ls) (the rotor emf
    // is small after 5 ms at standstill) and reaches zero in ~0.5 ms.
    const double Lr_ = c.motor.Llr_H + c.motor.Lm_H;
    const double sLs = c.motor.Lls_H + c.motor.Lm_H * c.motor.Llr_H / Lr_;
    const double slope = (2.0 / 3.0 * c.dc.vdc_V + c.motor.Rs_ohm * ia0) / sLs;
    plant_advance(&s, off, off, 1.0, 20e-6);
    plant_get_truth(&s, &tr);
    EXPECT_NEAR(ia0 - tr.ia_A, slope * 20e-6, 0.1 * slope * 20e-6);
    EXPECT_NEAR(tr.ib_A, tr.ic_A, 1e-9);
    for (int k = 0; k < 10; ++k)
        plant_advance(&s, off, off, 1.0, 200e-6);
    plant_get_truth(&s, &tr);
    EXPECT_NEAR(tr.ia_A, 0.0, 1e-9);
    EXPECT_NEAR(tr.ib_A, 0.0, 1e-9);
    EXPECT_NEAR(tr.ic_A, 0.0, 1e-9);
    // the magnetic energy went back into the link (and the source)
    EXPECT_GT(s.vc1 + s.vc2, vsum0 - 1e-6);

    // Open stator: dpsi_r/dt = -(Rr/Lr) psi_r + j p w psi_r, so |psi_r| decays
    // as exp(-t Rr / Lr) whatever the speed, and the stator currents stay 0.
    const double Lr = c.motor.Llr_H + c.motor.Lm_H;
    const double m0 = std::hypot(tr.psi_r_alpha_Wb, tr.psi_r_beta_Wb);
    ASSERT_GT(m0, 0.01);
    const double t0 = tr.t_s;
    double max_i = 0.0;
    for (int k = 0; k < 500; ++k) { // 0.1 s
        plant_advance(&s, off, off, 1.0, 200e-6);
        plant_get_truth(&s, &tr);
        max_i = std::fmax(max_i, std::fabs(tr.ia_A) + std::fabs(tr.ib_A) + std::fabs(tr.ic_A));
    }
    EXPECT_LT(max_i, 1e-9);
    const double m1 = std::hypot(tr.psi_r_alpha_Wb, tr.psi_r_beta_Wb);
    EXPECT_NEAR(m1 / m0, std::exp(-(tr.t_s - t0) * c.motor.Rr_ohm / Lr), 1e-6);
}

TEST(PlantInverter, SwitchingInstantsAreHonouredExactly)
{
    // One period with vec0 for duty0 * T then vec1 must equal two separate
    // periods of exactly those lengths, however short the first one is.
    plant_config c = inverter_cfg();
    plant_state a;
    ASSERT_EQ(plant_init(&a, &c), 0);
    const uint8_t pon[3] = {P, O, N}, ppn[3] = {P, P, N}, ooo[3] = {O, O, O};
    for (int k = 0; k < 20; ++k) // some current and speed first
        plant_advance(&a, pon, ooo, 0.6, 200e-6);
    for (double d : {0.013, 0.1, 0.5, 0.97}) {
        plant_state one = a, two = a, avg = a;
        plant_advance(&one, ppn, pon, d, 200e-6);
        plant_advance(&two, ppn, ppn, 1.0, d * 200e-6);
        plant_advance(&two, pon, pon, 1.0, 200e-6 - d * 200e-6);
        plant_advance(&avg, pon, pon, 1.0, 200e-6);
        SCOPED_TRACE(testing::Message() << "duty " << d);
        for (int k = 0; k < 2; ++k) {
            EXPECT_NEAR(one.psi_s[k], two.psi_s[k], 1e-12);
            EXPECT_NEAR(one.psi_r[k], two.psi_r[k], 1e-12);
        }
        EXPECT_NEAR(one.vc1, two.vc1, 1e-9);
        EXPECT_NEAR(one.vc2, two.vc2, 1e-9);
        EXPECT_NEAR(one.omega_m, two.omega_m, 1e-12);
        // The short vector acted for exactly d T: against a period of PON
        // alone, the stator flux differs by d T (v_PPN - v_PON). By hand:
        // PPN = (2, 2, -4) Vdc/6 -> (Vdc/3, Vdc/sqrt3); PON = (3, 0, -3) Vdc/6
        // -> (Vdc/2, Vdc/(2 sqrt3)); difference (-Vdc/6, Vdc/(2 sqrt3)).
        // (The Rs i_s drop is the same in both and cancels to first order.)
        const double dT = d * 200e-6, Vdc = c.dc.vdc_V;
        EXPECT_NEAR(one.psi_s[0] - avg.psi_s[0], dT * -Vdc / 6, 0.05 * dT * Vdc / 6);
        EXPECT_NEAR(one.psi_s[1] - avg.psi_s[1], dT * Vdc / (2 * std::sqrt(3.0)),
                    0.05 * dT * Vdc / (2 * std::sqrt(3.0)));
    }
}

TEST(PlantInverter, SwitchCountCountsLegCommutations)
{
    plant_config c = inverter_cfg();
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    const uint8_t ooo[3] = {O, O, O}, poo[3] = {P, O, O}, pon[3] = {P, O, N},
                  npn[3] = {N, P, N}, off[3] = {OFF, OFF, OFF};
    plant_advance(&s, ooo, poo, 0.5, 200e-6); // first vector: nothing; OOO->POO: 1
    EXPECT_EQ(s.switch_count, 1u);
    plant_advance(&s, poo, pon, 0.5, 200e-6); // POO->POO 0, POO->PON 1
    EXPECT_EQ(s.switch_count, 2u);
    plant_advance(&s, npn, npn, 1.0, 200e-6); // PON->NPN: 2 + 1 + 0; zero-length vec1 not applied
    EXPECT_EQ(s.switch_count, 5u);
    plant_advance(&s, poo, npn, 0.0, 200e-6); // vec0 has zero length: NPN->NPN 0
    EXPECT_EQ(s.switch_count, 5u);
    plant_advance(&s, off, ooo, 0.5, 200e-6); // to and from gates off: not counted
    EXPECT_EQ(s.switch_count, 5u);
    plant_advance(&s, poo, ooo, 0.5, 200e-6); // OOO->POO 1, POO->OOO 1
    EXPECT_EQ(s.switch_count, 7u);
}

} // namespace
