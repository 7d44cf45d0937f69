// Scenario parser: every key, every error path (with the exact line it must
// name), --set overrides, profile queries, the [control] registry and the
// documentation. Expected values are written out by hand here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "sim/control_keys.h"
#include "sim/scenario.h"
#include "sim_test_util.hpp"

using simtest::parse_text;

namespace {

const double kPi = 3.14159265358979323846;

// "t.ini:LINE: " prefix of an error message.
std::string at(int line) { return "t.ini:" + std::to_string(line) + ": "; }

// The parse of @p text fails with one line of message naming t.ini:LINE and
// containing @p what (asserted at the call: EXPECT_TRUE(fails_with(...))).
::testing::AssertionResult fails_with(const std::string &text, int line, const std::string &what)
{
    auto l = parse_text(text);
    if (l.rc != SCENARIO_EINPUT)
        return ::testing::AssertionFailure() << "rc " << l.rc << ", not SCENARIO_EINPUT, for:\n" << text;
    if (l.error.rfind(at(line), 0) != 0u)
        return ::testing::AssertionFailure() << "message: " << l.error << "\nnot at " << at(line) << "for:\n" << text;
    if (l.error.find(what) == std::string::npos)
        return ::testing::AssertionFailure() << "message: " << l.error << "\nwanted: " << what;
    if (l.error.find('\n') != std::string::npos)
        return ::testing::AssertionFailure() << "one line only: " << l.error;
    return ::testing::AssertionSuccess();
}

} // namespace

TEST(ScenarioParser, DefaultsAreTheTenHorsepowerDrive)
{
    auto l = parse_text("");
    ASSERT_EQ(l.rc, 0) << l.error;
    const scenario &sc = *l.sc;
    // docs/motor-10hp.json
    EXPECT_DOUBLE_EQ(sc.plant.motor.Rs_ohm, 0.288);
    EXPECT_DOUBLE_EQ(sc.plant.motor.Rr_ohm, 0.158);
    EXPECT_DOUBLE_EQ(sc.plant.motor.Lls_H, 0.00142);
    EXPECT_DOUBLE_EQ(sc.plant.motor.Llr_H, 0.00142);
    EXPECT_DOUBLE_EQ(sc.plant.motor.Lm_H, 0.0416);
    EXPECT_EQ(sc.plant.motor.pole_pairs, 2);
    EXPECT_DOUBLE_EQ(sc.plant.motor.J_kgm2, 0.045);
    EXPECT_DOUBLE_EQ(sc.plant.motor.B_Nms, 0.005);
    EXPECT_DOUBLE_EQ(sc.plant.dc.vdc_V, 311.0);
    EXPECT_EQ(sc.plant.supply, PLANT_SUPPLY_INVERTER);
    // New scenarios get the real inverter (docs/scenarios.md [inverter]), no
    // saturation and no load models.
    EXPECT_DOUBLE_EQ(sc.plant.inverter.dead_time_s, 2e-6);
    EXPECT_DOUBLE_EQ(sc.plant.inverter.v_on_V, 1.0);
    EXPECT_DOUBLE_EQ(sc.plant.motor.Lm_sat_psi_Wb, 0.0);
    EXPECT_DOUBLE_EQ(sc.plant.load.coulomb_Nm, 0.0);
    EXPECT_DOUBLE_EQ(sc.plant.load.viscous_Nms, 0.0);
    EXPECT_DOUBLE_EQ(sc.plant.load.fan_Nms2, 0.0);
    EXPECT_EQ(sc.n_faults, 0);
    EXPECT_DOUBLE_EQ(sc.duration_s, 1.0);
    EXPECT_DOUBLE_EQ(sc.period_s, 200e-6);
    EXPECT_DOUBLE_EQ(sc.trace_interval_s, 1e-3);
    EXPECT_EQ(sc.controller, SCENARIO_CTL_RBFN);
    EXPECT_EQ(sc.n_ref, 0);
    EXPECT_EQ(sc.n_load, 0);
    EXPECT_EQ(sc.n_events, 0);
    EXPECT_DOUBLE_EQ(scenario_ref_rpm(&sc, 0.5), 0.0);
}

TEST(ScenarioParser, DolStartFile)
{
    auto l = simtest::load_scenario(simtest::source_path("host_sim/scenarios/dol_start.ini"));
    ASSERT_EQ(l.rc, 0) << l.error;
    const scenario &sc = *l.sc;
    EXPECT_EQ(sc.plant.supply, PLANT_SUPPLY_SINE);
    EXPECT_DOUBLE_EQ(sc.plant.sine.v_ll_rms_V, 220.0);
    EXPECT_DOUBLE_EQ(sc.plant.sine.f_Hz, 60.0);
    EXPECT_DOUBLE_EQ(sc.duration_s, 1.0);
    ASSERT_EQ(sc.n_load, 1);
    EXPECT_DOUBLE_EQ(sc.load[0].t_s, 0.6);
    EXPECT_DOUBLE_EQ(sc.load[0].nm, 20.0);
    ASSERT_EQ(sc.n_windows, 2);
    EXPECT_STREQ(sc.windows[0].name, "noload");
    EXPECT_STREQ(sc.windows[1].name, "load");
    EXPECT_DOUBLE_EQ(sc.windows[1].t0_s, 0.85);
    EXPECT_DOUBLE_EQ(sc.windows[1].t1_s, 1.0);
}

