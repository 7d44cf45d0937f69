/**
 * @file plant_config.c
 * @brief Default plant (docs/motor-10hp.json) and the physical-range check.
 */
#include <math.h>
#include <stddef.h>

#include "plant_internal.h"

void plant_default_config(plant_config *cfg)
{
    int k;
    if (cfg == NULL)
        return;

    /* 10 hp, 220 V, 60 Hz, 4-pole squirrel cage (docs/motor-10hp.json). */
    cfg->motor.Rs_ohm = 0.288;
    cfg->motor.Rr_ohm = 0.158;
    cfg->motor.Lls_H = 0.00142;
    cfg->motor.Llr_H = 0.00142;
    cfg->motor.Lm_H = 0.0416;
    cfg->motor.pole_pairs = 2;
    cfg->motor.J_kgm2 = 0.045;
    cfg->motor.B_Nms = 0.005;
    cfg->motor.Lm_sat_psi_Wb = 0.0; /* linear magnetics */
    cfg->motor.Lm_sat_exponent = 6.0;

    cfg->load.coulomb_Nm = 0.0;
    cfg->load.viscous_Nms = 0.0;
    cfg->load.fan_Nms2 = 0.0;

    cfg->dc.vdc_V = 311.0;
    cfg->dc.r_src_ohm = 0.05;
    cfg->dc.c1_F = 0.0022;
    cfg->dc.c2_F = 0.0022;

    /* The ideal inverter: the plant's validation (T-equivalent circuit,
     * power balance, inverter table) is stated for it. */
    cfg->inverter.dead_time_s = 0.0;
    cfg->inverter.v_on_V = 0.0;

    cfg->sensor.adc_bits = 12;
    cfg->sensor.i_fs_A = 150.0;
    cfg->sensor.v_fs_V = 500.0;
    for (k = 0; k < 3; ++k) {
        cfg->sensor.i_gain[k] = 1.0;
        cfg->sensor.i_offset_A[k] = 0.0;
    }
    for (k = 0; k < 2; ++k) {
        cfg->sensor.v_gain[k] = 1.0;
        cfg->sensor.v_offset_V[k] = 0.0;
    }
    cfg->sensor.i_noise_A = 0.0;
    cfg->sensor.v_noise_V = 0.0;
    cfg->sensor.seed = 1u;

    cfg->supply = PLANT_SUPPLY_INVERTER;
    cfg->sine.v_ll_rms_V = 220.0;
    cfg->sine.f_Hz = 60.0;
    cfg->sine.phase_rad = 0.0;

    /* The shaft at rest, the rotor without residual flux. */
    cfg->initial_omega_m_rad_s = 0.0;
    cfg->initial_flux_frac = 0.0;

    /* 200 us / 5. Halving it changes the phase currents of an inverter-fed
     * run by about 0.002 A, 1/17 of the 0.1 %-of-rated (0.0345 A) budget
     * (test_plant_machine: Convergence); the error comes mostly from the
     * DC link's 55 us time constant. 25 us would cost 30 % more time. */
    cfg->h_max_s = 40e-6;
}

/* Checks return the first failing field's message. isfinite() rejects
 * infinities; the negated comparisons also reject NaN. */
#define REQ(cond, msg)           \
    do {                         \
        if (!(cond)) {           \
            *what = (msg);       \
            return PLANT_EINVAL; \
        }                        \
    } while (0)
#define POS(x, msg) REQ(isfinite(x) && (x) > 0.0, msg)
#define NONNEG(x, msg) REQ(isfinite(x) && (x) >= 0.0, msg)
#define FINITE(x, msg) REQ(isfinite(x), msg)

