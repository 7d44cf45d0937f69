// Protection and run-state machine of ctl_step: every fault of
// docs/faults.md latches its bit and turns the gates off in the very tick it
// is detected, the core stays FAULTED until ctl_clear_faults finds the cause
// gone, and bad samples change nothing else.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "dtc/bringup.h"
#include "dtc/ctl.h"
#include "dtc/npc.h"

namespace {

struct Core {
    ctl_cfg cfg;
    ctl_state s;
    ctl_out out;
    Core()
    {
        ctl_cfg_default(&cfg);
        ctl_init(&s, &cfg);
        std::memset(&out, 0, sizeof out);
    }
    static ctl_in nominal(bool run = true)
    {
        ctl_in in;
        std::memset(&in, 0, sizeof in);
        in.sample.vc1_V = 155.5f;
        in.sample.vc2_V = 155.5f;
        in.sample_fresh = true;
        in.run = run;
        return in;
    }
    void step(const ctl_in &in) { ctl_step(&s, &cfg, &in, &out); }
    void run_ticks(int n)
    {
        ctl_in in = nominal();
        for (int i = 0; i < n; ++i)
            step(in);
    }
};

bool all_legs_o(const hal_actuation &a)
{
    for (int v = 0; v < 2; ++v)
        for (int k = 0; k < 3; ++k)
            if (a.vector[v].leg[k] != HAL_LEG_O)
                return false;
    return true;
}

TEST(CtlDefaults, ProtectionLevelsOfThe10hpDrive)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    EXPECT_FLOAT_EQ(c.i_trip_A, 100.0f);
    EXPECT_FLOAT_EQ(c.vdc_max_V, 400.0f);
    EXPECT_FLOAT_EQ(c.vdc_min_V, 200.0f);
    EXPECT_FLOAT_EQ(c.np_trip_V, 30.0f);
    EXPECT_FLOAT_EQ(c.overspeed_rad_s, 310.0f);
    EXPECT_FLOAT_EQ(c.motor.Ls_H, 0.00142f + 0.0416f);
    EXPECT_FLOAT_EQ(c.dtc.psi_ref_Wb, 0.45f);
    EXPECT_FLOAT_EQ(c.period_s, 200e-6f);
    EXPECT_EQ(ctl_cfg_check(&c), CTL_CFG_OK);
}

TEST(CtlConfig, CheckNamesTheFirstViolatedRule)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    ctl_cfg bad = c;
    bad.motor.Ls_H = bad.motor.Lm_H; // no leakage: sigma = 0
    EXPECT_EQ(ctl_cfg_check(&bad), CTL_CFG_E_MOTOR);
    bad = c;
    bad.period_s = 0.0f;
    EXPECT_EQ(ctl_cfg_check(&bad), CTL_CFG_E_PERIOD);
    bad = c;
    bad.dtc.torque_band2_Nm = bad.dtc.torque_band_Nm;
    EXPECT_EQ(ctl_cfg_check(&bad), CTL_CFG_E_DTC);
    bad = c;
    bad.dtc.psi_ref_Wb = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(ctl_cfg_check(&bad), CTL_CFG_E_DTC);
    bad = c;
    bad.obs.k_gain = 0.5f;
    EXPECT_EQ(ctl_cfg_check(&bad), CTL_CFG_E_OBSERVER);
    bad = c;
    bad.vdc_min_V = 500.0f;
    EXPECT_EQ(ctl_cfg_check(&bad), CTL_CFG_E_PROTECTION);
    bad = c;
    bad.speed.te_max_Nm = -1.0f;
    EXPECT_EQ(ctl_cfg_check(&bad), CTL_CFG_E_SPEED);
}

TEST(CtlConfig, BringUpFrequencyStaysWithinTheTopSpeed)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    // The V/f frequency whose synchronous speed is the speed reference's limit, by hand:
    // f = (overspeed / 1.1) * p / (2 pi).
    const double top_rad_s = static_cast<double>(c.overspeed_rad_s) / 1.1;
    const double f_top_Hz = top_rad_s * static_cast<double>(c.motor.pole_pairs) / (2.0 * 3.14159265358979);
    ctl_cfg v = c;
    v.bringup_hz = static_cast<float>(f_top_Hz * 0.999);
    EXPECT_EQ(ctl_cfg_check(&v), CTL_CFG_OK);
    v.bringup_hz = static_cast<float>(-f_top_Hz * 0.999);
    EXPECT_EQ(ctl_cfg_check(&v), CTL_CFG_OK);
    v.bringup_hz = static_cast<float>(f_top_Hz * 1.001);
    EXPECT_EQ(ctl_cfg_check(&v), CTL_CFG_E_PROTECTION);
    v.bringup_hz = static_cast<float>(-f_top_Hz * 1.001);
    EXPECT_EQ(ctl_cfg_check(&v), CTL_CFG_E_PROTECTION);
}

