// The identification run against the plant (host_sim/plant), with the
// firmware's own parts: the identification module (dtc/ident.h) at
// standstill, ctl_step (bring-up level 5 torque control and level 6 speed
// control) under the rotating sequencer, as the drive will run them once the
// run state is part of ctl_step. Shared by the closed-loop tests
// (tests/sil/test_ident_*.cpp) and the table printer (dtc-ident-table).
//
// The motors: the Krause, Wasynczuk and Sudhoff table (Analysis of Electric
// Machinery and Drive Systems, induction machine parameters: 60 Hz, 4 poles,
// reactances at 60 Hz) and the project's 10 hp motor (docs/motor-10hp.json).
// Their plates (rated current, power factor, speed) are worked out here from
// the T-equivalent circuit at the rated power, as a manufacturer's test would
// state them. The plant runs with the real inverter (dead time, device drops)
// and the sensor chain (12-bit quantisation, noise, offsets) on.
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dtc/ctl.h"
#include "dead_time_leg_error.h"
#include "dtc/npc.h"
#include "dtc/ident.h"
#include "dtc/ident_apply.h"
#include "plant/plant.h"

namespace identrig {

constexpr double kPi = 3.14159265358979323846;
constexpr double kW60 = 2.0 * kPi * 60.0;
constexpr double kT = 200e-6;

struct Motor {
    std::string name;
    double rs, lls, lm, llr, rr; // ohm, H
    double J, B;                 // kg m^2, N m s/rad
    double v_ll, p_W;            // rated voltage (rms line), rated power
    double vdc;                  // DC link, V
    double dead_time_s, v_on_V;  // the power stage
    double i_fs_A, v_fs_V;       // sensor full scales
    double c_F, r_src_ohm;       // each DC-link capacitor, the source resistance
};

// Reactances at 60 Hz into inductances.
inline Motor krause(const std::string &name, double rs, double xls, double xm, double xlr, double rr, double J,
                    double v_ll, double hp)
{
    Motor m;
    m.name = name;
    m.rs = rs;
    m.lls = xls / kW60;
    m.lm = xm / kW60;
    m.llr = xlr / kW60;
    m.rr = rr;
    m.J = J;
    m.v_ll = v_ll;
    m.p_W = hp * 745.7;
    m.B = 0.0;
    return m;
}

// The plate of @p m: the T-equivalent circuit at rated voltage and 60 Hz, at
// the slip where the shaft power is the rated one (friction included).
struct Plate {
    double i_A, cos_phi, speed_rpm, slip, te_Nm;
};

inline Plate plate_of(const Motor &m)
{
    const double v = m.v_ll / std::sqrt(3.0);
    const double ws = kW60 / 2.0; // 4 poles
    auto point = [&](double s, double &p_mech, std::complex<double> &i) {
        std::complex<double> zr(m.rr / s, kW60 * m.llr), zm(0.0, kW60 * m.lm);
        std::complex<double> z = std::complex<double>(m.rs, kW60 * m.lls) + zm * zr / (zm + zr);
        i = v / z;
        std::complex<double> ir = i * zm / (zm + zr);
        double te = 3.0 * std::norm(ir) * m.rr / s / ws;
        double w = (1.0 - s) * ws;
        p_mech = (te - m.B * w) * w;
    };
    double lo = 1e-6, hi = 0.3;
    for (int it = 0; it < 200; ++it) {
        double s = 0.5 * (lo + hi), p;
        std::complex<double> i;
        point(s, p, i);
        (p > m.p_W ? hi : lo) = s;
    }
    Plate pl;
    double p;
    std::complex<double> i;
    point(0.5 * (lo + hi), p, i);
    pl.slip = 0.5 * (lo + hi);
    pl.i_A = std::abs(i);
    pl.cos_phi = std::cos(std::arg(i));
    pl.speed_rpm = std::round((1.0 - pl.slip) * 1800.0); // a plate states whole rpm
    pl.te_Nm = m.p_W / ((1.0 - pl.slip) * ws);
    return pl;
}

// Rated peak current and rated torque, from the plate.
inline double rated_peak_A(const Motor &m) { return std::sqrt(2.0) * plate_of(m).i_A; }

inline Motor with_drive(Motor m)
{
    const double ipk = rated_peak_A(m);
    if (m.v_ll > 1000.0) {
        // 2.3 kV motors: a 3.25 kV link, 3.3 kV IGBTs (3 V on-state per device, a 6 us
        // interlock: turn-off delay about 3.5 us plus fall and tail), 2 mF per capacitor
        m.vdc = 3250.0;
        m.dead_time_s = 6e-6;
        m.v_on_V = 3.0;
        m.v_fs_V = 2500.0;
        m.c_F = 2e-3;
        m.r_src_ohm = 0.2;
    } else {
        m.vdc = m.v_ll > 300.0 ? 650.0 : 311.0;
        m.dead_time_s = 2e-6;
        m.v_on_V = 1.0;
        m.v_fs_V = 500.0;
        m.c_F = 2.2e-3;
        m.r_src_ohm = 0.05;
    }
    // full scale: four times the rated peak, rounded up to 10 A
    m.i_fs_A = std::ceil(4.0 * ipk / 10.0) * 10.0;
    return m;
}

// Friction at the rated speed: @p frac of the rated torque (the table gives none).
inline Motor with_friction(Motor m, double frac)
{
    Plate pl = plate_of(m);
    double w = (1.0 - pl.slip) * kW60 / 2.0;
    m.B = frac * pl.te_Nm / w;
    return m;
}

inline std::vector<Motor> motors()
{
    std::vector<Motor> v;
    v.push_back(with_drive(with_friction(krause("3 hp 220 V", 0.435, 0.754, 26.13, 0.754, 0.816, 0.089, 220.0, 3.0), 0.01)));
    Motor m10;
    m10.name = "10 hp 220 V";
    m10.rs = 0.288;
    m10.lls = m10.llr = 0.00142;
    m10.lm = 0.0416;
    m10.rr = 0.158;
    m10.J = 0.045;
    m10.B = 0.005;
    m10.v_ll = 220.0;
    m10.p_W = 7457.0;
    v.push_back(with_drive(m10));
    v.push_back(with_drive(with_friction(krause("50 hp 460 V", 0.087, 0.302, 13.08, 0.302, 0.228, 1.662, 460.0, 50.0), 0.01)));
    v.push_back(with_drive(with_friction(krause("500 hp 2300 V", 0.262, 1.206, 54.02, 1.206, 0.187, 11.06, 2300.0, 500.0), 0.01)));
    v.push_back(with_drive(with_friction(krause("2250 hp 2300 V", 0.029, 0.226, 13.04, 0.226, 0.022, 63.87, 2300.0, 2250.0), 0.01)));
    return v;
}

// The true values the run is judged against.
struct Truth {
    double rs, sigma_ls, rr, lm, ls, tr, rr_ref, lm_ref, J, B;
};

inline Truth truth_of(const Motor &m)
{
    Truth t;
    double ls = m.lls + m.lm, lr = m.llr + m.lm;
    t.rs = m.rs;
    t.ls = ls;
    t.lm = m.lm;
    t.sigma_ls = ls - m.lm * m.lm / lr;
    t.rr = m.rr;
    t.tr = lr / m.rr;
    t.lm_ref = m.lm * m.lm / lr;
    t.rr_ref = m.rr * (m.lm / lr) * (m.lm / lr);
    t.J = m.J;
    t.B = m.B;
    return t;
}

struct Options {
    bool rotating = true;
    double comp_scale = 1.0;      // the firmware's dead-time and drop compensation, x the plant's
    double stop_at_s = -1.0;      // the run command drops at this time (a disable, a lost master)
    double fault_at_s = -1.0;     // the drive reports a fault at this time
    double turning_rad_s = 0.0;   // the shaft turns at this speed at the start (driven by the load)
    double inertia_x = 1.0;       // the load's inertia, x the motor's (a flywheel the drive cannot turn)
    double i_noise_frac = 1e-3;   // current noise rms, fraction of the full scale
    double v_noise_frac = 1e-3;   // voltage noise rms, fraction of the full scale
    double lm_sat_frac = 0.0;     // Lm saturation knee, x the rated flux (0: linear)
    bool ideal = false;           // the ideal inverter and sensors (for the estimators' own errors)
    unsigned seed = 1u;
    double max_s = 80.0;          // give up after this much simulated time
    // every actuation latched while the identification applies its own (not the drive's control)
    std::function<void(const hal_actuation &, ident_phase)> on_actuation;
};

inline ident_plate plate_for_ident(const Motor &m)
{
    Plate pl = plate_of(m);
    ident_plate p;
    p.p_W = float(m.p_W);
    p.v_ll_V = float(m.v_ll);
    p.i_A = float(pl.i_A);
    p.f_Hz = 60.0f;
    p.speed_rpm = float(pl.speed_rpm);
    p.cos_phi = float(pl.cos_phi);
    return p;
}

inline plant_config plant_for(const Motor &m, const Options &o)
{
    plant_config c;
    plant_default_config(&c);
    c.motor.Rs_ohm = m.rs;
    c.motor.Rr_ohm = m.rr;
    c.motor.Lls_H = m.lls;
    c.motor.Llr_H = m.llr;
    c.motor.Lm_H = m.lm;
    c.motor.pole_pairs = 2;
    c.motor.J_kgm2 = m.J;
    c.motor.B_Nms = m.B;
    if (o.lm_sat_frac > 0.0) {
        double psi_m = std::sqrt(2.0 / 3.0) * m.v_ll / kW60; // the rated flux, about the magnetising one
        c.motor.Lm_sat_psi_Wb = o.lm_sat_frac * psi_m;
    }
    c.dc.vdc_V = m.vdc;
    c.dc.c1_F = c.dc.c2_F = m.c_F;
    c.dc.r_src_ohm = m.r_src_ohm;
    c.inverter.dead_time_s = m.dead_time_s;
    c.inverter.v_on_V = m.v_on_V;
    c.sensor.i_fs_A = m.i_fs_A;
    c.sensor.v_fs_V = m.v_fs_V;
    c.sensor.i_noise_A = std::min(o.i_noise_frac * m.i_fs_A, 1.0);
    c.sensor.v_noise_V = o.v_noise_frac * m.v_fs_V;
    c.sensor.i_offset_A[0] = 1e-3 * m.i_fs_A; // small offsets (the standstill part measures them)
    c.sensor.i_offset_A[1] = -0.5e-3 * m.i_fs_A;
    c.sensor.seed = o.seed;
    if (o.ideal) {
        c.inverter.dead_time_s = 0.0;
        c.inverter.v_on_V = 0.0;
        c.sensor.i_noise_A = c.sensor.v_noise_V = 0.0;
        c.sensor.i_offset_A[0] = c.sensor.i_offset_A[1] = 0.0;
        c.sensor.adc_bits = 16;
    }
    return c;
}

inline ident_cfg ident_cfg_for(const Motor &m, const Options &o)
{
    ident_cfg c;
    std::memset(&c, 0, sizeof c);
    c.plate = plate_for_ident(m);
    c.i_max_A = 0.0f; // the rated peak
    c.period_s = float(kT);
    c.vdc_nom_V = float(m.vdc);
    c.vdc_min_V = float(0.7 * m.vdc);
    c.dead_time_s = float(o.comp_scale * m.dead_time_s);
    c.v_drop_V = float(o.comp_scale * m.v_on_V);
    c.rotating = o.rotating;
    c.te_J_frac = 0.3f;
    return c;
}

// The drive's configuration before the run: the 10 hp defaults scaled to
// the motor, its model a first guess from the plate (the run replaces it).
inline ctl_cfg ctl_orig_for(const Motor &m, const ident_cfg &ic, const Options &o)
{
    ctl_cfg c;
    ctl_cfg_default(&c);
    const ident_plate_est &e = ic.est;
    const double ipk = e.i_peak_A, psi = e.psi_s_Wb, te = e.te_Nm, k_v = m.vdc / 311.0;
    motor_model &mm = c.motor;
    double lsig = e.sigma_ls_H, lm = psi / e.i_mag_A;
    mm.Rs_ohm = float(0.02 * e.z_base_ohm);
    mm.Lm_H = float(lm);
    mm.Ls_H = mm.Lr_H = float(lm + 0.5 * lsig);
    mm.Rr_ohm = float((lm + 0.5 * lsig) / e.tr_s);
    mm.pole_pairs = 2.0f;
    mm.J_kgm2 = float(2.0 * m.J); // an engineer's guess, twice the true
    mm.B_Nms = 0.0f;
    c.vdc_nom_V = float(m.vdc);
    c.c_dc_F = float(m.c_F);
    c.dtc.psi_ref_Wb = float(psi);
    c.dtc.flux_band_Wb = float(0.022 * psi);
    c.dtc.torque_band_Nm = float(0.086 * te);
    c.dtc.torque_band2_Nm = float(0.2 * te);
    c.dtc.np_band_V = float(1.5 * k_v);
    c.dtc.premag_s = float(0.3 + e.tr_s);
    c.speed.mode = SPEED_MODE_IP;
    c.speed.te_max_Nm = float(2.0 * te);
    c.speed.ramp_rad_s2 = float(0.5 * te / mm.J_kgm2);
    c.obs.kp_speed = float(50.0 * 15.4 / (ipk * psi));
    c.obs.ki_speed = float(2000.0 * 15.4 / (ipk * psi));
    c.i_trip_A = float(3.0 * ipk);
    c.vdc_max_V = float(1.3 * m.vdc);
    c.vdc_min_V = float(0.6 * m.vdc);
    c.np_trip_V = float(0.1 * m.vdc);
    c.overspeed_rad_s = float(1.6 * e.w_m_rad_s);
    c.guard.v_tol_V = float(6.0 * k_v);
    c.dead_time_comp_s = float(o.comp_scale * m.dead_time_s);
    c.v_drop_V = float(o.comp_scale * m.v_on_V);
    c.bringup_level = BRINGUP_TORQUE;
    c.bringup_te_Nm = 0.0f;
    c.from_plate = false; // set by hand above: a re-derivation from the default plate must not replace it
    ctl_cfg_derive(&c);
    return c;
}

// The drive's reconstruction of the stator voltage over a period that applies
// @p act after a period that ended on @p end: the commanded leg voltages mixed
// by the duty, the device drops against the currents (softened over 0.5 A),
// the dead time's edges (dead_time_leg_error), one Clarke transform: the
// firmware's parts, as ctl.c's observe() puts them together.
inline void reconstruct(uint8_t end, const hal_actuation &act, const float i[3], float vc1, float vc2, double dt_per_T,
                        double v_drop_V, float v_ab[2])
{
    hal_actuation prev{};
    npc_legs(end, &prev.vector[0]);
    npc_legs(end, &prev.vector[1]);
    prev.duty0 = 0.5f;
    float dv[3];
    dead_time_leg_error(&prev, &act, i, vc1, vc2, float(dt_per_T), 0.5f, dv);
    const double level[3] = {-double(vc2), 0.0, double(vc1)};
    double leg[3];
    for (int k = 0; k < 3; ++k) {
        double cmd = act.duty0 * level[act.vector[0].leg[k]] + (1.0 - act.duty0) * level[act.vector[1].leg[k]];
        double s = std::max(-1.0, std::min(1.0, double(i[k]) / 0.5));
        leg[k] = cmd - 2.0 * v_drop_V * s + dv[k];
    }
    v_ab[0] = float((2.0 * leg[0] - leg[1] - leg[2]) / 3.0);
    v_ab[1] = float((leg[1] - leg[2]) / std::sqrt(3.0));
}

inline uint8_t end_state_of(const hal_actuation &a)
{
    return a.duty0 < 1.0f ? npc_state_of(&a.vector[1]) : npc_state_of(&a.vector[0]);
}

inline hal_actuation zero_act()
{
    hal_actuation a{};
    npc_legs(NPC_STATE_OOO, &a.vector[0]);
    npc_legs(NPC_STATE_OOO, &a.vector[1]);
    a.duty0 = 1.0f;
    return a;
}

struct Run {
    int start_rc = 0;
    ident id;
    ident_cfg ic;
    ident_result res;
    ctl_cfg orig, trial, fin;
    int apply_rc = 0;            // ident_apply at the end (IDENT_E_PHASE after an abort)
    double t_standstill_s = 0.0; // drive time of each part
    double t_rotating_s = 0.0;
    double i_peak_standstill_A = 0.0; // the largest true phase current at the samples
    double i_peak_rotating_A = 0.0;
    double np_dev_standstill_V = 0.0; // the largest |vc1 - vc2| (true) while the identification actuates
    double t_end_s = 0.0;
    uint32_t ctl_faults = 0u;
    ident_out_mode last_mode = IDENT_OUT_OFF; // the identification's output at the last tick
    double lm_secant_H = 0.0;    // the plant's Lm(|psi_m|) over the no-load window (saturation)
    std::vector<int> phases_seen;
};

// Run the identification on @p m; the run's state is large: a Run lives on the heap.
inline std::unique_ptr<Run> run_ident(const Motor &m, const Options &o = Options())
{
    auto run = std::make_unique<Run>();
    Run &r = *run;
    plant_config pc = plant_for(m, o);
    plant_state ps;
    if (plant_init(&ps, &pc) != 0)
        return run;
    if (o.turning_rad_s != 0.0) {
        plant_set_inertia(&ps, m.J * 1e4); // the load keeps it turning: a flywheel
        ps.omega_m = o.turning_rad_s;
    }
    if (o.inertia_x != 1.0)
        plant_set_inertia(&ps, m.J * o.inertia_x);
    r.ic = ident_cfg_for(m, o);
    if (ident_cfg_derive(&r.ic) != IDENT_OK) {
        r.start_rc = -100;
        return run;
    }
    r.orig = ctl_orig_for(m, r.ic, o);
    r.trial = r.orig;
    r.fin = r.orig;
    std::memset(&r.res, 0, sizeof r.res);
    ident_init(&r.id);
    ctl_state cs;
    ctl_init(&cs, &r.trial);
    plant_adc adc;
    plant_sample(&ps, &adc);
    double iu[3], vu[2];
    plant_adc_to_units(&ps.cfg, &adc, iu, vu);
    ident_start_in si{true, 0.0f, float(vu[0] + vu[1])};
    r.start_rc = ident_start(&r.id, &r.ic, &si);
    if (r.start_rc != IDENT_OK)
        return run;

    const double dt_per_T = o.comp_scale * m.dead_time_s / kT, v_drop = o.comp_scale * m.v_on_V;
    hal_actuation prev = zero_act(); // latched at the last tick, applied in the period now starting
    uint8_t end_before = NPC_STATE_OOO; // the state the period before that ended on
    bool ctl_mode = false, speed_mode = false;
    const uint8_t legs_off[3] = {PLANT_LEG_OFF, PLANT_LEG_OFF, PLANT_LEG_OFF};
    const unsigned n_max = unsigned(o.max_s / kT);
    int last_phase = -1;
    for (unsigned k = 0; k < n_max; ++k) {
        double t = k * kT;
        plant_sample(&ps, &adc);
        plant_adc_to_units(&ps.cfg, &adc, iu, vu);
        hal_sample hs{float(iu[0]), float(iu[1]), float(iu[2]), float(vu[0]), float(vu[1]), 0.0f, false, k + 1u};
        plant_truth tr;
        plant_get_truth(&ps, &tr);
        double ipk = std::max({std::fabs(tr.ia_A), std::fabs(tr.ib_A), std::fabs(tr.ic_A)});
        bool rot_phase = r.id.phase >= IDENT_ROT_START && r.id.phase <= IDENT_FIT_ROTATING;
        if (r.id.phase >= IDENT_PROBE && r.id.phase <= IDENT_ROTOR)
            r.np_dev_standstill_V = std::max(r.np_dev_standstill_V, std::fabs(tr.vc1_V - tr.vc2_V));
        (rot_phase ? r.i_peak_rotating_A : r.i_peak_standstill_A) =
            std::max(rot_phase ? r.i_peak_rotating_A : r.i_peak_standstill_A, ipk);

        ident_in in{};
        for (int j = 0; j < 3; ++j)
            in.i_abc_A[j] = (&hs.ia_A)[j];
        in.vc1_V = hs.vc1_V;
        in.vc2_V = hs.vc2_V;
        reconstruct(end_before, prev, in.i_abc_A, hs.vc1_V, hs.vc2_V, dt_per_T, v_drop, in.v_ab_V);
        in.omega_m_rad_s = ctl_mode ? cs.obs.omega_m_filt_rad_s : 0.0f;
        in.psi_s_Wb[0] = ctl_mode ? cs.obs_out.psi_s_Wb[0] : 0.0f;
        in.psi_s_Wb[1] = ctl_mode ? cs.obs_out.psi_s_Wb[1] : 0.0f;
        in.run = !(o.stop_at_s >= 0.0 && t >= o.stop_at_s);
        in.fault = (ctl_mode && cs.faults != 0u) || (o.fault_at_s >= 0.0 && t >= o.fault_at_s);
        in.control_running = ctl_mode && cs.run_state == CTL_RUNNING;
        ident_out out;
        uint32_t n_no_load = r.id.rot.no_load.n;
        ident_step(&r.id, &r.ic, &in, &out);
        if (r.id.rot.no_load.n != n_no_load) {
            // the secant magnetising inductance at the window's magnetising flux psi_m = psi_s - Lls i_s
            double ma = tr.psi_s_alpha_Wb - m.lls * tr.is_alpha_A, mb = tr.psi_s_beta_Wb - m.lls * tr.is_beta_A;
            double knee = pc.motor.Lm_sat_psi_Wb;
            double lm = knee > 0.0 ? m.lm / (1.0 + std::pow(std::hypot(ma, mb) / knee, pc.motor.Lm_sat_exponent)) : m.lm;
            r.lm_secant_H += (lm - r.lm_secant_H) / double(r.id.rot.no_load.n);
        }
        if (int(r.id.phase) != last_phase) {
            last_phase = int(r.id.phase);
            r.phases_seen.push_back(last_phase);
        }

        // the background pass
        ident_background(&r.id, &r.ic, &r.res);
        if (r.id.phase == IDENT_WAIT_APPLY && !r.id.go_rotating) {
            ident_apply(&r.id, &r.res, &r.orig, &r.trial);
            r.trial.bringup_level = BRINGUP_TORQUE;
            ctl_init(&cs, &r.trial);
            ident_continue(&r.id, &r.res);
        }

        hal_actuation act = zero_act();
        bool gates = false;
        if (out.mode == IDENT_OUT_ACTUATE) {
            act = out.act;
            gates = true;
            if (o.on_actuation)
                o.on_actuation(act, r.id.phase);
        } else if (out.mode == IDENT_OUT_TORQUE || out.mode == IDENT_OUT_SPEED) {
            bool want_speed = out.mode == IDENT_OUT_SPEED;
            if (want_speed && !speed_mode) {
                // bumpless into the speed loop: its reference and integrator from where the shaft is
                cs.speed_ref_ramped_rad_s = cs.obs.omega_m_filt_rad_s;
                speed_ctl_reset(&cs.speed, cs.te_ref_Nm);
                speed_ctl_set_ref(&cs.speed, cs.obs.omega_m_filt_rad_s);
                speed_ip_bumpless(&cs.speed.ip, &r.trial.speed.ip, cs.te_ref_Nm, cs.obs.omega_m_filt_rad_s);
            }
            speed_mode = want_speed;
            ctl_mode = true;
            r.trial.bringup_level = want_speed ? BRINGUP_SPEED : BRINGUP_TORQUE;
            r.trial.bringup_te_Nm = out.te_ref_Nm;
            ctl_in ci{};
            ci.sample = hs;
            ci.sample_fresh = true;
            ci.run = true;
            ci.speed_ref_rad_s = out.speed_ref_rad_s;
            ctl_out co;
            ctl_step(&cs, &r.trial, &ci, &co);
            r.ctl_faults |= cs.faults;
            act = co.act;
            gates = co.gate_enable;
        }
        if (gates)
            plant_advance(&ps, prev.vector[0].leg, prev.vector[1].leg, double(prev.duty0), kT);
        else
            plant_advance(&ps, legs_off, legs_off, 1.0, kT);
        end_before = gates ? end_state_of(prev) : uint8_t(NPC_STATE_OOO);
        prev = gates ? act : zero_act();
        r.last_mode = out.mode;
        if (r.id.phase == IDENT_DONE || r.id.phase == IDENT_ABORTED) {
            r.t_end_s = t;
            break;
        }
    }
    r.t_standstill_s = r.res.t_standstill_s;
    r.t_rotating_s = r.res.t_rotating_s;
    r.apply_rc = ident_apply(&r.id, &r.res, &r.orig, &r.fin);
    return run;
}

inline double err_pct(double found, double truth) { return 100.0 * (found / truth - 1.0); }

} // namespace identrig
