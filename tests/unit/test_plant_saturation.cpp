// Main-flux saturation of the plant: the currents it derives from the fluxes
// lie on the documented magnetising curve i_m = (psi_m/Lm0)(1 + (|psi_m|/psi_k)^n),
// and a direct-on-line run at no load settles on the magnetising current that
// the curve and the stator circuit predict (solved here independently).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "plant/plant.h"

namespace {

const double kPi = 3.14159265358979323846;

plant_config sat_cfg(double psi_k, double n)
{
    plant_config c;
    plant_default_config(&c);
    c.motor.Lm_sat_psi_Wb = psi_k;
    c.motor.Lm_sat_exponent = n;
    return c;
}

} // namespace

TEST(PlantSaturation, CurrentsLieOnTheMagnetisingCurve)
{
    for (double n : {2.0, 6.0, 12.0}) {
        plant_config c = sat_cfg(0.5, n);
        plant_state s;
        ASSERT_EQ(plant_init(&s, &c), 0);
        const double fluxes[][4] = {
            {0.6, 0.2, 0.55, 0.25}, {-0.3, 0.4, -0.28, 0.41}, {0.05, -0.01, 0.04, -0.02}, {0.9, -0.5, 0.7, -0.6}};
        for (const auto &f : fluxes) {
            s.psi_s[0] = f[0];
            s.psi_s[1] = f[1];
            s.psi_r[0] = f[2];
            s.psi_r[1] = f[3];
            plant_truth t;
            plant_get_truth(&s, &t);
            const double Lls = c.motor.Lls_H, Llr = c.motor.Llr_H, Lm0 = c.motor.Lm_H;
            // psi_m from either side of the T-circuit must agree.
            double pm0 = f[0] - Lls * t.is_alpha_A, pm1 = f[1] - Lls * t.is_beta_A;
            EXPECT_NEAR(f[2] - Llr * t.ir_alpha_A, pm0, 1e-12);
            EXPECT_NEAR(f[3] - Llr * t.ir_beta_A, pm1, 1e-12);
            double im0 = t.is_alpha_A + t.ir_alpha_A, im1 = t.is_beta_A + t.ir_beta_A;
            double pm = std::hypot(pm0, pm1), im = std::hypot(im0, im1);
            double curve = pm / Lm0 * (1.0 + std::pow(pm / 0.5, n));
            EXPECT_NEAR(im, curve, 1e-9 * curve) << "n " << n << " psi_m " << pm;
            EXPECT_NEAR(pm0 * im1 - pm1 * im0, 0.0, 1e-12); // i_m parallel to psi_m
        }
    }
}

// Far below the knee the machine is the linear one; at the knee Lm has halved.
TEST(PlantSaturation, LinearBelowTheKneeHalfAtTheKnee)
{
    plant_config lin;
    plant_default_config(&lin);
    plant_config c = sat_cfg(0.5, 6.0);
    plant_state a, b;
    ASSERT_EQ(plant_init(&a, &lin), 0);
    ASSERT_EQ(plant_init(&b, &c), 0);
    a.psi_s[0] = b.psi_s[0] = 0.05; // psi_m ~ 0.05 Wb: (0.1)^6 = 1e-6
    a.psi_r[0] = b.psi_r[0] = 0.049;
    plant_truth ta, tb;
    plant_get_truth(&a, &ta);
    plant_get_truth(&b, &tb);
    EXPECT_NEAR(tb.is_alpha_A, ta.is_alpha_A, 1e-5 * std::fabs(ta.is_alpha_A) + 1e-9);
    EXPECT_NEAR(tb.ir_alpha_A, ta.ir_alpha_A, 1e-5 * std::fabs(ta.is_alpha_A) + 1e-9);

    // Zero rotor current and psi_m exactly at the knee: i_m = 2 psi_k / Lm0.
    double im = 2.0 * 0.5 / c.motor.Lm_H;
    b.psi_s[0] = 0.5 + c.motor.Lls_H * im;
    b.psi_r[0] = 0.5;
    plant_get_truth(&b, &tb);
    EXPECT_NEAR(tb.is_alpha_A, im, 1e-9 * im);
    EXPECT_NEAR(tb.ir_alpha_A, 0.0, 1e-9 * im);
}

// Direct-on-line at no load with B = 0: the rotor reaches synchronous speed,
// the rotor current dies out and i_s = i_m. Amplitude-invariant peaks:
//   |V| = sqrt((Rs I)^2 + (w (Lls I + psi_m))^2),  I = i_m(psi_m),
// solved for psi_m by bisection. The saturated machine draws a markedly
// larger magnetising current than the linear one.
TEST(PlantSaturation, NoLoadMagnetisingCurrentMatchesTheCurve)
{
    const double psi_k = 0.5, n = 6.0;
    plant_config c = sat_cfg(psi_k, n);
    c.supply = PLANT_SUPPLY_SINE;
    c.sine.v_ll_rms_V = 220.0;
    c.sine.f_Hz = 60.0;
    c.motor.B_Nms = 0.0;
    const double w = 2.0 * kPi * 60.0, V = std::sqrt(2.0 / 3.0) * 220.0;
    const double Rs = c.motor.Rs_ohm, Lls = c.motor.Lls_H, Lm0 = c.motor.Lm_H;
    auto I_of = [&](double pm) { return pm / Lm0 * (1.0 + std::pow(pm / psi_k, n)); };
    auto V_of = [&](double pm) { double I = I_of(pm); return std::hypot(Rs * I, w * (Lls * I + pm)); };
    double lo = 0.0, hi = V / w;
    for (int i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        (V_of(mid) < V ? lo : hi) = mid;
    }
    const double is_rms_ref = I_of(0.5 * (lo + hi)) / std::sqrt(2.0);
    const double is_rms_lin = V / std::hypot(Rs, w * (Lls + Lm0)) / std::sqrt(2.0);

    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    const double T = 1.0 / 6000.0;
    for (int k = 0; k < 12000; ++k) // 2 s: start, then the rotor current decays
        plant_advance(&s, nullptr, nullptr, 1.0, T);
    double si2 = 0.0, sw = 0.0;
    plant_truth tr;
    for (int k = 0; k < 600; ++k) {
        plant_advance(&s, nullptr, nullptr, 1.0, T);
        plant_get_truth(&s, &tr);
        si2 += tr.ia_A * tr.ia_A + tr.ib_A * tr.ib_A + tr.ic_A * tr.ic_A;
        sw += tr.omega_m_rad_s;
    }
    double is_rms = std::sqrt(si2 / (3.0 * 600.0));
    std::printf("no load, saturated: %.4f A rms (curve %.4f A, linear machine %.4f A), %.3f rpm\n", is_rms,
                is_rms_ref, is_rms_lin, sw / 600.0 * 60.0 / (2.0 * kPi));
    EXPECT_NEAR(is_rms, is_rms_ref, 0.002 * is_rms_ref);
    EXPECT_GT(is_rms_ref, 1.2 * is_rms_lin); // the test would notice a linear machine
}
