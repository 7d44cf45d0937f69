// Steady state of an induction motor from its per-phase T-equivalent circuit,
// as an independent reference for tests (std::complex, no project code).
//
//   V_ph --Rs--jX_ls--+--jX_lr--Rr/s--+
//                     |               |
//                    jX_m             |
//                     +---------------+
//
// Per-phase rms phasors, V_ph = V_ll / sqrt(3). Electromagnetic torque from
// the air-gap power: Te = 3 |I_r|^2 (Rr / s) / omega_sync_mech, with
// omega_sync_mech = omega_e / p. The operating point solves
// Te(s) = T_load + B * omega_m(s) on the stable branch (0 < s < s_pullout).
#pragma once

#include <cmath>
#include <complex>

namespace tequiv {

struct Machine {
    double Rs, Rr;   // ohm
    double Lls, Llr; // H
    double Lm;       // H
    int p;           // pole pairs
    double B;        // viscous friction, N m s/rad
};

// Any struct with the plant's field names (plant_motor_params) converts.
template <class P>
Machine from_params(const P &m)
{
    return Machine{m.Rs_ohm, m.Rr_ohm, m.Lls_H, m.Llr_H, m.Lm_H, m.pole_pairs, m.B_Nms};
}

struct Point {
    double slip;          // per unit
    double omega_m_rad_s; // mechanical speed
    double speed_rpm;
    double is_rms_A;      // stator phase current, rms
    double ir_rms_A;      // rotor current (stator-referred), rms
    double te_Nm;         // electromagnetic torque
    double pf;            // power factor
    double psi_s_peak_Wb; // stator flux linkage, peak (= amplitude-invariant space vector)
};

inline Point at_slip(const Machine &m, double v_ll_rms, double f_hz, double s)
{
    using cd = std::complex<double>;
    const double pi = 3.14159265358979323846;
    const double we = 2.0 * pi * f_hz;
    const cd V(v_ll_rms / std::sqrt(3.0), 0.0);
    const cd Zs(m.Rs, we * m.Lls);
    const cd Zm(0.0, we * m.Lm);
    const cd Zr(m.Rr / s, we * m.Llr);
    const cd Zpar = Zm * Zr / (Zm + Zr);
    const cd Is = V / (Zs + Zpar);
    const cd Ir = Is * Zm / (Zm + Zr);
    const double w_sync_m = we / m.p;

    Point pt{};
    pt.slip = s;
    pt.omega_m_rad_s = (1.0 - s) * w_sync_m;
    pt.speed_rpm = pt.omega_m_rad_s * 60.0 / (2.0 * pi);
    pt.is_rms_A = std::abs(Is);
    pt.ir_rms_A = std::abs(Ir);
    pt.te_Nm = 3.0 * std::norm(Ir) * (m.Rr / s) / w_sync_m;
    pt.pf = std::cos(std::arg(V) - std::arg(Is));
    pt.psi_s_peak_Wb = std::sqrt(2.0) * std::abs(V - m.Rs * Is) / we;
    return pt;
}

// Slip of the largest torque (golden-section search on 0 < s < 1).
inline double pullout_slip(const Machine &m, double v_ll_rms, double f_hz)
{
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double a = 1e-6, b = 1.0;
    for (int i = 0; i < 200; ++i) {
        double c = b - g * (b - a), d = a + g * (b - a);
        if (at_slip(m, v_ll_rms, f_hz, c).te_Nm > at_slip(m, v_ll_rms, f_hz, d).te_Nm)
            b = d;
        else
            a = c;
    }
    return 0.5 * (a + b);
}

// Steady operating point with a constant load torque (bisection on slip).
// Returns slip = NaN when the load exceeds the pull-out torque.
inline Point solve(const Machine &m, double v_ll_rms, double f_hz, double t_load_Nm)
{
    auto f = [&](double s) {
        Point pt = at_slip(m, v_ll_rms, f_hz, s);
        return pt.te_Nm - t_load_Nm - m.B * pt.omega_m_rad_s;
    };
    double lo = 1e-12, hi = pullout_slip(m, v_ll_rms, f_hz);
    if (!(f(lo) < 0.0 && f(hi) > 0.0)) {
        Point bad{};
        bad.slip = std::nan("");
        return bad;
    }
    for (int i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        (f(mid) < 0.0 ? lo : hi) = mid;
    }
    return at_slip(m, v_ll_rms, f_hz, 0.5 * (lo + hi));
}

} // namespace tequiv
