// The SIL engine's plumbing through its library API: tick times, event
// quantisation, what reaches the firmware's configuration, the CAN backend,
// the NVM mirror, the per-tick hook and the stop request.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "dtc/drive.h"
#include "hal_host/hal_host.h"
#include "sim_test_util.hpp"

namespace {

struct TickLog {
    std::vector<double> t;
    int null_drive = 0;
};

void log_tick(void *user, double t_s, struct drive *d)
{
    auto *log = static_cast<TickLog *>(user);
    log->t.push_back(t_s);
    log->null_drive += d == nullptr;
}

// Column @p name of a CSV text, as numbers (empty cells skipped).
std::vector<double> csv_column(const std::string &text, const std::string &name)
{
    std::istringstream in(text);
    std::string line;
    std::getline(in, line);
    int col = -1, i = 0;
    std::istringstream h(line);
    for (std::string c; std::getline(h, c, ','); ++i)
        if (c == name)
            col = i;
    std::vector<double> v;
    while (col >= 0 && std::getline(in, line)) {
        std::istringstream r(line);
        std::string c;
        for (int j = 0; j <= col; ++j)
            std::getline(r, c, ',');
        if (!c.empty())
            v.push_back(std::stod(c));
    }
    return v;
}

} // namespace

TEST(SimEngine, TicksAtWholePeriodsAndNoFirmwareInSineMode)
{
    auto l = simtest::parse_text("[sim]\nduration_s = 0.01\nperiod_s = 250e-6\n[supply]\nmode = sine\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    TickLog log;
    sim_options o;
    sim_options_default(&o);
    o.on_tick = log_tick;
    o.user = &log;
    sim_result res;
    ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    ASSERT_EQ(log.t.size(), 41u); // k = 0 .. 40
    EXPECT_EQ(res.ticks, 41u);
    for (size_t k = 0; k < log.t.size(); ++k)
        EXPECT_NEAR(log.t[k], k * 250e-6, 1e-12);
    EXPECT_EQ(log.null_drive, 41);
    EXPECT_FALSE(res.metrics.firmware);
    EXPECT_NEAR(res.metrics.sim_seconds, 0.01, 1e-12);
}

TEST(SimEngine, EventsActFromTheFirstTickAtOrAfterTheirTime)
{
    simtest::TempDir d;
    auto l = simtest::parse_text("[sim]\nduration_s = 0.002\ntrace_interval_s = 200e-6\n[supply]\nmode = sine\n"
                                 "[load]\nstep = 0.00031 5\nstep = 0.0008 7\n"
                                 "[reference]\nstep = 0.0005 100\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    sim_options o;
    sim_options_default(&o);
    std::string csv = d.file("t.csv");
    o.csv_path = csv.c_str();
    sim_result res;
    ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    std::string text = simtest::read_file(csv);
    auto t = csv_column(text, "t_s");
    auto load = csv_column(text, "t_load_nm");
    auto ref = csv_column(text, "ref_cmd_rpm");
    ASSERT_EQ(t.size(), 11u);
    ASSERT_EQ(load.size(), 11u);
    // Ticks at 0, 0.2, 0.4, ... ms: the 0.31 ms step acts from 0.4 ms, the 0.8 ms one at 0.8 ms.
    const double want_load[11] = { 0, 0, 5, 5, 7, 7, 7, 7, 7, 7, 7 };
    const double want_ref[11] = { 0, 0, 0, 100, 100, 100, 100, 100, 100, 100, 100 };
    for (int k = 0; k < 11; ++k) {
        EXPECT_NEAR(t[k], k * 200e-6, 1e-9);
        EXPECT_DOUBLE_EQ(load[k], want_load[k]) << "tick " << k;
        EXPECT_DOUBLE_EQ(ref[k], want_ref[k]) << "tick " << k;
    }
}

namespace {

struct CfgSeen {
    bool seen = false;
    ctl_cfg cfg;
    uint32_t first_tick = 0, last_tick = 0;
    int calls = 0;
};

void grab_cfg(void *user, double, struct drive *d)
{
    auto *c = static_cast<CfgSeen *>(user);
    if (d == nullptr)
        return;
    if (!c->seen)
        c->cfg = *drive_cfg(d);
    drive_snapshot s;
    drive_read_snapshot(d, &s);
    if (!c->seen)
        c->first_tick = s.tick;
    c->last_tick = s.tick;
    c->seen = true;
    ++c->calls;
}

} // namespace

TEST(SimEngine, ScenarioReachesTheFirmwareConfiguration)
{
    auto l = simtest::parse_text("[sim]\nduration_s = 0.01\nperiod_s = 100e-6\n[motor]\nRs_ohm = 0.31\nRr_ohm = 0.17\n"
                                 "Lls_H = 0.002\nLlr_H = 0.003\nLm_H = 0.05\nJ_kgm2 = 0.06\nB_Nms = 0.004\n"
                                 "[drive]\nvdc_V = 320\n[controller]\nname = nominal\n"
                                 "[control]\npsi_ref_Wb = 0.42\nip_zeta = 0.9\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    CfgSeen seen;
    sim_options o;
    sim_options_default(&o);
    o.on_tick = grab_cfg;
    o.user = &seen;
    o.controller = SCENARIO_CTL_IP; // the command line wins over [controller]
    sim_result res;
    ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    ASSERT_TRUE(seen.seen);
    const ctl_cfg &c = seen.cfg;
    EXPECT_FLOAT_EQ(c.motor.Rs_ohm, 0.31f);
    EXPECT_FLOAT_EQ(c.motor.Rr_ohm, 0.17f);
    EXPECT_FLOAT_EQ(c.motor.Ls_H, 0.052f); // Lls + Lm
    EXPECT_FLOAT_EQ(c.motor.Lr_H, 0.053f); // Llr + Lm
    EXPECT_FLOAT_EQ(c.motor.Lm_H, 0.05f);
    EXPECT_FLOAT_EQ(c.motor.pole_pairs, 2.0f);
    EXPECT_FLOAT_EQ(c.motor.J_kgm2, 0.06f);
    EXPECT_FLOAT_EQ(c.motor.B_Nms, 0.004f);
    EXPECT_FLOAT_EQ(c.period_s, 100e-6f);
    EXPECT_FLOAT_EQ(c.vdc_nom_V, 320.0f);
    EXPECT_EQ(c.speed.mode, SPEED_MODE_IP);
    EXPECT_FLOAT_EQ(c.dtc.psi_ref_Wb, 0.42f);
    EXPECT_FLOAT_EQ(c.speed.ip.zeta, 0.9f);
    // The interrupt ran once per tick, before the hook.
    EXPECT_EQ(seen.first_tick, 1u);
    EXPECT_EQ(seen.last_tick, (uint32_t)seen.calls);
    EXPECT_EQ(res.ticks, 101u);
    EXPECT_STREQ(res.metrics.controller, "ip");
    EXPECT_TRUE(res.metrics.firmware);
}

namespace {

struct Bus {
    hal_host_can_loopback *q = nullptr;
    int got = 0;
    bool opened = false;
    int nvm_rc = 1;
    uint8_t nvm_seen[4] = { 0, 0, 0, 0 };
};

// Background work a test might do each tick, on the engine's bound board.
void bus_tick(void *user, double t_s, struct drive *)
{
    auto *b = static_cast<Bus *>(user);
    if (!b->opened) {
        b->opened = hal_can_open(500000) == HAL_OK;
        hal_nvm_read(64, b->nvm_seen, sizeof b->nvm_seen);
        const uint8_t v[4] = { 0xDE, 0xAD, 0xBE, 0xEF };
        b->nvm_rc = hal_nvm_write(64, v, sizeof v);
    }
    hal_can_frame f;
    while (hal_can_recv(&f) == HAL_OK) {
        ++b->got;
        f.id = (uint16_t)(f.id + 1);
        f.data[7] = (uint8_t)std::lround(t_s * 1e4); // tick index at 100 us
        hal_can_send(&f);
    }
}

} // namespace

TEST(SimEngine, CanBackendAndNvmMirrorAreTheBoards)
{
    simtest::TempDir d;
    std::string nvm = d.file("nvm.bin");
    auto l = simtest::parse_text("[sim]\nduration_s = 0.001\nperiod_s = 100e-6\n[supply]\nmode = sine\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    auto q = std::make_unique<hal_host_can_loopback>();
    hal_host_can_backend be;
    hal_host_can_loopback_init(q.get(), &be);
    hal_can_frame f;
    std::memset(&f, 0, sizeof f);
    f.id = 0x601;
    f.dlc = 8;
    ASSERT_EQ(hal_host_can_loopback_inject(q.get(), &f), HAL_OK);

    Bus bus;
    bus.q = q.get();
    sim_options o;
    sim_options_default(&o);
    o.can = &be;
    o.nvm_path = nvm.c_str();
    o.on_tick = bus_tick;
    o.user = &bus;
    sim_result res;
    ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    EXPECT_TRUE(bus.opened);
    EXPECT_EQ(bus.got, 1);
    hal_can_frame g;
    ASSERT_EQ(hal_host_can_loopback_take(q.get(), &g), HAL_OK);
    EXPECT_EQ(g.id, 0x602);
    EXPECT_EQ(g.data[7], 0); // answered in the first tick's background
    EXPECT_EQ(hal_host_bound(), nullptr); // the engine unbinds its board

    // The write reached the mirror file; a second run boots from it.
    EXPECT_EQ(bus.nvm_rc, HAL_OK);
    EXPECT_EQ(bus.nvm_seen[0], 0xFF);
    std::string img = simtest::read_file(nvm);
    ASSERT_EQ(img.size(), 4096u);
    EXPECT_EQ((uint8_t)img[64], 0xDE);
    Bus again;
    hal_host_can_loopback_init(q.get(), &be);
    o.user = &again;
    ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    EXPECT_EQ(again.nvm_seen[0], 0xDE);
    EXPECT_EQ(again.nvm_seen[3], 0xEF);
}

namespace {

struct Stopper {
    volatile sig_atomic_t flag = 0;
    double at = 0.0;
};

void stop_at(void *user, double t_s, struct drive *)
{
    auto *s = static_cast<Stopper *>(user);
    if (t_s >= s->at)
        s->flag = 1;
}

} // namespace

TEST(SimEngine, StopRequestAbandonsBatchAndEndsRealtimeCleanly)
{
    simtest::TempDir d;
    auto l = simtest::parse_text("[sim]\nduration_s = 1\n[supply]\nmode = sine\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    std::string csv = d.file("s.csv"), json = d.file("s.json");
    Stopper st;
    st.at = 0.004;
    sim_options o;
    sim_options_default(&o);
    o.csv_path = csv.c_str();
    o.metrics_path = json.c_str();
    o.on_tick = stop_at;
    o.user = &st;
    o.stop = &st.flag;
    sim_result res;
    EXPECT_EQ(sim_run(l.sc.get(), &o, &res), SIM_ERUNTIME);
    EXPECT_NE(std::string(res.error).find("interrupted"), std::string::npos) << res.error;
    EXPECT_FALSE(simtest::file_exists(csv));
    EXPECT_FALSE(simtest::file_exists(csv + ".partial"));
    EXPECT_FALSE(simtest::file_exists(json));

    st.flag = 0;
    o.realtime = true;
    o.run_forever = true;
    ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    EXPECT_TRUE(simtest::file_exists(csv));
    EXPECT_TRUE(simtest::file_exists(json));
    EXPECT_NEAR(res.metrics.sim_seconds, 0.004, 1e-9);
    // Paced: the wall clock cannot run behind the simulated time by more than a tick.
    EXPECT_GE(res.metrics.wall_seconds, res.metrics.sim_seconds - 200e-6);
}

TEST(SimEngine, BadOptionsAreInputErrors)
{
    auto l = simtest::parse_text("[sim]\nduration_s = 0.01\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    sim_options o;
    sim_options_default(&o);
    sim_result res;
    o.can_iface = "vcan0";
    EXPECT_EQ(sim_run(l.sc.get(), &o, &res), SIM_EINPUT);
    sim_options_default(&o);
    o.run_forever = true;
    EXPECT_EQ(sim_run(l.sc.get(), &o, &res), SIM_EINPUT);
    sim_options_default(&o);
    o.controller = 7;
    EXPECT_EQ(sim_run(l.sc.get(), &o, &res), SIM_EINPUT);
    sim_options_default(&o);
    o.metrics_path = "/nonexistent/dir/m.json";
    EXPECT_EQ(sim_run(l.sc.get(), &o, &res), SIM_EINPUT);
    EXPECT_NE(std::string(res.error).find("cannot create"), std::string::npos) << res.error;
}

// docs/faults.md: every fault the firmware knows can be injected from a
// scenario, and it latches exactly its own bit. The base run (300 rpm, no fault) ends with no fault.
TEST(SimEngine, EveryCatalogueFaultCanBeInjectedFromAScenario)
{
    const std::string base = "[sim]\nduration_s = 0.8\n[reference]\nramp = 0.2 0.4 300\n";
    struct Case {
        const char *extra;
        uint32_t bit;
    };
    const Case cases[] = {
        { "", 0u },
        { "[faults]\noffset = 0.6 a 120\n", CTL_FAULT_OVERCURRENT },
        { "[faults]\nvdc = 0.6 420\n", CTL_FAULT_DC_OVERVOLT },
        { "[faults]\nvdc = 0.6 150\n", CTL_FAULT_DC_UNDERVOLT },
        { "[faults]\noffset = 0.6 vc1 40\n", CTL_FAULT_NP_IMBALANCE },
        // The speed reference is limited below the trip level: an overhauling load exceeds it
        // (the stall check off: a braking command pinned at the limit trips it first).
        { "[control]\noverspeed_rad_s = 40\nte_max_Nm = 3\nstall_time_s = 0\n[load]\nstep = 0.45 -10\n",
          CTL_FAULT_OVERSPEED },
        { "[faults]\nstale = 0.6\n", CTL_FAULT_STALE_SAMPLE },
        { "[faults]\nhw = 0.6 on\n", CTL_FAULT_HW },
        { "[faults]\ninvalid = 0.6 b\n", CTL_FAULT_SAMPLE_INVALID },
        { "[faults]\noverrun = 0.6\n", CTL_FAULT_OVERRUN },
        { "[faults]\noffset = 0.6 a 10\n", CTL_FAULT_CURRENT_SENSOR },
        { "[faults]\nopen_phase = 0.6 a\n", CTL_FAULT_PHASE_LOSS },
        { "[faults]\ngain = 0 vc1 1.1\n", CTL_FAULT_DC_DIVIDER },
        // a load beyond the torque limit: the command pinned at the limit for stall_time_s
        { "[control]\nte_max_Nm = 3\nstall_time_s = 0.1\n[load]\nstep = 0.45 5\n", CTL_FAULT_STALL },
    };
    for (const Case &c : cases) {
        auto l = simtest::parse_text(base + c.extra);
        ASSERT_EQ(l.rc, 0) << l.error;
        sim_result res;
        ASSERT_EQ(sim_run(l.sc.get(), nullptr, &res), SIM_OK) << res.error;
        EXPECT_EQ(res.metrics.faults, c.bit) << c.extra;
        EXPECT_FALSE(res.metrics.runaway) << c.extra;
    }
}

// A sensor fault acts on the sample of the first tick at or after its time:
// a lost phase-a current sensor reads 0 A from then on (the firmware's
// telemetry sees it), and a restore brings the true reading back.
TEST(SimEngine, SensorFaultActsOnTheSampleAtItsTick)
{
    struct Seen {
        std::vector<double> t, ia;
    } seen;
    auto l = simtest::parse_text("[sim]\nduration_s = 0.5\n[reference]\nramp = 0.2 0.3 100\n"
                                 "[faults]\nlost = 0.40005 a\nrestore = 0.45 a\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    sim_options o;
    sim_options_default(&o);
    o.user = &seen;
    o.on_tick = [](void *user, double t_s, struct drive *d) {
        auto *s = static_cast<Seen *>(user);
        hal_sample smp;
        std::memcpy(&smp, &hal_host_bound()->sample, sizeof smp);
        (void)d;
        s->t.push_back(t_s);
        s->ia.push_back(smp.ia_A);
    };
    sim_result res;
    ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    int lost = 0, live_before = 0, live_after = 0;
    for (size_t k = 0; k < seen.t.size(); ++k) {
        double t = seen.t[k];
        if (t > 0.38 - 1e-9 && t < 0.4 - 1e-9)
            live_before += std::fabs(seen.ia[k]) > 0.2;
        else if (t >= 0.4002 - 1e-9 && t < 0.45 - 1e-9)
            lost += std::fabs(seen.ia[k]) < 0.05; // 0 A within one code (150 A / 2047)
        else if (t > 0.46 - 1e-9)
            live_after += std::fabs(seen.ia[k]) > 0.2;
    }
    // Magnetising current (about 11 A peak) flows: all but the samples next
    // to a slow zero crossing (3 Hz) read more than 0.2 A.
    EXPECT_GE(live_before, 80);  // of 100 ticks 0.38 .. 0.3998 s
    EXPECT_EQ(lost, 249);        // ticks 0.4002 .. 0.4498 s: every one reads 0 A
    EXPECT_GE(live_after, 150);  // of 200 ticks 0.46 .. 0.5 s
}

// Ramps and steps reach the plant at the tick: the value the plant holds at
// tick t is the hand-computed profile (linear interpolation inside a ramp) at
// t + 1 ns, the engine's tolerance for "the time has come" (as for the
// speed reference).
TEST(SimEngine, ParameterAndLoadRampsReachThePlantTickByTick)
{
    auto l = simtest::parse_text("[sim]\nduration_s = 0.05\n[supply]\nmode = sine\n"
                                 "[load]\nramp = 0.01 0.03 6\ncoulomb_Nm = 0.5\n"
                                 "[events]\nRs_ramp = 0.01 0.02 1.5\nLm_scale = 0.02 0.8\nRr_ramp = 0.03 0.04 2\n"
                                 "[faults]\nvdc = 0.025 250\ngain = 0.03 vc2 1.1\n");
    ASSERT_EQ(l.rc, 0) << l.error;
    struct Seen {
        std::vector<double> t, rs, rr, lm, tl, vdc, g2, coul;
    } seen;
    sim_options o;
    sim_options_default(&o);
    o.user = &seen;
    o.on_plant = [](void *user, double t_s, const plant_state *ps) {
        auto *s = static_cast<Seen *>(user);
        s->t.push_back(t_s);
        s->rs.push_back(ps->cfg.motor.Rs_ohm);
        s->rr.push_back(ps->cfg.motor.Rr_ohm);
        s->lm.push_back(ps->cfg.motor.Lm_H);
        s->tl.push_back(ps->t_load_Nm);
        s->vdc.push_back(ps->cfg.dc.vdc_V);
        s->g2.push_back(ps->cfg.sensor.v_gain[1]);
        s->coul.push_back(ps->cfg.load.coulomb_Nm);
    };
    sim_result res;
    ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    ASSERT_EQ(seen.t.size(), 251u);
    const double Rs0 = 0.288, Rr0 = 0.158, Lm0 = 0.0416;
    for (size_t k = 0; k < seen.t.size(); ++k) {
        double t = k * 200e-6 + 1e-9;
        double rs = t < 0.01 ? 1.0 : (t < 0.02 ? 1.0 + 0.5 * (t - 0.01) / 0.01 : 1.5);
        double rr = t < 0.03 ? 1.0 : (t < 0.04 ? 1.0 + (t - 0.03) / 0.01 : 2.0);
        double tl = t < 0.01 ? 0.0 : (t < 0.03 ? 6.0 * (t - 0.01) / 0.02 : 6.0);
        EXPECT_NEAR(seen.rs[k], Rs0 * rs, 1e-14) << "t = " << t;
        EXPECT_NEAR(seen.rr[k], Rr0 * rr, 1e-14) << "t = " << t;
        EXPECT_DOUBLE_EQ(seen.lm[k], t < 0.02 ? Lm0 : Lm0 * 0.8) << "t = " << t;
        EXPECT_NEAR(seen.tl[k], tl, 1e-12) << "t = " << t;
        EXPECT_DOUBLE_EQ(seen.vdc[k], t < 0.025 ? 311.0 : 250.0) << "t = " << t;
        EXPECT_DOUBLE_EQ(seen.g2[k], t < 0.03 ? 1.0 : 1.1) << "t = " << t;
        EXPECT_DOUBLE_EQ(seen.coul[k], 0.5);
    }
}
