// The identification run against the plant for every motor of the table
// (tests/common/ident_rig.hpp: the Krause, Wasynczuk and Sudhoff motors from
// 3 hp to 2250 hp and the 10 hp motor), with the real inverter (dead time,
// device drops) and the sensor chain (quantisation, noise, offsets) on:
// the tolerances and drive times of docs/commissioning.md ("Identification"),
// the current bound, and what ident_apply writes.
#include <gtest/gtest.h>

#include <cctype>
#include <cstring>

#include "ident_rig.hpp"

using namespace identrig;

namespace {

std::string motor_name(const testing::TestParamInfo<int> &info)
{
    std::string n = motors()[size_t(info.param)].name;
    std::string out;
    for (char c : n)
        if (std::isalnum(static_cast<unsigned char>(c)))
            out += c;
    return out;
}

class IdentMotor : public testing::TestWithParam<int> {};

// The values against the truth, in percent.
void expect_within(const char *what, double found, double truth, double tol_pct)
{
    EXPECT_LE(std::fabs(err_pct(found, truth)), tol_pct) << what << ": " << found << " against " << truth;
}

TEST_P(IdentMotor, StandstillAndRotatingWithinTheTolerancesAndTimes)
{
    const Motor m = motors()[size_t(GetParam())];
    auto r = run_ident(m);
    const Truth t = truth_of(m);
    const ident_result &x = r->res;
    ASSERT_EQ(r->start_rc, IDENT_OK);
    ASSERT_EQ(r->id.phase, IDENT_DONE) << "aborted: " << int(r->id.abort_reason);
    EXPECT_EQ(r->ctl_faults, 0u);
    expect_within("Rs", x.rs_ohm.value, t.rs, 3.0);
    expect_within("sigma Ls", x.sigma_ls_H.value, t.sigma_ls, 10.0);
    expect_within("Rr", x.rr_ohm.value, t.rr, 10.0);
    expect_within("Lm", x.lm_H.value, t.lm, 10.0);
    expect_within("J", x.j_kgm2.value, t.J, 10.0);
    EXPECT_TRUE(x.lm_from_rotation);
    for (const ident_value *v : {&x.rs_ohm, &x.sigma_ls_H, &x.rr_ohm, &x.lm_H, &x.ls_H, &x.j_kgm2})
        EXPECT_EQ(v->verdict, IDENT_VERDICT_OK);
    EXPECT_NE(x.b_Nms.verdict, IDENT_VERDICT_NONE); // measured, whatever its verdict
    // drive time of each part
    EXPECT_GT(r->t_standstill_s, 0.5);
    EXPECT_LE(r->t_standstill_s, 30.0);
    EXPECT_GT(r->t_rotating_s, 1.0);
    EXPECT_LE(r->t_rotating_s, 30.0);
    // the standstill part within its bound; the rotating part within the drive's trip
    EXPECT_LE(r->i_peak_standstill_A, r->ic.ss.i_max_A);
    EXPECT_LE(x.i_peak_A, r->ic.ss.i_max_A);
    EXPECT_LT(r->i_peak_rotating_A, r->orig.i_trip_A);
    // what ident_apply wrote: the model from the run, what depends on it derived again
    ASSERT_GE(r->apply_rc, 0);
    EXPECT_EQ(r->apply_rc & (IDENT_APPLIED_RS | IDENT_APPLIED_MAGNETICS | IDENT_APPLIED_J),
              IDENT_APPLIED_RS | IDENT_APPLIED_MAGNETICS | IDENT_APPLIED_J);
    EXPECT_EQ(r->fin.motor.Rs_ohm, x.rs_ohm.value);
    EXPECT_EQ(r->fin.motor.Lm_H, x.lm_H.value);
    EXPECT_EQ(r->fin.motor.Ls_H, x.ls_H.value);
    EXPECT_EQ(r->fin.motor.Rr_ohm, x.rr_ohm.value);
    EXPECT_EQ(r->fin.motor.J_kgm2, x.j_kgm2.value);
    EXPECT_EQ(ctl_cfg_check(&r->fin), CTL_CFG_OK);
    ctl_cfg again = r->fin;
    ctl_cfg_derive(&again);
    EXPECT_EQ(std::memcmp(&again, &r->fin, sizeof again), 0); // derived from the new model already
    EXPECT_NE(r->fin.obs.m.b, r->orig.obs.m.b);               // the observer's model moved with it
    EXPECT_NE(r->fin.speed.ip.kp, r->orig.speed.ip.kp);       // the speed loop's gains with J
}

TEST_P(IdentMotor, StandstillOnlyWithinTheTolerancesAndTime)
{
    const Motor m = motors()[size_t(GetParam())];
    Options o;
    o.rotating = false;
    auto r = run_ident(m, o);
    const Truth t = truth_of(m);
    const ident_result &x = r->res;
    ASSERT_EQ(r->id.phase, IDENT_DONE) << "aborted: " << int(r->id.abort_reason);
    expect_within("Rs", x.rs_ohm.value, t.rs, 3.0);
    expect_within("sigma Ls", x.sigma_ls_H.value, t.sigma_ls, 10.0);
    expect_within("Rr", x.rr_ohm.value, t.rr, 10.0);
    expect_within("Lm (standstill)", x.lm_H.value, t.lm, 25.0);
    EXPECT_FALSE(x.lm_from_rotation);
    EXPECT_EQ(x.j_kgm2.verdict, IDENT_VERDICT_NONE);
    EXPECT_LE(r->t_standstill_s, 30.0);
    EXPECT_EQ(r->t_rotating_s, 0.0);
    EXPECT_LE(r->i_peak_standstill_A, r->ic.ss.i_max_A);
    // the neutral point stays balanced (the small vectors' pair chosen by its sign; bursts in turn)
    EXPECT_LT(r->np_dev_standstill_V, 0.01 * m.vdc);
    // J and B stay the drive's own
    ASSERT_GE(r->apply_rc, 0);
    EXPECT_EQ(r->apply_rc, IDENT_APPLIED_RS | IDENT_APPLIED_MAGNETICS);
    EXPECT_EQ(r->fin.motor.J_kgm2, r->orig.motor.J_kgm2);
    EXPECT_EQ(r->fin.motor.B_Nms, r->orig.motor.B_Nms);
}

TEST_P(IdentMotor, EveryActuationIsAStandstillPatternWithoutAPNStep)
{
    const Motor m = motors()[size_t(GetParam())];
    Options o;
    o.rotating = false;
    uint8_t last = NPC_STATE_OOO;
    unsigned n = 0, pn = 0, foreign = 0;
    o.on_actuation = [&](const hal_actuation &a, ident_phase) {
        for (int k = 0; k < 2; ++k) {
            uint8_t st = npc_state_of(&a.vector[k]);
            // the zero vector and the small vectors along +alpha (POO, ONN) and -alpha (NOO, OPP)
            if (st != NPC_STATE_OOO && st != 22u && st != 9u && st != 4u && st != 17u)
                foreign++;
            if (npc_pn_step(last, st))
                pn++;
            last = st;
        }
        if (!(a.duty0 > 0.0f && a.duty0 <= 1.0f))
            foreign++;
        last = end_state_of(a);
        n++;
    };
    auto r = run_ident(m, o);
    ASSERT_EQ(r->id.phase, IDENT_DONE);
    EXPECT_GT(n, 1000u);
    EXPECT_EQ(pn, 0u);
    EXPECT_EQ(foreign, 0u);
}

INSTANTIATE_TEST_SUITE_P(Table, IdentMotor, testing::Values(0, 1, 2, 3, 4), motor_name);

// The inverter's errors the firmware compensates wrongly: the estimators do not rely on it.
TEST(IdentRobust, HalfOrOneAndAHalfTimesTheTrueCompensationStaysWithinTheTolerances)
{
    for (int which : {1, 4}) {
        for (double k : {0.0, 0.5, 1.5}) {
            const Motor m = motors()[size_t(which)];
            Options o;
            o.rotating = false;
            o.comp_scale = k;
            auto r = run_ident(m, o);
            const Truth t = truth_of(m);
            ASSERT_EQ(r->id.phase, IDENT_DONE) << m.name << " x" << k;
            SCOPED_TRACE(m.name + " compensation x" + std::to_string(k));
            expect_within("Rs", r->res.rs_ohm.value, t.rs, 3.0);
            expect_within("sigma Ls", r->res.sigma_ls_H.value, t.sigma_ls, 10.0);
            expect_within("Rr", r->res.rr_ohm.value, t.rr, 10.0);
        }
    }
}

TEST(IdentRobust, AnotherNoiseSeed)
{
    for (unsigned seed : {7u, 23u}) {
        const Motor m = motors()[0];
        Options o;
        o.rotating = false;
        o.seed = seed;
        auto r = run_ident(m, o);
        const Truth t = truth_of(m);
        ASSERT_EQ(r->id.phase, IDENT_DONE);
        expect_within("Rs", r->res.rs_ohm.value, t.rs, 3.0);
        expect_within("Rr", r->res.rr_ohm.value, t.rr, 10.0);
    }
}

TEST(IdentRobust, SensorNoiseIsNoTurningRotor)
{
    // the probe and the first bins of the DC part, 20 seeds x the five motors: no abort
    for (unsigned seed = 1u; seed <= 20u; ++seed)
        for (const Motor &m : motors()) {
            Options o;
            o.rotating = false;
            o.seed = seed;
            o.max_s = 0.25;
            auto r = run_ident(m, o);
            EXPECT_NE(r->id.phase, IDENT_ABORTED) << m.name << " seed " << seed << " abort " << int(r->id.abort_reason);
        }
}

// A saturating machine (Lm halves at 1.2 x the rated flux): the rotating part
// finds the magnetising inductance at the flux the drive runs with.
TEST(IdentSaturation, TheRotatingPartFindsTheSecantLmAtTheOperatingFlux)
{
    const Motor m = motors()[1];
    Options o;
    o.lm_sat_frac = 1.2;
    auto r = run_ident(m, o);
    ASSERT_EQ(r->id.phase, IDENT_DONE);
    ASSERT_TRUE(r->res.lm_from_rotation);
    EXPECT_GT(r->lm_secant_H, 0.0);
    EXPECT_LT(r->lm_secant_H, 0.9 * m.lm); // it does saturate there
    expect_within("Lm at the operating flux", r->res.lm_H.value, r->lm_secant_H, 2.0);
}

// ---------------------------------------------------------------- safety

// An abort leaves the drive's parameters as they were.
void expect_untouched(const Run &r)
{
    EXPECT_EQ(r.id.phase, IDENT_ABORTED);
    EXPECT_EQ(r.apply_rc, IDENT_E_PHASE);
    EXPECT_EQ(std::memcmp(&r.fin, &r.orig, sizeof r.fin), 0);
    EXPECT_EQ(r.last_mode, IDENT_OUT_OFF); // gates off
}

TEST(IdentAbort, ARunCommandDroppedAtStandstillWritesNothing)
{
    Options o;
    o.stop_at_s = 0.5; // magnetising
    auto r = run_ident(motors()[1], o);
    expect_untouched(*r);
    EXPECT_EQ(r->id.abort_reason, IDENT_ABORT_STOPPED);
    EXPECT_NEAR(r->t_end_s, 0.5, 1e-3); // in the very tick
}

TEST(IdentAbort, ARunCommandDroppedWhileTurningWritesNothing)
{
    Options o;
    o.stop_at_s = 4.0; // the rotating part (the standstill part takes 2.4 s)
    auto r = run_ident(motors()[1], o);
    ASSERT_GT(r->res.t_standstill_s, 0.0f); // the standstill results were in, and ran the trial
    EXPECT_NE(std::memcmp(&r->trial, &r->orig, sizeof r->trial), 0);
    expect_untouched(*r);
    EXPECT_EQ(r->id.abort_reason, IDENT_ABORT_STOPPED);
}

TEST(IdentAbort, AFaultOfTheDriveWritesNothing)
{
    for (double t : {1.0, 5.0}) {
        Options o;
        o.fault_at_s = t;
        auto r = run_ident(motors()[1], o);
        expect_untouched(*r);
        EXPECT_EQ(r->id.abort_reason, IDENT_ABORT_FAULT);
    }
}

TEST(IdentAbort, AShaftTurnedByTheLoadStopsTheStandstillPart)
{
    for (const Motor &m : motors())
        for (double w : {0.5, 2.0, 20.0, 100.0}) { // 5 to 950 rpm, demagnetised: the beta current gives it away
            Options o;
            o.turning_rad_s = w;
            auto r = run_ident(m, o);
            SCOPED_TRACE(m.name + " at " + std::to_string(w) + " rad/s");
            expect_untouched(*r);
            EXPECT_EQ(r->id.abort_reason, IDENT_ABORT_TURNING);
            EXPECT_LT(r->t_end_s, 1.0);
        }
}

TEST(IdentAbort, ALoadTheDriveCannotTurnTimesOut)
{
    Options o;
    o.inertia_x = 1e4; // the inertia test's torque accelerates it by 0.03 rad/s^2
    auto r = run_ident(motors()[1], o);
    expect_untouched(*r);
    EXPECT_EQ(r->id.abort_reason, IDENT_ABORT_TIMEOUT);
    EXPECT_EQ(r->res.rs_ohm.verdict, IDENT_VERDICT_OK); // the standstill part had no trouble with it
}

} // namespace
