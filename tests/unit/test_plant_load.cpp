// Shaft load models of the plant against closed forms and an independent
// steady state: a coasting rotor braked by Coulomb + viscous friction, a
// stuck rotor held by static friction, the breakaway, and the operating
// point of a fan load on the sine supply from the T-equivalent circuit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>

#include "plant/plant.h"
#include "tequiv.hpp"

namespace {

const double kPi = 3.14159265358979323846;

// A demagnetised motor with its gates off carries no current: Te = 0, so the
// rotor only feels the mechanics.
void coast(plant_state &s, int n, double T)
{
    for (int k = 0; k < n; ++k)
        plant_advance(&s, nullptr, nullptr, 1.0, T);
}

} // namespace

// J dw/dt = -Tc - b w (b = B + viscous) from w0 > 0:
//   w(t) = (w0 + Tc/b) exp(-b t / J) - Tc/b until t_stop = (J/b) ln(1 + b w0 / Tc),
// then w = 0 for good (Tc holds the rotor; no other torque).
TEST(PlantLoad, CoulombPlusViscousCoastDownFollowsTheClosedForm)
{
    plant_config c;
    plant_default_config(&c);
    c.load.coulomb_Nm = 2.0;
    c.load.viscous_Nms = 0.02;
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    const double w0 = 100.0, J = c.motor.J_kgm2, b = c.motor.B_Nms + c.load.viscous_Nms, Tc = 2.0;
    s.omega_m = w0;
    const double t_stop = J / b * std::log(1.0 + b * w0 / Tc); // 1.4597 s
    const double T = 1e-3;
    double worst = 0.0;
    int k_stop = -1;
    for (int k = 1; k <= 2000; ++k) {
        coast(s, 1, T);
        double t = k * T;
        if (t < t_stop - T) {
            double ref = (w0 + Tc / b) * std::exp(-b * t / J) - Tc / b;
            worst = std::fmax(worst, std::fabs(s.omega_m - ref));
        } else if (t > t_stop + T) {
            EXPECT_EQ(s.omega_m, 0.0) << "t = " << t; // stopped, not reversed, not creeping
        }
        if (k_stop < 0 && s.omega_m == 0.0)
            k_stop = k;
    }
    std::printf("coast-down: worst |w - closed form| %.3g rad/s, stop at %.4f s (closed form %.4f s)\n", worst,
                k_stop * T, t_stop);
    EXPECT_LT(worst, 1e-9);
    EXPECT_NEAR(k_stop * T, t_stop, T); // the stop lands in the period that contains t_stop
    EXPECT_DOUBLE_EQ(plant_load_torque(&s, -3.0), -2.0 - 0.02 * 3.0);
}

// The same rotor coasting backwards brakes symmetrically (the friction follows the sign of w).
TEST(PlantLoad, FrictionFollowsTheSignOfTheSpeed)
{
    plant_config c;
    plant_default_config(&c);
    c.load.coulomb_Nm = 1.0;
    c.motor.B_Nms = 0.0;
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    s.omega_m = -10.0;
    coast(s, 100, 1e-3); // 0.1 s: pure Coulomb, w = -10 + (Tc/J) t
    EXPECT_NEAR(s.omega_m, -10.0 + 1.0 / c.motor.J_kgm2 * 0.1, 1e-9);
}

// Static friction: an active load below the Coulomb level leaves a stopped
// rotor stopped (exactly); above it the rotor breaks away with (T_L - Tc)/J.
TEST(PlantLoad, StuckRotorStaysAndBreaksAwayAboveTheCoulombLevel)
{
    plant_config c;
    plant_default_config(&c);
    c.load.coulomb_Nm = 3.0;
    c.motor.B_Nms = 0.0;
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    plant_set_load(&s, 2.9);
    coast(s, 200, 1e-3);
    EXPECT_EQ(s.omega_m, 0.0);
    plant_set_load(&s, -2.9);
    coast(s, 200, 1e-3);
    EXPECT_EQ(s.omega_m, 0.0);
    plant_set_load(&s, 5.0); // drives backwards against 3 N m of friction
    coast(s, 100, 1e-3);
    EXPECT_NEAR(s.omega_m, -(5.0 - 3.0) / c.motor.J_kgm2 * 0.1, 1e-9);
}

// Fan load T = k w |w| on the 220 V / 60 Hz supply: the steady speed is where
// the T-equivalent circuit's torque equals B w + k w^2.
TEST(PlantLoad, FanLoadSteadyStateBalancesTheMotorTorque)
{
    plant_config c;
    plant_default_config(&c);
    c.supply = PLANT_SUPPLY_SINE;
    c.sine.v_ll_rms_V = 220.0;
    c.sine.f_Hz = 60.0;
    c.load.fan_Nms2 = 0.0008; // about 28 N m near 1790 rpm
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);

    tequiv::Machine m = tequiv::from_params(c.motor);
    auto f = [&](double sl) {
        tequiv::Point p = tequiv::at_slip(m, 220.0, 60.0, sl);
        return p.te_Nm - c.motor.B_Nms * p.omega_m_rad_s - 0.0008 * p.omega_m_rad_s * p.omega_m_rad_s;
    };
    double lo = 1e-9, hi = tequiv::pullout_slip(m, 220.0, 60.0);
    ASSERT_LT(f(lo), 0.0);
    ASSERT_GT(f(hi), 0.0);
    for (int i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        (f(mid) < 0.0 ? lo : hi) = mid;
    }
    tequiv::Point ref = tequiv::at_slip(m, 220.0, 60.0, 0.5 * (lo + hi));

    const double T = 1.0 / 6000.0; // 100 samples per electrical cycle
    for (int k = 0; k < 9000; ++k)  // 1.5 s: start and the slip's settling
        plant_advance(&s, nullptr, nullptr, 1.0, T);
    double sw = 0.0, ste = 0.0;
    plant_truth tr;
    for (int k = 0; k < 600; ++k) { // 6 cycles
        plant_advance(&s, nullptr, nullptr, 1.0, T);
        plant_get_truth(&s, &tr);
        sw += tr.omega_m_rad_s;
        ste += tr.te_Nm;
    }
    double w = sw / 600.0, te = ste / 600.0;
    double rpm = w * 60.0 / (2.0 * kPi);
    std::printf("fan load: %.3f rpm (T-equivalent %.3f), Te %.3f N m (B w + k w^2 = %.3f)\n", rpm, ref.speed_rpm, te,
                c.motor.B_Nms * w + 0.0008 * w * w);
    double slip = 1.0 - rpm / 1800.0;
    EXPECT_NEAR(slip, ref.slip, 0.01 * ref.slip);
    EXPECT_NEAR(te, ref.te_Nm, 0.01 * ref.te_Nm);
    EXPECT_NEAR(te, c.motor.B_Nms * w + 0.0008 * w * w, 0.005 * te); // the balance itself
    EXPECT_NEAR(plant_load_torque(&s, w), 0.0008 * w * w, 1e-12);
}
