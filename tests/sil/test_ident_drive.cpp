// The identification run through the drive (not the rig): the plant, the host
// board, drive_isr (ctl_ident_step in place of ctl_step while the run lasts)
// and drive_background (the fits, the results written to the active
// configuration). Judged against the plant's true values with the issue's
// standstill tolerances (Rs 3 %, sigma Ls and Rr 10 %, Lm 25 %); an abort by a
// fault or a turning shaft writes nothing, neither to the configuration in
// use nor to the stored set; a start is refused while the drive runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "dtc/param_table.h"
#include "dtc/drive.h"
#include "dtc/drive_ident.h"
#include "hal/hal.h"
#include "hal_host/hal_host.h"
#include "ident_rig.hpp"
#include "sim/sim.h"
#include "sim_test_util.hpp"

using namespace identrig;

namespace {

struct Bench {
    Motor m;
    Options o;
    plant_state ps;
    hal_host_board b;
    drive d;
    hal_actuation prev{};
    unsigned k = 0;
};

std::unique_ptr<Bench> make_bench(const Motor &m, const Options &o)
{
    auto p = std::make_unique<Bench>();
    Bench &x = *p;
    x.m = m;
    x.o = o;
    plant_config pc = plant_for(m, o);
    EXPECT_EQ(plant_init(&x.ps, &pc), 0);
    if (o.turning_rad_s != 0.0) {
        plant_set_inertia(&x.ps, m.J * 1e4); // the load keeps it turning: a flywheel
        x.ps.omega_m = o.turning_rad_s;
    }
    hal_host_board_init(&x.b);
    hal_host_bind(&x.b);
    drive_init(&x.d);
    // the drive's configuration before the run: the rig's first guess from the plate
    ident_cfg ic = ident_cfg_for(m, o);
    EXPECT_EQ(ident_cfg_derive(&ic), IDENT_OK);
    ctl_cfg *c = drive_cfg_edit(&x.d);
    const uint8_t level = c->bringup_level;
    *c = ctl_orig_for(m, ic, o);
    c->bringup_level = level; // the drive's normal run, not the rig's torque level
    EXPECT_EQ(ctl_cfg_check(c), CTL_CFG_OK);
    drive_cfg_commit(&x.d);
    ctl_init(&x.d.ctl, drive_cfg(&x.d));
    EXPECT_EQ(hal_tick_start(drive_isr, &x.d, 200u), HAL_OK);
    x.prev = zero_act();
    return p;
}

// One tick: the plant's sample, the interrupt, one background pass, the plant advanced.
void tick(Bench &x)
{
    plant_adc adc;
    plant_sample(&x.ps, &adc);
    double iu[3], vu[2];
    plant_adc_to_units(&x.ps.cfg, &adc, iu, vu);
    hal_sample s{float(iu[0]), float(iu[1]), float(iu[2]), float(vu[0]), float(vu[1]), 0.0f, true, x.k + 1u};
    hal_host_set_sample(&x.b, &s);
    x.b.t_s = x.k * kT;
    hal_host_run_tick(&x.b);
    drive_background(&x.d);
    hal_actuation act;
    bool gates = false;
    hal_host_take_actuation(&x.b, &act, &gates);
    const uint8_t off[3] = {PLANT_LEG_OFF, PLANT_LEG_OFF, PLANT_LEG_OFF};
    if (gates)
        plant_advance(&x.ps, x.prev.vector[0].leg, x.prev.vector[1].leg, double(x.prev.duty0), kT);
    else
        plant_advance(&x.ps, off, off, 1.0, kT);
    x.prev = act;
    x.k++;
}

// Ticks until the run has ended (or @p max_s), calling @p at each tick with its time.
template <class F> void run_until_ended(Bench &x, double max_s, F at)
{
    for (unsigned n = 0; n < unsigned(max_s / kT); ++n) {
        at(x.k * kT);
        tick(x);
        if (!drive_ident_running(&x.d))
            return;
    }
}

void expect_within(double found, double truth, double tol_pct, const char *what)
{
    EXPECT_LE(std::fabs(err_pct(found, truth)), tol_pct) << what << ": " << found << " against " << truth;
}

bool same_motor(const motor_model &a, const motor_model &b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The configuration's bytes (padding included: a struct copy need not copy it).
std::vector<uint8_t> bytes_of(const ctl_cfg *c)
{
    const uint8_t *p = reinterpret_cast<const uint8_t *>(c);
    return std::vector<uint8_t>(p, p + sizeof *c);
}

int save(drive &d)
{
    std::vector<uint8_t> work(PERSIST_HEADER_SIZE + CO_PERSIST_BYTES);
    return persist_save(&d.persist, PERSIST_SAVE_VALUES, work.data(), work.size());
}

class IdentDrive : public testing::TestWithParam<int> {};

TEST_P(IdentDrive, StandstillThroughTheDriveWithinTheTolerancesAndWritten)
{
    const Motor m = motors()[size_t(GetParam())];
    Options o;
    o.rotating = false;
    auto x = make_bench(m, o);
    for (int i = 0; i < 10; ++i)
        tick(*x); // the snapshot has the link's voltage
    const motor_model before = drive_cfg(&x->d)->motor;
    ident_plate pl = plate_for_ident(m);
    ASSERT_EQ(drive_ident_start(&x->d, &pl, false), 0);
    EXPECT_TRUE(drive_ident_running(&x->d));
    uint32_t last_progress = 0;
    bool progress_monotonic = true;
    run_until_ended(*x, 40.0, [&](double) {
        uint32_t p = drive_ident_progress(&x->d);
        progress_monotonic = progress_monotonic && p >= last_progress && p <= 100u;
        last_progress = p;
    });
    ASSERT_FALSE(drive_ident_running(&x->d));
    ASSERT_EQ(x->d.ident_outcome, DRIVE_IDENT_DONE) << "abort reason " << int(x->d.ident.abort_reason);
    EXPECT_TRUE(progress_monotonic);
    EXPECT_EQ(drive_ident_progress(&x->d), 100u);
    EXPECT_LE(x->d.ident_res.t_standstill_s, 30.0);
    EXPECT_EQ(x->d.ctl.faults, 0u);

    const Truth t = truth_of(m);
    const ident_result &r = x->d.ident_res;
    std::printf("%s through the drive: Rs %+.2f %%, sigma Ls %+.2f %%, Rr %+.2f %%, Lm %+.2f %%, %.1f s\n",
                m.name.c_str(), err_pct(r.rs_ohm.value, t.rs), err_pct(r.sigma_ls_H.value, t.sigma_ls),
                err_pct(r.rr_ohm.value, t.rr), err_pct(r.lm_H.value, t.lm), double(r.t_standstill_s));
    expect_within(r.rs_ohm.value, t.rs, 3.0, "Rs");
    expect_within(r.sigma_ls_H.value, t.sigma_ls, 10.0, "sigma Ls");
    expect_within(r.rr_ohm.value, t.rr, 10.0, "Rr");
    expect_within(r.lm_H.value, t.lm, 25.0, "Lm");

    // written to the configuration in use: Rs and the magnetics
    EXPECT_TRUE((x->d.ident_applied & IDENT_APPLIED_RS) != 0u);
    EXPECT_TRUE((x->d.ident_applied & IDENT_APPLIED_MAGNETICS) != 0u);
    const motor_model &a = drive_cfg(&x->d)->motor;
    EXPECT_FALSE(same_motor(a, before));
    expect_within(a.Rs_ohm, t.rs, 3.0, "applied Rs");
    expect_within(a.Rr_ohm, t.rr, 10.0, "applied Rr");
    expect_within(a.Lm_H, t.lm, 25.0, "applied Lm");
    expect_within(double(a.Ls_H) - double(a.Lm_H) * a.Lm_H / a.Lr_H, t.sigma_ls, 10.0, "applied sigma Ls");
    EXPECT_FLOAT_EQ(a.J_kgm2, before.J_kgm2); // the standstill part leaves the mechanics
}

// The 10 hp motor and the Krause table's 50 hp 460 V one (650 V link).
INSTANTIATE_TEST_SUITE_P(Motors, IdentDrive, testing::Values(1, 2),
                         [](const testing::TestParamInfo<int> &i) { return i.param == 1 ? "m10hp" : "m50hp"; });

// A run started without a plate (the CAN object 0x2800:1 does this) sizes itself with the
// plate of the motor the drive is configured for (ctl_cfg.plate): the 50 hp 460 V one here,
// not the 10 hp reference; it ends within the same tolerances.
TEST(IdentDriveCan, WithoutAPlateTheRunTakesTheConfiguredRatings)
{
    const Motor m = motors()[2];
    Options o;
    o.rotating = false;
    auto x = make_bench(m, o);
    const ident_plate pl = plate_for_ident(m);
    ctl_cfg *c = drive_cfg_edit(&x->d);
    c->plate.P_W = pl.p_W;
    c->plate.V_ll_V = pl.v_ll_V;
    c->plate.I_A = pl.i_A;
    c->plate.f_Hz = pl.f_Hz;
    c->plate.n_rpm = pl.speed_rpm;
    c->plate.cos_phi = pl.cos_phi;
    c->plate.vdc_nom_V = float(m.vdc);
    drive_cfg_commit(&x->d);
    for (int i = 0; i < 10; ++i)
        tick(*x);
    ASSERT_EQ(drive_ident_start(&x->d, nullptr, false), 0);
    EXPECT_EQ(std::memcmp(&x->d.ident_cfg.plate, &pl, sizeof pl), 0);
    run_until_ended(*x, 40.0, [](double) {});
    ASSERT_EQ(x->d.ident_outcome, DRIVE_IDENT_DONE) << "abort reason " << int(x->d.ident.abort_reason);
    const Truth t = truth_of(m);
    expect_within(x->d.ident_res.rs_ohm.value, t.rs, 3.0, "Rs");
    expect_within(x->d.ident_res.rr_ohm.value, t.rr, 10.0, "Rr");
}

TEST(IdentDriveAbort, AFaultMidRunLeavesTheConfigurationAndTheStoredSetUnchanged)
{
    const Motor m = motors()[1];
    Options o;
    o.rotating = false;
    auto x = make_bench(m, o);
    for (int i = 0; i < 10; ++i)
        tick(*x);
    ASSERT_EQ(save(x->d), HAL_OK); // a stored set to keep
    std::vector<uint8_t> nvm(x->b.nvm, x->b.nvm + sizeof x->b.nvm);
    const std::vector<uint8_t> before = bytes_of(drive_cfg(&x->d));
    ident_plate pl = plate_for_ident(m);
    ASSERT_EQ(drive_ident_start(&x->d, &pl, false), 0);
    ident_phase at_fault = IDENT_IDLE;
    run_until_ended(*x, 40.0, [&](double t) {
        if (t >= 1.0 && !x->b.fault_input) {
            x->b.fault_input = true; // the hardware fault input, in the middle of the standstill part
            at_fault = x->d.ident.phase;
        }
    });
    EXPECT_GE(int(at_fault), int(IDENT_MAGNETISE));
    EXPECT_LE(int(at_fault), int(IDENT_ROTOR));
    ASSERT_FALSE(drive_ident_running(&x->d));
    EXPECT_EQ(x->d.ident_outcome, DRIVE_IDENT_ABORTED);
    EXPECT_EQ(x->d.ident.abort_reason, IDENT_ABORT_FAULT);
    EXPECT_TRUE((x->d.ctl.faults & CTL_FAULT_HW) != 0u);
    EXPECT_TRUE(bytes_of(drive_cfg(&x->d)) == before);
    EXPECT_TRUE(std::equal(nvm.begin(), nvm.end(), x->b.nvm));
    bool gates = true;
    hal_actuation act;
    hal_host_take_actuation(&x->b, &act, &gates);
    EXPECT_FALSE(gates);
}

TEST(IdentDriveAbort, AStopCommandMidRunWritesNothing)
{
    const Motor m = motors()[1];
    Options o;
    o.rotating = false;
    auto x = make_bench(m, o);
    for (int i = 0; i < 10; ++i)
        tick(*x);
    const std::vector<uint8_t> before = bytes_of(drive_cfg(&x->d));
    ident_plate pl = plate_for_ident(m);
    ASSERT_EQ(drive_ident_start(&x->d, &pl, false), 0);
    run_until_ended(*x, 40.0, [&](double t) {
        if (t >= 1.0)
            drive_ident_stop(&x->d); // a CiA 402 disable, a quick stop, a lost master
    });
    EXPECT_EQ(x->d.ident_outcome, DRIVE_IDENT_ABORTED);
    EXPECT_EQ(x->d.ident.abort_reason, IDENT_ABORT_STOPPED);
    EXPECT_LT(x->k * kT, 1.1);
    EXPECT_TRUE(bytes_of(drive_cfg(&x->d)) == before);
}

TEST(IdentDriveRefused, WhileTheShaftTurnsTheRunEndsAtItsProbeAndWritesNothing)
{
    const Motor m = motors()[1];
    Options o;
    o.rotating = false;
    o.turning_rad_s = 0.3 * 2.0 * kPi * 1743.0 / 60.0; // 30 % of the rated speed, driven by the load
    auto x = make_bench(m, o);
    for (int i = 0; i < 10; ++i)
        tick(*x);
    const std::vector<uint8_t> before = bytes_of(drive_cfg(&x->d));
    ident_plate pl = plate_for_ident(m);
    ASSERT_EQ(drive_ident_start(&x->d, &pl, false), 0); // the drive never ran: no estimate yet
    run_until_ended(*x, 40.0, [](double) {});
    EXPECT_EQ(x->d.ident_outcome, DRIVE_IDENT_ABORTED);
    EXPECT_EQ(x->d.ident.abort_reason, IDENT_ABORT_TURNING);
    EXPECT_LT(x->k * kT, 1.0);
    EXPECT_TRUE(bytes_of(drive_cfg(&x->d)) == before);
}

TEST(IdentDriveRefused, WhileTheDriveRunsOrWithTheRotatingPart)
{
    const Motor m = motors()[1];
    Options o;
    auto x = make_bench(m, o);
    for (int i = 0; i < 10; ++i)
        tick(*x);
    ident_plate pl = plate_for_ident(m);
    EXPECT_EQ(drive_ident_start(&x->d, &pl, true), DRIVE_IDENT_E_ROTATING);
    drive_set_run(&x->d, true);
    for (int i = 0; i < 100; ++i)
        tick(*x);
    EXPECT_EQ(drive_ident_start(&x->d, &pl, false), IDENT_E_NOT_STOPPED);
    EXPECT_FALSE(drive_ident_running(&x->d));
    EXPECT_EQ(x->d.ident_outcome, DRIVE_IDENT_REFUSED);
    ident_plate bad = pl;
    bad.speed_rpm = 3600.0f; // at the synchronous speed of a 2-pole motor: no pole count fits
    drive_set_run(&x->d, false);
    for (int i = 0; i < 10; ++i)
        tick(*x);
    EXPECT_EQ(drive_ident_start(&x->d, &bad, false), IDENT_E_PLATE);
}

} // namespace

// [commission] identify = standstill: the run on the scenario's plant before the profile,
// through the SIL engine; the profile then runs on the identified model.
namespace {

struct SeenCfg {
    bool seen = false;
    ctl_cfg cfg;
    uint8_t outcome = 0, applied = 0;
    ident_result res;
    uint32_t faults = 0;
};

void grab(void *user, double, drive *d)
{
    auto *s = static_cast<SeenCfg *>(user);
    if (d == nullptr)
        return;
    if (!s->seen) {
        s->cfg = *drive_cfg(d);
        s->outcome = d->ident_outcome;
        s->applied = d->ident_applied;
        s->res = d->ident_res;
        s->seen = true;
    }
    s->faults |= d->out.tel.faults;
}

} // namespace

TEST(IdentScenario, StandstillBeforeTheProfileWritesTheIdentifiedModelAndTheProfileHolds)
{
    // the 10 hp plant with the real inverter and sensor defaults, CASE1's reference
    auto l = simtest::parse_text("[sim]\nduration_s = 2.5\n[commission]\nidentify = standstill\n"
                                 "[reference]\nramp = 0.3 1.3 500\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    SeenCfg seen;
    sim_options o;
    sim_options_default(&o);
    o.on_tick = grab;
    o.user = &seen;
    sim_result res;
    ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    ASSERT_TRUE(seen.seen);
    EXPECT_EQ(seen.outcome, DRIVE_IDENT_DONE);
    EXPECT_EQ(seen.applied & (IDENT_APPLIED_RS | IDENT_APPLIED_MAGNETICS), IDENT_APPLIED_RS | IDENT_APPLIED_MAGNETICS);
    const plant_motor_params &pm = l.sc->plant.motor;
    const double ls = pm.Lls_H + pm.Lm_H, lr = pm.Llr_H + pm.Lm_H;
    const motor_model &a = seen.cfg.motor;
    EXPECT_FLOAT_EQ(a.Rs_ohm, seen.res.rs_ohm.value); // the identified value, not the scenario's
    expect_within(a.Rs_ohm, pm.Rs_ohm, 3.0, "Rs");
    expect_within(a.Rr_ohm, pm.Rr_ohm, 10.0, "Rr");
    expect_within(a.Lm_H, pm.Lm_H, 25.0, "Lm");
    expect_within(double(a.Ls_H) - double(a.Lm_H) * a.Lm_H / a.Lr_H, ls - pm.Lm_H * pm.Lm_H / lr, 10.0, "sigma Ls");
    EXPECT_EQ(seen.faults, 0u);
    EXPECT_NEAR(res.metrics.speed_final_rpm, 500.0, 5.0);
}

TEST(IdentScenario, FullIsRefusedWithTheKeysLine)
{
    auto l = simtest::parse_text("[sim]\nduration_s = 0.1\n\n[commission]\nidentify = full\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    sim_options o;
    sim_options_default(&o);
    sim_result res;
    EXPECT_EQ(sim_run(l.sc.get(), &o, &res), SIM_EINPUT);
    EXPECT_NE(std::string(res.error).find(":5: [commission] identify = full"), std::string::npos) << res.error;
}