// Every scalar key, with a valid value and where it must land.
TEST(ScenarioParser, EveryScalarKeyLands)
{
    struct Case {
        const char *section, *key, *value;
        std::function<double(const scenario &)> get;
        double expect;
    };
    const std::vector<Case> cases = {
        { "sim", "duration_s", "2.5", [](const scenario &s) { return s.duration_s; }, 2.5 },
        { "sim", "period_s", "100e-6", [](const scenario &s) { return s.period_s; }, 100e-6 },
        { "sim", "h_max_s", "2e-5", [](const scenario &s) { return s.plant.h_max_s; }, 2e-5 },
        { "sim", "trace_interval_s", "0.002", [](const scenario &s) { return s.trace_interval_s; }, 0.002 },
        { "sim", "seed", "4294967295", [](const scenario &s) { return (double)s.plant.sensor.seed; }, 4294967295.0 },
        { "motor", "Rs_ohm", "0.3", [](const scenario &s) { return s.plant.motor.Rs_ohm; }, 0.3 },
        { "motor", "Rr_ohm", "0.2", [](const scenario &s) { return s.plant.motor.Rr_ohm; }, 0.2 },
        { "motor", "Lls_H", "0.002", [](const scenario &s) { return s.plant.motor.Lls_H; }, 0.002 },
        { "motor", "Llr_H", "0.003", [](const scenario &s) { return s.plant.motor.Llr_H; }, 0.003 },
        { "motor", "Lm_H", "0.05", [](const scenario &s) { return s.plant.motor.Lm_H; }, 0.05 },
        { "motor", "pole_pairs", "3", [](const scenario &s) { return (double)s.plant.motor.pole_pairs; }, 3 },
        { "motor", "J_kgm2", "0.063", [](const scenario &s) { return s.plant.motor.J_kgm2; }, 0.063 },
        { "motor", "B_Nms", "0", [](const scenario &s) { return s.plant.motor.B_Nms; }, 0.0 },
        { "motor", "Lm_sat_psi_Wb", "0.7", [](const scenario &s) { return s.plant.motor.Lm_sat_psi_Wb; }, 0.7 },
        { "motor", "Lm_sat_exponent", "8", [](const scenario &s) { return s.plant.motor.Lm_sat_exponent; }, 8 },
        { "load", "coulomb_Nm", "1.5", [](const scenario &s) { return s.plant.load.coulomb_Nm; }, 1.5 },
        { "load", "viscous_Nms", "0.02", [](const scenario &s) { return s.plant.load.viscous_Nms; }, 0.02 },
        { "load", "fan_Nms2", "0.0008", [](const scenario &s) { return s.plant.load.fan_Nms2; }, 0.0008 },
        { "inverter", "dead_time_s", "3e-6", [](const scenario &s) { return s.plant.inverter.dead_time_s; }, 3e-6 },
        { "inverter", "v_on_V", "0", [](const scenario &s) { return s.plant.inverter.v_on_V; }, 0.0 },
        { "drive", "vdc_V", "540", [](const scenario &s) { return s.plant.dc.vdc_V; }, 540 },
        { "drive", "r_src_ohm", "0.1", [](const scenario &s) { return s.plant.dc.r_src_ohm; }, 0.1 },
        { "drive", "c1_F", "0.001", [](const scenario &s) { return s.plant.dc.c1_F; }, 0.001 },
        { "drive", "c2_F", "0.0015", [](const scenario &s) { return s.plant.dc.c2_F; }, 0.0015 },
        { "sensors", "adc_bits", "16", [](const scenario &s) { return (double)s.plant.sensor.adc_bits; }, 16 },
        { "sensors", "i_fs_A", "100", [](const scenario &s) { return s.plant.sensor.i_fs_A; }, 100 },
        { "sensors", "v_fs_V", "600", [](const scenario &s) { return s.plant.sensor.v_fs_V; }, 600 },
        { "sensors", "i_gain_a", "1.01", [](const scenario &s) { return s.plant.sensor.i_gain[0]; }, 1.01 },
        { "sensors", "i_gain_b", "0.99", [](const scenario &s) { return s.plant.sensor.i_gain[1]; }, 0.99 },
        { "sensors", "i_gain_c", "1.02", [](const scenario &s) { return s.plant.sensor.i_gain[2]; }, 1.02 },
        { "sensors", "i_offset_a_A", "-0.1", [](const scenario &s) { return s.plant.sensor.i_offset_A[0]; }, -0.1 },
        { "sensors", "i_offset_b_A", "0.2", [](const scenario &s) { return s.plant.sensor.i_offset_A[1]; }, 0.2 },
        { "sensors", "i_offset_c_A", "0.3", [](const scenario &s) { return s.plant.sensor.i_offset_A[2]; }, 0.3 },
        { "sensors", "v_gain_1", "1.03", [](const scenario &s) { return s.plant.sensor.v_gain[0]; }, 1.03 },
        { "sensors", "v_gain_2", "0.97", [](const scenario &s) { return s.plant.sensor.v_gain[1]; }, 0.97 },
        { "sensors", "v_offset_1_V", "1.5", [](const scenario &s) { return s.plant.sensor.v_offset_V[0]; }, 1.5 },
        { "sensors", "v_offset_2_V", "-2", [](const scenario &s) { return s.plant.sensor.v_offset_V[1]; }, -2 },
        { "sensors", "i_noise_A", "0.05", [](const scenario &s) { return s.plant.sensor.i_noise_A; }, 0.05 },
        { "sensors", "v_noise_V", "0.5", [](const scenario &s) { return s.plant.sensor.v_noise_V; }, 0.5 },
        { "supply", "mode", "sine", [](const scenario &s) { return (double)s.plant.supply; }, PLANT_SUPPLY_SINE },
        { "supply", "v_ll_rms_V", "380", [](const scenario &s) { return s.plant.sine.v_ll_rms_V; }, 380 },
        { "supply", "f_Hz", "50", [](const scenario &s) { return s.plant.sine.f_Hz; }, 50 },
        { "supply", "phase_deg", "90", [](const scenario &s) { return s.plant.sine.phase_rad; }, kPi / 2 },
        { "plant", "initial_speed_rpm", "-600", [](const scenario &s) { return s.plant.initial_omega_m_rad_s; },
          -600.0 * kPi / 30.0 },
        { "plant", "initial_flux_frac", "0.3", [](const scenario &s) { return s.plant.initial_flux_frac; }, 0.3 },
        { "controller", "name", "nominal", [](const scenario &s) { return (double)s.controller; }, SCENARIO_CTL_NOMINAL },
        { "metrics", "disturbance_t_s", "2.5", [](const scenario &s) { return s.has_disturbance ? s.disturbance_t_s : -1; }, 2.5 },
        { "commission", "identify", "standstill", [](const scenario &s) { return (double)s.identify; }, SCENARIO_IDENTIFY_STANDSTILL },
        { "metrics", "startup_end_s", "1.5", [](const scenario &s) { return s.has_startup_end ? s.startup_end_s : -1; }, 1.5 },
    };
    std::set<std::string> covered;
    for (const auto &c : cases) {
        std::string text = std::string("[") + c.section + "]\n" + c.key + " = " + c.value + "   # comment\n";
        auto l = parse_text(text);
        ASSERT_EQ(l.rc, 0) << c.section << "." << c.key << ": " << l.error;
        EXPECT_NEAR(c.get(*l.sc), c.expect, 1e-12 * std::fabs(c.expect)) << c.section << "." << c.key;
        scenario_key_info info;
        for (size_t i = 0; scenario_key_info_at(i, &info); ++i) {
            if (std::string(info.section) == c.section && std::string(info.key) == c.key) {
                EXPECT_EQ(l.sc->key_line[i], 2) << c.key;
            }
        }
        covered.insert(std::string(c.section) + "." + c.key);
    }
    // [ratings] and [commission] are judged as a whole plate: TheRatingsSectionLands.
    for (const char *k : { "P_W", "V_ll_V", "I_A", "f_Hz", "n_rpm", "cos_phi", "vdc_nom_V", "inv_I_rated_A",
                           "inv_I_peak_A" })
        covered.insert(std::string("ratings.") + k);
    covered.insert("commission.model");
    // The table above covers every scalar key the parser knows.
    scenario_key_info info;
    for (size_t i = 0; scenario_key_info_at(i, &info); ++i)
        EXPECT_TRUE(covered.count(std::string(info.section) + "." + info.key)) << info.section << "." << info.key;
}

