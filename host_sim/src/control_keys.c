/**
 * @file control_keys.c
 * @brief Registry of the [control] scenario keys: name -> ctl_cfg field.
 *
 * The single place that ties scenario spelling to firmware fields. Ranges are
 * sanity limits for a scenario file (the firmware's own parameter table may be
 * tighter); speeds here are rad/s because the firmware fields are.
 */
#include "sim/control_keys.h"

#include <stdint.h>
#include <string.h>

#define REAL(name, field, lo, hi, unit) { name, offsetof(ctl_cfg, field), SIM_CK_REAL, lo, hi, unit, #field }
#define U32(name, field, lo, hi, unit) { name, offsetof(ctl_cfg, field), SIM_CK_U32, lo, hi, unit, #field }
#define BOOL(name, field) { name, offsetof(ctl_cfg, field), SIM_CK_BOOL, 0.0, 1.0, "bool", #field }
#define RBFN_NODE(i)                                                                          \
    REAL("rbfn_centre_" #i "_rad_s", speed.rbfn.centre[i], -1000.0, 1000.0, "rad/s"),         \
    REAL("rbfn_width_" #i "_rad_s", speed.rbfn.width[i], 1e-3, 1000.0, "rad/s")

static const sim_control_key keys[] = {
    /* speed loop, common */
    REAL("te_max_Nm", speed.te_max_Nm, 0.0, 500.0, "N m"),
    REAL("ramp_rad_s2", speed.ramp_rad_s2, 0.0, 1e5, "rad/s^2"),
    REAL("ref_wn_rad_s", speed.ref_wn_rad_s, 0.0, 2000.0, "rad/s"),
    REAL("ref_zeta", speed.ref_zeta, 0.05, 10.0, "1"),
    /* IP controller (eq. 1-3) */
    REAL("ip_wn_rad_s", speed.ip.wn_rad_s, 0.1, 2000.0, "rad/s"),
    REAL("ip_zeta", speed.ip.zeta, 0.05, 10.0, "1"),
    /* nominal controller (eq. 6, eps = 0) */
    REAL("nominal_k_x", speed.nominal.k_x, 0.0, 5000.0, "1/s"),
    /* RBFN controller (eq. 8-14, 21) */
    REAL("rbfn_k", speed.rbfn.k, 0.0, 5000.0, "1/s"),
    REAL("rbfn_gamma_w", speed.rbfn.gamma_w, 0.0, 1e9, "1"),
    REAL("rbfn_gamma_zeta", speed.rbfn.gamma_zeta, 0.0, 1e9, "1"),
    REAL("rbfn_m_w", speed.rbfn.m_w, 0.0, 1e9, "1"),
    REAL("rbfn_boundary_rad_s", speed.rbfn.boundary_rad_s, 0.0, 1000.0, "rad/s"),
    REAL("rbfn_zeta_dead_zone_rad_s", speed.rbfn.zeta_dead_zone_rad_s, 0.0, 1000.0, "rad/s"),
    REAL("rbfn_zeta_max", speed.rbfn.zeta_max, 0.0, 1e9, "rad/s^2"),
    REAL("rbfn_zeta_leak", speed.rbfn.zeta_leak, 0.0, 1e6, "1/s"),
    U32("rbfn_n_nodes", speed.rbfn.n_nodes, 1.0, (double)RBFN_NODES_MAX, "1"),
    RBFN_NODE(0), RBFN_NODE(1), RBFN_NODE(2), RBFN_NODE(3), RBFN_NODE(4),
    RBFN_NODE(5), RBFN_NODE(6), RBFN_NODE(7), RBFN_NODE(8),
    /* three-level DTC */
    REAL("psi_ref_Wb", dtc.psi_ref_Wb, 0.01, 2.0, "Wb"),
    REAL("premag_s", dtc.premag_s, 0.0, 10.0, "s"),
    REAL("flux_band_Wb", dtc.flux_band_Wb, 0.0, 0.5, "Wb"),
    REAL("torque_band_Nm", dtc.torque_band_Nm, 0.0, 100.0, "N m"),
    BOOL("ripple_reduction", dtc.ripple_reduction),
    REAL("ripple_speed_max_rad_s", dtc.ripple_speed_max_rad_s, 0.0, 1000.0, "rad/s"),
    REAL("np_band_V", dtc.np_band_V, 0.0, 100.0, "V"),
    /* observer */
    REAL("obs_k_gain", obs.k_gain, 1.0, 100.0, "1"),
    REAL("obs_kp_speed", obs.kp_speed, 0.0, 1e9, "1"),
    REAL("obs_ki_speed", obs.ki_speed, 0.0, 1e12, "1"),
    REAL("obs_ki_rs", obs.ki_rs, 0.0, 1e9, "1"),
    REAL("obs_speed_lpf_hz", obs.speed_lpf_hz, 0.0, 10000.0, "Hz"),
    REAL("obs_regen_angle_rad", obs.regen_angle_rad, 0.0, 1.5, "rad"),
    REAL("obs_regen_speed_rad_s", obs.regen_speed_rad_s, 1e-3, 2000.0, "rad/s"),
    REAL("obs_rs_ident_tol", rs_ident_tol, 0.0, 1.0, "1"),
    REAL("regen_flux_min_frac", regen_flux_min_frac, 0.5, 1.0, "1"),
    /* protection */
    REAL("i_trip_A", i_trip_A, 0.0, 1000.0, "A"),
    REAL("vdc_max_V", vdc_max_V, 0.0, 2000.0, "V"),
    REAL("vdc_min_V", vdc_min_V, 0.0, 2000.0, "V"),
    REAL("np_trip_V", np_trip_V, 0.0, 1000.0, "V"),
    REAL("overspeed_rad_s", overspeed_rad_s, 0.0, 2000.0, "rad/s"),
    REAL("fw_voltage_frac", fw_voltage_frac, 0.01, 1.2, "1"),
    REAL("te_pullout_frac", te_pullout_frac, 0.01, 1.0, "1"),
    REAL("fsw_max_hz", fsw_max_hz, 0.0, 20000.0, "Hz"),
    REAL("band_scale_max", band_scale_max, 1.0, 100.0, "1"),
    REAL("guard_wc_rad_s", guard.wc_rad_s, 0.01, 1000.0, "rad/s"),
    REAL("guard_flux_err_frac", guard.flux_err_frac, 0.0, 10.0, "1"),
    REAL("guard_time_s", guard.time_s, 0.0, 10.0, "s"),
    REAL("guard_rs_tol_frac", guard.rs_tol_frac, 0.0, 10.0, "1"),
    REAL("guard_v_tol_V", guard.v_tol_V, 0.0, 100.0, "V"),
    REAL("v_drop_V", v_drop_V, 0.0, 20.0, "V"),
    REAL("dead_time_comp_s", dead_time_comp_s, 0.0, 10e-6, "s"),
    U32("bringup_level", bringup_level, 1.0, 6.0, "1"),
    REAL("stall_time_s", stall_time_s, 0.0, 60.0, "s"),
    REAL("bringup_hz", bringup_hz, -100.0, 100.0, "Hz"),
    REAL("bringup_te_Nm", bringup_te_Nm, -200.0, 200.0, "N m"),
};

const sim_control_key *sim_control_keys(size_t *count)
{
    *count = sizeof keys / sizeof keys[0];
    return keys;
}

int sim_control_key_find(const char *name)
{
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (strcmp(keys[i].name, name) == 0)
            return (int)i;
    return -1;
}

void sim_control_key_apply(int index, ctl_cfg *cfg, double value)
{
    const sim_control_key *k = &keys[index];
    unsigned char *p = (unsigned char *)cfg + k->offset;
    switch (k->type) {
    case SIM_CK_REAL: {
        real_t v = (real_t)value;
        memcpy(p, &v, sizeof v);
        break;
    }
    case SIM_CK_U32: {
        uint32_t v = (uint32_t)value;
        memcpy(p, &v, sizeof v);
        break;
    }
    case SIM_CK_BOOL: {
        bool v = value != 0.0;
        memcpy(p, &v, sizeof v);
        break;
    }
    }
}

double sim_control_key_read(int index, const ctl_cfg *cfg)
{
    const sim_control_key *k = &keys[index];
    const unsigned char *p = (const unsigned char *)cfg + k->offset;
    switch (k->type) {
    case SIM_CK_REAL: {
        real_t v;
        memcpy(&v, p, sizeof v);
        return (double)v;
    }
    case SIM_CK_U32: {
        uint32_t v;
        memcpy(&v, p, sizeof v);
        return (double)v;
    }
    case SIM_CK_BOOL: {
        bool v;
        memcpy(&v, p, sizeof v);
        return v ? 1.0 : 0.0;
    }
    }
    return 0.0;
}