int plant_check_config(const plant_config *cfg, const char **what)
{
    const char *dummy;
    const plant_sensor_params *sp;
    if (what == NULL)
        what = &dummy;
    *what = NULL;
    REQ(cfg != NULL, "config is NULL");

    POS(cfg->motor.Rs_ohm, "motor.Rs_ohm must be > 0");
    POS(cfg->motor.Rr_ohm, "motor.Rr_ohm must be > 0");
    POS(cfg->motor.Lls_H, "motor.Lls_H must be > 0");
    POS(cfg->motor.Llr_H, "motor.Llr_H must be > 0");
    POS(cfg->motor.Lm_H, "motor.Lm_H must be > 0");
    REQ(cfg->motor.pole_pairs >= 1 && cfg->motor.pole_pairs <= 64,
        "motor.pole_pairs must be in 1..64");
    POS(cfg->motor.J_kgm2, "motor.J_kgm2 must be > 0");
    NONNEG(cfg->motor.B_Nms, "motor.B_Nms must be >= 0");

    NONNEG(cfg->motor.Lm_sat_psi_Wb, "motor.Lm_sat_psi_Wb must be >= 0");
    REQ(isfinite(cfg->motor.Lm_sat_exponent) && cfg->motor.Lm_sat_exponent >= 2.0 &&
            cfg->motor.Lm_sat_exponent <= 20.0,
        "motor.Lm_sat_exponent must be in [2, 20]");
    NONNEG(cfg->load.coulomb_Nm, "load.coulomb_Nm must be >= 0");
    NONNEG(cfg->load.viscous_Nms, "load.viscous_Nms must be >= 0");
    NONNEG(cfg->load.fan_Nms2, "load.fan_Nms2 must be >= 0");

    POS(cfg->dc.vdc_V, "dc.vdc_V must be > 0");
    POS(cfg->dc.r_src_ohm, "dc.r_src_ohm must be > 0");
    POS(cfg->dc.c1_F, "dc.c1_F must be > 0");
    POS(cfg->dc.c2_F, "dc.c2_F must be > 0");

    REQ(isfinite(cfg->inverter.dead_time_s) && cfg->inverter.dead_time_s >= 0.0 &&
            cfg->inverter.dead_time_s <= 50e-6,
        "inverter.dead_time_s must be in [0, 5e-05] s");
    REQ(isfinite(cfg->inverter.v_on_V) && cfg->inverter.v_on_V >= 0.0 && cfg->inverter.v_on_V <= 50.0,
        "inverter.v_on_V must be in [0, 50] V");

    sp = &cfg->sensor;
    REQ(sp->adc_bits >= 1 && sp->adc_bits <= 16, "sensor.adc_bits must be in 1..16");
    POS(sp->i_fs_A, "sensor.i_fs_A must be > 0");
    POS(sp->v_fs_V, "sensor.v_fs_V must be > 0");
    POS(sp->i_gain[0], "sensor.i_gain[0] must be > 0");
    POS(sp->i_gain[1], "sensor.i_gain[1] must be > 0");
    POS(sp->i_gain[2], "sensor.i_gain[2] must be > 0");
    FINITE(sp->i_offset_A[0], "sensor.i_offset_A[0] must be finite");
    FINITE(sp->i_offset_A[1], "sensor.i_offset_A[1] must be finite");
    FINITE(sp->i_offset_A[2], "sensor.i_offset_A[2] must be finite");
    POS(sp->v_gain[0], "sensor.v_gain[0] must be > 0");
    POS(sp->v_gain[1], "sensor.v_gain[1] must be > 0");
    FINITE(sp->v_offset_V[0], "sensor.v_offset_V[0] must be finite");
    FINITE(sp->v_offset_V[1], "sensor.v_offset_V[1] must be finite");
    NONNEG(sp->i_noise_A, "sensor.i_noise_A must be >= 0");
    NONNEG(sp->v_noise_V, "sensor.v_noise_V must be >= 0");

    REQ(cfg->supply == PLANT_SUPPLY_INVERTER || cfg->supply == PLANT_SUPPLY_SINE,
        "supply must be PLANT_SUPPLY_INVERTER or PLANT_SUPPLY_SINE");
    NONNEG(cfg->sine.v_ll_rms_V, "sine.v_ll_rms_V must be >= 0");
    NONNEG(cfg->sine.f_Hz, "sine.f_Hz must be >= 0");
    FINITE(cfg->sine.phase_rad, "sine.phase_rad must be finite");

    REQ(isfinite(cfg->h_max_s) && cfg->h_max_s >= 1e-7 && cfg->h_max_s <= 1e-4,
        "h_max_s must be in [1e-7, 1e-4] s");
    REQ(isfinite(cfg->initial_omega_m_rad_s) && fabs(cfg->initial_omega_m_rad_s) <= 2000.0,
        "initial_omega_m_rad_s must be in [-2000, 2000] rad/s");
    REQ(isfinite(cfg->initial_flux_frac) && cfg->initial_flux_frac >= 0.0 && cfg->initial_flux_frac <= 1.2,
        "initial_flux_frac must be in [0, 1.2]");
    REQ(cfg->initial_flux_frac == 0.0 || cfg->sine.f_Hz > 0.0,
        "initial_flux_frac needs the nameplate supply's frequency sine.f_Hz > 0");
    return 0;
}
