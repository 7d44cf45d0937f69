/**
 * @file ctl_guard.c
 * @brief Loss-of-control monitor: voltage-model flux against the observer's.
 */
#include "dtc/ctl_guard.h"

#include <float.h>

void ctl_guard_cfg_derive(ctl_guard_cfg *cfg, real_t period_s)
{
    real_t a = num_mul(cfg->wc_rad_s, period_s);
    cfg->wc_T = num_sat(a, R(0.0), R(1.0));
    cfg->two_wc_rad_s = R(2.0) * cfg->wc_rad_s;
    real_t window_s = num_mul((real_t)CTL_GUARD_WINDOW_MAX, period_s);
    cfg->window_s = window_s;
    cfg->leak = num_mul((real_t)CTL_GUARD_WINDOW_MAX, cfg->wc_T);
    /* 1 - exp(-2 pi 50 Hz x window): the stator-frequency low-pass per window */
    cfg->w_lpf = num_sat(R(1.0) - num_exp(-num_mul(R(314.159265), window_s)), R(0.0), R(1.0));
    /* the same over the window's duration: the frequency's division by the window folded in */
    cfg->w_lpf_per_s = num_div(cfg->w_lpf, window_s);
    /* off (flux_err_frac 0): a time never reached, instead of a test per check */
    cfg->trip_time_s = cfg->flux_err_frac > R(0.0) ? cfg->time_s : FLT_MAX;
}

void ctl_guard_reset(ctl_guard *g)
{
    g->psi_vm_Wb[0] = g->psi_vm_Wb[1] = R(0.0);
    g->psi_obs_lp_Wb[0] = g->psi_obs_lp_Wb[1] = R(0.0);
    g->err_Wb = R(0.0);
    g->t_above_s = R(0.0);
    g->omega_s_rad_s = R(0.0);
    g->tol_Wb = R(0.0);
    g->sum_v_V[0] = g->sum_v_V[1] = R(0.0);
    g->sum_is_A[0] = g->sum_is_A[1] = R(0.0);
}

void ctl_guard_accumulate(ctl_guard *g, const real_t v_V[2], const real_t is_A[2])
{
    g->sum_v_V[0] += v_V[0];
    g->sum_v_V[1] += v_V[1];
    g->sum_is_A[0] += is_A[0];
    g->sum_is_A[1] += is_A[1];
}

bool ctl_guard_check(ctl_guard *g, const ctl_guard_cfg *cfg, real_t period_s, const real_t is_A[2], real_t rs_ohm,
                     const real_t psi_obs_Wb[2], real_t psi_ref_Wb, bool judge)
{
    /* the window: CTL_GUARD_WINDOW_MAX ticks in the caller's schedule, taken as such also in
     * the first window after a reset, which may hold fewer (no tick count kept):
     * psi_vm and the frequency start from zero, so only the observer flux's low-pass takes
     * up to 3 ticks too many of its 1 Hz corner once (<= 0.4 % of that flux) */
    real_t a = cfg->leak; /* the leak over the window (1 - wc T)^n to first order */
    real_t window_s = cfg->window_s;
    real_t prev[2] = {g->psi_vm_Wb[0], g->psi_vm_Wb[1]};
    real_t d[2];
    for (int i = 0; i < 2; i++) {
        /* psi_vm' = v - Rs is - wc psi_vm (s / (s + wc) of the machine's flux), on to t_k:
         * the volt-seconds of the window are exact (v is constant over each period) */
        real_t emf_sum = num_mac(-rs_ohm, g->sum_is_A[i], g->sum_v_V[i]);
        g->psi_vm_Wb[i] = num_mac(period_s, emf_sum, num_mac(-a, prev[i], prev[i]));
        /* the same high-pass on the observer's flux: psi - lowpass(psi), sampled at the checks */
        g->psi_obs_lp_Wb[i] = num_mac(a, psi_obs_Wb[i] - g->psi_obs_lp_Wb[i], g->psi_obs_lp_Wb[i]);
        /* both at t_k */
        d[i] = g->psi_vm_Wb[i] - (psi_obs_Wb[i] - g->psi_obs_lp_Wb[i]);
    }
    real_t e2 = num_mac(d[0], d[0], num_mul(d[1], d[1]));
    /* a sum of squares, never negative: the bare square root (num_sqrt's clamp would map
     * a NaN, a broken voltage or current, to 0, and NaN must stay NaN) */
    g->err_Wb = sqrtf(e2);

    /* stator frequency of the machine's flux: rotation of psi_vm over the
     * window, low-passed (the PWM ripple of one period is ~10 % of the flux) */
    real_t n2 = num_mac(prev[0], prev[0], num_mul(prev[1], prev[1]));
    real_t cr = num_mac(prev[0], g->psi_vm_Wb[1], -num_mul(prev[1], g->psi_vm_Wb[0]));
    real_t w_dt = n2 > R(1e-4) ? num_div(cr, n2) : R(0.0); /* the rotation over the window, rad */
    real_t omega_s = num_mac(cfg->w_lpf_per_s, w_dt, num_mac(-cfg->w_lpf, g->omega_s_rad_s, g->omega_s_rad_s));
    g->omega_s_rad_s = omega_s;
    /* an Rs error dR gives a flux error up to dR |is| / |omega_s| through
     * the integrator (at most dR |is| / wc): allowed for rs_tol_frac of Rs */
    real_t wabs = num_abs(omega_s);
    /* Near standstill the voltage model integrates mostly the voltage errors
     * (device drops, dead time) and the leak: judged only above twice its corner. */
    bool slow = wabs < cfg->two_wc_rad_s;
    if (wabs < cfg->wc_rad_s)
        wabs = cfg->wc_rad_s;
    real_t is_abs = sqrtf(num_mac(is_A[0], is_A[0], num_mul(is_A[1], is_A[1]))); /* as err_Wb */
    /* an error dV of the applied voltage (device drops, dead time: neither is
     * compensated) integrates the same way: at most dV / |omega_s| */
    g->tol_Wb = num_mac(cfg->flux_err_frac, psi_ref_Wb,
                        num_div(num_mac(num_mul(cfg->rs_tol_frac, rs_ohm), is_abs, cfg->v_tol_V), wabs));
    /* not judged when slow: a level no error reaches, but a NaN error (written so that it
     * counts as above) is judged at any frequency */
    real_t level_Wb = slow ? FLT_MAX : g->tol_Wb;
    bool trip = false;
    if (!judge || g->err_Wb <= level_Wb) {
        g->t_above_s = R(0.0);
    } else {
        g->t_above_s += window_s; /* the whole window counts */
        trip = g->t_above_s >= cfg->trip_time_s;
    }
    /* The next window's sums start at -0.0: x + -0.0 is x exactly, so the additions of the
     * accumulate that follows in the control step fold away and, with these stores the
     * last thing here (no load of cfg after them), these stores too. */
    g->sum_v_V[0] = g->sum_v_V[1] = R(-0.0);
    g->sum_is_A[0] = g->sum_is_A[1] = R(-0.0);
    return trip;
}
