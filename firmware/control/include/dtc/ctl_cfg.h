/**
 * @file ctl_cfg.h
 * @brief The configuration of the control step: every tunable of the control
 *        core and the constants derived from them, the defaults for the 10 hp
 *        motor, and the check before a configuration is published.
 *
 * Written by the background only (through the parameter layer, which then
 * calls ctl_cfg_derive()), read by the interrupt. Units are SI; speeds are
 * MECHANICAL rad/s unless named _elec.
 */
#ifndef DTC_CTL_CFG_H
#define DTC_CTL_CFG_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/ctl_guard.h"
#include "dtc/ctl_schedule.h"
#include "dtc/dtc3l.h"
#include "dtc/inverter_model.h"
#include "dtc/motor_model.h"
#include "dtc/num.h"
#include "dtc/observer.h"
#include "dtc/ratings_types.h"
#include "dtc/rs_ident.h"
#include "dtc/speed_ctl.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Error codes of ctl_cfg_check() (negative, first violated rule). */
enum ctl_cfg_error {
    CTL_CFG_OK = 0,
    CTL_CFG_E_MOTOR = -1,     /**< a motor parameter not > 0, or Ls, Lr not > Lm */
    CTL_CFG_E_PERIOD = -2,    /**< period_s outside 20e-6..2e-3 or vdc_nom_V not > 0 */
    CTL_CFG_E_DTC = -3,       /**< psi_ref not > 0, a band < 0, band2 <= band, level_down >= level_up, duty_min outside 0..0.45 */
    CTL_CFG_E_OBSERVER = -4,  /**< k_gain < 1, a gain < 0, speed_lpf_hz < 0 or regen_flux_min_frac outside 0.5..1 */
    CTL_CFG_E_PROTECTION = -5,/**< a trip level not > 0, or vdc_min_V >= vdc_max_V */
    CTL_CFG_E_SPEED = -6,     /**< speed_cfg_check failed */
};

/** All tunables of the control core. Written by the background only, through
 *  the parameter layer, which then calls ctl_cfg_derive(). */