// The speed-deviation supervision's two parameters: hostile values refused
// (the run-supervision rule of ctl_cfg_check), the limits themselves accepted.
TEST(CtlConfig, SpeedDeviationParametersOutOfRangeRefused)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    EXPECT_FLOAT_EQ(c.speed_dev_band_rad_s, 5.86f); /* the rated slip speed, 1800 - 1744 rpm */
    EXPECT_FLOAT_EQ(c.speed_dev_time_s, 1.0f);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (float v : {-1.0f, -1e-6f, 500.01f, nan, inf, -inf}) {
        ctl_cfg bad = c;
        bad.speed_dev_band_rad_s = v;
        EXPECT_EQ(ctl_cfg_check(&bad), CTL_CFG_E_PROTECTION) << v;
    }
    for (float v : {-1.0f, 60.01f, nan, inf}) {
        ctl_cfg bad = c;
        bad.speed_dev_time_s = v;
        EXPECT_EQ(ctl_cfg_check(&bad), CTL_CFG_E_PROTECTION) << v;
    }
    for (float b : {0.0f, 500.0f})
        for (float t : {0.0f, 60.0f}) {
            ctl_cfg ok = c;
            ok.speed_dev_band_rad_s = b;
            ok.speed_dev_time_s = t;
            ctl_cfg_derive(&ok);
            EXPECT_EQ(ctl_cfg_check(&ok), CTL_CFG_OK) << b << " " << t;
            EXPECT_FLOAT_EQ(ok.speed_dev_shrink_rad_s_per_s, t > 0.0f ? b / t : 0.0f);
        }
}

TEST(CtlRunState, StoppedMagnetisingRunningStopped)
{
    Core c;
    ctl_in in = Core::nominal(false);
    c.step(in);
    EXPECT_EQ(c.out.tel.state, CTL_STOPPED);
    EXPECT_FALSE(c.out.gate_enable);

    in.run = true;
    c.step(in);
    EXPECT_EQ(c.out.tel.state, CTL_MAGNETISING);
    EXPECT_TRUE(c.out.gate_enable);
    EXPECT_FLOAT_EQ(c.out.tel.te_ref_Nm, 0.0f); // zero torque while magnetising

    // premag_s later the speed loop takes over
    int n = int(std::lround(c.cfg.dtc.premag_s / c.cfg.period_s));
    for (int i = 0; i < n - 2; ++i)
        c.step(in);
    EXPECT_EQ(c.out.tel.state, CTL_MAGNETISING);
    c.step(in);
    c.step(in);
    EXPECT_EQ(c.out.tel.state, CTL_RUNNING);

    in.run = false; // stop: gates off at once
    c.step(in);
    EXPECT_EQ(c.out.tel.state, CTL_STOPPED);
    EXPECT_FALSE(c.out.gate_enable);
    EXPECT_TRUE(all_legs_o(c.out.act));
}

// Magnetising at standstill builds the flux with the DTC and never asks for
// a P<->N step, from the first tick on.
TEST(CtlRunState, FirstVectorsAfterStartAreSafe)
{
    Core c;
    ctl_in in = Core::nominal();
    uint8_t prev = NPC_STATE_OOO; // the board holds OOO while the gates are off
    for (int i = 0; i < 50; ++i) {
        c.step(in);
        ASSERT_TRUE(c.out.gate_enable);
        uint8_t s0 = npc_state_of(&c.out.act.vector[0]);
        uint8_t s1 = npc_state_of(&c.out.act.vector[1]);
        ASSERT_LT(s0, 27);
        ASSERT_LT(s1, 27);
        EXPECT_FALSE(npc_pn_step(prev, s0));
        EXPECT_FALSE(npc_pn_step(s0, s1));
        prev = s1;
    }
}

