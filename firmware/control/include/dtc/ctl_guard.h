/**
 * @file ctl_guard.h
 * @brief Loss-of-control monitor: a check of the observer that does not
 *        trust its speed estimate.
 *
 * A second stator flux is integrated from the stator voltage equation alone,
 * psi_vm = integral(v - Rs is): the applied voltage (reconstructed from the
 * switching states and the measured capacitor voltages, the same the
 * observer gets) and the measured current; no speed, no rotor model. It is
 * the flux the machine really carries (up to the Rs error), whatever the
 * observer believes. A pure integral drifts, so both fluxes pass the same
 * first-order high-pass s / (s + wc): psi_vm is integrated with the leak wc,
 * and the observer's stator flux is high-passed with the same corner, so
 * the two agree at every frequency on a healthy drive and differ only where
 * the observer's flux is not the machine's. The error |psi_vm - hp(psi_obs)|
 * is low-passed (one more wc) and compared with a fraction of the flux
 * reference; above it for guard_time_s, the monitor reports loss of control
 * (the control step latches CTL_FAULT_LOSS_OF_CONTROL).
 *
 * What it catches: a diverged speed estimate (the observer's rotor model
 * then rotates its flux at a wrong frequency, so its stator flux leaves the
 * voltage-model one within a fraction of a slip cycle), a pulled-out machine
 * (the observer's flux no longer explains the current drawn). What it cannot
 * see: errors slower than wc (a slowly drifting estimate at a stator
 * frequency near zero), where both fluxes are filtered away; those are left
 * to the overspeed trip. Design and measurements: docs/envelope.md.
 *
 * Rate: the tick only sums the window's voltage and current
 * (ctl_guard_accumulate, four additions); the integration, the comparison and
 * the verdict run every CTL_GUARD_WINDOW_MAX ticks (ctl_guard_check) on those
 * sums. The volt-seconds are exact (the voltage is constant over a period);
 * the leak over the window, (1 - wc T)^n, is taken to first order (n wc T =
 * 0.5 %: an error of 1e-5 of the flux per window). The trip then waits for
 * guard_time_s counted in whole windows from the first check that sees the
 * error: at the defaults the 13th such check, at most 10.2 ms after the error
 * rose (9.8 ms judged every tick).
 */
#ifndef DTC_CTL_GUARD_H
#define DTC_CTL_GUARD_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Ticks between two checks (the caller's schedule: dtc/ctl_schedule.h). */
#define CTL_GUARD_WINDOW_MAX 4u

/** Tunables of the monitor (part of ctl_cfg). */
typedef struct {
    real_t wc_rad_s;          /**< corner of the voltage-model leak and of the high-pass, rad/s (> 0) */
    real_t flux_err_frac;     /**< trip when the filtered flux error exceeds this x psi_ref (0 = off) */
    real_t time_s;            /**< ... for this long, s */
    real_t rs_tol_frac;       /**< Rs error tolerated without a trip, fraction of Rs (adds
                                   rs_tol_frac Rs |is| / max(|omega_s|, wc) to the level) */
    real_t v_tol_V;           /**< error of the applied-voltage model tolerated, V (device drops
                                   and dead time, not compensated: adds v_tol_V / max(|omega_s|, wc)) */
    /* derived by ctl_guard_cfg_derive() */
    real_t wc_T;              /**< wc_rad_s x period, 0..1 */
    real_t w_lpf;             /**< stator-frequency low-pass coefficient (50 Hz) over a window, 0..1 */
    real_t window_s;          /**< CTL_GUARD_WINDOW_MAX x period: a window, s */
    real_t leak;              /**< CTL_GUARD_WINDOW_MAX x wc_T: the leak over a window, 0..4 */
    real_t w_lpf_per_s;       /**< w_lpf / window_s, 1/s */
    real_t two_wc_rad_s;      /**< 2 x wc_rad_s: judged only above this stator frequency, rad/s */
    real_t trip_time_s;       /**< time_s, or FLT_MAX when off (flux_err_frac 0), s */
} ctl_guard_cfg;

/** State of the monitor (part of ctl_state). */
typedef struct {
    real_t psi_vm_Wb[2];      /**< leaky-integrated voltage-model stator flux, Wb */
    real_t psi_obs_lp_Wb[2];  /**< low-passed observer stator flux (hp = flux - this), Wb */
    real_t err_Wb;            /**< |psi_vm - hp(psi_obs)| at the last check, Wb */
    real_t t_above_s;         /**< time the error has been above the trip level, s */
    real_t omega_s_rad_s;     /**< stator frequency of psi_vm (electrical), low-passed, rad/s */
    real_t tol_Wb;            /**< trip level of the last check, Wb */
    real_t sum_v_V[2];        /**< sum of the applied voltages of the window's ticks, V */
    real_t sum_is_A[2];       /**< sum of the sampled currents of the window's ticks, A */
} ctl_guard;

/** Derive wc_T and the per-window constants from @p period_s (the period ctl_guard_check is given). Context: BG. */
void ctl_guard_cfg_derive(ctl_guard_cfg *cfg, real_t period_s);

/** Zero the state (at a start). Context: ANY. */
void ctl_guard_reset(ctl_guard *g);

/**
 * Add one period to the window: the voltage applied from t_k to t_{k+1} and
 * the current sampled at t_k, alpha-beta (V, A). Every tick the monitor runs,
 * after the check if this tick has one. Context: ISR.
 */
void ctl_guard_accumulate(ctl_guard *g, const real_t v_V[2], const real_t is_A[2]);

/**
 * Close the window (the ticks accumulated since the last check: the caller
 * calls this every CTL_GUARD_WINDOW_MAX ticks; the first window after a
 * reset may hold fewer, the rest of the window's ticks are not counted):
 * integrate its volt-seconds, compare the fluxes at t_k, judge.
 * Context: ISR.
 * @param period_s  the control period, s
 * @param is_A      stator current sampled at t_k, alpha-beta, A (the trip level's Rs term)
 * @param rs_ohm    stator resistance in use (the observer's), ohm
 * @param psi_obs_Wb the observer's stator flux at t_k, alpha-beta, Wb
 * @param psi_ref_Wb the flux reference, Wb (sets the trip level)
 * @param judge     false while magnetising: filters run, no verdict
 * @return true when the error has stayed above the level for time_s
 */
bool ctl_guard_check(ctl_guard *g, const ctl_guard_cfg *cfg, real_t period_s, const real_t is_A[2], real_t rs_ohm,
                     const real_t psi_obs_Wb[2], real_t psi_ref_Wb, bool judge);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CTL_GUARD_H */