// A plate lands field by field, each at its line; the model defaults to exact.
TEST(ScenarioParser, TheRatingsSectionLands)
{
    const char *text = "[ratings]\nP_W = 37285\nV_ll_V = 460\nI_A = 62.8\nf_Hz = 60\nn_rpm = 1705\n"
                       "cos_phi = 0.9045\nvdc_nom_V = 650\ninv_I_rated_A = 78.5\ninv_I_peak_A = 257.6\n";
    auto l = parse_text(text);
    ASSERT_EQ(l.rc, 0) << l.error;
    const scenario_ratings &r = l.sc->ratings;
    EXPECT_TRUE(l.sc->has_ratings);
    EXPECT_EQ(r.P_W, 37285.0);
    EXPECT_EQ(r.V_ll_V, 460.0);
    EXPECT_EQ(r.I_A, 62.8);
    EXPECT_EQ(r.f_Hz, 60.0);
    EXPECT_EQ(r.n_rpm, 1705.0);
    EXPECT_EQ(r.cos_phi, 0.9045);
    EXPECT_EQ(r.vdc_nom_V, 650.0);
    EXPECT_EQ(r.inv_I_rated_A, 78.5);
    EXPECT_EQ(r.inv_I_peak_A, 257.6);
    EXPECT_EQ(scenario_key_line(l.sc.get(), "ratings", "n_rpm"), 6);
    EXPECT_EQ(l.sc->model, int(SCENARIO_MODEL_EXACT));
    auto p = parse_text(std::string(text) + "[commission]\nmodel = plate\n");
    ASSERT_EQ(p.rc, 0) << p.error;
    EXPECT_EQ(p.sc->model, int(SCENARIO_MODEL_PLATE));
    // without a plate nothing is derived, and cos phi may be left out
    auto none = parse_text("[sim]\nduration_s = 1\n");
    EXPECT_FALSE(none.sc->has_ratings);
    auto no_pf = parse_text("[ratings]\nP_W = 37285\nV_ll_V = 460\nI_A = 62.8\nf_Hz = 60\nn_rpm = 1705\n"
                            "vdc_nom_V = 650\ninv_I_rated_A = 78.5\ninv_I_peak_A = 257.6\n");
    EXPECT_EQ(no_pf.rc, 0) << no_pf.error;
}

