/**
 * @file ctl_supervise.c
 * @brief The supervision of the operating point (see ctl_supervise.h): the
 *        flux target with field weakening and its voltage-margin trim, the
 *        lowered flux for regeneration near zero stator frequency, the torque
 *        limit, the flux ramp, the stall windows and the switching-frequency
 *        regulation.
 */
#include "ctl_supervise.h"

#include "dtc/ctl_schedule.h"
#include "dtc/npc.h"
#include "real_bits.h"

/* Lowered flux for regeneration near zero stator frequency. A load driving
 * the motor at low speed puts the stator frequency (rotor speed minus the
 * slip) near zero, where the speed estimate drifts (the machine is not
 * observable there; docs/envelope.md section 6). The slip grows as 1/flux^2
 * at a given torque, so a lower flux takes the stator frequency through zero
 * to the side opposing the rotation, LOWFLUX_MARGIN_RAD_S beyond it, where
 * the observer holds the speed. Decided on the rated-flux slip of the torque
 * command and the estimated speed (neither moves with the flux, so the
 * decision does not feed back on itself), with hysteresis; only where a flux
 * of at least regen_flux_min_frac x rated reaches the margin (the torque
 * limit at that flux stays above the rated torque). Returns the flux factor
 * (1 = rated) and sets the observer's regen_low_flux. */
#define LOWFLUX_MARGIN_RAD_S R(2.5)    /* stator frequency aimed at: 0.4 Hz against the rotation */
#define LOWFLUX_ENTER_RAD_S R(6.3)     /* rated-flux stator frequency below which it starts, 1.0 Hz */
#define LOWFLUX_EXIT_RAD_S R(8.8)      /* ... and above which it ends, 1.4 Hz */
#define LOWFLUX_EXIT_K2 R(0.92)        /* hysteresis of the reach test, x regen_k2_min */
#define LOWFLUX_MIN_NM R(2.0)          /* below this the sign of the command is noise */
static real_t regen_flux_factor(ctl_state *s, const ctl_cfg *cfg)
{
    real_t w = s->obs.omega_e_rad_s;
    real_t te = s->te_ref_Nm;
    bool regen = s->run_state == CTL_RUNNING && (w >= R(0.0) ? te < -LOWFLUX_MIN_NM : te > LOWFLUX_MIN_NM);
    if (!regen || !(cfg->regen_flux_min_frac < R(1.0))) { /* the usual case, and cheap */
        s->obs.regen_low_flux = false;
        return R(1.0);
    }
    real_t a = num_abs(w);
    real_t slip = num_mul(num_abs(te), cfg->slip_rad_s_per_Nm);
    real_t k2 = num_div(slip, a + LOWFLUX_MARGIN_RAD_S);
    bool on = s->obs.regen_low_flux ? (a - slip < LOWFLUX_EXIT_RAD_S && k2 >= num_mul(LOWFLUX_EXIT_K2, cfg->regen_k2_min))
                                    : (a - slip < LOWFLUX_ENTER_RAD_S && k2 >= cfg->regen_k2_min);
    s->obs.regen_low_flux = on;
    if (!on || k2 >= R(1.0))
        return R(1.0);
    return num_sqrt(k2 > cfg->regen_k2_min ? k2 : cfg->regen_k2_min);
}

/* Once per slot cycle: the operating point moves slowly against that. */
void ctl_supervise_operating_point(ctl_state *s, const ctl_cfg *cfg, const hal_sample *x)
{
    /* Voltage margin: a DTC that keeps falling short of the torque command
     * by more than the band has no voltage left to raise the torque; the
     * weakening flux is then trimmed down (and recovers when it is not).
     * The shortfall is the mean of the ticks since the last step. */
    real_t short_Nm = num_mul(s->short_sum_Nm, R(1.0) / (real_t)CTL_SLOW_SLOTS);
    s->short_sum_Nm = R(0.0);
    s->te_short_Nm = num_mac(cfg->sup_lpf_a, short_Nm - s->te_short_Nm, s->te_short_Nm);
    real_t over = num_div(s->te_short_Nm - cfg->dtc.torque_band2_Nm, cfg->speed.te_max_Nm);
    s->fw_trim = num_sat(s->fw_trim - num_mul(cfg->sup_rate_T, over), R(0.85), R(1.0));

    real_t target = num_mul(cfg->dtc.psi_ref_Wb, regen_flux_factor(s, cfg));
    real_t v_max = num_mul(num_mul(cfg->fw_v_per_vdc, s->fw_trim), x->vc1_V + x->vc2_V);
    real_t w = num_abs(s->obs.omega_e_rad_s);
    if (num_mul(target, w) > v_max)
        target = num_div(v_max, w);
    s->psi_target_Wb = target;
    real_t psi = s->dtc_cmd.psi_ref_Wb;
    real_t te_po = num_mul(cfg->te_limit_Nm_Wb2, num_mul(psi, psi));
    s->te_limit_Nm = te_po < cfg->speed.te_max_Nm ? te_po : cfg->speed.te_max_Nm;
}

