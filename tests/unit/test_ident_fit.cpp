// The identification run's estimators (dtc/ident_fit.h) against closed-form
// and independently generated signals: least squares against Eigen's (double)
// solution, the DC fit against the inverse-Gamma machine integrated finely in
// double, the burst regression against Eigen, L_M against the T-model's
// steady state by phasors (with switching ripple added), the inertia against
// a simulated speed change with viscous and Coulomb friction.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include "dtc/ident_fit.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(IdentLsq, MatchesEigenOnANoisyOverdeterminedProblem)
{
    std::mt19937 rng(7u);
    std::normal_distribution<double> n01(0.0, 1.0);
    const int m = 200, n = 4;
    Eigen::MatrixXd A(m, n);
    Eigen::VectorXd y(m);
    const double truth[n] = {0.435, -2.0, 17.0, 0.01};
    ident_lsq q;
    ident_lsq_init(&q, n);
    for (int i = 0; i < m; ++i) {
        // columns of very different scale, as the DC fit's (current, 1, exp)
        A(i, 0) = 5.0 + 0.5 * n01(rng);
        A(i, 1) = 0.2 * n01(rng);
        A(i, 2) = 1.0;
        A(i, 3) = 100.0 * std::exp(-i / 40.0);
        y(i) = 0.0;
        for (int j = 0; j < n; ++j)
            y(i) += A(i, j) * truth[j];
        y(i) += 0.01 * n01(rng);
        real_t row[4] = {float(A(i, 0)), float(A(i, 1)), float(A(i, 2)), float(A(i, 3))};
        ident_lsq_add(&q, row, float(y(i)));
    }
    Eigen::VectorXd ref = A.colPivHouseholderQr().solve(y);
    real_t c[4];
    ASSERT_EQ(ident_lsq_solve(&q, c), 0);
    for (int j = 0; j < n; ++j)
        EXPECT_NEAR(c[j], ref(j), 1e-4 * (std::fabs(ref(j)) + 1.0)) << "coefficient " << j;
    double rss = (A * ref - y).squaredNorm();
    EXPECT_NEAR(q.rss, rss, 0.05 * rss);
    EXPECT_EQ(q.rows, uint32_t(m));
}

TEST(IdentLsq, RefusesARankDeficientProblem)
{
    ident_lsq q;
    ident_lsq_init(&q, 2u);
    for (int i = 0; i < 10; ++i) {
        real_t row[2] = {float(i), float(2 * i)}; // the second column is twice the first
        ident_lsq_add(&q, row, float(i));
    }
    real_t c[2];
    EXPECT_EQ(ident_lsq_solve(&q, c), -1);
    ident_lsq empty;
    ident_lsq_init(&empty, 3u);
    real_t c3[3];
    EXPECT_EQ(ident_lsq_solve(&empty, c3), -1);
}

// The standstill record of an inverse-Gamma machine (Rs, R_R, Tr, Lsig) fed
// with a regulated current: 0 -> i_hi at t = 0 and i_hi -> i_lo at t_step,
// each a first-order rise with tau_c; integrated in sub-steps of a bin and
// summed into bins as the interrupt does (means over the bin). An initial
// rotor flux psi0 (as a current i_f(0)) and a constant voltage error u_off.
struct Machine {
    double rs = 0.435, rr_ref = 0.7709, tr = 0.0874, lsig = 3.944e-3;
};

