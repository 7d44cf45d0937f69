/**
 * @file ctl_cfg.c
 * @brief The control step's configuration: defaults, derived constants and
 *        the check before publication (see dtc/ctl_cfg.h). Context: BG.
 */
#include "dtc/ctl_cfg.h"

#include <string.h>

#include "dtc/bringup.h"

void ctl_cfg_fixed_default(ctl_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    /* Only what no plate derives (docs/commissioning.md, "What stays
     * absolute"); the derivable values, the motor model and the ratings are
     * ctl_cfg_default's (ctl_cfg_ratings.c). */
    cfg->period_s = R(200e-6);
    speed_cfg_default(&cfg->speed, &cfg->motor); /* the mode, zeta, n_nodes; its absolute values are derived */

    dtc3l_cfg *d = &cfg->dtc;
    d->ripple_reduction = true;
    d->level_up = R(0.6);            /* 660 rpm at rated flux and 311 V */
    d->level_down = R(0.5);
    d->duty_min = R(0.05);           /* 10 us at 200 us */

    observer_cfg *o = &cfg->obs;
    o->k_gain = R(1.3);
    o->ki_rs = R(0.0);
    o->regen_angle_rad = R(1.4);      /* regenerating-mode stabilisation (observer.c: its shape) */
    o->speed_lpf_hz = R(50.0);

    cfg->fw_voltage_frac = R(0.9);
    cfg->te_pullout_frac = R(0.9);
    cfg->fsw_max_hz = R(850.0);            /* 0.5..1 kHz at 500 rpm, <= 1.5 kHz everywhere */
    cfg->band_scale_max = R(4.0);
    cfg->rs_ident_tol = R(0.1); /* docs/envelope.md section 6 */
    cfg->regen_flux_min_frac = R(0.7); /* docs/envelope.md section 6; the torque limit at 0.7 x rated flux is 44.6 N m */
    cfg->guard.flux_err_frac = R(0.15);
    cfg->guard.rs_tol_frac = R(0.3);       /* a winding 30 % warmer than modelled */
    cfg->bringup_level = BRINGUP_SPEED;
    cfg->bringup_te_Nm = R(0.0);
    cfg->dead_time_comp_s = R(1.0e-6);     /* the board's HRTIM dead time (docs/board.md) */
    cfg->v_drop_V = R(1.0);                /* on-state drop per device, board-dependent (0: none) */

    /* Speed-deviation supervision: the reference plate's values (ratings.c
     * REF_SPEED_DEV_*, derived from the plate by ctl_cfg_default). */
    cfg->speed_dev_band_rad_s = R(5.86);
    cfg->speed_dev_time_s = R(1.0);
}

