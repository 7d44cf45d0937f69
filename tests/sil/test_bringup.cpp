// Bring-up levels (dtc/bringup.h, docs/bringup.md) on the plant, each judged
// from what the plant sees: the gate-test patterns reach the legs and never
// step P<->N, level 2 never enables the gates, V/f turns the motor at the
// commanded frequency less the slip (closed form: synchronous speed f/pp),
// level 4's observer follows the true speed, level 5 produces the commanded
// torque (the observer's torque against the plant's true torque).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

extern "C" {
#include "dtc/ctl.h"
#include "dtc/drive.h"
#include "sim/sim.h"
}
#include "sim_test_util.hpp"

namespace {

constexpr double kRpmPerRadS = 60.0 / (2.0 * M_PI);

struct Seen {
    std::vector<double> t, true_rpm, est_rpm, te_est;
    std::vector<hal_vector> v0, v1;
    bool gates_ever = false;
    uint32_t faults = 0;
};

Seen run(const std::string &control, double duration_s, const std::string &extra = "")
{
    auto l = simtest::parse_text("[sim]\nduration_s = " + std::to_string(duration_s) +
                                 "\n[reference]\nstep = 0 0\n[control]\n" + control + extra);
    EXPECT_EQ(l.rc, 0) << l.error;
    Seen s;
    sim_options o;
    sim_options_default(&o);
    o.user = &s;
    o.on_tick = [](void *user, double t_s, struct drive *d) {
        auto *x = static_cast<Seen *>(user);
        x->t.push_back(t_s);
        x->true_rpm.push_back(d->snap.omega_meas_rad_s * kRpmPerRadS);
        x->est_rpm.push_back(d->snap.tel.omega_est_rad_s * kRpmPerRadS);
        x->te_est.push_back(d->snap.tel.te_est_Nm);
        x->v0.push_back(d->out.act.vector[0]);
        x->v1.push_back(d->out.act.vector[1]);
        x->gates_ever = x->gates_ever || d->out.gate_enable;
        x->faults |= d->snap.tel.faults;
    };
    sim_result res;
    EXPECT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
    return s;
}

double mean_after(const std::vector<double> &t, const std::vector<double> &x, double t0)
{
    double sum = 0;
    int n = 0;
    for (size_t i = 0; i < t.size(); i++)
        if (t[i] >= t0) {
            sum += x[i];
            n++;
        }
    return n ? sum / n : NAN;
}

} // namespace

TEST(Bringup, Level1GatePatternsWithoutPnSteps)
{
    // As on the bench: a low-voltage supply (20 V) instead of the DC link.
    Seen s = run("bringup_level = 1\n", 6.2, "[drive]\nvdc_V = 20\n");
    EXPECT_EQ(s.faults, 0u);
    EXPECT_TRUE(s.gates_ever);
    // Every leg reaches P and N (in its own step of the 6 s cycle), and no leg
    // ever steps P<->N between two consecutive applied vectors.
    bool seen_p[3] = {}, seen_n[3] = {};
    for (size_t i = 0; i < s.v0.size(); i++)
        for (int k = 0; k < 3; k++) {
            seen_p[k] = seen_p[k] || s.v0[i].leg[k] == HAL_LEG_P;
            seen_n[k] = seen_n[k] || s.v0[i].leg[k] == HAL_LEG_N;
            if (i > 0) {
                int a = s.v1[i - 1].leg[k], b = s.v0[i].leg[k];
                EXPECT_FALSE((a == HAL_LEG_P && b == HAL_LEG_N) || (a == HAL_LEG_N && b == HAL_LEG_P)) << i;
            }
        }
    for (int k = 0; k < 3; k++)
        EXPECT_TRUE(seen_p[k] && seen_n[k]) << "leg " << k;
}

TEST(Bringup, Level2NeverEnablesTheGates)
{
    Seen s = run("bringup_level = 2\n", 0.5);
    EXPECT_FALSE(s.gates_ever);
    EXPECT_EQ(s.faults, 0u);
}

TEST(Bringup, Level3VfTurnsTheMotorAtTheCommandedFrequency)
{
    // 5 Hz on a 2-pole-pair motor, no load: synchronous speed 150 rpm; the
    // no-load slip of this motor is about 1 rpm (dol_start: 1798.9 of 1800).
    Seen s = run("bringup_level = 3\nbringup_hz = 5\n", 3.0);
    EXPECT_EQ(s.faults, 0u);
    EXPECT_NEAR(mean_after(s.t, s.true_rpm, 2.0), 150.0, 5.0);
    Seen r = run("bringup_level = 3\nbringup_hz = -5\n", 3.0);
    EXPECT_NEAR(mean_after(r.t, r.true_rpm, 2.0), -150.0, 5.0) << "the sign sets the direction";
}

TEST(Bringup, Level4ObserverFollowsTheVfSpeed)
{
    Seen s = run("bringup_level = 4\nbringup_hz = 10\n", 3.0);
    EXPECT_EQ(s.faults, 0u);
    double tr = mean_after(s.t, s.true_rpm, 2.0), est = mean_after(s.t, s.est_rpm, 2.0);
    EXPECT_NEAR(tr, 300.0, 10.0);
    EXPECT_NEAR(est, tr, 0.05 * tr) << "the observer check of level 4";
}

TEST(Bringup, Level5ProducesTheCommandedTorque)
{
    // A friction load holds the speed down (viscous 0.5 N m s/rad): the motor
    // settles where 10 N m balances it, about 20 rad/s = 191 rpm.
    Seen s = run("bringup_level = 5\nbringup_te_Nm = 10\n", 3.0, "[load]\nviscous_Nms = 0.5\n");
    EXPECT_EQ(s.faults, 0u);
    EXPECT_NEAR(mean_after(s.t, s.te_est, 2.0), 10.0, 1.0);
    EXPECT_NEAR(mean_after(s.t, s.true_rpm, 2.5), 10.0 / 0.5 * kRpmPerRadS, 20.0);
}