std::vector<ident_bin> record(const Machine &mc, double bin_s, int n_bins, int step_bin, double tau_c, double i_f0,
                              double u_off, double noise_V, unsigned seed, double i_hi = 5.36, double i_lo = 2.68)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> n01(0.0, 1.0);
    const int sub = 400;
    const double h = bin_s / sub, t_step = step_bin * bin_s;
    std::vector<ident_bin> b(n_bins);
    double f = i_f0, t = 0.0;
    double i_at_step = i_hi * (1.0 - std::exp(-t_step / tau_c));
    for (int k = 0; k < n_bins; ++k) {
        double vs = 0.0, is = 0.0;
        for (int j = 0; j < sub; ++j) {
            double tm = t + 0.5 * h, i, di;
            if (tm < t_step) {
                i = i_hi * (1.0 - std::exp(-tm / tau_c));
                di = i_hi / tau_c * std::exp(-tm / tau_c);
            } else {
                double e = std::exp(-(tm - t_step) / tau_c);
                i = i_lo + (i_at_step - i_lo) * e;
                di = -(i_at_step - i_lo) / tau_c * e;
            }
            double fm = f + 0.5 * h * (i - f) / mc.tr; // midpoint
            vs += mc.rs * i + mc.lsig * di + mc.rr_ref * (i - fm) + u_off;
            is += i;
            f += h * (i - fm) / mc.tr;
            t += h;
        }
        b[k].v_sum_V = float(vs / sub + noise_V * n01(rng));
        b[k].i_sum_A = float(is / sub);
        b[k].ib_sum_A = 0.0f;
        b[k].n_v = b[k].n_i = 1u;
        // as the interrupt marks them: settled bins only
        b[k].use = uint8_t((k >= 3 && k < step_bin) || k >= step_bin + 3);
    }
    return b;
}

TEST(IdentRotorFit, FindsRsRrAndTrOfAnExactRecord)
{
    Machine mc;
    const double bin = 9.2e-3;
    auto b = record(mc, bin, 125, 70, 1e-3, 0.0, 0.0, 0.0, 1u);
    ident_rotor_fit_out o;
    ident_rotor_fit(b.data(), uint32_t(b.size()), float(bin), float(bin / 2), float(10 * 125 * bin), &o);
    ASSERT_EQ(o.status, 0);
    EXPECT_NEAR(o.rs_ohm, mc.rs, 1e-3 * mc.rs);
    EXPECT_NEAR(o.rr_ref_ohm, mc.rr_ref, 3e-3 * mc.rr_ref);
    EXPECT_NEAR(o.tr_s, mc.tr, 3e-3 * mc.tr);
    EXPECT_NEAR(o.lm_ref_H, mc.rr_ref * mc.tr, 5e-3 * mc.rr_ref * mc.tr);
    EXPECT_LT(o.resid_V, 1e-4f);
    EXPECT_GT(o.v_span_V, 0.5f); // the transients were there to be seen
}

TEST(IdentRotorFit, AConstantVoltageErrorAndARotorFluxAtTheStartDropOut)
{
    // an inverter error of 2 V (much more than Rs i_lo) and a rotor already magnetised to half of i_hi
    Machine mc;
    const double bin = 9.2e-3;
    auto b = record(mc, bin, 125, 70, 1e-3, 2.68, 2.0, 0.0, 1u);
    ident_rotor_fit_out o;
    ident_rotor_fit(b.data(), uint32_t(b.size()), float(bin), float(bin / 2), float(10 * 125 * bin), &o);
    ASSERT_EQ(o.status, 0);
    EXPECT_NEAR(o.rs_ohm, mc.rs, 2e-3 * mc.rs);
    EXPECT_NEAR(o.rr_ref_ohm, mc.rr_ref, 5e-3 * mc.rr_ref);
    EXPECT_NEAR(o.tr_s, mc.tr, 5e-3 * mc.tr);
    EXPECT_NEAR(o.u_off_V, 2.0, 2e-3);
    EXPECT_LT(o.psi0_V, -0.1f); // the flux present at the start lowers the voltage it takes to build it
}