typedef struct {
    /* nominal motor model used by the observer and the controllers */
    motor_model motor;
    real_t period_s;          /**< control period, s (2e-4) */
    real_t vdc_nom_V;         /**< nominal DC link, V */
    real_t c_dc_F;            /**< each of the two DC-link capacitors, F (NP prediction; 0 = none) */

    speed_cfg speed;          /**< speed loop: mode, IP, nominal, RBFN, torque limit */
    dtc3l_cfg dtc;            /**< flux reference, bands, ripple reduction, NP balance */
    observer_cfg obs;         /**< observer gains and adaptation */

    /* protection */
    real_t i_trip_A;          /**< instantaneous phase-current trip, A */
    real_t vdc_max_V;         /**< DC-link over-voltage trip, V */
    real_t vdc_min_V;         /**< DC-link under-voltage trip while running, V */
    real_t np_trip_V;         /**< |vc1 - vc2| trip, V */
    real_t overspeed_rad_s;   /**< estimated-speed trip, rad/s; the speed reference is limited
                                   to overspeed_rad_s / 1.1 (speed_max_rad_s) */
    /* field weakening (docs/envelope.md section 3) */
    real_t fw_voltage_frac;   /**< flux reference <= this x (measured Vdc / sqrt 3) / |omega_e|, 0..1.2 */
    real_t te_pullout_frac;   /**< torque limit <= this x the pull-out torque at the flux reference, 0..1 */
    /* switching-frequency regulation (docs/envelope.md section 4) */
    real_t fsw_max_hz;        /**< device switching frequency above which the torque bands widen, Hz (0 = off) */
    uint32_t bringup_level;   /**< 1 gate test, 2 ADC readout, 3 V/f, 4 V/f + observer, 5 torque control,
                                   6 speed control (the drive); dtc/bringup.h, docs/bringup.md */
    real_t bringup_hz;        /**< V/f electrical frequency at levels 3 and 4, Hz (sign: direction) */
    real_t stall_time_s;      /**< the speed loop's torque command at the limit this long trips STALL, s (0: off) */
    real_t bringup_te_Nm;     /**< torque command at level 5, N m (limited to the torque limit) */
    real_t dead_time_comp_s;  /**< dead time of the power stage, s (0..10e-6, 0 = not compensated): its
                                   volt-seconds are added to the applied voltage the observer and the
                                   loss-of-control monitor use (dtc/inverter_model.h) */
    real_t v_drop_V;          /**< on-state drop of one device, V: subtracted from the applied voltage the
                                   observer and the loss-of-control monitor use (0 = none) */
    real_t band_scale_max;    /**< largest widening of the torque bands, x (>= 1) */
    real_t regen_flux_min_frac; /**< lowest flux for low-speed regeneration, fraction of dtc.psi_ref_Wb,
                                   0.5..1 (1 = never lowered; ctl_supervise.c, regen_flux_factor) */
    real_t rs_ident_tol;      /**< Rs identified while magnetising replaces the model's when they differ by
                                   more than this fraction, 0..1 (1 = never; dtc/rs_ident.h) */
    ctl_guard_cfg guard;      /**< loss-of-control monitor (voltage-model flux check) */
    /* speed-deviation supervision (docs/faults.md, SPEED_DEV) */
    real_t speed_dev_band_rad_s; /**< |ramped reference - filtered estimate| beyond this counts, rad/s (0..500) */
    real_t speed_dev_time_s;  /**< counted this long trips SPEED_DEV, half of it warns, s (0..60; 0: off) */

    /* what the configuration is derived from (background only; dtc/ratings.h, docs/commissioning.md) */
    ratings plate;            /**< the motor's plate and the inverter's label */
    ratings_mask set;         /**< the derivable values the user set (kept); the others are derived */
    bool from_plate;          /**< true: every commit derives the values not in @c set from @c plate
                                   (ratings_derive_cfg, then ctl_cfg_derive); false: the configuration is
                                   absolute, given as a whole (ctl_cfg_derive only) */

    /* derived by ctl_cfg_derive() */
    real_t psi_ramp_Wb_s;     /**< flux-reference slew rate, Wb/s: keeps the magnetising
                                   current transient (the rotor flux lags the stator flux
                                   by sigma Tr) below a fifth of i_trip_A */
    real_t np_V_per_A;        /**< period_s / c_dc_F: change of vc1 - vc2 per ampere of NP current over one period */
    real_t inv_period_per_s;  /**< 1 / period_s */
    inverter_consts inv;      /**< the inverter model's constants (dtc/inverter_model.h): dead_time_comp_s x
                                   inv_period_per_s, the dead time per period (0..0.5); real: v_drop_V > 0
                                   or dead_time_comp_s > 0, the observer's voltage built leg by leg, else the
                                   ideal inverter's; -4 v_drop_V, the drop's slope in the late fraction of a
                                   leg's current, V */
    real_t te_pullout_Nm_Wb2; /**< pull-out torque per Wb^2 of stator flux: 1.5 p (1 - sigma) / (2 sigma Ls) */
    real_t speed_max_rad_s;   /**< speed-reference limit, overspeed_rad_s / 1.1, rad/s */
    real_t fsw_per_change_hz; /**< device switching frequency per leg change per period: 1 / (6 T), Hz */
    real_t fsw_lpf_a;         /**< low-pass coefficient (20 ms) of the measured switching frequency per
                                   regulation step (CTL_SLOW_SLOTS periods, CTL_SLOT_FSW), 0..1 */
    real_t band_rate_T;       /**< adaptation step of the band scale per regulation step (5 1/s x CTL_SLOW_SLOTS T) */
    real_t sup_lpf_a;         /**< low-pass coefficient (20 ms) of the torque shortfall per supervision step
                                   (CTL_SLOW_SLOTS periods), 0..1 */
    real_t sup_rate_T;        /**< step of the field-weakening trim per supervision step (5 1/s x CTL_SLOW_SLOTS T) */
    real_t inv_fsw_max_s;     /**< 1 / fsw_max_hz, s (0 when the regulation is off) */
    real_t fw_v_per_vdc;      /**< fw_voltage_frac / sqrt 3: usable phase voltage per volt of DC link */
    real_t te_limit_Nm_Wb2;   /**< te_pullout_frac x te_pullout_Nm_Wb2, N m/Wb^2 */
    real_t slip_rad_s_per_Nm; /**< electrical slip per N m at the rated flux, (rad/s)/(N m) */
    real_t regen_k2_min;      /**< regen_flux_min_frac^2 */
    real_t psi_ramp_step_Wb;  /**< psi_ramp_Wb_s x period_s: the flux reference's slew per tick, Wb */
    real_t speed_T_s;         /**< CTL_RBFN_TICKS x period_s: the speed loop's step, s (0.8 ms) */
    real_t speed_ramp_step_rad_s; /**< speed.ramp_rad_s2 x speed_T_s: the speed reference's slew per
                                   speed-loop step, rad/s */
    real_t sup_T_s;           /**< CTL_SLOW_SLOTS x period_s: the slot cycle, the speed-deviation step, s (1.6 ms) */
    real_t speed_dev_shrink_rad_s_per_s; /**< speed_dev_band_rad_s / speed_dev_time_s: the error's fall that
                                   counts as a recovery in the speed-deviation windows, (rad/s)/s (0 when off) */
    real_t inv_speed_T_per_s; /**< inv_period_per_s / CTL_RBFN_TICKS (exact: a power of 2), 1/s */
    rs_ident_cfg rsid;        /**< constants of the Rs identification */
} ctl_cfg;

/**
 * Fill @p cfg with the defaults: the reference drive's ratings (the 10 hp
 * plate on 311 V and the board's inverter label, ratings_reference()), its
 * motor's own model set (docs/motor-10hp.json), every other derivable value
 * derived from the plate (ratings_derive_cfg), the values that are not
 * derivable at the 10 hp drive's (ctl_cfg_fixed_default). The 10 hp plate
 * derives exactly the 10 hp drive's tuned values. Context: BG.
 */
void ctl_cfg_default(ctl_cfg *cfg);

/**
 * The values no plate derives (the period, the controller's mode, the
 * inverter's dead time and device drop, dimensionless tunings, switches;
 * docs/commissioning.md "What stays absolute"), the rest zero or at
 * speed_cfg_default's: the start of ctl_cfg_default(), complete only after
 * ratings_derive_cfg. Context: BG.
 */
void ctl_cfg_fixed_default(ctl_cfg *cfg);

/**
 * Commit a changed configuration (background): with @c from_plate, every
 * derivable value not in @c set derived again from @c plate
 * (ratings_derive_cfg, which ends with ctl_cfg_derive); else, or when the
 * plate is refused, ctl_cfg_derive() alone. Context: BG.
 * @return true when the plate derived the configuration (or none was asked)
 */
bool ctl_cfg_rederive(ctl_cfg *cfg);

/** Recompute derived quantities (IP gains from wn and zeta, ...) after a change. Context: BG. */
void ctl_cfg_derive(ctl_cfg *cfg);

/**
 * Check a configuration before it is published (ctl_step stays bounded with a
 * bad one, but it would not control). @return CTL_CFG_OK or the first
 * violated rule (enum ctl_cfg_error). Context: BG.
 */
int ctl_cfg_check(const ctl_cfg *cfg);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CTL_CFG_H */