TEST(ScenarioParser, RepeatedKeysAndProfile)
{
    auto l = parse_text("[reference]\n"
                        "step = 0.1 100\n"
                        "ramp = 0.5 1.5 600    # 100 -> 600 rpm\n"
                        "step = 2.0 -300\n"
                        "[load]\nstep = 1 5\nstep = 2 8\n"
                        "[events]\nJ_scale = 2.5 1.4\nB_scale = 2.5 1.4\nRs_scale = 3 1.2\nRr_scale = 3 1.5\n"
                        "[metrics]\nwindow = a 0.2 0.4\nwindow = b_2 1 2\n"
                        "[sim]\nduration_s = 4\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    const scenario *sc = l.sc.get();
    ASSERT_EQ(sc->n_ref, 3);
    EXPECT_DOUBLE_EQ(scenario_ref_rpm(sc, 0.0), 0.0);
    EXPECT_DOUBLE_EQ(scenario_ref_rpm(sc, 0.1), 100.0);
    EXPECT_DOUBLE_EQ(scenario_ref_rpm(sc, 0.4), 100.0);
    EXPECT_DOUBLE_EQ(scenario_ref_rpm(sc, 0.5), 100.0);
    EXPECT_DOUBLE_EQ(scenario_ref_rpm(sc, 1.0), 350.0); // halfway
    EXPECT_DOUBLE_EQ(scenario_ref_rpm(sc, 1.5), 600.0);
    EXPECT_DOUBLE_EQ(scenario_ref_rpm(sc, 1.9), 600.0);
    EXPECT_DOUBLE_EQ(scenario_ref_rpm(sc, 2.0), -300.0);
    EXPECT_EQ(sc->n_load, 2);
    ASSERT_EQ(sc->n_events, 4);
    EXPECT_EQ(sc->events[3].kind, SCENARIO_EV_RR);
    EXPECT_DOUBLE_EQ(sc->events[3].factor, 1.5);
    EXPECT_EQ(sc->events[3].line, 12);

    double t;
    ASSERT_TRUE(scenario_disturbance(sc, &t));
    EXPECT_DOUBLE_EQ(t, 1.0); // the first load step after 0
    EXPECT_DOUBLE_EQ(scenario_startup_end(sc), 1.5); // later of 1.0 and the first ramp's end
    double from, to;
    ASSERT_TRUE(scenario_last_ref_change(sc, &t, &from, &to));
    EXPECT_DOUBLE_EQ(t, 2.0);
    EXPECT_DOUBLE_EQ(from, 600.0);
    EXPECT_DOUBLE_EQ(to, -300.0);
    ASSERT_EQ(sc->n_windows, 2);
    EXPECT_STREQ(sc->windows[1].name, "b_2");
}

TEST(ScenarioParser, DerivedMetricTimes)
{
    auto l = parse_text("[reference]\nramp = 0.2 0.6 500\n[events]\nJ_scale = 0 2\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    double t;
    EXPECT_FALSE(scenario_disturbance(l.sc.get(), &t)); // an event AT t = 0 is not a disturbance
    EXPECT_DOUBLE_EQ(scenario_startup_end(l.sc.get()), 1.0);
    auto m = parse_text("[metrics]\ndisturbance_t_s = 0.3\nstartup_end_s = 0.25\n");
    ASSERT_EQ(m.rc, 0) << m.error;
    ASSERT_TRUE(scenario_disturbance(m.sc.get(), &t));
    EXPECT_DOUBLE_EQ(t, 0.3);
    EXPECT_DOUBLE_EQ(scenario_startup_end(m.sc.get()), 0.25);
}

// Load and parameter ramps: the profile value at t is the linear interpolation
// written out by hand; steps and ramps of one parameter chain; other
// parameters are independent.
TEST(ScenarioParser, LoadAndParameterRamps)
{
    auto l = parse_text("[load]\nstep = 1 5\nramp = 2 4 9   # 5 -> 9 N m\nstep = 5 -3\n"
                        "[events]\nRs_scale = 0.5 1.1\nRr_ramp = 1 3 1.5\nRs_ramp = 2 8 1.5\n"
                        "Lm_scale = 3 0.9\nJ_ramp = 3 3.5 2\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    const scenario *sc = l.sc.get();
    ASSERT_EQ(sc->n_load, 3);
    EXPECT_TRUE(sc->load[1].ramp);
    EXPECT_DOUBLE_EQ(sc->load[1].t1_s, 4.0);
    EXPECT_DOUBLE_EQ(scenario_load_nm(sc, 0.99), 0.0);
    EXPECT_DOUBLE_EQ(scenario_load_nm(sc, 1.0), 5.0);
    EXPECT_DOUBLE_EQ(scenario_load_nm(sc, 2.0), 5.0);
    EXPECT_DOUBLE_EQ(scenario_load_nm(sc, 2.5), 6.0);   // 5 + (9 - 5) * 0.5 / 2
    EXPECT_DOUBLE_EQ(scenario_load_nm(sc, 4.0), 9.0);
    EXPECT_DOUBLE_EQ(scenario_load_nm(sc, 4.9), 9.0);
    EXPECT_DOUBLE_EQ(scenario_load_nm(sc, 5.0), -3.0);

    ASSERT_EQ(sc->n_events, 5);
    // Rs: 1 until 0.5 s, 1.1 until 2 s, then linear to 1.5 at 8 s (gradual heating).
    EXPECT_DOUBLE_EQ(scenario_param_factor(sc, SCENARIO_EV_RS, 0.4), 1.0);
    EXPECT_DOUBLE_EQ(scenario_param_factor(sc, SCENARIO_EV_RS, 0.5), 1.1);
    EXPECT_DOUBLE_EQ(scenario_param_factor(sc, SCENARIO_EV_RS, 2.0), 1.1);
    EXPECT_NEAR(scenario_param_factor(sc, SCENARIO_EV_RS, 5.0), 1.1 + 0.4 * 3.0 / 6.0, 1e-15);
    EXPECT_DOUBLE_EQ(scenario_param_factor(sc, SCENARIO_EV_RS, 8.0), 1.5);
    EXPECT_DOUBLE_EQ(scenario_param_factor(sc, SCENARIO_EV_RS, 100.0), 1.5);
    // Rr: from 1 at 1 s to 1.5 at 3 s.
    EXPECT_DOUBLE_EQ(scenario_param_factor(sc, SCENARIO_EV_RR, 1.5), 1.125);
    EXPECT_DOUBLE_EQ(scenario_param_factor(sc, SCENARIO_EV_RR, 3.0), 1.5);
    EXPECT_DOUBLE_EQ(scenario_param_factor(sc, SCENARIO_EV_LM, 2.99), 1.0);
    EXPECT_DOUBLE_EQ(scenario_param_factor(sc, SCENARIO_EV_LM, 3.0), 0.9);
    EXPECT_DOUBLE_EQ(scenario_param_factor(sc, SCENARIO_EV_J, 3.25), 1.5);
    EXPECT_DOUBLE_EQ(scenario_param_factor(sc, SCENARIO_EV_B, 7.0), 1.0);

    double t;
    ASSERT_TRUE(scenario_disturbance(sc, &t));
    EXPECT_DOUBLE_EQ(t, 0.5); // the first parameter event after 0

    // --set replaces all steps and ramps of that parameter, and the whole load profile.
    auto m = parse_text("[load]\nramp = 1 2 5\n[events]\nRs_ramp = 1 2 1.5\nRr_scale = 1 2\n",
                        { "events.Rs_scale=3 1.2", "load.ramp=0.5 1.5 4" });
    ASSERT_EQ(m.rc, 0) << m.error;
    EXPECT_DOUBLE_EQ(scenario_param_factor(m.sc.get(), SCENARIO_EV_RS, 2.0), 1.0);
    EXPECT_DOUBLE_EQ(scenario_param_factor(m.sc.get(), SCENARIO_EV_RS, 3.0), 1.2);
    EXPECT_DOUBLE_EQ(scenario_param_factor(m.sc.get(), SCENARIO_EV_RR, 3.0), 2.0);
    ASSERT_EQ(m.sc->n_load, 1);
    EXPECT_DOUBLE_EQ(scenario_load_nm(m.sc.get(), 1.0), 2.0);
}

TEST(ScenarioSet, FaultKeysReplaceOnlyTheirOwnEntries)
{
    auto l = parse_text("[faults]\nvdc = 1 250\nvdc = 1.5 311\nstale = 2\n",
                        { "faults.vdc=0.5 420", "inverter.dead_time_s=0", "load.fan_Nms2=0.001" });
    ASSERT_EQ(l.rc, 0) << l.error;
    ASSERT_EQ(l.sc->n_faults, 2);
    EXPECT_EQ(l.sc->faults[0].kind, SCENARIO_FAULT_STALE);
    EXPECT_EQ(l.sc->faults[1].kind, SCENARIO_FAULT_VDC);
    EXPECT_DOUBLE_EQ(l.sc->faults[1].value, 420.0);
    EXPECT_EQ(l.sc->faults[1].line, SCENARIO_LINE_SET);
    EXPECT_DOUBLE_EQ(l.sc->plant.inverter.dead_time_s, 0.0);
    EXPECT_DOUBLE_EQ(l.sc->plant.load.fan_Nms2, 0.001);
    auto e = parse_text("", { "faults.gain=1 x 2" });
    EXPECT_EQ(e.rc, SCENARIO_EINPUT);
    EXPECT_EQ(e.error, "--set faults.gain: [faults] gain: unknown channel 'x' (expected a, b, c, vc1 or vc2)");
    auto v = parse_text("", { "inverter.v_on_V=-1" });
    EXPECT_EQ(v.rc, SCENARIO_EINPUT);
    EXPECT_EQ(v.error, "--set inverter.v_on_V: [inverter] v_on_V must be in [0, 50] V");
}

TEST(ScenarioParser, FaultEntries)
{
    auto l = parse_text("[faults]\ngain = 0.5 a 1.2\noffset = 0.5 vc2 -3\nstuck = 0.6 b\nlost = 0.7 c\n"
                        "invalid = 0.8 vc1\nrestore = 0.9 b\nvdc = 1 250\nvdc = 1.2 311\nstale = 1.3\n"
                        "hw = 1.4 on\nhw = 1.5 0\nopen_phase = 1.6 c\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    const scenario *sc = l.sc.get();
    ASSERT_EQ(sc->n_faults, 12);
    EXPECT_EQ(sc->faults[11].kind, SCENARIO_FAULT_OPEN_PHASE);
    EXPECT_EQ(sc->faults[11].channel, 2);
    EXPECT_EQ(sc->faults[0].kind, SCENARIO_FAULT_GAIN);
    EXPECT_EQ(sc->faults[0].channel, 0);
    EXPECT_DOUBLE_EQ(sc->faults[0].value, 1.2);
    EXPECT_EQ(sc->faults[1].channel, 4);
    EXPECT_DOUBLE_EQ(sc->faults[1].value, -3.0);
    EXPECT_EQ(sc->faults[2].kind, SCENARIO_FAULT_STUCK);
    EXPECT_EQ(sc->faults[3].kind, SCENARIO_FAULT_LOST);
    EXPECT_EQ(sc->faults[3].channel, 2);
    EXPECT_EQ(sc->faults[4].kind, SCENARIO_FAULT_INVALID);
    EXPECT_EQ(sc->faults[4].channel, 3);
    EXPECT_EQ(sc->faults[5].kind, SCENARIO_FAULT_RESTORE);
    EXPECT_EQ(sc->faults[6].kind, SCENARIO_FAULT_VDC);
    EXPECT_EQ(sc->faults[6].channel, -1);
    EXPECT_DOUBLE_EQ(sc->faults[6].value, 250.0);
    EXPECT_EQ(sc->faults[8].kind, SCENARIO_FAULT_STALE);
    EXPECT_DOUBLE_EQ(sc->faults[8].t_s, 1.3);
    EXPECT_DOUBLE_EQ(sc->faults[9].value, 1.0);
    EXPECT_DOUBLE_EQ(sc->faults[10].value, 0.0);
    EXPECT_EQ(sc->faults[10].line, 12);
    double t;
    EXPECT_FALSE(scenario_disturbance(sc, &t)); // faults are not load disturbances
}

// Hostile values for the new keys: exit status 2 (SCENARIO_EINPUT) and one
// line naming the file and the line of the offending key.
TEST(ScenarioParser, NewKeyErrors)
{
    EXPECT_TRUE(fails_with("[load]\ncoulomb_Nm = -1\n", 2, "[load] coulomb_Nm must be >= 0"));
    EXPECT_TRUE(fails_with("[load]\nviscous_Nms = 0\nfan_Nms2 = -0.1\n", 3, "[load] fan_Nms2 must be >= 0"));
    EXPECT_TRUE(fails_with("[load]\nfan_Nms2 = 1000\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[load]\nfan_Nms2 = nan\n", 2, "malformed number"));
    EXPECT_TRUE(fails_with("[load]\nviscous_Nms = 1e999\n", 2, "malformed number"));
    EXPECT_TRUE(fails_with("[load]\nramp = 2 1 5\n", 2, "end time 1 s must be after the start 2 s"));
    EXPECT_TRUE(fails_with("[load]\nramp = 1 3 5\nstep = 2 1\n", 3, "out of time order (the ramp on line 2 ends at 3 s)"));
    EXPECT_TRUE(fails_with("[load]\nramp = 1 3\n", 2, "expected 'ramp = T0_S T1_S NM', got 2 values"));
    EXPECT_TRUE(fails_with("[load]\nramp = 1 3 20000\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[events]\nRs_ramp = 2 8 1.5\nRs_scale = 5 1.2\n", 3, "starts inside the ramp on line 2"));
    EXPECT_TRUE(fails_with("[events]\nRs_ramp = 2 8 1.5\nRr_scale = 1 1.2\n", 3, "out of time order"));
    EXPECT_TRUE(fails_with("[events]\nLm_ramp = 2 2 1.5\n", 2, "end time"));
    EXPECT_TRUE(fails_with("[events]\nLm_scale = 1 0\n", 2, "factor 0 is out of range"));
    EXPECT_TRUE(fails_with("[events]\nJ_ramp = 1 2 -1\n", 2, "factor"));
    EXPECT_TRUE(fails_with("[events]\nRr_ramp = 1 x 1.5\n", 2, "malformed number 'x'"));
    EXPECT_TRUE(fails_with("[inverter]\ndead_time_s = -1e-6\n", 2, "[inverter] dead_time_s must be in [0, 5e-05] s"));
    EXPECT_TRUE(fails_with("[inverter]\ndead_time_s = 1e-3\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[inverter]\n\nv_on_V = -0.5\n", 3, "[inverter] v_on_V must be in [0, 50] V"));
    EXPECT_TRUE(fails_with("[inverter]\nv_on_V = 1\nv_on_V = 2\n", 3, "set twice (first on line 2)"));
    EXPECT_TRUE(fails_with("[inverter]\nswitch_s = 1\n", 2, "unknown key 'switch_s' in section [inverter]"));
    EXPECT_TRUE(fails_with("[motor]\nLm_sat_psi_Wb = -0.7\n", 2, "[motor] Lm_sat_psi_Wb must be >= 0"));
    EXPECT_TRUE(fails_with("[motor]\nLm_sat_exponent = 1\n", 2, "[motor] Lm_sat_exponent must be in [2, 20]"));
    EXPECT_TRUE(fails_with("[motor]\nLm_sat_exponent = 21\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[faults]\ngain = 1 d 2\n", 2, "unknown channel 'd' (expected a, b, c, vc1 or vc2)"));
    EXPECT_TRUE(fails_with("[faults]\ngain = 1 a 0\n", 2, "factor 0 is out of range"));
    EXPECT_TRUE(fails_with("[faults]\ngain = 1 a\n", 2, "expected 'gain = T_S CHANNEL FACTOR', got 2 values"));
    EXPECT_TRUE(fails_with("[faults]\noffset = 1 vc1 2e4\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[faults]\noffset = 1 vc1 inf\n", 2, "malformed number 'inf'"));
    EXPECT_TRUE(fails_with("[faults]\nstuck = 1 a 5\n", 2, "expected 'stuck = T_S CHANNEL', got 3 values"));
    EXPECT_TRUE(fails_with("[faults]\nlost = -1 a\n", 2, "time -1 s is out of range"));
    EXPECT_TRUE(fails_with("[faults]\nvdc = 1 0\n", 2, "vdc: 0 V is out of range"));
    EXPECT_TRUE(fails_with("[faults]\nvdc = 1\n", 2, "expected 'vdc = T_S VOLTS', got 1 value"));
    EXPECT_TRUE(fails_with("[faults]\nstale = 1 2\n", 2, "expected 'stale = T_S', got 2 values"));
    EXPECT_TRUE(fails_with("[faults]\noverrun = 1 2\n", 2, "expected 'overrun = T_S', got 2 values"));
    EXPECT_TRUE(fails_with("[faults]\noverrun = -1\n", 2, "time -1 s is out of range"));
    EXPECT_TRUE(fails_with("[faults]\nhw = 1 maybe\n", 2, "expected on or off, got 'maybe'"));
    EXPECT_TRUE(fails_with("[faults]\nvdc = 2 250\nstale = 1\n", 3, "out of time order (line 2 is at 2 s)"));
    EXPECT_TRUE(fails_with("[faults]\nopen_phase = 1 vc1\n", 2, "unknown phase 'vc1' (expected a, b or c)"));
    EXPECT_TRUE(fails_with("[faults]\nopen_phase = 1\n", 2, "expected 'open_phase = T_S PHASE', got 1 value"));
    EXPECT_TRUE(fails_with("[faults]\nbroken = 1 a\n", 2, "unknown key 'broken' in section [faults]"));
    EXPECT_TRUE(fails_with("[fault]\nstale = 1\n", 1 + 1, "unknown section [fault]"));
    EXPECT_TRUE(fails_with("[plant]\ninitial_speed_rpm = 20000\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[plant]\ninitial_speed_rpm = -19001\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[plant]\ninitial_speed_rpm = nan\n", 2, "malformed number"));
    EXPECT_TRUE(fails_with("[plant]\ninitial_flux_frac = -0.1\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[plant]\n\ninitial_flux_frac = 1.3\n", 3, "out of range"));
    EXPECT_TRUE(fails_with("[supply]\nf_Hz = 0\n[plant]\ninitial_flux_frac = 0.5\n", 4,
                           "initial_flux_frac needs the nameplate supply's frequency"));
}

TEST(ScenarioParser, ErrorsNameFileAndLine)
{
    EXPECT_TRUE(fails_with("[sim]\nduration_s = 1\n[foo]\nx = 1\n", 4, "unknown section [foo]"));
    EXPECT_TRUE(fails_with("[motor]\n# inertia\nfoo = 1\n", 3, "unknown key 'foo'"));
    EXPECT_TRUE(fails_with("[sim]\nduration_s = 1.0x\n", 2, "malformed number '1.0x'"));
    EXPECT_TRUE(fails_with("[sim]\nduration_s = nan\n", 2, "malformed number"));
    EXPECT_TRUE(fails_with("[sim]\nduration_s = inf\n", 2, "malformed number"));
    EXPECT_TRUE(fails_with("[sim]\nduration_s = -inf\n", 2, "malformed number"));
    EXPECT_TRUE(fails_with("[sim]\nduration_s = 1e999\n", 2, "malformed number"));
}

TEST(ScenarioParser, CommissionIdentifyValuesAndLine)
{
    auto l = parse_text("");
    ASSERT_EQ(l.rc, 0);
    EXPECT_EQ(l.sc->identify, SCENARIO_IDENTIFY_NONE); // the default: the model the scenario gives
    EXPECT_EQ(l.sc->identify_line, 0);
    l = parse_text("[sim]\nduration_s = 1\n\n[commission]\nidentify = full\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    EXPECT_EQ(l.sc->identify, SCENARIO_IDENTIFY_FULL);
    EXPECT_EQ(l.sc->identify_line, 5);
    l = parse_text("[commission]\nidentify = none\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    EXPECT_EQ(l.sc->identify, SCENARIO_IDENTIFY_NONE);
}

TEST(ScenarioParser, MoreErrors)
{
    EXPECT_TRUE(fails_with("[sim]\nduration_s =\n", 2, "missing value"));
    EXPECT_TRUE(fails_with("[sim]\nduration_s = 0\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[sim]\n\nduration_s = 700\n", 3, "out of range"));
    EXPECT_TRUE(fails_with("[sim]\nperiod_s = 150.5e-6\n", 2, "whole number of microseconds"));
    EXPECT_TRUE(fails_with("[sim]\nperiod_s = 1e-3\ntrace_interval_s = 2e-4\n", 3, "must be >= period_s"));
    EXPECT_TRUE(fails_with("[sim]\nperiod_s = 1e-5\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[sim]\nseed = -1\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[sim]\nseed = 1.5\n", 2, "whole number"));
    EXPECT_TRUE(fails_with("[sim]\nduration_s = 1\nduration_s = 2\n", 3, "set twice (first on line 2)"));
    EXPECT_TRUE(fails_with("[motor]\nJ_kgm2 = -0.045\n", 2, "J_kgm2 must be > 0"));
    EXPECT_TRUE(fails_with("[motor]\nRs_ohm = 0.3\nB_Nms = -1\n", 3, "B_Nms must be >= 0"));
    EXPECT_TRUE(fails_with("[motor]\npole_pairs = 2.5\n", 2, "whole number"));
    EXPECT_TRUE(fails_with("[motor]\npole_pairs = 0\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[drive]\nc1_F = 0.002\nvdc_V = 0\n", 3, "vdc_V must be > 0"));
    EXPECT_TRUE(fails_with("[sensors]\ni_gain_b = 0\n", 2, "i_gain_b must be > 0"));
    EXPECT_TRUE(fails_with("[sensors]\nadc_bits = 17\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[supply]\nmode = dc\n", 2, "unknown mode 'dc'"));
    EXPECT_TRUE(fails_with("[supply]\nf_Hz = -60\n", 2, "f_Hz must be >= 0"));
    EXPECT_TRUE(fails_with("[controller]\nname = pid\n", 2, "unknown controller 'pid'"));
    EXPECT_TRUE(fails_with("[sim]\nduration_s = 1\n[commission]\nidentify = rotating\n", 4,
                           "[commission] identify: unknown value 'rotating' (expected none, standstill or full)"));
    EXPECT_TRUE(fails_with("[commission]\nidentify = none\nidentify = full\n", 3, "set twice"));
    EXPECT_TRUE(fails_with("[events]\nJ_scale = 2.5 1.4\nB_scale = 1.0 1.4\n", 3, "out of time order"));
    EXPECT_TRUE(fails_with("[events]\nJ_scale = 2.5 0\n", 2, "factor"));
    EXPECT_TRUE(fails_with("[events]\nJ_scale = -1 2\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[events]\nK_scale = 1 2\n", 2, "unknown key 'K_scale'"));
    EXPECT_TRUE(fails_with("[reference]\nramp = 0 1 500\nstep = 0.5 100\n", 3, "out of time order"));
    EXPECT_TRUE(fails_with("[reference]\nramp = 1 0.5 500\n", 2, "end time"));
    EXPECT_TRUE(fails_with("[reference]\nstep = 1\n", 2, "expected 'step = T_S RPM', got 1 value"));
    EXPECT_TRUE(fails_with("[reference]\nstep = 1 fast\n", 2, "malformed number 'fast'"));
    EXPECT_TRUE(fails_with("[load]\nstep = 1 2 3\n", 2, "got 3 values"));
    EXPECT_TRUE(fails_with("[load]\nstep = 2 1\nstep = 1 5\n", 3, "out of time order"));
    EXPECT_TRUE(fails_with("[metrics]\nwindow = a 1 0.5\n", 2, "T0_S < T1_S"));
    EXPECT_TRUE(fails_with("[metrics]\nwindow = a-b 0 1\n", 2, "letters, digits"));
    EXPECT_TRUE(fails_with("[metrics]\nwindow = a 0 1\nwindow = a 1 2\n", 3, "defined twice"));
    EXPECT_TRUE(fails_with("[metrics]\nwindow = a 0\n", 2, "expected"));
    EXPECT_TRUE(fails_with("[control]\nfoo = 1\n", 2, "unknown key 'foo'"));
    EXPECT_TRUE(fails_with("[control]\nip_zeta = -1\n", 2, "out of range"));
    EXPECT_TRUE(fails_with("[control]\nrbfn_n_nodes = 2.5\n", 2, "whole number"));
    EXPECT_TRUE(fails_with("[control]\nripple_reduction = maybe\n", 2, "expected true or false"));
    EXPECT_TRUE(fails_with("[control]\nip_zeta = 0.8\nip_zeta = 0.9\n", 3, "set twice (first on line 2)"));
    EXPECT_TRUE(fails_with("duration_s = 1\n", 1, "outside a section"));
    EXPECT_TRUE(fails_with("[sim]\nthis line has no equals sign\n", 2, "syntax error"));
    EXPECT_TRUE(fails_with("[sim\nduration_s = 1\n", 1, "syntax error"));
    EXPECT_TRUE(fails_with("[sim]\nduration_s = 1\n# " + std::string(300, 'x') + "\nperiod_s = 1e-4\n", 3, "line too long"));
    EXPECT_TRUE(fails_with("[sim]\nduration_s = " + std::string(250, '1') + "\n", 2, "line too long"));
}

TEST(ScenarioParser, AcceptsCommentsBlankLinesAndCrLf)
{
    auto l = parse_text("; a comment\r\n# another\r\n\r\n[sim]\r\nduration_s = 2 ; inline\r\n"
                        "period_s = 1e-4 # inline hash\r\n[reference]\r\nstep = 0.5, 300\r\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    EXPECT_DOUBLE_EQ(l.sc->duration_s, 2.0);
    EXPECT_DOUBLE_EQ(l.sc->period_s, 1e-4);
    ASSERT_EQ(l.sc->n_ref, 1);
    EXPECT_DOUBLE_EQ(l.sc->ref[0].rpm, 300.0);
}

TEST(ScenarioParser, MissingFile)
{
    auto l = simtest::load_scenario("/nonexistent/dir/x.ini");
    EXPECT_EQ(l.rc, SCENARIO_EINPUT);
    EXPECT_EQ(l.error.rfind("/nonexistent/dir/x.ini: ", 0), 0u) << l.error;
    EXPECT_NE(l.error.find("cannot open"), std::string::npos) << l.error;
}

TEST(ScenarioParser, DirectoryIsNotAScenario)
{
    auto l = simtest::load_scenario("/tmp");
    EXPECT_EQ(l.rc, SCENARIO_EINPUT);
    EXPECT_EQ(l.error.rfind("/tmp:", 0), 0u) << l.error;
}

TEST(ScenarioSet, OverridesScalarsAndReplacesLists)
{
    const std::string file = "[sim]\nduration_s = 3\n[reference]\nramp = 0 1 500\nstep = 2 200\n"
                             "[events]\nJ_scale = 2.5 1.4\nB_scale = 2.5 1.4\n[control]\nip_zeta = 0.8\n"
                             "[metrics]\nwindow = a 0 1\nwindow = b 1 2\n";
    auto l = parse_text(file, { "sim.duration_s=5", "reference.step = 0.5 300", "events.J_scale=1 2",
                                "control.ip_zeta=1.1", "control.ip_wn_rad_s=30", "metrics.window=c 2 3",
                                "controller.name=ip", "load.step=1 4" });
    ASSERT_EQ(l.rc, 0) << l.error;
    const scenario *sc = l.sc.get();
    EXPECT_DOUBLE_EQ(sc->duration_s, 5.0);
    EXPECT_EQ(sc->key_line[0], SCENARIO_LINE_SET);
    ASSERT_EQ(sc->n_ref, 1); // the whole profile replaced
    EXPECT_FALSE(sc->ref[0].ramp);
    EXPECT_DOUBLE_EQ(sc->ref[0].rpm, 300.0);
    ASSERT_EQ(sc->n_events, 2); // J replaced, B kept
    int nj = 0, nb = 0;
    for (int i = 0; i < sc->n_events; ++i) {
        if (sc->events[i].kind == SCENARIO_EV_J) {
            ++nj;
            EXPECT_DOUBLE_EQ(sc->events[i].t_s, 1.0);
            EXPECT_DOUBLE_EQ(sc->events[i].factor, 2.0);
        }
        nb += sc->events[i].kind == SCENARIO_EV_B;
    }
    EXPECT_EQ(nj, 1);
    EXPECT_EQ(nb, 1);
    ASSERT_EQ(sc->n_control, 2);
    EXPECT_DOUBLE_EQ(sc->control[0].value, 1.1);
    EXPECT_EQ(sc->n_windows, 1);
    EXPECT_STREQ(sc->windows[0].name, "c");
    EXPECT_EQ(sc->controller, SCENARIO_CTL_IP);
    EXPECT_EQ(sc->n_load, 1);
}

TEST(ScenarioSet, Errors)
{
    struct Case {
        const char *set, *prefix, *what;
    };
    const Case cases[] = {
        { "sim.duration_s", "--set sim.duration_s: ", "no '='" },
        { "duration_s=1", "--set duration_s: ", "no '.'" },
        { "sim.nokey=1", "--set sim.nokey: ", "unknown key 'nokey'" },
        { "nosection.x=1", "--set nosection.x: ", "unknown section [nosection]" },
        { "sim.duration_s=abc", "--set sim.duration_s: ", "malformed number 'abc'" },
        { "sim.duration_s=-1", "--set sim.duration_s: ", "out of range" },
        { "sim.duration_s=", "--set sim.duration_s: ", "missing value" },
        { "motor.J_kgm2=-1", "--set motor.J_kgm2: ", "J_kgm2 must be > 0" },
        { "control.nokey=1", "--set control.nokey: ", "unknown key 'nokey'" },
        { "reference.ramp=2 1 5", "--set reference.ramp: ", "end time" },
        { "=5", "--set : ", "no '.'" },
    };
    for (const auto &c : cases) {
        auto l = parse_text("[sim]\nduration_s = 1\n", { c.set });
        EXPECT_EQ(l.rc, SCENARIO_EINPUT) << c.set;
        EXPECT_EQ(l.error.rfind(c.prefix, 0), 0u) << c.set << " -> " << l.error;
        EXPECT_NE(l.error.find(c.what), std::string::npos) << c.set << " -> " << l.error;
    }
}

TEST(ControlKeys, RegistryIsConsistent)
{
    size_t n = 0;
    const sim_control_key *k = sim_control_keys(&n);
    ASSERT_GT(n, 10u);
    std::set<std::string> names;
    for (size_t i = 0; i < n; ++i) {
        EXPECT_TRUE(names.insert(k[i].name).second) << "duplicate " << k[i].name;
        EXPECT_LE(k[i].min, k[i].max) << k[i].name;
        size_t width = k[i].type == SIM_CK_BOOL ? sizeof(bool) : 4u;
        EXPECT_LE(k[i].offset + width, sizeof(ctl_cfg)) << k[i].name;
        EXPECT_EQ(sim_control_key_find(k[i].name), (int)i);
    }
    EXPECT_EQ(sim_control_key_find("no_such_key"), -1);
    // Spot checks against the ctl_cfg layout, written by hand.
    int i = sim_control_key_find("ip_wn_rad_s");
    ASSERT_GE(i, 0);
    EXPECT_EQ(k[i].offset, offsetof(ctl_cfg, speed.ip.wn_rad_s));
    i = sim_control_key_find("psi_ref_Wb");
    ASSERT_GE(i, 0);
    EXPECT_EQ(k[i].offset, offsetof(ctl_cfg, dtc.psi_ref_Wb));
}

TEST(ControlKeys, ApplyWritesTheNamedField)
{
    ctl_cfg cfg;
    std::memset(&cfg, 0, sizeof cfg);
    sim_control_key_apply(sim_control_key_find("ip_zeta"), &cfg, 0.75);
    EXPECT_FLOAT_EQ(cfg.speed.ip.zeta, 0.75f);
    sim_control_key_apply(sim_control_key_find("rbfn_width_3_rad_s"), &cfg, 12.5);
    EXPECT_FLOAT_EQ(cfg.speed.rbfn.width[3], 12.5f);
    sim_control_key_apply(sim_control_key_find("rbfn_n_nodes"), &cfg, 7.0);
    EXPECT_EQ(cfg.speed.rbfn.n_nodes, 7u);
    sim_control_key_apply(sim_control_key_find("ripple_reduction"), &cfg, 1.0);
    EXPECT_TRUE(cfg.dtc.ripple_reduction);
    sim_control_key_apply(sim_control_key_find("i_trip_A"), &cfg, 90.0);
    EXPECT_FLOAT_EQ(cfg.i_trip_A, 90.0f);
    // Nothing else moved.
    EXPECT_FLOAT_EQ(cfg.speed.ip.wn_rad_s, 0.0f);
    EXPECT_FLOAT_EQ(cfg.speed.rbfn.width[2], 0.0f);
    EXPECT_DOUBLE_EQ(sim_control_key_read(sim_control_key_find("ip_zeta"), &cfg), 0.75);
}

TEST(ControlKeys, ParsedIntoTheScenario)
{
    auto l = parse_text("[control]\nripple_reduction = off\nrbfn_m_w = 40\nrbfn_n_nodes = 5\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    ASSERT_EQ(l.sc->n_control, 3);
    EXPECT_EQ(l.sc->control[0].key, sim_control_key_find("ripple_reduction"));
    EXPECT_DOUBLE_EQ(l.sc->control[0].value, 0.0);
    EXPECT_DOUBLE_EQ(l.sc->control[1].value, 40.0);
    EXPECT_EQ(l.sc->control[2].line, 4);
}

// docs/scenarios.md documents every key the parser accepts.
TEST(ScenarioDocs, EveryKeyIsDocumented)
{
    std::string doc = simtest::read_file(simtest::source_path("docs/scenarios.md"));
    ASSERT_FALSE(doc.empty());
    scenario_key_info info;
    for (size_t i = 0; scenario_key_info_at(i, &info); ++i) {
        EXPECT_NE(doc.find("## `[" + std::string(info.section) + "]`"), std::string::npos) << info.section;
        EXPECT_NE(doc.find("`" + std::string(info.key) + "`"), std::string::npos) << info.section << "." << info.key;
    }
    for (size_t i = 0; scenario_list_key_at(i, &info); ++i)
        EXPECT_NE(doc.find("`" + std::string(info.key) + "`"), std::string::npos) << info.section << "." << info.key;
    size_t n = 0;
    const sim_control_key *k = sim_control_keys(&n);
    for (size_t j = 0; j < n; ++j) {
        std::string name = k[j].name;
        // Node arrays are documented as a range: rbfn_centre_0_rad_s .. rbfn_centre_8_rad_s.
        bool node = name.find("_centre_") != std::string::npos || name.find("_width_") != std::string::npos;
        if (node && name.find("_0_") == std::string::npos && name.find("_8_") == std::string::npos)
            continue;
        EXPECT_NE(doc.find("`" + name + "`"), std::string::npos) << "[control] " << name;
    }
}

// Random and mangled input never crashes and always gives one clean line.
TEST(ScenarioParser, GarbageNeverCrashes)
{
    const std::vector<std::string> vocab = {
        "[sim]", "[motor]", "[reference]", "[events]", "[control]", "[metrics]", "[load]", "[", "]",
        "[faults]", "[inverter]", "gain", "stuck", "vdc", "hw", "a", "vc2", "on", "Rs_ramp", "fan_Nms2",
        "dead_time_s", "Lm_sat_exponent",
        "duration_s", "J_kgm2", "step", "ramp", "window", "J_scale", "ip_zeta", "mode", "=", " = ", ":",
        "1", "-1", "0.5", "1e-4", "nan", "inf", "1e999", "abc", "#", ";", "\n", "\n", "\n", "\r\n", " ", "\t",
        std::string(1, '\0'), "\xff\xfe", std::string(120, 'x'),
    };
    std::mt19937 rng(12345);
    for (int iter = 0; iter < 3000; ++iter) {
        std::string text;
        int n = (int)(rng() % 40);
        for (int i = 0; i < n; ++i) {
            if (rng() % 8 == 0)
                text.push_back((char)(rng() % 256));
            else
                text += vocab[rng() % vocab.size()];
        }
        std::string set = vocab[rng() % vocab.size()] + "." + vocab[rng() % vocab.size()] + "=" +
                          vocab[rng() % vocab.size()];
        auto l = parse_text(text.c_str(), { set }); // c_str: stop at an embedded NUL like a C caller
        ASSERT_TRUE(l.rc == 0 || l.rc == SCENARIO_EINPUT);
        if (l.rc != 0) {
            EXPECT_FALSE(l.error.empty());
            EXPECT_EQ(l.error.find('\n'), std::string::npos) << l.error;
            EXPECT_TRUE(l.error.rfind("t.ini", 0) == 0 || l.error.rfind("--set ", 0) == 0) << l.error;
        }
    }
}

// Numbers are decimal only (sim/decimal.h): what a scenario author writes is
// what runs. Each refused spelling is named in the one-line message; each
// accepted one lands with the value written out here.
TEST(ScenarioParser, NumbersAreDecimalOnly)
{
    for (const char *bad : { "0x10", "0X10", "0x1p-4", "0x.8p1", "inf", "-inf", "infinity", "nan", "NAN", "1e",
                             "1e+", ".", "-", "+", "1.2.3", "1_000", "1e400", "1e-400", "0b101", "1d",
                             "5f", "--1", "+-1", "e5", "0x" }) {
        SCOPED_TRACE(bad);
        EXPECT_TRUE(fails_with(std::string("[sim]\nduration_s = ") + bad + "\n", 2,
                               std::string("malformed number '") + bad + "'"));
        // the same in a list key and a [control] key
        EXPECT_TRUE(fails_with(std::string("[reference]\nstep = 1 ") + bad + "\n", 2,
                               std::string("malformed number '") + bad + "'"));
        EXPECT_TRUE(fails_with(std::string("[control]\nip_zeta = ") + bad + "\n", 2,
                               std::string("malformed number '") + bad + "'"));
    }
    // (a list splits "1,5" at the comma; a scalar takes it whole)
    EXPECT_TRUE(fails_with("[sim]\nduration_s = 1,5\n", 2, "malformed number '1,5'"));
    struct Good {
        const char *text;
        double value;
    };
    for (const Good &g : { Good{ "2", 2.0 }, Good{ "0.25", 0.25 }, Good{ ".5", 0.5 }, Good{ "5.", 5.0 },
                           Good{ "+1.5", 1.5 }, Good{ "2e-1", 0.2 }, Good{ "1.5E+1", 15.0 }, Good{ "007", 7.0 },
                           Good{ "0.05000000000000000000000000000000000000000000000", 0.05 } }) {
        SCOPED_TRACE(g.text);
        auto l = parse_text(std::string("[sim]\nduration_s = ") + g.text + "\n");
        ASSERT_EQ(l.rc, 0) << l.error;
        EXPECT_EQ(l.sc->duration_s, g.value);
    }
    // In --set, the same syntax.
    auto l = parse_text("[sim]\nduration_s = 1\n", { "sim.duration_s=0x1p-4" });
    EXPECT_EQ(l.rc, SCENARIO_EINPUT);
    EXPECT_EQ(l.error, "--set sim.duration_s: [sim] duration_s: malformed number '0x1p-4'");
}

// A key or value that does not fit its buffer is refused, never cut short
// into something that runs.
TEST(ScenarioSet, OverLongKeysAndValuesAreRefused)
{
    // 127 characters of key fit ("sim.duration_s" then blanks, trimmed) ...
    auto l = parse_text("", { "sim.duration_s" + std::string(113, ' ') + "=0.5" });
    ASSERT_EQ(l.rc, 0) << l.error;
    EXPECT_EQ(l.sc->duration_s, 0.5);
    // ... 128 do not, whatever follows: the junk would have been cut off.
    l = parse_text("", { "sim.duration_s" + std::string(114, ' ') + "=0.5" });
    EXPECT_EQ(l.rc, SCENARIO_EINPUT);
    EXPECT_NE(l.error.find("the key is longer than 127 characters"), std::string::npos) << l.error;
    l = parse_text("", { "sim.duration_s" + std::string(120, ' ') + "junk=0.5" });
    EXPECT_EQ(l.rc, SCENARIO_EINPUT);
    EXPECT_EQ(l.error.rfind("--set sim.duration_s", 0), 0u) << l.error;
    EXPECT_EQ(l.error.find('\n'), std::string::npos);
    // A value: 255 characters fit, 256 do not (a number with trailing junk
    // past the old cut would have run as 0.05).
    std::string fits = "0.05" + std::string(251, '0');
    l = parse_text("", { "sim.duration_s=" + fits });
    ASSERT_EQ(l.rc, 0) << l.error;
    EXPECT_EQ(l.sc->duration_s, 0.05);
    l = parse_text("", { "sim.duration_s=" + fits + "x" });
    EXPECT_EQ(l.rc, SCENARIO_EINPUT);
    EXPECT_EQ(l.error, "--set sim.duration_s: [sim] duration_s: value longer than 255 characters");
    for (const char *key : { "reference.step=1 ", "control.ip_zeta=" }) {
        l = parse_text("", { key + std::string(300, '5') });
        EXPECT_EQ(l.rc, SCENARIO_EINPUT) << key;
        EXPECT_NE(l.error.find("value longer than 255 characters"), std::string::npos) << l.error;
    }
    // A file name that does not fit the messages' buffer.
    l = parse_text("[sim]\nduration_s = 1\n", {}, std::string(2000, 'f'));
    EXPECT_EQ(l.rc, SCENARIO_EINPUT);
    EXPECT_NE(l.error.find("the file name is longer than 1023 characters"), std::string::npos) << l.error;
}