TEST(IdentRotorFit, NoiseOfTheVoltageAveragesOut)
{
    // 20 mV rms per bin (1.4 % of Rs times the step, a 2250 hp motor); five seeds
    Machine mc;
    mc.rs = 0.029;
    mc.rr_ref = 0.0213;
    mc.tr = 1.6;
    mc.lsig = 1.19e-3;
    const double bin = 0.114;
    for (unsigned seed = 1u; seed <= 5u; ++seed) {
        auto b = record(mc, bin, 125, 55, 3e-3, 0.0, 0.5, 0.02, seed, 95.0, 47.5);
        ident_rotor_fit_out o;
        ident_rotor_fit(b.data(), uint32_t(b.size()), float(bin), float(bin / 2), float(10 * 125 * bin), &o);
        ASSERT_EQ(o.status, 0);
        EXPECT_NEAR(o.rs_ohm, mc.rs, 0.02 * mc.rs) << "seed " << seed;
        EXPECT_NEAR(o.rr_ref_ohm, mc.rr_ref, 0.05 * mc.rr_ref) << "seed " << seed;
        EXPECT_NEAR(o.tr_s, mc.tr, 0.05 * mc.tr) << "seed " << seed;
        EXPECT_NEAR(o.resid_V, 0.02, 0.01) << "seed " << seed; // the residual is the noise
    }
}

TEST(IdentRotorFit, WithoutARotorRsComesFromTheTwoLevelsAlone)
{
    // a resistor and an inductor: no transient, so a Tr beyond the record; R_R would share Rs
    Machine mc;
    mc.rr_ref = 0.0;
    const double bin = 9.2e-3;
    auto b = record(mc, bin, 125, 70, 1e-3, 0.0, 0.3, 1e-3, 1u);
    ident_rotor_fit_out o;
    ident_rotor_fit(b.data(), uint32_t(b.size()), float(bin), float(bin / 2), float(10 * 125 * bin), &o);
    EXPECT_EQ(o.status, 1);
    EXPECT_NEAR(o.rs_ohm, mc.rs, 2e-3 * mc.rs);
    EXPECT_NEAR(o.u_off_V, 0.3, 2e-3);
    EXPECT_EQ(o.rr_ref_ohm, 0.0f);
    EXPECT_EQ(o.tr_s, 0.0f);
}

TEST(IdentRotorFit, TooFewBinsOrBadArgumentsFail)
{
    Machine mc;
    const double bin = 9.2e-3;
    auto b = record(mc, bin, 125, 70, 1e-3, 0.0, 0.0, 0.0, 1u);
    for (auto &x : b)
        x.use = 0u;
    for (int k = 80; k < 86; ++k)
        b[k].use = 1u; // six bins: fewer than the eight the fit needs
    ident_rotor_fit_out o;
    ident_rotor_fit(b.data(), uint32_t(b.size()), float(bin), float(bin / 2), float(10 * 125 * bin), &o);
    EXPECT_EQ(o.status, -1);
    EXPECT_EQ(o.rs_ohm, 0.0f);
    auto good = record(mc, bin, 125, 70, 1e-3, 0.0, 0.0, 0.0, 1u);
    ident_rotor_fit(good.data(), uint32_t(good.size()), float(bin), 1.0f, 0.5f, &o); // lo > hi
    EXPECT_EQ(o.status, -1);
    ident_rotor_fit(good.data(), uint32_t(good.size()), 0.0f, 1e-3f, 1.0f, &o);
    EXPECT_EQ(o.status, -1);
}

TEST(IdentHf, MatchesEigenOnBurstRows)
{
    // bursts +, -, -, + of 1.9 A around the bias, with a slow drift of the bias voltage and noise
    std::mt19937 rng(3u);
    std::normal_distribution<double> n01(0.0, 1.0);
    const double T = 200e-6, L = 2.79e-3, R = 0.44;
    ident_hf_sums s;
    ident_hf_reset(&s);
    std::vector<std::array<double, 4>> rows;
    for (int burst = 0; burst < 64; ++burst) {
        const double x1s[4] = {1.9, -1.9, -1.9, 1.9}, x2s[4] = {0.95, 0.95, -0.95, -0.95};
        double c = 3.0 - 0.01 * burst; // the bias voltage falls as the rotor flux settles
        for (int q = 0; q < 4; ++q) {
            double x1 = x1s[q] * (1.0 + 0.02 * n01(rng)), x2 = x2s[q] + 0.01 * n01(rng);
            double y = L * x1 + R * T * x2 + c * T + 2e-5 * n01(rng);
            ident_hf_add(&s, float(y), float(x1), float(x2));
            rows.push_back({x1, x2, 1.0, y});
        }
    }
    Eigen::MatrixXd A(rows.size(), 3);
    Eigen::VectorXd y(rows.size());
    for (size_t i = 0; i < rows.size(); ++i) {
        A(i, 0) = rows[i][0];
        A(i, 1) = rows[i][1];
        A(i, 2) = rows[i][2];
        y(i) = rows[i][3];
    }
    Eigen::VectorXd ref = A.colPivHouseholderQr().solve(y);
    real_t lsig, r_hf, misfit;
    ASSERT_EQ(ident_hf_solve(&s, float(T), &lsig, &r_hf, &misfit), 0);
    EXPECT_NEAR(lsig, ref(0), 1e-3 * ref(0));
    EXPECT_NEAR(r_hf, ref(1) / T, 0.02 * std::fabs(ref(1) / T));
    EXPECT_NEAR(lsig, L, 0.01 * L);
    EXPECT_LT(misfit, 0.02f);
}

