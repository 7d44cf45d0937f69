// Induction machine of the plant against independent references: the
// steady-state T-equivalent circuit (std::complex), a current-state model
// integrated here with Eigen, energy conservation, and step convergence.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "plant/plant.h"
#include "tequiv.hpp"

namespace {

const double kPi = 3.14159265358979323846;
const double kRatedPeakA = 24.4 * std::sqrt(2.0);

plant_config sine_cfg()
{
    plant_config c;
    plant_default_config(&c);
    c.supply = PLANT_SUPPLY_SINE;
    c.sine.v_ll_rms_V = 220.0;
    c.sine.f_Hz = 60.0;
    c.sine.phase_rad = 0.0;
    return c;
}

struct Window {
    double speed_rpm;
    double is_rms_A;
};

// Advance n periods of T and average over them: speed (mean) and stator
// current rms over all three phases. With n * T an integer number of
// electrical periods, the sample mean of a sinusoid squared is exact.
Window run_window(plant_state &s, int n, double T)
{
    const uint8_t ooo[3] = {1, 1, 1};
    double sw = 0.0, si2 = 0.0;
    plant_truth tr;
    for (int k = 0; k < n; ++k) {
        plant_advance(&s, ooo, ooo, 1.0, T);
        plant_get_truth(&s, &tr);
        sw += tr.omega_m_rad_s;
        si2 += tr.ia_A * tr.ia_A + tr.ib_A * tr.ib_A + tr.ic_A * tr.ic_A;
    }
    return {sw / n * 60.0 / (2.0 * kPi), std::sqrt(si2 / (3.0 * n))};
}

void run(plant_state &s, int n, double T)
{
    const uint8_t ooo[3] = {1, 1, 1};
    for (int k = 0; k < n; ++k)
        plant_advance(&s, ooo, ooo, 1.0, T);
}

TEST(PlantMachine, TEquivalentReferenceMatchesTheDocumentedFigures)
{
    plant_config c = sine_cfg();
    tequiv::Machine m = tequiv::from_params(c.motor);
    tequiv::Point nl = tequiv::solve(m, 220.0, 60.0, 0.0);
    tequiv::Point ld = tequiv::solve(m, 220.0, 60.0, 20.0);
    tequiv::Point rt = tequiv::solve(m, 220.0, 60.0, 40.0);
    // docs/motor-10hp.json, rounded there to 0.1 rpm and 0.01 A
    EXPECT_NEAR(nl.speed_rpm, 1798.9, 0.05);
    EXPECT_NEAR(nl.is_rms_A, 7.84, 0.005);
    EXPECT_NEAR(ld.speed_rpm, 1773.7, 0.05);
    EXPECT_NEAR(ld.is_rms_A, 13.70, 0.005);
    EXPECT_NEAR(rt.speed_rpm, 1744.2, 0.05);
    EXPECT_NEAR(rt.is_rms_A, 24.35, 0.005);
    EXPECT_NEAR(rt.pf, 0.886, 0.0005);
    double sp = tequiv::pullout_slip(m, 220.0, 60.0);
    EXPECT_NEAR(sp, 0.145, 0.0005);
    EXPECT_NEAR(tequiv::at_slip(m, 220.0, 60.0, sp).te_Nm, 88.2, 0.05);
    EXPECT_TRUE(std::isnan(tequiv::solve(m, 220.0, 60.0, 100.0).slip));
}

TEST(PlantMachine, DirectOnLineSteadyStateMatchesTEquivalent)
{
    plant_config c = sine_cfg();
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    const double T = 1.0 / (60.0 * 100); // 100 periods per electrical cycle
    tequiv::Machine m = tequiv::from_params(c.motor);

    // The start is over by 0.3 s; the no-load slip then creeps in with the
    // rotor time constant (Lr/Rr = 0.27 s), so settle until 0.9 s.
    run(s, 5400, T);                      // 0 .. 0.9 s
    Window nl = run_window(s, 600, T);    // 0.9 .. 1.0 s, 6 cycles
    tequiv::Point rnl = tequiv::solve(m, 220.0, 60.0, 0.0);

    plant_set_load(&s, 20.0);
    run(s, 3000, T);                      // 1.0 .. 1.5 s
    Window ld = run_window(s, 600, T);    // 1.5 .. 1.6 s
    tequiv::Point rld = tequiv::solve(m, 220.0, 60.0, 20.0);

    std::printf("no load: %.3f rpm (ref %.3f), %.4f A (ref %.4f)\n", nl.speed_rpm,
                rnl.speed_rpm, nl.is_rms_A, rnl.is_rms_A);
    std::printf("20 N m : %.3f rpm (ref %.3f), %.4f A (ref %.4f)\n", ld.speed_rpm,
                rld.speed_rpm, ld.is_rms_A, rld.is_rms_A);
    EXPECT_NEAR(nl.speed_rpm, rnl.speed_rpm, 0.002 * rnl.speed_rpm);
    EXPECT_NEAR(nl.is_rms_A, rnl.is_rms_A, 0.01 * rnl.is_rms_A);
    EXPECT_NEAR(ld.speed_rpm, rld.speed_rpm, 0.002 * rld.speed_rpm);
    EXPECT_NEAR(ld.is_rms_A, rld.is_rms_A, 0.01 * rld.is_rms_A);
    // slip is what the load changes: check it more tightly than 0.2 % of speed
    double slip_nl = 1.0 - nl.speed_rpm / 1800.0, slip_ld = 1.0 - ld.speed_rpm / 1800.0;
    EXPECT_NEAR(slip_nl, rnl.slip, 0.01 * rnl.slip);
    EXPECT_NEAR(slip_ld, rld.slip, 0.01 * rld.slip);
}

// The same machine written in current states, i = (is_a, is_b, ir_a, ir_b):
// L di/dt = (v_s - Rs i_s, -Rr i_r + j p w psi_r), psi = L i, integrated here
// with a fine RK4; the plant integrates fluxes with its own step.
struct CurrentModel {
    Eigen::Matrix4d L, Linv;
    double Rs, Rr, Lm, p, J, B, TL = 0.0;
    CurrentModel(const plant_motor_params &m)
    {
        double Ls = m.Lls_H + m.Lm_H, Lr = m.Llr_H + m.Lm_H;
        L << Ls, 0, m.Lm_H, 0, 0, Ls, 0, m.Lm_H, m.Lm_H, 0, Lr, 0, 0, m.Lm_H, 0, Lr;
        Linv = L.inverse();
        Rs = m.Rs_ohm;
        Rr = m.Rr_ohm;
        Lm = m.Lm_H;
        p = m.pole_pairs;
        J = m.J_kgm2;
        B = m.B_Nms;
    }
    // y = (i[4], w)
    Eigen::Matrix<double, 5, 1> f(const Eigen::Matrix<double, 5, 1> &y, double va, double vb) const
    {
        Eigen::Vector4d i = y.head<4>();
        Eigen::Vector4d psi = L * i;
        double w = y(4);
        Eigen::Vector4d u(va - Rs * i(0), vb - Rs * i(1), -Rr * i(2) - p * w * psi(3),
                          -Rr * i(3) + p * w * psi(2));
        Eigen::Matrix<double, 5, 1> d;
        d.head<4>() = Linv * u;
        double te = 1.5 * p * Lm * (i(2) * i(1) - i(3) * i(0));
        d(4) = (te - B * w - TL) / J;
        return d;
    }
};

TEST(PlantMachine, DirectOnLineTransientMatchesIndependentCurrentModel)
{
    plant_config c = sine_cfg();
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    CurrentModel ref(c.motor);
    const double Vp = std::sqrt(2.0 / 3.0) * 220.0, we = 2 * kPi * 60.0;
    Eigen::Matrix<double, 5, 1> y = Eigen::Matrix<double, 5, 1>::Zero();
    const double T = 200e-6, h = 5e-6;
    const int sub = int(std::lround(T / h));
    double max_di = 0.0, max_dw = 0.0, max_i = 0.0;
    const uint8_t ooo[3] = {1, 1, 1};
    for (int k = 0; k < 1500; ++k) { // 0.3 s: the whole start
        for (int j = 0; j < sub; ++j) {
            double t = (k * sub + j) * h;
            auto v = [&](double tt, double &a, double &b) {
                // va = Vp cos(we t); alpha-beta of the balanced set, by hand
                a = Vp * std::cos(we * tt);
                b = Vp * std::sin(we * tt);
            };
            double a1, b1, a2, b2, a3, b3;
            v(t, a1, b1);
            v(t + h / 2, a2, b2);
            v(t + h, a3, b3);
            auto k1 = ref.f(y, a1, b1);
            auto k2 = ref.f(y + h / 2 * k1, a2, b2);
            auto k3 = ref.f(y + h / 2 * k2, a2, b2);
            auto k4 = ref.f(y + h * k3, a3, b3);
            y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
        }
        plant_advance(&s, ooo, ooo, 1.0, T);
        plant_truth tr;
        plant_get_truth(&s, &tr);
        // phase currents of the reference by the inverse Clarke, by hand
        double ia = y(0), ib = -0.5 * y(0) + 0.5 * std::sqrt(3.0) * y(1),
               ic = -0.5 * y(0) - 0.5 * std::sqrt(3.0) * y(1);
        max_di = std::fmax(max_di, std::fabs(tr.ia_A - ia));
        max_di = std::fmax(max_di, std::fabs(tr.ib_A - ib));
        max_di = std::fmax(max_di, std::fabs(tr.ic_A - ic));
        max_dw = std::fmax(max_dw, std::fabs(tr.omega_m_rad_s - y(4)));
        max_i = std::fmax(max_i, std::fabs(ia));
        // the truth's fluxes are L times its currents
        Eigen::Vector4d it(tr.is_alpha_A, tr.is_beta_A, tr.ir_alpha_A, tr.ir_beta_A);
        Eigen::Vector4d psi = ref.L * it;
        ASSERT_NEAR(psi(0), tr.psi_s_alpha_Wb, 1e-9);
        ASSERT_NEAR(psi(1), tr.psi_s_beta_Wb, 1e-9);
        ASSERT_NEAR(psi(2), tr.psi_r_alpha_Wb, 1e-9);
        ASSERT_NEAR(psi(3), tr.psi_r_beta_Wb, 1e-9);
        ASSERT_NEAR(tr.ia_A + tr.ib_A + tr.ic_A, 0.0, 1e-9);
    }
    std::printf("DOL start vs current model: max |di| %.3g A (peak %.1f A), max |dw| %.3g rad/s, "
                "final %.2f rpm\n", max_di, max_i, max_dw, y(4) * 30 / kPi);
    EXPECT_GT(max_i, 100.0);         // a real DOL inrush happened
    EXPECT_GT(y(4), 0.95 * 188.5);   // and it ran up
    EXPECT_LT(max_di, 1e-3 * kRatedPeakA);
    EXPECT_LT(max_dw, 1e-4);
}

TEST(PlantMachine, PowerBalanceOverTheStart)
{
    plant_config c = sine_cfg();
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    const plant_motor_params &m = c.motor;
    const double Ls = m.Lls_H + m.Lm_H, Lr = m.Llr_H + m.Lm_H;
    const double T = 1.0 / (60.0 * 200);
    const uint8_t ooo[3] = {1, 1, 1};

    struct P {
        double in, cu, mech, w, wmag, fric, load;
    };
    auto powers = [&](const plant_truth &t, double TL) {
        P r;
        r.in = t.va_V * t.ia_A + t.vb_V * t.ib_A + t.vc_V * t.ic_A;
        // rotor copper in abc terms: 1.5 |i_r|^2 per ohm (amplitude-invariant)
        r.cu = m.Rs_ohm * (t.ia_A * t.ia_A + t.ib_A * t.ib_A + t.ic_A * t.ic_A) +
               1.5 * m.Rr_ohm * (t.ir_alpha_A * t.ir_alpha_A + t.ir_beta_A * t.ir_beta_A);
        double te = 1.5 * m.pole_pairs * m.Lm_H *
                    (t.ir_alpha_A * t.is_beta_A - t.ir_beta_A * t.is_alpha_A);
        r.mech = te * t.omega_m_rad_s;
        r.w = t.omega_m_rad_s;
        // 1.5 * (1/2) i^T L i with L the alpha-beta inductance matrix
        r.wmag = 1.5 * (0.5 * Ls * (t.is_alpha_A * t.is_alpha_A + t.is_beta_A * t.is_beta_A) +
                        m.Lm_H * (t.is_alpha_A * t.ir_alpha_A + t.is_beta_A * t.ir_beta_A) +
                        0.5 * Lr * (t.ir_alpha_A * t.ir_alpha_A + t.ir_beta_A * t.ir_beta_A));
        r.fric = m.B_Nms * t.omega_m_rad_s * t.omega_m_rad_s;
        r.load = TL * t.omega_m_rad_s;
        return r;
    };

    plant_truth tr;
    plant_get_truth(&s, &tr);
    // at t = 0 the source voltage is va = Vp, vb = vc = -Vp/2 but the truth
    // reports the last instant of an advance; with zero current p_in(0) = 0.
    P prev = powers(tr, 0.0);
    prev.in = 0.0;
    const P first = prev;
    double E_in = 0, E_cu = 0, E_mech = 0, E_fric = 0, E_load = 0;
    double TL = 0.0;
    for (int k = 0; k < 4800; ++k) { // 0.4 s
        if (k == 3000) {             // 0.25 s: 20 N m load
            TL = 20.0;
            plant_set_load(&s, TL);
        }
        plant_advance(&s, ooo, ooo, 1.0, T);
        plant_get_truth(&s, &tr);
        P now = powers(tr, TL);
        E_in += 0.5 * T * (prev.in + now.in);
        E_cu += 0.5 * T * (prev.cu + now.cu);
        E_mech += 0.5 * T * (prev.mech + now.mech);
        E_fric += 0.5 * T * (prev.fric + now.fric);
        // the load torque steps at a period boundary: integrate it with the
        // torque of the interval (now.load), not a trapezoid across the step
        E_load += 0.5 * T * (TL * prev.w + now.load);
        prev = now;
    }
    const double dW = prev.wmag - first.wmag;
    const double dKE = 0.5 * m.J_kgm2 * (prev.w * prev.w - first.w * first.w);
    const double elec_err = (E_in - (E_cu + E_mech + dW)) / E_in;
    const double mech_err = (E_mech - (dKE + E_fric + E_load)) / E_mech;
    std::printf("E_in %.1f J = cu %.1f + mech %.1f + dWmag %.2f: error %.2e\n", E_in, E_cu,
                E_mech, dW, elec_err);
    std::printf("E_mech %.1f J = dKE %.1f + friction %.2f + load %.1f: error %.2e\n", E_mech,
                dKE, E_fric, E_load, mech_err);
    std::printf("plant accumulators: e_in %.1f, e_cu %.1f, e_mech %.1f\n", s.e_in_J, s.e_cu_J,
                s.e_mech_J);
    EXPECT_GT(E_load, 100.0); // the load did work
    EXPECT_LT(std::fabs(elec_err), 0.005);
    EXPECT_LT(std::fabs(mech_err), 0.005);
    // the plant's own accumulators agree with the test's quadrature
    EXPECT_NEAR(s.e_in_J, E_in, 0.005 * E_in);
    EXPECT_NEAR(s.e_cu_J, E_cu, 0.005 * E_cu);
    EXPECT_NEAR(s.e_mech_J, E_mech, 0.005 * E_mech);
}

// Open-loop inverter drive: large vector of the sector nearest a 30 Hz
// rotating reference for 43 % of the period, then the zero vector OOO.
std::vector<double> inverter_run(double h_max, int n)
{
    static const uint8_t large[6][3] = {{2, 0, 0}, {2, 2, 0}, {0, 2, 0},
                                        {0, 2, 2}, {0, 0, 2}, {2, 0, 2}};
    const uint8_t ooo[3] = {1, 1, 1};
    plant_config c;
    plant_default_config(&c);
    c.h_max_s = h_max;
    plant_state s;
    EXPECT_EQ(plant_init(&s, &c), 0);
    std::vector<double> out;
    const double T = 200e-6;
    for (int k = 0; k < n; ++k) {
        double th = 2 * kPi * 30.0 * k * T;
        int sec = int(std::floor(th / (kPi / 3) + 0.5)) % 6;
        plant_advance(&s, large[sec], ooo, 0.43, T);
        plant_truth tr;
        plant_get_truth(&s, &tr);
        out.push_back(tr.ia_A);
        out.push_back(tr.ib_A);
        out.push_back(tr.ic_A);
    }
    out.push_back(s.omega_m);
    return out;
}

std::vector<double> sine_run(double h_max, int n)
{
    plant_config c = sine_cfg();
    c.h_max_s = h_max;
    plant_state s;
    EXPECT_EQ(plant_init(&s, &c), 0);
    std::vector<double> out;
    const uint8_t ooo[3] = {1, 1, 1};
    for (int k = 0; k < n; ++k) {
        plant_advance(&s, ooo, ooo, 1.0, 200e-6);
        plant_truth tr;
        plant_get_truth(&s, &tr);
        out.push_back(tr.ia_A);
        out.push_back(tr.ib_A);
        out.push_back(tr.ic_A);
    }
    return out;
}

double max_abs_diff(const std::vector<double> &a, const std::vector<double> &b, size_t n)
{
    double d = 0.0;
    for (size_t i = 0; i < n; ++i)
        d = std::fmax(d, std::fabs(a[i] - b[i]));
    return d;
}

TEST(PlantMachine, HalvingTheStepChangesCurrentsByLessThanOnePermilleOfRated)
{
    plant_config c;
    plant_default_config(&c);
    const int n = 2500; // 0.5 s: start from standstill and run up to ~900 rpm
    std::vector<double> a = inverter_run(c.h_max_s, n), b = inverter_run(c.h_max_s / 2, n);
    double d_inv = max_abs_diff(a, b, 3 * n);
    double peak = 0.0;
    for (int i = 0; i < 3 * n; ++i)
        peak = std::fmax(peak, std::fabs(a[i]));
    std::vector<double> sa = sine_run(c.h_max_s, n), sb = sine_run(c.h_max_s / 2, n);
    double d_sine = max_abs_diff(sa, sb, 3 * n);
    std::printf("h_max %.1f us: inverter max |di| %.3g A (peak %.1f A, final %.1f rpm), "
                "sine %.3g A; limit %.4f A\n",
                c.h_max_s * 1e6, d_inv, peak, a.back() * 30 / kPi, d_sine, 1e-3 * kRatedPeakA);
    EXPECT_GT(peak, 50.0);                 // the run has real currents
    EXPECT_GT(a.back() * 30 / kPi, 700.0); // and the motor follows the 30 Hz field
    EXPECT_LT(d_inv, 1e-3 * kRatedPeakA);
    EXPECT_LT(d_sine, 1e-3 * kRatedPeakA);
}

} // namespace