// The latched actuation's leg codes are its states' (applied.act.vector[k] is
// applied.state[k]) after every tick, whatever path wrote them: running,
// magnetising, gates off after a stop or a fault, and every bring-up level.
// The real inverter's voltage (dtc/inverter_model.h) reads levels from the
// codes and edge directions from the states and relies on it.
bool latched_codes_match(const ctl_state &s)
{
    return npc_state_of(&s.applied.act.vector[0]) == s.applied.state[0] &&
           npc_state_of(&s.applied.act.vector[1]) == s.applied.state[1];
}

TEST(CtlRunState, LatchedActuationIsTheLatchedStatesOnEveryPath)
{
    for (uint32_t level = BRINGUP_GATE_TEST; level <= BRINGUP_SPEED; ++level) {
        SCOPED_TRACE(level);
        Core c; // the defaults: the real inverter's compensation on
        c.cfg.bringup_level = level;
        ctl_cfg_derive(&c.cfg);
        ASSERT_TRUE(c.cfg.inv.real);
        ctl_init(&c.s, &c.cfg);
        ctl_in in = Core::nominal();
        int n_on = 0;
        for (int i = 0; i < 3000; ++i) { // through magnetising (or the bring-up steps) into running
            in.sample.ia_A = 4.0f * std::sin(0.01f * float(i));
            in.sample.ib_A = 4.0f * std::sin(0.01f * float(i) - 2.0944f);
            in.sample.ic_A = -in.sample.ia_A - in.sample.ib_A;
            c.step(in);
            ASSERT_TRUE(latched_codes_match(c.s)) << "tick " << i;
            n_on += c.out.gate_enable ? 1 : 0;
        }
        if (level == BRINGUP_ADC) {
            EXPECT_EQ(n_on, 0) << "the ADC readout never switches";
        } else {
            EXPECT_GT(n_on, 1000);
        }
        in.run = false; // a stop: gates off
        c.step(in);
        EXPECT_TRUE(latched_codes_match(c.s));
        in.run = true;
        for (int i = 0; i < 20; ++i)
            c.step(in);
        in.overrun = true; // a fault: gates off
        c.step(in);
        EXPECT_NE(c.out.tel.faults, 0u);
        EXPECT_TRUE(latched_codes_match(c.s));
    }
}

struct FaultCase {
    const char *name;
    uint32_t bit;
    void (*inject)(ctl_in &in, ctl_state &s);
};

const FaultCase kFaults[] = {
    {"overcurrent a", CTL_FAULT_OVERCURRENT, [](ctl_in &in, ctl_state &) { in.sample.ia_A = 100.5f; }},
    {"overcurrent b negative", CTL_FAULT_OVERCURRENT, [](ctl_in &in, ctl_state &) { in.sample.ib_A = -100.5f; }},
    {"overcurrent c", CTL_FAULT_OVERCURRENT, [](ctl_in &in, ctl_state &) { in.sample.ic_A = 150.0f; }},
    {"dc overvoltage", CTL_FAULT_DC_OVERVOLT,
     [](ctl_in &in, ctl_state &) { in.sample.vc1_V = in.sample.vc2_V = 200.5f; }},
    {"dc undervoltage", CTL_FAULT_DC_UNDERVOLT,
     [](ctl_in &in, ctl_state &) { in.sample.vc1_V = in.sample.vc2_V = 99.5f; }},
    {"np imbalance", CTL_FAULT_NP_IMBALANCE,
     [](ctl_in &in, ctl_state &) {
         in.sample.vc1_V = 171.0f;
         in.sample.vc2_V = 140.0f;
     }},
    {"overspeed", CTL_FAULT_OVERSPEED, [](ctl_in &, ctl_state &s) { s.obs.omega_m_filt_rad_s = -311.0f; }},
    // a diverged observer (NaN speed) must not slip past the overspeed check
    {"NaN speed estimate", CTL_FAULT_OVERSPEED,
     [](ctl_in &, ctl_state &s) { s.obs.omega_m_filt_rad_s = std::numeric_limits<float>::quiet_NaN(); }},
    {"stale sample", CTL_FAULT_STALE_SAMPLE, [](ctl_in &in, ctl_state &) { in.sample_fresh = false; }},
    {"hardware input", CTL_FAULT_HW, [](ctl_in &in, ctl_state &) { in.fault_input = true; }},
    {"overrun", CTL_FAULT_OVERRUN, [](ctl_in &in, ctl_state &) { in.overrun = true; }},
    {"NaN current", CTL_FAULT_SAMPLE_INVALID,
     [](ctl_in &in, ctl_state &) { in.sample.ib_A = std::numeric_limits<float>::quiet_NaN(); }},
    {"infinite voltage", CTL_FAULT_SAMPLE_INVALID,
     [](ctl_in &in, ctl_state &) { in.sample.vc2_V = std::numeric_limits<float>::infinity(); }},
};