void ctl_ramp_flux_reference(ctl_state *s, const ctl_cfg *cfg)
{
    s->short_sum_Nm += num_abs(s->te_ref_Nm) - num_abs(s->obs_out.te_Nm);
    /* at the target (most ticks) the clamp would return the target's very bits: skipped,
     * judged on the bits (a NaN stays NaN, -0 stays -0) */
    if (f32_bits(s->psi_target_Wb) == f32_bits(s->dtc_cmd.psi_ref_Wb))
        return;
    real_t dpsi = cfg->psi_ramp_step_Wb;
    s->dtc_cmd.psi_ref_Wb = num_sat(s->psi_target_Wb, s->dtc_cmd.psi_ref_Wb - dpsi, s->dtc_cmd.psi_ref_Wb + dpsi);
}

/* Speed error beyond which a torque command at the limit counts towards a stall: 3 rad/s = 29 rpm. */
#define STALL_SPEED_ERR_RAD_S R(3.0)
#define STALL_WINDOW_S R(0.1)

/* Braking at the torque limit, off speed, at low speed, and the (estimated)
 * speed does not fall at all over BRAKE_STALL_TIME_S: the load drives the
 * machine harder than the drive can brake, or the estimate no longer follows
 * a shaft the load is running away with (a rated generating load at 100 rpm:
 * the estimate stays near 130 rpm while the shaft passes 1000 rpm within
 * 0.3 s). Only below BRAKE_STALL_SPEED_RAD_S (477 rpm), where the
 * loss-of-control monitor is blind at low stator frequency; above it the
 * stall timer and that monitor judge. A deceleration at the limit lowers the
 * filtered estimate in every window, however large the inertia (at 1 rad/s^2
 * by 0.1 rad/s), so it does not trip this. */
#define BRAKE_STALL_TIME_S R(0.1)
#define BRAKE_STALL_SPEED_RAD_S R(50.0)
static void brake_stall_step(ctl_state *s, const ctl_cfg *cfg, bool at_limit, bool off_speed, real_t T)
{
    real_t w = num_abs(s->obs.omega_m_filt_rad_s);
    bool braking = num_mul(s->te_ref_Nm, s->obs.omega_m_filt_rad_s) < R(0.0);
    if (!(at_limit && cfg->stall_time_s > R(0.0) && braking && w < BRAKE_STALL_SPEED_RAD_S)) {
        s->t_brake_limit_s = R(0.0);
        return;
    }
    if (!off_speed)
        return; /* on speed at the limit: full braking power, the window waits */
    if (s->t_brake_limit_s == R(0.0))
        s->w_brake_start_rad_s = w;
    s->t_brake_limit_s += T;
    if (s->t_brake_limit_s < BRAKE_STALL_TIME_S)
        return;
    if (!(w < s->w_brake_start_rad_s))
        s->brake_stall = true;
    s->t_brake_limit_s = R(0.0); /* next window */
}

/* Counted in windows of STALL_WINDOW_S: a window whose error shrank (an
 * acceleration or deceleration at the limit, however slow) does not count, nor
 * does time at the limit on speed (full power); leaving the limit restarts the
 * count. Off speed is judged on the filtered estimate: a noisy estimate
 * hovering at the threshold would restart a plain timer for ever (100 rpm with
 * the rated load generating ran away with no trip). In its own slot, not the
 * speed command's, on the command held since. */
void ctl_stall_step(ctl_state *s, const ctl_cfg *cfg, real_t T)
{
    bool at_limit = num_abs(s->te_ref_Nm) >= num_mul(R(0.98), s->te_limit_Nm);
    real_t err = num_abs(s->speed_ref_ramped_rad_s - s->obs.omega_m_filt_rad_s);
    bool off_speed = err > STALL_SPEED_ERR_RAD_S;
    if (!at_limit) {
        s->t_at_limit_s = R(0.0);
        s->t_stall_win_s = R(0.0);
    } else if (off_speed) {
        if (s->t_stall_win_s == R(0.0))
            s->err_win_start_rad_s = err;
        s->t_stall_win_s += T;
        if (s->t_stall_win_s >= STALL_WINDOW_S) {
            if (!(err < s->err_win_start_rad_s))
                s->t_at_limit_s += s->t_stall_win_s;
            s->t_stall_win_s = R(0.0);
        }
    }
    brake_stall_step(s, cfg, at_limit, off_speed, T);
    /* the verdict, judged here where its inputs change rather than every tick: the rare
     * conditions first, the configuration's switch-off last */
    bool stall = (s->brake_stall || s->t_at_limit_s >= cfg->stall_time_s) && cfg->stall_time_s > R(0.0);
    s->monitor_faults = (s->monitor_faults & ~(uint32_t)CTL_FAULT_STALL) | (stall ? (uint32_t)CTL_FAULT_STALL : 0u);
}