TEST(IdentHf, RefusesTooFewOrFlatRows)
{
    ident_hf_sums s;
    ident_hf_reset(&s);
    real_t l, r, m;
    EXPECT_EQ(ident_hf_solve(&s, 200e-6f, &l, &r, &m), -1);
    for (int k = 0; k < 40; ++k)
        ident_hf_add(&s, 1e-3f, 0.0f, 0.0f); // no current step: nothing to see
    EXPECT_EQ(ident_hf_solve(&s, 200e-6f, &l, &r, &m), -1);
    EXPECT_EQ(l, 0.0f);
}

// The T-model's steady state at electrical frequency w and slip frequency ws,
// driven by the stator current phasor I (by phasors: no dtc code).
struct Steady {
    std::complex<double> psi, i;
};

Steady t_model_steady(double lls, double llr, double lm, double rr, double w, double ws, std::complex<double> i)
{
    // rotor: 0 = rr ir + j ws psi_r, psi_r = lm i + (lm + llr) ir
    std::complex<double> j(0.0, 1.0);
    std::complex<double> ir = -j * ws * lm * i / (rr + j * ws * (lm + llr));
    Steady s;
    s.i = i;
    s.psi = (lls + lm) * i + lm * ir;
    (void)w;
    return s;
}

TEST(IdentLmNoLoad, IsTheMagnetisingInductanceAtAnySlipWithSwitchingRipple)
{
    const double lls = 1.42e-3, llr = 1.42e-3, lm = 0.0416, rr = 0.158;
    const double lsig = lls + lm - lm * lm / (lm + llr), l_m = lm * lm / (lm + llr);
    for (double ws : {0.0, 0.5, 5.0}) { // no load, friction, a fifth of the rated slip
        Steady st = t_model_steady(lls, llr, lm, rr, 188.5, ws, std::polar(11.0, 0.3));
        // window means over 1 s at 5 kHz, with a ripple current of 8 A rms at 1.37 kHz whose flux is Lsig times it
        double p = 0, q = 0, i2 = 0, psi2 = 0;
        const int n = 5000;
        for (int k = 0; k < n; ++k) {
            double t = k * 200e-6;
            std::complex<double> rot = std::polar(1.0, 188.5 * t);
            std::complex<double> di = std::polar(8.0 * std::sqrt(2.0), 2.0 * kPi * 1370.0 * t + 0.7);
            std::complex<double> i = st.i * rot + di, psi = st.psi * rot + lsig * di;
            std::complex<double> c = std::conj(psi) * i;
            p += c.real();
            q += c.imag();
            i2 += std::norm(i);
            psi2 += std::norm(psi);
        }
        real_t i0;
        real_t got = ident_lm_from_no_load(float(p / n), float(q / n), float(i2 / n), float(psi2 / n), float(lsig), &i0);
        EXPECT_NEAR(got, l_m, 2e-3 * l_m) << "slip " << ws;
        EXPECT_NEAR(i0, 11.0, 0.03) << "slip " << ws; // the fundamental's, not the ripple's
        // the same with |i|^2 in place of the flux (what the ripple spoils): far off
        double a = p / n - lsig * i2 / n;
        EXPECT_LT((a * a + (q / n) * (q / n)) / (a * i2 / n), 0.7 * l_m);
    }
    EXPECT_EQ(ident_lm_from_no_load(1.0f, 0.0f, 1000.0f, 1.0f, 0.01f, nullptr), 0.0f); // A <= 0
    EXPECT_EQ(ident_lm_from_no_load(5.0f, 0.0f, 0.0f, 0.2f, 0.003f, nullptr), 0.0f);
}