void ctl_cfg_derive(ctl_cfg *cfg)
{
    const motor_model *m = &cfg->motor;
    speed_cfg_derive(&cfg->speed, m);
    observer_cfg_derive(&cfg->obs, m, cfg->period_s);

    /* With |psi_s| ramped at rate r, the rotor flux lags by r sigma Tr and the
     * stator current exceeds psi/Ls by r (1 - sigma) Tr / Ls. */
    real_t sigma = R(1.0) - num_div(num_mul(m->Lm_H, m->Lm_H), num_mul(m->Ls_H, m->Lr_H));
    real_t tr = num_div(m->Lr_H, m->Rr_ohm);
    real_t a_per_wb_s = num_div(num_mul(R(1.0) - sigma, tr), m->Ls_H);
    cfg->psi_ramp_Wb_s = a_per_wb_s > R(0.0) ? num_div(num_mul(R(0.2), cfg->i_trip_A), a_per_wb_s) : R(1.0);
    cfg->np_V_per_A = cfg->c_dc_F > R(0.0) ? num_div(cfg->period_s, cfg->c_dc_F) : R(0.0);
    cfg->dtc.np_V_per_A = cfg->np_V_per_A;
    cfg->inv_period_per_s = cfg->period_s > R(0.0) ? num_div(R(1.0), cfg->period_s) : R(0.0);
    /* the inverter model's per-tick constants: one byte's test per tick, and the
     * products the tick needs (-4 v_drop is exact: a power of 2) */
    cfg->inv.dead_time_per_T = num_mul(cfg->dead_time_comp_s, cfg->inv_period_per_s);
    cfg->inv.real = cfg->v_drop_V > R(0.0) || cfg->dead_time_comp_s > R(0.0);
    cfg->inv.drop4_V = num_mul(R(-4.0), cfg->v_drop_V);
    ctl_guard_cfg_derive(&cfg->guard, cfg->period_s);
    rs_ident_cfg_derive(&cfg->rsid, m, cfg->period_s, cfg->rs_ident_tol);
    /* stator-flux-oriented pull-out torque: Te_max = 1.5 p psi_s^2 (1 - sigma) / (2 sigma Ls) */
    real_t den = num_mul(R(2.0) * sigma, m->Ls_H);
    cfg->te_pullout_Nm_Wb2 = den > R(0.0) ? num_div(num_mul(R(1.5) * m->pole_pairs, R(1.0) - sigma), den) : R(0.0);
    cfg->speed_max_rad_s = num_div(cfg->overspeed_rad_s, R(1.1));
    cfg->fsw_per_change_hz = cfg->period_s > R(0.0) ? num_div(R(1.0), R(6.0) * cfg->period_s) : R(0.0);
    real_t t_sup = num_mul((real_t)CTL_SLOW_SLOTS, cfg->period_s); /* the supervision and regulation step */
    cfg->fsw_lpf_a = num_sat(R(1.0) - num_exp(-num_div(t_sup, R(0.02))), R(0.0), R(1.0));
    cfg->band_rate_T = num_mul(R(5.0), t_sup);
    cfg->sup_lpf_a = num_sat(R(1.0) - num_exp(-num_div(t_sup, R(0.02))), R(0.0), R(1.0));
    cfg->sup_rate_T = num_mul(R(5.0), t_sup);
    cfg->inv_fsw_max_s = cfg->fsw_max_hz > R(0.0) ? num_div(R(1.0), cfg->fsw_max_hz) : R(0.0);
    cfg->fw_v_per_vdc = num_mul(cfg->fw_voltage_frac, NUM_INV_SQRT3);
    cfg->te_limit_Nm_Wb2 = num_mul(cfg->te_pullout_frac, cfg->te_pullout_Nm_Wb2);
    /* rated-flux slip per N m: Rr / (1.5 p psi_r^2), psi_r = psi_ref Lm / Ls (no load) */
    real_t psi_r = num_div(num_mul(cfg->dtc.psi_ref_Wb, m->Lm_H), m->Ls_H);
    real_t slip_den = num_mul(num_mul(R(1.5), m->pole_pairs), num_mul(psi_r, psi_r));
    cfg->slip_rad_s_per_Nm = slip_den > R(0.0) ? num_div(m->Rr_ohm, slip_den) : R(0.0);
    cfg->regen_k2_min = num_mul(cfg->regen_flux_min_frac, cfg->regen_flux_min_frac);
    /* per-tick constants of the flux ramp and the speed loop */
    cfg->psi_ramp_step_Wb = num_mul(cfg->psi_ramp_Wb_s, cfg->period_s);
    cfg->speed_T_s = num_mul((real_t)CTL_RBFN_TICKS, cfg->period_s);
    cfg->speed_ramp_step_rad_s = num_mul(cfg->speed.ramp_rad_s2, cfg->speed_T_s);
    cfg->sup_T_s = t_sup;
    cfg->speed_dev_shrink_rad_s_per_s =
        cfg->speed_dev_time_s > R(0.0) ? num_div(cfg->speed_dev_band_rad_s, cfg->speed_dev_time_s) : R(0.0);
    cfg->inv_speed_T_per_s = num_mul(R(1.0) / (real_t)CTL_RBFN_TICKS, cfg->inv_period_per_s);
}

