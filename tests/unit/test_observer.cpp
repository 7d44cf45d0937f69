// The adaptive flux observer against an independent reference: the machine's
// continuous state-space model written from its flux and voltage equations
// (tests/common/im_ref.hpp) and discretised exactly with Eigen's matrix
// exponential.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <complex>
#include <vector>

#include "dtc/ctl.h"
#include "dtc/observer.h"
#include "im_ref.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kT = 200e-6;

observer_cfg default_obs()
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    return c.obs;
}

struct ModelCase {
    const char *name;
    double omega_e;  // rotor speed, electrical rad/s
    double f_hz;     // supply frequency (negative: reverse sequence)
    double v_peak;   // supply amplitude (phase peak), V
};

struct ModelErrors {
    double obs_is, obs_psi;   // max error of the firmware model, relative to the peak
    double euler_is, euler_psi;
};

// Run the firmware's discretised model (G = 0, fixed speed), the exact ZOH
// solution and forward Euler side by side from rest for n steps.
ModelErrors run_open_loop(const ModelCase &c, int n)
{
    observer_cfg cfg = default_obs();
    const observer_model &m = cfg.m;
    imref::Params P;
    imref::Mat4 A, Phi;
    imref::Mat42 B, Gam;
    imref::state_space(P, c.omega_e, A, B);
    imref::zoh(A, B, kT, Phi, Gam);

    imref::Vec4 xr = imref::Vec4::Zero(), xe = imref::Vec4::Zero();
    float xo[4] = {0, 0, 0, 0};
    double peak_is = 0, peak_psi = 0, err_is = 0, err_psi = 0, eul_is = 0, eul_psi = 0;
    for (int k = 0; k < n; ++k) {
        double th = 2 * kPi * c.f_hz * k * kT;
        Eigen::Vector2d v(c.v_peak * std::cos(th), c.v_peak * std::sin(th));
        float u_is[2] = {float(m.b * v[0]), float(m.b * v[1])};
        float u_psi[2] = {0, 0};
        float xn[4];
        observer_model_advance(&m, m.rs_nom_ohm, float(c.omega_e), xo, u_is, u_psi, xn);
        std::copy(xn, xn + 4, xo);
        xe = xe + kT * (A * xe + B * v);
        xr = Phi * xr + Gam * v;

        peak_is = std::max(peak_is, xr.head<2>().norm());
        peak_psi = std::max(peak_psi, xr.tail<2>().norm());
        Eigen::Vector2d eo_i(xo[0] - xr[0], xo[1] - xr[1]), eo_p(xo[2] - xr[2], xo[3] - xr[3]);
        err_is = std::max(err_is, eo_i.norm());
        err_psi = std::max(err_psi, eo_p.norm());
        eul_is = std::max(eul_is, (xe - xr).head<2>().norm());
        eul_psi = std::max(eul_psi, (xe - xr).tail<2>().norm());
    }
    return {err_is / peak_is, err_psi / peak_psi, eul_is / peak_is, eul_psi / peak_psi};
}

// 0.5 s from rest: 2500 steps, 30 electrical cycles at 60 Hz.
TEST(ObserverModel, MatchesMatrixExponentialWhereEulerFails)
{
    const double bound = 2e-3; // 0.2 % of the peak, over the whole run
    const ModelCase cases[] = {
        {"60 Hz, rated speed 1744 rpm", 2 * 1744.0 * 2 * kPi / 60.0, 60.0, 179.6},
        {"60 Hz reverse, rated speed reverse", -2 * 1744.0 * 2 * kPi / 60.0, -60.0, 179.6},
        {"60 Hz, overspeed 2200 rpm (generating)", 2 * 2200.0 * 2 * kPi / 60.0, 60.0, 179.6},
    };
    for (const ModelCase &c : cases) {
        SCOPED_TRACE(c.name);
        ModelErrors e = run_open_loop(c, 2500);
        EXPECT_LT(e.obs_is, bound);
        EXPECT_LT(e.obs_psi, bound);
        // forward Euler on the same steps leaves the same bound far behind
        EXPECT_GT(std::max(e.euler_is, e.euler_psi), 10 * bound);
        RecordProperty(std::string("obs_err_") + c.name, std::to_string(std::max(e.obs_is, e.obs_psi)));
        RecordProperty(std::string("euler_err_") + c.name, std::to_string(std::max(e.euler_is, e.euler_psi)));
    }
}

// Slow supply: the same bound also holds near standstill (5 Hz, locked rotor).
TEST(ObserverModel, MatchesMatrixExponentialAtStandstill)
{
    ModelErrors e = run_open_loop({"5 Hz locked", 0.0, 5.0, 20.0}, 5000);
    EXPECT_LT(e.obs_is, 2e-3);
    EXPECT_LT(e.obs_psi, 2e-3);
}

std::vector<std::complex<double>> sorted_eig(const Eigen::Matrix4d &M)
{
    Eigen::EigenSolver<Eigen::Matrix4d> es(M);
    std::vector<std::complex<double>> ev(es.eigenvalues().data(), es.eigenvalues().data() + 4);
    std::sort(ev.begin(), ev.end(), [](auto a, auto b) {
        return a.real() != b.real() ? a.real() < b.real() : a.imag() < b.imag();
    });
    return ev;
}