// A speed change at constant torque with viscous and Coulomb friction,
// integrated finely; the window between w_from and w_to as the sequencer
// takes it (torque integral, time, speed change).
ident_speed_window speed_change(double J, double B, double Tc, double te, double w0, double w_from, double w_to)
{
    const double h = 1e-5;
    double w = w0, t = 0.0, I = 0.0, t0 = -1.0, w_open = 0.0;
    bool rising = w_to > w_from;
    ident_speed_window win{};
    for (int k = 0; k < 10000000; ++k) {
        bool past_from = rising ? w >= w_from : w <= w_from;
        bool past_to = rising ? w >= w_to : w <= w_to;
        if (t0 < 0.0 && past_from) {
            t0 = t;
            w_open = w;
        }
        if (t0 >= 0.0 && past_to) {
            win.t_s = float(t - t0);
            win.dw_rad_s = float(w - w_open);
            win.te_int_Nms = float(I);
            return win;
        }
        if (t0 >= 0.0)
            I += te * h;
        w += h * (te - B * w - Tc * (w > 0 ? 1.0 : -1.0)) / J;
        t += h;
    }
    return win;
}

TEST(IdentInertia, FrictionDropsOutOfAnAccelerationAndADeceleration)
{
    const double J = 0.045, B = 0.005, Tc = 0.4, te = 12.0;
    ident_speed_window up = speed_change(J, B, Tc, te, 0.0, 56.0, 113.0);
    ident_speed_window down = speed_change(J, B, Tc, -te, 132.0, 113.0, 56.0);
    EXPECT_NEAR(ident_inertia(&up, &down), J, 2e-3 * J);
    // from one window alone the friction would be counted as inertia
    EXPECT_GT(std::fabs(up.te_int_Nms / up.dw_rad_s - J), 0.02 * J);
    ident_speed_window zero{};
    EXPECT_EQ(ident_inertia(&up, &zero), 0.0f);
}

TEST(IdentFriction, IsTheSlopeOfTheTorqueOverTheSpeed)
{
    // Te = Tc + B w at two speeds: the Coulomb part drops out
    EXPECT_NEAR(ident_friction(0.4f + 0.005f * 94.0f, 94.0f, 0.4f + 0.005f * 150.0f, 150.0f), 0.005f, 1e-6f);
    EXPECT_EQ(ident_friction(1.0f, 50.0f, 2.0f, 50.0f), 0.0f);
}

TEST(IdentTModel, InvertsTheInverseGammaModelWithEqualLeakages)
{
    const double lls = 1.42e-3, lm = 0.0416, rr = 0.158, lr = lls + lm;
    const double lsig = lr - lm * lm / lr, l_m = lm * lm / lr, r_r = rr * (lm / lr) * (lm / lr);
    ident_t_params t;
    ASSERT_EQ(ident_t_model(float(lsig), float(l_m), float(r_r), &t), 0);
    EXPECT_NEAR(t.lm_H, lm, 1e-5 * lm);
    EXPECT_NEAR(t.ls_H, lr, 1e-5 * lr);
    EXPECT_NEAR(t.lr_H, lr, 1e-5 * lr);
    EXPECT_NEAR(t.rr_ohm, rr, 1e-5 * rr);
    EXPECT_EQ(ident_t_model(0.0f, float(l_m), float(r_r), &t), -1);
    EXPECT_EQ(t.lm_H, 0.0f);
}

} // namespace
