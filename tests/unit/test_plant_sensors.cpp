// Plant sensors (ADC chain), configuration checks, scheduled parameter
// changes and bad input, against hand-computed codes and closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "plant/plant.h"

namespace {

plant_config quiet_cfg()
{
    plant_config c;
    plant_default_config(&c);
    return c;
}

// Put phase currents (zero sum) into the state with zero rotor current:
// psi_s = Ls i_s, psi_r = Lm i_s (alpha-beta, amplitude-invariant Clarke).
void set_currents(plant_state &s, double ia, double ib, double ic)
{
    const plant_motor_params &m = s.cfg.motor;
    double a = ia, b = (ib - ic) / std::sqrt(3.0);
    double Ls = m.Lls_H + m.Lm_H;
    s.psi_s[0] = Ls * a;
    s.psi_s[1] = Ls * b;
    s.psi_r[0] = m.Lm_H * a;
    s.psi_r[1] = m.Lm_H * b;
}

TEST(PlantSensors, CurrentTruthFollowsTheFluxes)
{
    plant_config c = quiet_cfg();
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    set_currents(s, 30.0, -10.0, -20.0);
    plant_truth t;
    plant_get_truth(&s, &t);
    EXPECT_NEAR(t.ia_A, 30.0, 1e-9);
    EXPECT_NEAR(t.ib_A, -10.0, 1e-9);
    EXPECT_NEAR(t.ic_A, -20.0, 1e-9);
    EXPECT_NEAR(t.ir_alpha_A, 0.0, 1e-9);
    EXPECT_NEAR(t.ir_beta_A, 0.0, 1e-9);
}

TEST(PlantSensors, CodesByHandAndClamping)
{
    plant_config c = quiet_cfg(); // 12 bits, +-150 A, 0..500 V
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    plant_adc a;

    // code = (i/150 + 1)/2 * 4095: 0 A -> 2047.5 -> 2048; 75 A -> 3071.25;
    // -75 A -> 1023.75 -> 1024; +-200 A clamps to 4095 / 0.
    set_currents(s, 75.0, -75.0, 0.0);
    s.vc1 = 155.5; // 155.5/500*4095 = 1273.545 -> 1274
    s.vc2 = 600.0; // above full scale -> 4095
    plant_sample(&s, &a);
    EXPECT_EQ(a.i_code[0], 3071);
    EXPECT_EQ(a.i_code[1], 1024);
    EXPECT_EQ(a.i_code[2], 2048);
    EXPECT_EQ(a.v_code[0], 1274);
    EXPECT_EQ(a.v_code[1], 4095);

    set_currents(s, 200.0, -200.0, 0.0);
    s.vc1 = -5.0;
    s.vc2 = 500.0;
    plant_sample(&s, &a);
    EXPECT_EQ(a.i_code[0], 4095);
    EXPECT_EQ(a.i_code[1], 0);
    EXPECT_EQ(a.v_code[0], 0);
    EXPECT_EQ(a.v_code[1], 4095);

    // converting back: 3071 -> (3071/4095*2 - 1)*150 = 74.9817 A
    set_currents(s, 75.0, -75.0, 0.0);
    plant_sample(&s, &a);
    double i[3], v[2];
    plant_adc_to_units(&s.cfg, &a, i, v);
    EXPECT_NEAR(i[0], 74.98168498, 1e-6);
    EXPECT_NEAR(i[2], 0.03663004, 1e-6);
}

TEST(PlantSensors, QuantisationStepIsFullScaleOverCodes)
{
    plant_config c = quiet_cfg();
    c.sensor.adc_bits = 10; // a coarser converter shows the step plainly
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    const double q = 300.0 / 1023.0, qv = 500.0 / 1023.0;
    std::vector<double> seen;
    double max_err = 0.0, max_verr = 0.0;
    for (int k = -1200; k <= 1200; ++k) {
        double ia = k * 0.1234567;
        set_currents(s, ia, -ia, 0.0);
        s.vc1 = 250.0 + k * 0.2;
        plant_adc a;
        plant_sample(&s, &a);
        double i[3], v[2];
        plant_adc_to_units(&s.cfg, &a, i, v);
        max_err = std::fmax(max_err, std::fabs(i[0] - ia));
        max_verr = std::fmax(max_verr, std::fabs(v[0] - s.vc1));
        if (seen.empty() || std::fabs(i[0] - seen.back()) > 1e-9)
            seen.push_back(i[0]);
    }
    EXPECT_LE(max_err, q / 2 + 1e-9);
    EXPECT_LE(max_verr, qv / 2 + 1e-9);
    for (size_t j = 1; j < seen.size(); ++j)
        EXPECT_NEAR(seen[j] - seen[j - 1], q, 1e-9);
}

TEST(PlantSensors, GainAndOffsetAreApplied)
{
    plant_config c = quiet_cfg();
    c.sensor.i_gain[0] = 1.1;
    c.sensor.i_offset_A[0] = 2.0;
    c.sensor.v_gain[1] = 0.9;
    c.sensor.v_offset_V[1] = 3.0;
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    set_currents(s, 10.0, -10.0, 0.0);
    s.vc2 = 100.0;
    plant_adc a;
    plant_sample(&s, &a);
    // 1.1 * 10 + 2 = 13 A: (13/150 + 1)/2*4095 = 2224.93 -> 2225
    EXPECT_EQ(a.i_code[0], 2225);
    // ideal phase b: -10 A: (1 - 10/150)/2*4095 = 1911.0 -> 1911
    EXPECT_EQ(a.i_code[1], 1911);
    // 0.9 * 100 + 3 = 93 V: 93/500*4095 = 761.67 -> 762
    EXPECT_EQ(a.v_code[1], 762);
}

struct NoiseStats {
    double mean[5], rms[5], corr01;
    std::vector<uint16_t> codes;
};

NoiseStats noise_run(uint32_t seed, int n)
{
    plant_config c = quiet_cfg();
    c.sensor.i_noise_A = 1.0;
    c.sensor.v_noise_V = 2.0;
    c.sensor.seed = seed;
    plant_state s;
    EXPECT_EQ(plant_init(&s, &c), 0);
    set_currents(s, 20.0, -5.0, -15.0);
    const double truth[5] = {20.0, -5.0, -15.0, s.vc1, s.vc2};
    NoiseStats st{};
    double sum[5] = {0}, sum2[5] = {0}, s01 = 0.0;
    for (int k = 0; k < n; ++k) {
        plant_adc a;
        plant_sample(&s, &a);
        double i[3], v[2];
        plant_adc_to_units(&s.cfg, &a, i, v);
        double e[5] = {i[0] - truth[0], i[1] - truth[1], i[2] - truth[2], v[0] - truth[3],
                       v[1] - truth[4]};
        for (int j = 0; j < 5; ++j) {
            sum[j] += e[j];
            sum2[j] += e[j] * e[j];
        }
        s01 += e[0] * e[1];
        for (int j = 0; j < 3; ++j)
            st.codes.push_back(a.i_code[j]);
    }
    for (int j = 0; j < 5; ++j) {
        st.mean[j] = sum[j] / n;
        st.rms[j] = std::sqrt(sum2[j] / n);
    }
    st.corr01 = s01 / n / (st.rms[0] * st.rms[1]);
    return st;
}

TEST(PlantSensors, NoiseIsSeededRepeatableAndHasTheConfiguredRms)
{
    const int n = 20000;
    NoiseStats a = noise_run(7, n), b = noise_run(7, n), d = noise_run(8, n);
    EXPECT_EQ(a.codes, b.codes);
    EXPECT_NE(a.codes, d.codes);
    // white noise plus uniform quantisation error q^2/12
    const double qi = 300.0 / 4095.0, qv = 500.0 / 4095.0;
    const double ri = std::sqrt(1.0 + qi * qi / 12), rv = std::sqrt(4.0 + qv * qv / 12);
    for (int j = 0; j < 3; ++j) {
        EXPECT_NEAR(a.rms[j], ri, 0.03 * ri) << "phase " << j;
        EXPECT_NEAR(a.mean[j], 0.0, 0.05);
    }
    for (int j = 3; j < 5; ++j) {
        EXPECT_NEAR(a.rms[j], rv, 0.03 * rv) << "voltage " << j - 3;
        EXPECT_NEAR(a.mean[j], 0.0, 0.1);
    }
    EXPECT_LT(std::fabs(a.corr01), 0.05); // independent channels
}

TEST(PlantSensors, NoNoiseMeansNoDraws)
{
    plant_config c = quiet_cfg();
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    uint64_t r0 = s.rng;
    plant_adc a;
    plant_sample(&s, &a);
    EXPECT_EQ(s.rng, r0);
}

// --- configuration checks ---

TEST(PlantConfig, DefaultsAreTheDocumentedMotorAndPass)
{
    plant_config c = quiet_cfg();
    const char *what = "untouched";
    EXPECT_EQ(plant_check_config(&c, &what), 0);
    EXPECT_EQ(c.motor.Rs_ohm, 0.288);
    EXPECT_EQ(c.motor.Lm_H, 0.0416);
    EXPECT_EQ(c.motor.pole_pairs, 2);
    EXPECT_EQ(c.dc.vdc_V, 311.0);
    EXPECT_EQ(c.sensor.adc_bits, 12);
    EXPECT_EQ(c.supply, PLANT_SUPPLY_INVERTER);
    EXPECT_GE(c.h_max_s, 1e-7);
    EXPECT_LE(c.h_max_s, 1e-4);
}

TEST(PlantConfig, EveryBadFieldIsNamed)
{
    struct Case {
        std::function<void(plant_config &)> edit;
        const char *field;
    };
    const double nan = std::nan("");
    const std::vector<Case> cases = {
        {[](plant_config &c) { c.motor.Rs_ohm = 0; }, "motor.Rs_ohm"},
        {[](plant_config &c) { c.motor.Rr_ohm = -1; }, "motor.Rr_ohm"},
        {[&](plant_config &c) { c.motor.Lls_H = nan; }, "motor.Lls_H"},
        {[](plant_config &c) { c.motor.Llr_H = 0; }, "motor.Llr_H"},
        {[](plant_config &c) { c.motor.Lm_H = INFINITY; }, "motor.Lm_H"},
        {[](plant_config &c) { c.motor.pole_pairs = 0; }, "motor.pole_pairs"},
        {[](plant_config &c) { c.motor.J_kgm2 = -0.045; }, "motor.J_kgm2"},
        {[](plant_config &c) { c.motor.B_Nms = -1e-3; }, "motor.B_Nms"},
        {[](plant_config &c) { c.dc.vdc_V = 0; }, "dc.vdc_V"},
        {[](plant_config &c) { c.dc.r_src_ohm = 0; }, "dc.r_src_ohm"},
        {[](plant_config &c) { c.dc.c1_F = 0; }, "dc.c1_F"},
        {[](plant_config &c) { c.dc.c2_F = -1; }, "dc.c2_F"},
        {[](plant_config &c) { c.sensor.adc_bits = 0; }, "sensor.adc_bits"},
        {[](plant_config &c) { c.sensor.adc_bits = 17; }, "sensor.adc_bits"},
        {[](plant_config &c) { c.sensor.i_fs_A = 0; }, "sensor.i_fs_A"},
        {[](plant_config &c) { c.sensor.v_fs_V = -5; }, "sensor.v_fs_V"},
        {[](plant_config &c) { c.sensor.i_gain[2] = 0; }, "sensor.i_gain[2]"},
        {[&](plant_config &c) { c.sensor.i_offset_A[1] = nan; }, "sensor.i_offset_A[1]"},
        {[](plant_config &c) { c.sensor.v_gain[0] = -1; }, "sensor.v_gain[0]"},
        {[](plant_config &c) { c.sensor.v_offset_V[1] = INFINITY; }, "sensor.v_offset_V[1]"},
        {[](plant_config &c) { c.sensor.i_noise_A = -0.1; }, "sensor.i_noise_A"},
        {[](plant_config &c) { c.sensor.v_noise_V = -0.1; }, "sensor.v_noise_V"},
        {[](plant_config &c) { c.supply = (plant_supply_mode)7; }, "supply"},
        {[](plant_config &c) { c.sine.v_ll_rms_V = -220; }, "sine.v_ll_rms_V"},
        {[](plant_config &c) { c.sine.f_Hz = -60; }, "sine.f_Hz"},
        {[&](plant_config &c) { c.sine.phase_rad = nan; }, "sine.phase_rad"},
        {[](plant_config &c) { c.h_max_s = 2e-4; }, "h_max_s"},
        {[](plant_config &c) { c.h_max_s = 1e-8; }, "h_max_s"},
    };
    for (const Case &k : cases) {
        plant_config c = quiet_cfg();
        k.edit(c);
        const char *what = nullptr;
        EXPECT_LT(plant_check_config(&c, &what), 0) << k.field;
        ASSERT_NE(what, nullptr) << k.field;
        EXPECT_EQ(std::string(what).rfind(k.field, 0), 0u) << what;

        // plant_init refuses it and leaves the state as it was
        plant_state s, before;
        std::memset(&s, 0x5a, sizeof s);
        std::memcpy(&before, &s, sizeof s);
        EXPECT_EQ(plant_init(&s, &c), PLANT_EINVAL) << k.field;
        EXPECT_EQ(std::memcmp(&s, &before, sizeof s), 0) << k.field;
    }
    const char *what = nullptr;
    EXPECT_LT(plant_check_config(nullptr, &what), 0);
    EXPECT_NE(what, nullptr);
}

// --- mechanics, scheduled changes, bad input ---

TEST(PlantMechanics, ConstantLoadAndParameterChangesFollowTheClosedForm)
{
    // Unexcited motor (sine source at 0 V): Te = 0, so J dw/dt = -B w - T_L
    // with T_L a plain constant: w(t) = w_inf + (w0 - w_inf) exp(-B t / J),
    // w_inf = -T_L / B. At t1 the inertia and friction change by 1.4.
    plant_config c = quiet_cfg();
    c.supply = PLANT_SUPPLY_SINE;
    c.sine.v_ll_rms_V = 0.0;
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    s.omega_m = 50.0;
    plant_set_load(&s, 8.0);
    const uint8_t ooo[3] = {1, 1, 1};
    const double T = 200e-6, J = c.motor.J_kgm2, B = c.motor.B_Nms, TL = 8.0;
    auto w_at = [](double w0, double t, double JJ, double BB, double tl) {
        double winf = -tl / BB;
        return winf + (w0 - winf) * std::exp(-BB * t / JJ);
    };
    for (int k = 0; k < 2500; ++k)
        plant_advance(&s, ooo, ooo, 1.0, T);
    double w1 = w_at(50.0, 0.5, J, B, TL);
    EXPECT_NEAR(s.omega_m, w1, 1e-6 * std::fabs(w1));
    EXPECT_LT(s.omega_m, 0.0); // the constant load drives it backwards
    plant_set_inertia(&s, 1.4 * J);
    plant_set_friction(&s, 1.4 * B);
    for (int k = 0; k < 2500; ++k)
        plant_advance(&s, ooo, ooo, 1.0, T);
    double w2 = w_at(w1, 0.5, 1.4 * J, 1.4 * B, TL);
    EXPECT_NEAR(s.omega_m, w2, 1e-6 * std::fabs(w2));
    EXPECT_NEAR(s.t_s, 1.0, 1e-12);
}

TEST(PlantMechanics, SettersRefuseNonsenseAndKeepTheOldValue)
{
    plant_config c = quiet_cfg();
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    plant_set_inertia(&s, -1.0);
    plant_set_inertia(&s, std::nan(""));
    plant_set_friction(&s, -0.1);
    plant_set_rs(&s, 0.0);
    plant_set_rr(&s, INFINITY);
    plant_set_load(&s, std::nan(""));
    EXPECT_EQ(s.cfg.motor.J_kgm2, c.motor.J_kgm2);
    EXPECT_EQ(s.cfg.motor.B_Nms, c.motor.B_Nms);
    EXPECT_EQ(s.cfg.motor.Rs_ohm, c.motor.Rs_ohm);
    EXPECT_EQ(s.cfg.motor.Rr_ohm, c.motor.Rr_ohm);
    EXPECT_EQ(s.t_load_Nm, 0.0);
    plant_set_rs(&s, 0.3);
    plant_set_rr(&s, 0.2);
    plant_set_friction(&s, 0.0);
    EXPECT_EQ(s.cfg.motor.Rs_ohm, 0.3);
    EXPECT_EQ(s.cfg.motor.Rr_ohm, 0.2);
    EXPECT_EQ(s.cfg.motor.B_Nms, 0.0);
}

TEST(PlantMechanics, BadAdvanceInputIsHarmless)
{
    plant_config c = quiet_cfg();
    plant_state s, before;
    ASSERT_EQ(plant_init(&s, &c), 0);
    const uint8_t pon[3] = {2, 1, 0};
    plant_advance(&s, pon, pon, 1.0, 200e-6);
    std::memcpy(&before, &s, sizeof s);
    plant_advance(&s, pon, pon, 0.5, std::nan(""));
    plant_advance(&s, pon, pon, 0.5, -1.0);
    plant_advance(&s, pon, pon, 0.5, 0.0);
    plant_advance(&s, pon, pon, 0.5, INFINITY);
    EXPECT_EQ(std::memcmp(&s, &before, sizeof s), 0);

    // NaN duty is 0 (vec1 for the whole period): same as an explicit 0
    plant_state a = s, b = s;
    const uint8_t ooo[3] = {1, 1, 1};
    plant_advance(&a, pon, ooo, std::nan(""), 200e-6);
    plant_advance(&b, pon, ooo, 0.0, 200e-6);
    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0);
    // NULL vectors and codes above 3 are gates off
    plant_state d = s, e = s;
    const uint8_t junk[3] = {200, 4, 9}, off[3] = {3, 3, 3};
    plant_advance(&d, nullptr, junk, 0.5, 200e-6);
    plant_advance(&e, off, off, 0.5, 200e-6);
    EXPECT_EQ(d.psi_s[0], e.psi_s[0]);
    EXPECT_EQ(d.vc1, e.vc1);
    EXPECT_TRUE(std::isfinite(d.psi_s[0]));
}

} // namespace