// Kubota's gain: the error dynamics A + G C have k times the motor's poles.
TEST(ObserverGain, PolesAreKTimesMotorPoles)
{
    imref::Params P;
    for (double k : {1.0, 1.3, 2.0}) {
        for (double w : {0.0, 104.7, 377.0, -250.0}) {
            ctl_cfg cc;
            ctl_cfg_default(&cc);
            cc.obs.k_gain = float(k);
            ctl_cfg_derive(&cc); // the gain's constants are per configuration
            observer_cfg cfg = cc.obs;
            float gi[2], gp[2];
            observer_gain(&cfg, float(w), cfg.m.rs_nom_ohm, gi, gp);
            Eigen::Matrix<double, 4, 2> G;
            G << gi[0], -gi[1], gi[1], gi[0], gp[0], -gp[1], gp[1], gp[0];
            Eigen::Matrix<double, 2, 4> C = Eigen::Matrix<double, 2, 4>::Zero();
            C(0, 0) = C(1, 1) = 1.0;
            imref::Mat4 A;
            imref::Mat42 B;
            imref::state_space(P, w, A, B);
            auto motor = sorted_eig(A);
            auto obs = sorted_eig(A + G * C);
            SCOPED_TRACE(testing::Message() << "k=" << k << " omega=" << w);
            for (int i = 0; i < 4; ++i) {
                std::complex<double> want = k * motor[i];
                EXPECT_LT(std::abs(obs[i] - want), 1e-3 * std::abs(want) + 1e-3)
                    << "pole " << i << ": " << obs[i] << " vs " << want;
            }
        }
    }
}

// Exact simulation of the motor at a constant speed fed by a sinusoidal
// voltage; the observer gets the sampled currents and the applied voltage.
struct AdaptRun {
    std::vector<double> omega_hat;  // electrical, per step
    std::vector<double> rs_hat;
};

AdaptRun run_adaptation(const observer_cfg &cfg, const imref::Params &plant, double omega_e, double f_hz,
                        double v_peak, int n, double omega_init, bool freeze_speed)
{
    imref::Mat4 A, Phi;
    imref::Mat42 B, Gam;
    imref::state_space(plant, omega_e, A, B);
    imref::zoh(A, B, kT, Phi, Gam);
    observer obs;
    observer_init(&obs, &cfg);
    obs.omega_int_rad_s = obs.omega_e_rad_s = float(omega_init);
    imref::Vec4 x = imref::Vec4::Zero();
    AdaptRun r;
    for (int k = 0; k < n; ++k) {
        double th = 2 * kPi * f_hz * k * kT;
        Eigen::Vector2d v(v_peak * std::cos(th), v_peak * std::sin(th));
        float is[2] = {float(x[0]), float(x[1])}, vf[2] = {float(v[0]), float(v[1])};
        observer_out out;
        observer_step(&obs, &cfg, is, vf, &out);
        if (freeze_speed)
            obs.omega_int_rad_s = obs.omega_e_rad_s = float(omega_init);
        r.omega_hat.push_back(obs.omega_e_rad_s);
        r.rs_hat.push_back(obs.rs_ohm);
        x = Phi * x + Gam * v;
    }
    return r;
}

double mean_tail(const std::vector<double> &v, int n)
{
    double s = 0;
    for (int i = int(v.size()) - n; i < int(v.size()); ++i)
        s += v[i];
    return s / n;
}

TEST(ObserverSpeed, AdaptationConvergesToTrueSpeed)
{
    struct Case {
        const char *name;
        double omega_e, f_hz, v_peak;
    } cases[] = {
        {"500 rpm, motoring (slip 5 %)", 2 * 500.0 * 2 * kPi / 60.0, 17.5, 58.0},
        {"500 rpm reverse", -2 * 500.0 * 2 * kPi / 60.0, -17.5, 58.0},
        {"1744 rpm, 60 Hz", 2 * 1744.0 * 2 * kPi / 60.0, 60.0, 179.6},
        {"100 rpm", 2 * 100.0 * 2 * kPi / 60.0, 3.6, 14.0},
    };
    observer_cfg cfg = default_obs();
    for (const Case &c : cases) {
        SCOPED_TRACE(c.name);
        AdaptRun r = run_adaptation(cfg, imref::Params{}, c.omega_e, c.f_hz, c.v_peak, 10000, 0.0, false);
        double last = mean_tail(r.omega_hat, 1000); // last 0.2 s
        EXPECT_NEAR(last, c.omega_e, 0.005 * std::abs(c.omega_e) + 0.05);
        // and it stays there: no drift or oscillation over the last 0.2 s
        double worst = 0;
        for (int i = 9000; i < 10000; ++i)
            worst = std::max(worst, std::abs(r.omega_hat[i] - c.omega_e));
        EXPECT_LT(worst, 0.02 * std::abs(c.omega_e) + 0.2);
    }
}