TEST(CtlProtection, EachFaultLatchesAndDisablesTheGatesInTheSameTick)
{
    for (const FaultCase &f : kFaults) {
        SCOPED_TRACE(f.name);
        Core c;
        c.run_ticks(20); // magnetising, gates on
        ASSERT_TRUE(c.out.gate_enable);
        ASSERT_EQ(c.out.tel.faults, 0u);

        ctl_in in = Core::nominal();
        f.inject(in, c.s);
        c.step(in);
        EXPECT_FALSE(c.out.gate_enable);
        EXPECT_EQ(c.out.tel.faults, f.bit);
        EXPECT_EQ(c.out.tel.state, CTL_FAULTED);
        EXPECT_TRUE(all_legs_o(c.out.act));

        // the cause disappears: still latched, gates stay off, even with run
        ctl_in ok = Core::nominal();
        c.s.obs.omega_m_filt_rad_s = 0.0f;
        for (int i = 0; i < 5; ++i) {
            c.step(ok);
            EXPECT_FALSE(c.out.gate_enable);
            EXPECT_EQ(c.out.tel.faults, f.bit);
        }
        // cleared by the background: stopped, then a normal start
        EXPECT_EQ(ctl_clear_faults(&c.s), 0u);
        c.step(ok);
        EXPECT_EQ(c.out.tel.faults, 0u);
        EXPECT_EQ(c.out.tel.state, CTL_MAGNETISING);
        EXPECT_TRUE(c.out.gate_enable);
    }
}

TEST(CtlProtection, ClearKeepsAFaultWhoseCauseIsStillThere)
{
    Core c;
    c.run_ticks(5);
    ctl_in in = Core::nominal();
    in.sample.vc1_V = in.sample.vc2_V = 210.0f; // 420 V > 400 V
    c.step(in);
    c.step(in); // still there at the last step
    EXPECT_EQ(ctl_clear_faults(&c.s), (uint32_t)CTL_FAULT_DC_OVERVOLT);
    c.step(Core::nominal());
    EXPECT_EQ(c.out.tel.state, CTL_FAULTED);
    EXPECT_FALSE(c.out.gate_enable);
    EXPECT_EQ(ctl_clear_faults(&c.s), 0u); // gone at the last step
    c.step(Core::nominal());
    EXPECT_TRUE(c.out.gate_enable);
}

TEST(CtlProtection, SeveralCausesLatchTogether)
{
    Core c;
    c.run_ticks(5);
    ctl_in in = Core::nominal();
    in.sample.ia_A = 120.0f;
    in.fault_input = true;
    in.sample.vc1_V = 175.0f;
    in.sample.vc2_V = 140.0f;
    c.step(in);
    EXPECT_EQ(c.out.tel.faults, (uint32_t)(CTL_FAULT_OVERCURRENT | CTL_FAULT_HW | CTL_FAULT_NP_IMBALANCE));
    EXPECT_FALSE(c.out.gate_enable);
}

// Levels just inside the limits do not trip.
TEST(CtlProtection, NoTripInsideTheLimits)
{
    Core c;
    c.run_ticks(5);
    ctl_in in = Core::nominal();
    in.sample.ia_A = 99.0f;
    in.sample.ib_A = -50.0f;
    in.sample.ic_A = -49.0f;
    in.sample.vc1_V = 199.0f + 14.0f; // vc1 + vc2 = 398 V, vc1 - vc2 = 28 V
    in.sample.vc2_V = 185.0f;
    c.step(in);
    EXPECT_EQ(c.out.tel.faults, 0u);
    EXPECT_TRUE(c.out.gate_enable);
}

