// Induction-machine reference for tests: the continuous state-space model
// written from the flux-linkage and voltage equations (no project code), and
// its exact zero-order-hold discretisation with Eigen's matrix exponential.
//
// Stationary alpha-beta frame, amplitude-invariant Clarke, rotor referred to
// the stator, omega_e = p * omega_m:
//   psi_s = Ls is + Lm ir,   psi_r = Lm is + Lr ir
//   v     = Rs is + d psi_s/dt
//   0     = Rr ir + d psi_r/dt - J omega_e psi_r        (J = rotation by +90 deg)
//   Te    = 1.5 p (psi_s x is)
// State x = [is_alpha, is_beta, psi_r_alpha, psi_r_beta], input v = [v_alpha, v_beta].
#pragma once

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

namespace imref {

struct Params {
    double Rs = 0.288, Rr = 0.158;
    double Lls = 0.00142, Llr = 0.00142, Lm = 0.0416;
    int p = 2;
    double Ls() const { return Lls + Lm; }
    double Lr() const { return Llr + Lm; }
};

using Vec4 = Eigen::Matrix<double, 4, 1>;
using Mat4 = Eigen::Matrix<double, 4, 4>;
using Mat42 = Eigen::Matrix<double, 4, 2>;

// dx/dt from the machine equations.
inline Vec4 deriv(const Params &m, double omega_e, const Vec4 &x, const Eigen::Vector2d &v)
{
    Eigen::Vector2d is(x[0], x[1]), psr(x[2], x[3]);
    Eigen::Vector2d ir = (psr - m.Lm * is) / m.Lr();
    Eigen::Vector2d jpsr(-psr[1], psr[0]);
    Eigen::Vector2d dpsr = -m.Rr * ir + omega_e * jpsr;
    Eigen::Vector2d dpss = v - m.Rs * is;
    double sigma_ls = m.Ls() - m.Lm * m.Lm / m.Lr();
    Eigen::Vector2d dis = (dpss - (m.Lm / m.Lr()) * dpsr) / sigma_ls;
    Vec4 d;
    d << dis, dpsr;
    return d;
}

// A and B of dx/dt = A x + B v, column by column from deriv().
inline void state_space(const Params &m, double omega_e, Mat4 &A, Mat42 &B)
{
    for (int c = 0; c < 4; ++c)
        A.col(c) = deriv(m, omega_e, Vec4::Unit(c), Eigen::Vector2d::Zero());
    for (int c = 0; c < 2; ++c)
        B.col(c) = deriv(m, omega_e, Vec4::Zero(), Eigen::Vector2d::Unit(c));
}

// Exact ZOH step: x+ = Phi x + Gam v, from exp([[A, B], [0, 0]] T).
inline void zoh(const Mat4 &A, const Mat42 &B, double T, Mat4 &Phi, Mat42 &Gam)
{
    Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
    M.topLeftCorner<4, 4>() = A * T;
    M.topRightCorner<4, 2>() = B * T;
    Eigen::Matrix<double, 6, 6> E = M.exp();
    Phi = E.topLeftCorner<4, 4>();
    Gam = E.topRightCorner<4, 2>();
}

inline Eigen::Vector2d psi_s(const Params &m, const Vec4 &x)
{
    Eigen::Vector2d is(x[0], x[1]), psr(x[2], x[3]);
    double sigma_ls = m.Ls() - m.Lm * m.Lm / m.Lr();
    return sigma_ls * is + (m.Lm / m.Lr()) * psr;
}

inline double torque(const Params &m, const Vec4 &x)
{
    Eigen::Vector2d ps = psi_s(m, x);
    return 1.5 * m.p * (ps[0] * x[1] - ps[1] * x[0]);
}

// Clarke (amplitude invariant) of a phase triple.
inline Eigen::Vector2d clarke(const double a[3])
{
    return {(2.0 * a[0] - a[1] - a[2]) / 3.0, (a[1] - a[2]) / std::sqrt(3.0)};
}

} // namespace imref
