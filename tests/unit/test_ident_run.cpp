// The identification run's phases, refusals and aborts (dtc/ident.h), the
// plate's estimates (dtc/ident_plate.h) and ident_apply, on synthetic inputs:
// a resistor-inductor load in place of the machine (no rotor: the rotor's
// values must not pass), and the plates of the Krause table's motors.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstring>
#include <set>
#include <string>

#include "dtc/npc.h"
#include "dtc/ident.h"
#include "dtc/ident_apply.h"
#include "ident_rig.hpp"

namespace {

using identrig::Motor;

ident_cfg cfg_for(const Motor &m, bool rotating)
{
    identrig::Options o;
    o.rotating = rotating;
    ident_cfg c = identrig::ident_cfg_for(m, o);
    EXPECT_EQ(ident_cfg_derive(&c), IDENT_OK);
    return c;
}

// A wye-connected R-L load on the inverter (no rotor), its current along alpha
// integrated exactly over each vector of the period; the ideal inverter.
struct RlLoad {
    double r = 0.3, l = 3e-3, i = 0.0, vc = 155.5;
    void advance(const hal_actuation &a, double T)
    {
        for (int k = 0; k < 2; ++k) {
            double d = k == 0 ? a.duty0 : 1.0 - a.duty0;
            float v[2];
            npc_state_voltage(npc_state_of(&a.vector[k]), float(vc), float(vc), v);
            double e = std::exp(-r * d * T / l), i_inf = v[0] / r;
            i = i_inf + (i - i_inf) * e;
        }
    }
    ident_in in(bool run = true) const
    {
        ident_in x{};
        x.i_abc_A[0] = float(i);
        x.i_abc_A[1] = x.i_abc_A[2] = float(-0.5 * i);
        x.vc1_V = x.vc2_V = float(vc);
        x.run = run;
        return x;
    }
};

// The voltage of a period on the ideal inverter, alpha.
float alpha_voltage(const hal_actuation &a, double vc)
{
    float v0[2], v1[2];
    npc_state_voltage(npc_state_of(&a.vector[0]), float(vc), float(vc), v0);
    npc_state_voltage(npc_state_of(&a.vector[1]), float(vc), float(vc), v1);
    return a.duty0 * v0[0] + (1.0f - a.duty0) * v1[0];
}

struct Driven {
    ident id;
    ident_result res;
    ident_out out;
    std::set<int> phases;
    unsigned ticks = 0;
    bool progress_monotonic = true;
};

// Step @p id on the R-L load until it is done or aborted (or @p max ticks),
// with the run command dropped from tick @p stop_at on.
void drive(Driven &d, const ident_cfg &c, RlLoad &load, unsigned max, unsigned stop_at = ~0u)
{
    hal_actuation applied{};
    npc_legs(NPC_STATE_OOO, &applied.vector[0]);
    npc_legs(NPC_STATE_OOO, &applied.vector[1]);
    applied.duty0 = 1.0f;
    uint32_t last_progress = 0u;
    for (unsigned k = 0; k < max; ++k) {
        ident_in in = load.in(k < stop_at);
        in.v_ab_V[0] = alpha_voltage(applied, load.vc);
        ident_step(&d.id, &c, &in, &d.out);
        ident_background(&d.id, &c, &d.res);
        d.phases.insert(int(d.id.phase));
        uint32_t p = ident_progress(&d.id, &c);
        if (d.id.phase != IDENT_ABORTED && p < last_progress)
            d.progress_monotonic = false;
        last_progress = p;
        if (d.out.mode == IDENT_OUT_ACTUATE) {
            load.advance(applied, 200e-6);
            applied = d.out.act;
        } else {
            load.i = 0.0; // gates off: the current falls through the diodes within a period
            npc_legs(NPC_STATE_OOO, &applied.vector[0]);
            npc_legs(NPC_STATE_OOO, &applied.vector[1]);
            applied.duty0 = 1.0f;
        }
        d.ticks = k + 1;
        if (d.id.phase == IDENT_DONE || d.id.phase == IDENT_ABORTED)
            break;
    }
}

const ident_start_in kStopped{true, 0.0f, 311.0f};

TEST(IdentRun, AResistorInductorLoadGivesRsAndSigmaLsAndNoRotor)
{
    const Motor m = identrig::motors()[1];
    ident_cfg c = cfg_for(m, true);
    RlLoad load;
    Driven d;
    ident_init(&d.id);
    ASSERT_EQ(ident_start(&d.id, &c, &kStopped), IDENT_OK);
    drive(d, c, load, 200000u);
    ASSERT_EQ(d.id.phase, IDENT_DONE); // no rotor: the rotating part is not allowed
    EXPECT_TRUE(d.progress_monotonic);
    EXPECT_EQ(ident_progress(&d.id, &c), 100u);
    for (int p : {IDENT_PROBE, IDENT_MAGNETISE, IDENT_SIGMA, IDENT_ROTOR, IDENT_FIT_STANDSTILL})
        EXPECT_TRUE(d.phases.count(p)) << ident_phase_name(ident_phase(p));
    EXPECT_FALSE(d.phases.count(IDENT_ROT_START));
    EXPECT_NEAR(d.res.rs_ohm.value, load.r, 0.01 * load.r);
    EXPECT_EQ(d.res.rs_ohm.verdict, IDENT_VERDICT_OK);
    EXPECT_NEAR(d.res.sigma_ls_H.value, load.l, 0.01 * load.l);
    EXPECT_NEAR(d.res.r_hf_ohm, load.r, 0.1 * load.r);
    // no rotor: no transient to fit, so no rotor resistance the drive could use
    EXPECT_NE(d.res.rr_ohm.verdict, IDENT_VERDICT_OK);
    EXPECT_NE(d.res.lm_H.verdict, IDENT_VERDICT_OK);
    EXPECT_EQ(d.res.j_kgm2.verdict, IDENT_VERDICT_NONE);
    EXPECT_FLOAT_EQ(d.res.t_standstill_s, float(ident_ss_ticks(&c.ss)) * 200e-6f);
    // apply: Rs only; the configuration derived again
    ctl_cfg from, to;
    ctl_cfg_default(&from);
    EXPECT_EQ(ident_apply(&d.id, &d.res, &from, &to), int(IDENT_APPLIED_RS));
    EXPECT_EQ(to.motor.Rs_ohm, d.res.rs_ohm.value);
    EXPECT_EQ(to.motor.Lm_H, from.motor.Lm_H);
    EXPECT_EQ(to.rsid.rs_model_ohm, d.res.rs_ohm.value); // what depends on Rs moved with it
}

TEST(IdentRun, StartIsRefusedUnlessStoppedAtRestAndTheLinkReady)
{
    const Motor m = identrig::motors()[1];
    ident_cfg c = cfg_for(m, false);
    ident id;
    ident_init(&id);
    ident_start_in x = kStopped;
    x.drive_stopped = false;
    EXPECT_EQ(ident_start(&id, &c, &x), IDENT_E_NOT_STOPPED);
    x = kStopped;
    x.omega_m_rad_s = 0.05f * c.est.w_m_rad_s; // 5 % of the rated speed
    EXPECT_EQ(ident_start(&id, &c, &x), IDENT_E_TURNING);
    x.omega_m_rad_s = NAN;
    EXPECT_EQ(ident_start(&id, &c, &x), IDENT_E_TURNING);
    x = kStopped;
    x.vdc_V = 0.5f * c.vdc_nom_V;
    EXPECT_EQ(ident_start(&id, &c, &x), IDENT_E_LINK);
    EXPECT_EQ(id.phase, IDENT_IDLE); // refused: nothing started
    EXPECT_EQ(ident_start(&id, &c, &kStopped), IDENT_OK);
    EXPECT_EQ(id.phase, IDENT_PROBE);
    EXPECT_EQ(ident_start(&id, &c, &kStopped), IDENT_E_BUSY);
    ident_result r{};
    EXPECT_EQ(ident_continue(&id, &r), IDENT_E_PHASE);
    EXPECT_EQ(ident_background(&id, &c, &r), IDENT_BG_NONE);
}

// Every abort: gates off in that tick, the phase ABORTED with its reason, nothing to apply.
void expect_aborted(const Driven &d, const ident_cfg &c, ident_abort why)
{
    EXPECT_EQ(d.id.phase, IDENT_ABORTED);
    EXPECT_EQ(d.id.abort_reason, why);
    EXPECT_EQ(d.out.mode, IDENT_OUT_OFF);
    EXPECT_EQ(ident_progress(&d.id, &c), 0u);
    ctl_cfg from, to;
    ctl_cfg_default(&from);
    std::memset(&to, 0x5A, sizeof to);
    EXPECT_EQ(ident_apply(&d.id, &d.res, &from, &to), IDENT_E_PHASE);
    EXPECT_EQ(std::memcmp(&from, &to, sizeof to), 0);
}

TEST(IdentRun, TheRunCommandDroppingAbortsInEveryStandstillPhase)
{
    const Motor m = identrig::motors()[1];
    ident_cfg c = cfg_for(m, false);
    const unsigned probe = c.ss.probe_ticks, g0 = 2 * probe;
    for (unsigned at : {probe / 2, probe + 3, g0 + 100, g0 + c.ss.g_sigma + 50, g0 + c.ss.g_rotor + 50}) {
        RlLoad load;
        Driven d;
        ident_init(&d.id);
        ASSERT_EQ(ident_start(&d.id, &c, &kStopped), IDENT_OK);
        drive(d, c, load, 200000u, at);
        expect_aborted(d, c, IDENT_ABORT_STOPPED);
        EXPECT_EQ(d.ticks, at + 1) << at; // in the very tick
        ident_out again;
        ident_in in = load.in();
        ident_step(&d.id, &c, &in, &again);
        EXPECT_EQ(again.mode, IDENT_OUT_OFF); // and stays off
    }
}

TEST(IdentRun, AFaultAnOverCurrentOrASaggingLinkAborts)
{
    const Motor m = identrig::motors()[1];
    ident_cfg c = cfg_for(m, false);
    for (int kind = 0; kind < 3; ++kind) {
        ident id;
        ident_init(&id);
        ASSERT_EQ(ident_start(&id, &c, &kStopped), IDENT_OK);
        RlLoad load;
        ident_out out{};
        for (int k = 0; k < 500 && id.phase != IDENT_ABORTED; ++k) {
            ident_in in = load.in();
            if (k >= 300) {
                if (kind == 0)
                    in.fault = true;
                else if (kind == 1)
                    in.i_abc_A[1] = 1.01f * c.ss.i_max_A;
                else
                    in.vc1_V = in.vc2_V = 0.3f * c.vdc_nom_V;
            }
            ident_step(&id, &c, &in, &out);
        }
        EXPECT_EQ(id.phase, IDENT_ABORTED);
        EXPECT_EQ(id.abort_reason, kind == 0 ? IDENT_ABORT_FAULT : (kind == 1 ? IDENT_ABORT_OVERCURRENT : IDENT_ABORT_LINK));
        EXPECT_EQ(out.mode, IDENT_OUT_OFF);
    }
}

TEST(IdentRun, ACurrentInTheZeroVectorMeansATurningRotor)
{
    const Motor m = identrig::motors()[1];
    ident_cfg c = cfg_for(m, false);
    ident id;
    ident_init(&id);
    ASSERT_EQ(ident_start(&id, &c, &kStopped), IDENT_OK);
    ident_out out{};
    // a magnetised rotor turning drives a current through the shorted winding
    for (unsigned k = 0; k < 2 * c.ss.probe_ticks && id.phase != IDENT_ABORTED; ++k) {
        ident_in in{};
        in.vc1_V = in.vc2_V = 155.5f;
        in.run = true;
        if (k >= c.ss.probe_ticks) {
            double th = 0.05 * k;
            for (int j = 0; j < 3; ++j)
                in.i_abc_A[j] = float(3.0 * std::cos(th - 2.0 * identrig::kPi * j / 3.0));
        }
        ident_step(&id, &c, &in, &out);
    }
    EXPECT_EQ(id.phase, IDENT_ABORTED);
    EXPECT_EQ(id.abort_reason, IDENT_ABORT_TURNING);
}

TEST(IdentRun, NamesAndVerdicts)
{
    std::set<std::string> names;
    for (int p = IDENT_IDLE; p <= IDENT_ABORTED; ++p)
        names.insert(ident_phase_name(ident_phase(p)));
    EXPECT_EQ(names.size(), size_t(IDENT_ABORTED + 1));
    EXPECT_STREQ(ident_phase_name(ident_phase(99)), "?");
    EXPECT_STREQ(ident_verdict_name(IDENT_VERDICT_OK), "ok");
    EXPECT_STREQ(ident_verdict_name(IDENT_VERDICT_DOUBTFUL), "doubtful");
    EXPECT_STREQ(ident_verdict_name(IDENT_VERDICT_FAILED), "failed");
    EXPECT_STREQ(ident_verdict_name(IDENT_VERDICT_NONE), "-");
}

TEST(IdentCfg, RefusesABadPlateOrDrive)
{
    const Motor m = identrig::motors()[1];
    identrig::Options o;
    ident_cfg c = identrig::ident_cfg_for(m, o);
    ident_cfg bad = c;
    bad.plate.cos_phi = 1.2f;
    EXPECT_EQ(ident_cfg_derive(&bad), IDENT_E_PLATE);
    bad = c;
    bad.plate.i_A = NAN;
    EXPECT_EQ(ident_cfg_derive(&bad), IDENT_E_PLATE);
    bad = c;
    bad.plate.speed_rpm = 4000.0f; // above 3600 rpm at 60 Hz
    EXPECT_EQ(ident_cfg_derive(&bad), IDENT_E_PLATE);
    EXPECT_EQ(ident_plate_check(&bad.plate), IDENT_PLATE_E_SPEED);
    bad = c;
    bad.vdc_min_V = bad.vdc_nom_V;
    EXPECT_EQ(ident_cfg_derive(&bad), IDENT_E_DRIVE);
    bad = c;
    bad.dead_time_s = 20e-6f;
    EXPECT_EQ(ident_cfg_derive(&bad), IDENT_E_DRIVE);
    bad = c;
    bad.period_s = 0.0f;
    EXPECT_EQ(ident_cfg_derive(&bad), IDENT_E_DRIVE);
}

TEST(IdentCfg, TheStandstillScheduleFitsItsBinsAndItsTime)
{
    for (const Motor &m : identrig::motors()) {
        ident_cfg c = cfg_for(m, true);
        const ident_ss_cfg &s = c.ss;
        SCOPED_TRACE(m.name);
        EXPECT_GE(s.n_block, 2u);
        EXPECT_LE(s.n_block, 16u);
        EXPECT_EQ(s.bin_ticks % s.n_block, 0u);
        EXPECT_EQ(s.g_sigma % s.bin_ticks, 0u);
        EXPECT_EQ(s.g_rotor % s.bin_ticks, 0u);
        EXPECT_EQ(s.g_end % s.bin_ticks, 0u);
        EXPECT_LE(s.g_end / s.bin_ticks, IDENT_BINS);
        EXPECT_GE(s.g_rotor - s.g_sigma, s.bursts * s.cycle);
        EXPECT_LE(ident_ss_ticks(&s) * 200e-6, 30.0);
        EXPECT_LT(s.i_hi_A, s.i_max_A);
        EXPECT_LT(s.i_hi_A + s.hf_di_A, s.i_max_A);
        EXPECT_GT(s.i_lo_A - s.hf_di_A, 0.0f); // no current reverses
        EXPECT_GE(s.w_min_s, 1.5f * s.dead_time_s);
    }
    // a plate that says "huge Tr" (a tiny slip): the stages stay capped
    const Motor m = identrig::motors()[4];
    identrig::Options o;
    ident_cfg c = identrig::ident_cfg_for(m, o);
    c.plate.speed_rpm = 1799.0f;
    ASSERT_EQ(ident_cfg_derive(&c), IDENT_OK);
    EXPECT_LE(ident_ss_ticks(&c.ss) * 200e-6, 30.0);
}

// The plate's estimates of the table's motors against their circuits: they
// size the run, so a factor of two either way would still work.
TEST(IdentPlate, EstimatesOfTheTablesMotorsAreWithinAFactorOfOnePointSix)
{
    for (const Motor &m : identrig::motors()) {
        SCOPED_TRACE(m.name);
        ident_plate p = identrig::plate_for_ident(m);
        ASSERT_EQ(ident_plate_check(&p), IDENT_PLATE_OK);
        ident_plate_est e;
        ident_plate_estimate(&p, &e);
        identrig::Truth t = identrig::truth_of(m);
        EXPECT_EQ(e.pole_pairs, 2.0f);
        // the no-load current at rated voltage (phasors), peak
        std::complex<double> z(m.rs, identrig::kW60 * (m.lls + m.lm));
        double i0 = std::sqrt(2.0) * m.v_ll / std::sqrt(3.0) / std::abs(z);
        for (double ratio : {e.tr_s / t.tr, e.i_mag_A / i0, e.sigma_ls_H / t.sigma_ls}) {
            EXPECT_GT(ratio, 1.0 / 1.6);
            EXPECT_LT(ratio, 1.6);
        }
        EXPECT_NEAR(e.te_Nm, m.p_W / e.w_m_rad_s, 1e-3 * e.te_Nm);
        EXPECT_NEAR(e.psi_s_Wb, std::sqrt(2.0 / 3.0) * m.v_ll / identrig::kW60, 1e-3);
    }
}

} // namespace
