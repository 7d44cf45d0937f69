// Rs identified while magnetising (dtc/rs_ident.h) against an independent
// machine: the induction machine at standstill from its flux and voltage
// equations, discretised exactly (tests/common/im_ref.hpp), fed with a
// switched voltage like the DTC's while it builds the flux.
#include <gtest/gtest.h>

#include <cmath>

#include "dtc/ctl.h"
#include "dtc/rs_ident.h"
#include "im_ref.hpp"

namespace {

constexpr double kT = 200e-6;

struct Ident {
    real_t result_ohm;
    double rs_true_ohm;
};

// 0.3 s of magnetising: the voltage vector (60 V along 20 deg) switched on for
// a duty that falls as the current rises (a hysteresis-like pattern), rotor
// at omega_e; the identification sees the applied voltage of each period and
// the current sampled at its start.
Ident magnetise(double rs_true, double omega_e, double tol, double v_amp = 60.0)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    rs_ident_cfg rc;
    rs_ident_cfg_derive(&rc, &c.motor, (real_t)kT, (real_t)tol);
    rs_ident s;
    rs_ident_reset(&s);

    imref::Params m;
    m.Rs = rs_true;
    imref::Mat4 A, Phi;
    imref::Mat42 B, Gam;
    imref::state_space(m, omega_e, A, B);
    imref::zoh(A, B, kT, Phi, Gam);
    imref::Vec4 x = imref::Vec4::Zero();
    const double ang = 20.0 * 3.14159265358979 / 180.0;
    for (int k = 0; k < 1500; ++k) {
        double i_mag = std::hypot(x[0], x[1]);
        bool on = (k % 4) < (i_mag < 15.0 ? 3 : 1);  // more volt-seconds while the current is low
        Eigen::Vector2d v(on ? v_amp * std::cos(ang) : 0.0, on ? v_amp * std::sin(ang) : 0.0);
        const real_t vv[2] = {(real_t)v[0], (real_t)v[1]};
        const real_t is[2] = {(real_t)x[0], (real_t)x[1]};
        rs_ident_step(&s, &rc, vv, is, (real_t)omega_e);
        x = Phi * x + Gam * v;
    }
    return {rs_ident_result(&s, &rc), rs_true};
}

}  // namespace

TEST(RsIdent, FindsAWarmAndAColdStatorWithinTwoPercent)
{
    for (double rs : {0.288 * 0.7, 0.288 * 1.3, 0.288 * 1.5}) {
        Ident r = magnetise(rs, 0.0, 0.0);  // tolerance 0: always the identified value
        EXPECT_NEAR(r.result_ohm, rs, 0.02 * rs) << "Rs " << rs;
    }
}

TEST(RsIdent, KeepsTheModelsRsExactlyWithinTheTolerance)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    Ident near = magnetise(0.288 * 1.05, 0.0, 0.1);
    EXPECT_EQ(near.result_ohm, c.motor.Rs_ohm);  // 5 % off: kept
    Ident warm = magnetise(0.288 * 1.3, 0.0, 0.1);
    EXPECT_NEAR(warm.result_ohm, 0.288 * 1.3, 0.02 * 0.288 * 1.3);  // 30 % off: replaced
    Ident never = magnetise(0.288 * 1.3, 0.0, 1.0);
    EXPECT_EQ(never.result_ohm, c.motor.Rs_ohm);  // tolerance 1: never replaced
}

TEST(RsIdent, ARotorThatTurnsOrNoCurrentKeepsTheModel)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    EXPECT_EQ(magnetise(0.288 * 1.3, 50.0, 0.0).result_ohm, c.motor.Rs_ohm);  // 8 Hz electrical
    EXPECT_EQ(magnetise(0.288 * 1.3, 0.0, 0.0, 0.0).result_ohm, c.motor.Rs_ohm);  // no voltage, no current
}

TEST(RsIdent, TooLittleChargeKeepsTheModel)
{
    // 0.2 V: about 0.5 A, 0.15 A s over the 0.3 s, below the 0.2 A s needed; the value found
    // is still credible (the test above finds Rs within 2 % with more current), so only the
    // charge check keeps the model's Rs here.
    ctl_cfg c;
    ctl_cfg_default(&c);
    EXPECT_EQ(magnetise(0.288 * 1.3, 0.0, 0.0, 0.2).result_ohm, c.motor.Rs_ohm);
}

TEST(RsIdent, ARotorJustUnderTheSpeedGateStillReadsRsWithinTwoPercent)
{
    Ident r = magnetise(0.288 * 1.3, 1.9, 0.0);  // 1.9 rad/s electrical, the gate is 2
    EXPECT_NEAR(r.result_ohm, 0.288 * 1.3, 0.02 * 0.288 * 1.3);
}