int ctl_cfg_check(const ctl_cfg *cfg)
{
    const motor_model *m = &cfg->motor;
    if (!(m->Rs_ohm > R(0.0) && m->Rr_ohm > R(0.0) && m->Lm_H > R(0.0) && m->Ls_H > m->Lm_H &&
          m->Lr_H > m->Lm_H && m->pole_pairs >= R(1.0) && m->J_kgm2 > R(0.0) && m->B_Nms >= R(0.0)))
        return CTL_CFG_E_MOTOR;
    if (!(cfg->period_s >= R(20e-6) && cfg->period_s <= R(2e-3) && cfg->vdc_nom_V > R(0.0) && cfg->c_dc_F >= R(0.0)))
        return CTL_CFG_E_PERIOD;
    const dtc3l_cfg *d = &cfg->dtc;
    if (!(d->psi_ref_Wb > R(0.0) && d->premag_s >= R(0.0) && d->flux_band_Wb >= R(0.0) &&
          d->torque_band_Nm >= R(0.0) && d->torque_band2_Nm > d->torque_band_Nm &&
          d->ripple_speed_max_rad_s >= R(0.0) && d->np_band_V >= R(0.0) && d->level_down < d->level_up &&
          d->level_down >= R(0.0) && d->duty_min >= R(0.0) && d->duty_min <= R(0.45)))
        return CTL_CFG_E_DTC;
    const observer_cfg *o = &cfg->obs;
    if (!(o->k_gain >= R(1.0) && o->kp_speed >= R(0.0) && o->ki_speed >= R(0.0) && o->ki_rs >= R(0.0) &&
          o->speed_lpf_hz >= R(0.0) && o->regen_angle_rad >= R(0.0) && o->regen_angle_rad <= R(1.5) &&
          o->regen_speed_rad_s > R(0.0) && cfg->regen_flux_min_frac >= R(0.5) && cfg->regen_flux_min_frac <= R(1.0)))
        return CTL_CFG_E_OBSERVER;
    if (!(cfg->i_trip_A > R(0.0) && cfg->vdc_max_V > R(0.0) && cfg->vdc_min_V >= R(0.0) &&
          cfg->vdc_min_V < cfg->vdc_max_V && cfg->np_trip_V > R(0.0) && cfg->overspeed_rad_s > R(0.0) &&
          cfg->guard.wc_rad_s > R(0.0) && cfg->guard.flux_err_frac >= R(0.0) && cfg->guard.time_s >= R(0.0) &&
          cfg->guard.rs_tol_frac >= R(0.0) && cfg->guard.v_tol_V >= R(0.0) && cfg->v_drop_V >= R(0.0) &&
          cfg->dead_time_comp_s >= R(0.0) && cfg->dead_time_comp_s <= R(10e-6) &&
          cfg->bringup_level >= BRINGUP_GATE_TEST && cfg->bringup_level <= BRINGUP_SPEED &&
          num_abs(cfg->bringup_hz) <= R(100.0) && cfg->stall_time_s >= R(0.0) && cfg->fw_voltage_frac > R(0.0) && cfg->fw_voltage_frac <= R(1.2) &&
          cfg->te_pullout_frac > R(0.0) && cfg->te_pullout_frac <= R(1.0) && cfg->fsw_max_hz >= R(0.0) &&
          cfg->band_scale_max >= R(1.0) && cfg->rs_ident_tol >= R(0.0) && cfg->rs_ident_tol <= R(1.0)))
        return CTL_CFG_E_PROTECTION;
    /* The V/f bring-up is a speed source too: its synchronous speed stays within the speed
     * reference's limit (overspeed_rad_s / 1.1, what ctl_cfg_derive sets speed_max_rad_s to). */
    if (!(num_mul(num_abs(cfg->bringup_hz), R(2.0) * NUM_PI) <=
          num_mul(num_div(cfg->overspeed_rad_s, R(1.1)), m->pole_pairs)))
        return CTL_CFG_E_PROTECTION;
    if (!(cfg->speed_dev_band_rad_s >= R(0.0) && cfg->speed_dev_band_rad_s <= R(500.0) &&
          cfg->speed_dev_time_s >= R(0.0) && cfg->speed_dev_time_s <= R(60.0)))
        return CTL_CFG_E_PROTECTION;
    if (speed_cfg_check(&cfg->speed, m) != SPEED_CFG_OK)
        return CTL_CFG_E_SPEED;
    return CTL_CFG_OK;
}
