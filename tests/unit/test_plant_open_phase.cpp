// A motor phase disconnected from its inverter leg (plant_set_phase_open):
// no current in it, and the remaining line current against the hand-derived
// initial slope of two leakage inductances in series.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "plant/plant.h"

namespace {

constexpr uint8_t N = 0, O = 1, P = 2;
const double kT = 200e-6;
const double kVdc = 311.0;

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

} // namespace

// A disconnected phase: its current is cut to zero and stays zero; the other
// two carry i_b = -i_c. From standstill and zero flux, with phase a open and
// v_bc = vc1 + vc2 applied (legs b at P, c at N), the line current starts
// with di_b/dt = v_bc / (2 sigma Ls) (two leakage paths in series; the rotor
// flux has not moved yet).
TEST(PlantOpenPhase, OpenPhaseCarriesNoCurrentAndTheOthersSeeTwoLeakages)
{
    plant_config c;
    plant_default_config(&c);
    c.dc.c1_F = c.dc.c2_F = 1e3;
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    set_currents(s, 10.0, -4.0, -6.0);
    plant_set_phase_open(&s, 0, 1);
    const uint8_t pon[3] = {P, P, N}, ooo[3] = {O, O, O};
    plant_advance(&s, ooo, ooo, 1.0, kT);
    plant_truth tr;
    plant_get_truth(&s, &tr);
    EXPECT_NEAR(tr.ia_A, 0.0, 1e-9); // cut at once
    for (int k = 0; k < 20; ++k) {
        plant_advance(&s, pon, ooo, 0.5, kT);
        plant_get_truth(&s, &tr);
        EXPECT_NEAR(tr.ia_A, 0.0, 1e-9);
        EXPECT_NEAR(tr.ib_A + tr.ic_A, 0.0, 1e-9);
    }

    plant_state z;
    ASSERT_EQ(plant_init(&z, &c), 0);
    plant_set_phase_open(&z, 0, 1);
    const double Ls = c.motor.Lls_H + c.motor.Lm_H, Lr = c.motor.Llr_H + c.motor.Lm_H;
    const double sigma_Ls = Ls - c.motor.Lm_H * c.motor.Lm_H / Lr;
    const double dt = 10e-6;
    plant_advance(&z, pon, pon, 1.0, dt);
    plant_get_truth(&z, &tr);
    double expect = kVdc * dt / (2.0 * sigma_Ls);
    EXPECT_NEAR(tr.ib_A, expect, 0.01 * expect);
    EXPECT_NEAR(tr.ia_A, 0.0, 1e-9);
    plant_set_phase_open(&z, 0, 0); // reconnected: phase a conducts again
    plant_advance(&z, pon, pon, 1.0, dt);
    plant_get_truth(&z, &tr);
    EXPECT_GT(std::fabs(tr.ia_A), 0.1);
}