TEST(ObserverRs, AdaptationMovesTowardTrueRs)
{
    ctl_cfg cc;
    ctl_cfg_default(&cc);
    cc.obs.ki_rs = 0.01f;
    ctl_cfg_derive(&cc); // ki_rs x T is a per-configuration constant
    observer_cfg cfg = cc.obs;
    imref::Params hot;
    hot.Rs = 1.3 * 0.288; // the winding is 30 % hotter than modelled
    double we = 2 * 500.0 * 2 * kPi / 60.0;
    AdaptRun r = run_adaptation(cfg, hot, we, 17.5, 58.0, 20000, we, true); // 4 s
    double start_err = std::abs(0.288 - hot.Rs);
    double end_err = std::abs(mean_tail(r.rs_hat, 500) - hot.Rs);
    EXPECT_LT(end_err, 0.25 * start_err) << "Rs_hat ends at " << mean_tail(r.rs_hat, 500);
    // it moved in the right direction from the start
    EXPECT_GT(r.rs_hat[2000], 0.288f);

    // a cold winding (Rs lower than modelled) is followed downwards as well
    imref::Params cold;
    cold.Rs = 0.8 * 0.288;
    r = run_adaptation(cfg, cold, we, 17.5, 58.0, 20000, we, true);
    EXPECT_LT(std::abs(mean_tail(r.rs_hat, 500) - cold.Rs), 0.25 * std::abs(0.288 - cold.Rs));
}

// With the adaptation off and the right speed, the observer reproduces the
// motor's torque and stator flux (the quantities the DTC acts on).
TEST(ObserverOutputs, TorqueAndFluxMatchReference)
{
    observer_cfg cfg = default_obs();
    imref::Params P;
    double we = 2 * 500.0 * 2 * kPi / 60.0;
    imref::Mat4 A, Phi;
    imref::Mat42 B, Gam;
    imref::state_space(P, we, A, B);
    imref::zoh(A, B, kT, Phi, Gam);
    observer obs;
    observer_init(&obs, &cfg);
    imref::Vec4 x = imref::Vec4::Zero();
    double worst_te = 0, worst_psi = 0, worst_pred_te = 0, worst_slope = 0, peak_slope = 0;
    for (int k = 0; k < 10000; ++k) {
        double th = 2 * kPi * 17.5 * k * kT;
        Eigen::Vector2d v(58.0 * std::cos(th), 58.0 * std::sin(th));
        float is[2] = {float(x[0]), float(x[1])}, vf[2] = {float(v[0]), float(v[1])};
        observer_out out;
        obs.omega_int_rad_s = obs.omega_e_rad_s = float(we);
        observer_step(&obs, &cfg, is, vf, &out);
        imref::Vec4 xn = Phi * x + Gam * v;
        if (k > 5000) {
            worst_te = std::max(worst_te, std::abs(out.te_Nm - imref::torque(P, x)));
            worst_psi = std::max(worst_psi, std::abs(out.psi_s_abs_Wb - imref::psi_s(P, x).norm()));
            worst_pred_te = std::max(worst_pred_te, std::abs(out.te_pred_Nm - imref::torque(P, xn)));
            // the torque slopes at t_{k+1}: dTe/dt of the machine equations,
            // 1.5 p (dpsi_s x is + psi_s x dis), at the reference state, under zero voltage
            // (dte0) and per volt of each axis (dte_dv); a steady state's own voltage would
            // give a slope near 0 whatever the terms
            auto slope_ref = [&](const Eigen::Vector2d &vv) {
                imref::Vec4 dx = imref::deriv(P, we, xn, vv);
                Eigen::Vector2d ps = imref::psi_s(P, xn);
                double sigma_ls = P.Ls() - P.Lm * P.Lm / P.Lr();
                Eigen::Vector2d dps = sigma_ls * dx.head<2>() + (P.Lm / P.Lr()) * dx.tail<2>();
                return 1.5 * P.p * (dps[0] * xn[1] - dps[1] * xn[0] + ps[0] * dx[1] - ps[1] * dx[0]);
            };
            double s0 = slope_ref(Eigen::Vector2d::Zero());
            double sa = slope_ref(Eigen::Vector2d(1.0, 0.0)) - s0, sb = slope_ref(Eigen::Vector2d(0.0, 1.0)) - s0;
            worst_slope = std::max(worst_slope, std::abs(out.dte0_Nm_s - s0));
            worst_slope = std::max(worst_slope, 100.0 * std::abs(out.dte_dv[0] - sa)); // per 100 V
            worst_slope = std::max(worst_slope, 100.0 * std::abs(out.dte_dv[1] - sb));
            peak_slope = std::max(peak_slope, std::abs(s0));
        }
        x = xn;
    }
    EXPECT_LT(worst_te, 0.05);      // N m, at about 20 N m of load
    EXPECT_LT(worst_psi, 1e-3);     // Wb
    EXPECT_LT(worst_pred_te, 0.05); // the one-period prediction too
    std::printf("torque slope: worst error %.1f N m/s of peak %.1f N m/s\n", worst_slope, peak_slope);
    EXPECT_LT(worst_slope, 1e-4 * peak_slope); // and its slopes (the DTC's duty calculation)
}

} // namespace