/* Windows of the speed-deviation count: the stall's. A window counts unless
 * its error shrank by more than the band's share of the window
 * (speed_dev_band x window / speed_dev_time: a recovery that would reach the
 * band within the time), so that the estimate's noise on a lasting error
 * (+-1.5 rpm at 41 N m) does not halve the count. At the torque limit the
 * count holds: the stall monitor judges there (an acceleration at the limit
 * however slow is not a deviation). */
#define SPEED_DEV_WINDOW_S STALL_WINDOW_S
void ctl_speed_dev_step(ctl_state *s, const ctl_cfg *cfg, real_t T)
{
    real_t ref = s->speed_ref_ramped_rad_s;
    real_t err = num_abs(ref - s->obs.omega_m_filt_rad_s);
    bool ramping = f32_bits(ref) != f32_bits(s->dev_ref_prev_rad_s);
    s->dev_ref_prev_rad_s = ref;
    if (!(cfg->speed_dev_time_s > R(0.0)) || err <= cfg->speed_dev_band_rad_s) {
        s->t_dev_s = R(0.0);
        s->t_dev_win_s = R(0.0);
        s->warnings &= ~(uint32_t)CTL_WARN_SPEED_DEV;
        return;
    }
    /* beyond the band (a NaN estimate too: the overspeed trip has it first) */
    if (ramping || num_abs(s->te_ref_Nm) >= num_mul(R(0.98), s->te_limit_Nm)) {
        s->t_dev_win_s = R(0.0); /* the count holds; a new window starts when the ramp rests */
        return;
    }
    if (s->t_dev_win_s == R(0.0))
        s->err_dev_win_start_rad_s = err;
    s->t_dev_win_s += T;
    if (s->t_dev_win_s < SPEED_DEV_WINDOW_S)
        return;
    if (!(err < s->err_dev_win_start_rad_s - num_mul(cfg->speed_dev_shrink_rad_s_per_s, s->t_dev_win_s)))
        s->t_dev_s += s->t_dev_win_s;
    s->t_dev_win_s = R(0.0);
    if (s->t_dev_s >= num_mul(R(0.5), cfg->speed_dev_time_s))
        s->warnings |= (uint32_t)CTL_WARN_SPEED_DEV;
    if (s->t_dev_s >= cfg->speed_dev_time_s)
        s->monitor_faults |= (uint32_t)CTL_FAULT_SPEED_DEV;
}

/* The 20 ms filter and the 5 1/s band rate need no per-tick step: the sum of
 * the leg changes is the only per-tick work. */
void ctl_regulate_switching_frequency(ctl_state *s, const ctl_cfg *cfg, uint8_t prev_state, uint8_t a0, uint8_t a1)
{
    uint32_t n = s->fsw_changes + npc_leg_changes_unchecked(prev_state, a0); /* all three 0..26 */
    if (a1 != a0)
        n += npc_leg_changes_unchecked(a0, a1);
    if (!ctl_slot_fsw(s->slow_slot)) {
        s->fsw_changes = (uint8_t)n; /* at most 4 x 12 */
        return;
    }
    s->fsw_changes = 0u;
    real_t f = num_mul(num_mul((real_t)n, cfg->fsw_per_change_hz), R(1.0) / (real_t)CTL_SLOW_SLOTS);
    s->fsw_hz = num_mac(cfg->fsw_lpf_a, f - s->fsw_hz, s->fsw_hz);
    if (!(cfg->fsw_max_hz > R(0.0))) {
        s->dtc_cmd.band_scale = R(1.0);
        return;
    }
    real_t rel = num_mul(s->fsw_hz, cfg->inv_fsw_max_s) - R(1.0);
    real_t k = num_mul(cfg->band_rate_T, s->dtc_cmd.band_scale);
    s->dtc_cmd.band_scale = num_sat(num_mac(k, rel, s->dtc_cmd.band_scale), R(1.0), cfg->band_scale_max);
}