// Timed sensor faults: codes before and after, by hand (12 bit, 500 V and
// +-150 A full scale: v code = round(v / 500 * 4095), i code =
// round((i / 150 + 1) / 2 * 4095)).
TEST(PlantSensors, GainOffsetStuckAndLostFaults)
{
    plant_config c = quiet_cfg();
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    set_currents(s, 10.0, -4.0, -6.0);
    s.vc1 = 150.0;
    s.vc2 = 160.0;
    plant_adc a;
    plant_sample(&s, &a);
    auto vcode = [](double v) { return (uint16_t)std::floor(v / 500.0 * 4095.0 + 0.5); };
    auto icode = [](double i) { return (uint16_t)std::floor((i / 150.0 + 1.0) * 0.5 * 4095.0 + 0.5); };
    EXPECT_EQ(a.v_code[0], vcode(150.0));
    EXPECT_EQ(a.i_code[0], icode(10.0));

    plant_set_sensor_gain(&s, PLANT_CH_VC1, 1.2);
    plant_set_sensor_offset(&s, PLANT_CH_IB, 2.5);
    plant_set_sensor_fault(&s, PLANT_CH_VC2, PLANT_SENSOR_STUCK);
    plant_set_sensor_fault(&s, PLANT_CH_IC, PLANT_SENSOR_LOST);
    s.vc2 = 100.0; // the stuck channel must not see this
    plant_sample(&s, &a);
    EXPECT_EQ(a.v_code[0], vcode(180.0));
    EXPECT_EQ(a.i_code[1], icode(-4.0 + 2.5));
    EXPECT_EQ(a.v_code[1], vcode(160.0)); // the last conversion before the fault
    EXPECT_EQ(a.i_code[2], icode(0.0));   // lost phase: 0 A
    EXPECT_EQ(a.i_code[0], icode(10.0));  // the others untouched

    plant_set_sensor_fault(&s, PLANT_CH_VC1, PLANT_SENSOR_LOST);
    plant_set_sensor_fault(&s, PLANT_CH_VC2, PLANT_SENSOR_OK);
    plant_set_sensor_fault(&s, PLANT_CH_IC, PLANT_SENSOR_OK);
    plant_sample(&s, &a);
    EXPECT_EQ(a.v_code[0], 0u);
    EXPECT_EQ(a.v_code[1], vcode(100.0));
    EXPECT_EQ(a.i_code[2], icode(-6.0));

    // Nonsense is ignored (channel out of range, gain <= 0, NaN offset).
    plant_set_sensor_gain(&s, 5, 2.0);
    plant_set_sensor_gain(&s, PLANT_CH_IA, 0.0);
    plant_set_sensor_offset(&s, PLANT_CH_IA, NAN);
    plant_set_sensor_fault(&s, -1, PLANT_SENSOR_LOST);
    plant_sample(&s, &a);
    EXPECT_EQ(a.i_code[0], icode(10.0));
}

// A stuck channel from the first sample on holds that first conversion.
TEST(PlantSensors, StuckFromTheStartHoldsTheFirstConversion)
{
    plant_config c = quiet_cfg();
    plant_state s;
    ASSERT_EQ(plant_init(&s, &c), 0);
    plant_set_sensor_fault(&s, PLANT_CH_VC1, PLANT_SENSOR_STUCK);
    plant_adc a;
    plant_sample(&s, &a);
    uint16_t first = a.v_code[0];
    EXPECT_EQ(first, (uint16_t)std::floor(155.5 / 500.0 * 4095.0 + 0.5));
    s.vc1 = 10.0;
    plant_sample(&s, &a);
    EXPECT_EQ(a.v_code[0], first);
}