// Under-voltage counts only while the drive runs: a link that is still
// charging does not latch a fault in STOPPED.
TEST(CtlProtection, UndervoltageOnlyWhileActive)
{
    Core c;
    ctl_in in = Core::nominal(false);
    in.sample.vc1_V = in.sample.vc2_V = 50.0f;
    for (int i = 0; i < 10; ++i)
        c.step(in);
    EXPECT_EQ(c.out.tel.faults, 0u);
    EXPECT_EQ(c.out.tel.state, CTL_STOPPED);
    in.run = true;
    c.step(in); // starting on a low link: the first active tick trips
    c.step(in);
    EXPECT_EQ(c.out.tel.faults, (uint32_t)CTL_FAULT_DC_UNDERVOLT);
    EXPECT_FALSE(c.out.gate_enable);
}

// A refused or invalid sample changes nothing but the fault word: the
// observer and the actuation memory are those of the tick before.
TEST(CtlProtection, BadSampleLosesNothing)
{
    Core c;
    c.run_ticks(30);
    observer before = c.s.obs;
    ctl_in in = Core::nominal();
    in.sample.ia_A = std::numeric_limits<float>::quiet_NaN();
    c.step(in);
    EXPECT_EQ(std::memcmp(&before, &c.s.obs, sizeof before), 0);
    EXPECT_EQ(c.out.tel.faults, (uint32_t)CTL_FAULT_SAMPLE_INVALID);
    EXPECT_TRUE(std::isfinite(c.out.tel.te_ref_Nm));
    EXPECT_TRUE(std::isfinite(c.out.tel.omega_est_rad_s));
}

} // namespace

// The operating point's supervision (once per slot cycle, not every tick): at
// the voltage limit the flux target is the DC link's usable phase voltage over
// the electrical speed, fw_voltage_frac / sqrt(3) x Vdc / |w_e|, worked out
// only in the supervision slot (every speed mode) and held in the ticks
// between, while the reference ramps towards it every tick.
TEST(CtlSupervision, FluxTargetStepsOncePerSlotCycleAtTheVoltageLimit)
{
    for (speed_mode mode : {SPEED_MODE_IP, SPEED_MODE_RBFN}) {
        SCOPED_TRACE(mode);
        Core c;
        c.cfg.speed.mode = mode;
        ctl_cfg_derive(&c.cfg);
        ctl_in in = Core::nominal();
        c.step(in); // starts magnetising
        ASSERT_EQ(c.s.run_state, CTL_MAGNETISING);
        int steps = 0;
        float psi_prev = c.s.dtc_cmd.psi_ref_Wb;
        const int ticks = 3 * (int)CTL_SLOW_SLOTS; // three slot cycles
        for (int k = 0; k < ticks; ++k) {
            const float w_e = 450.0f + 5.0f * (float)k; // a new speed each tick, rad/s electrical (below overspeed)
            c.s.obs.omega_int_rad_s = w_e;
            c.s.obs.omega_e_rad_s = w_e;
            const float target_before = c.s.psi_target_Wb;
            c.step(in);
            const double w = std::abs((double)c.s.obs.omega_e_rad_s); // the speed this tick's step used
            const double expect = (double)c.cfg.fw_voltage_frac / std::sqrt(3.0) * 311.0 / w;
            if (ctl_slot_supervise(c.s.slow_slot)) { // this tick's slot (dtc/ctl_schedule.h)
                ++steps;
                EXPECT_NEAR(c.s.psi_target_Wb, expect, 1e-5 * expect) << "tick " << k;
            } else {
                EXPECT_EQ(c.s.psi_target_Wb, target_before) << "tick " << k << ": changed outside its slot";
            }
            // the reference ramps every tick, by the slew limit at most
            const double dpsi = (double)c.cfg.psi_ramp_Wb_s * c.cfg.period_s;
            EXPECT_LE(std::abs((double)c.s.dtc_cmd.psi_ref_Wb - psi_prev), dpsi * 1.0001);
            EXPECT_NE(c.s.dtc_cmd.psi_ref_Wb, psi_prev) << "tick " << k << ": the ramp stood still";
            psi_prev = c.s.dtc_cmd.psi_ref_Wb;
        }
        EXPECT_EQ(steps, 3);
    }
}
