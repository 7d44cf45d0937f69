/**
 * @file ctl_supervise.h
 * @brief The supervision of the operating point: what flux the DTC is given
 *        and how fast it gets there, the torque limit, whether the speed loop
 *        has stalled, and how wide the torque bands are. Private to
 *        firmware/control (ctl.c runs each in its slot, dtc/ctl_schedule.h).
 *
 * All of them move slowly against the tick (docs/envelope.md): the flux
 * target, the torque limit and the band scale step once per slot cycle on
 * what the ticks in between summed, the stall windows once per speed-loop
 * step; only the flux reference's ramp and the sums run every tick.
 */
#ifndef DTC_CTL_SUPERVISE_H
#define DTC_CTL_SUPERVISE_H

#include <stdint.h>

#include "dtc/ctl.h"

/**
 * One supervision step (in the slot ctl_slot_supervise): the flux target,
 * rated (lowered while regenerating near zero stator frequency) or what the
 * measured DC link (@p x's vc1 + vc2) allows at the present speed (field
 * weakening, trimmed down while the DTC keeps falling short of the torque
 * command), whichever is lower, into s->psi_target_Wb (Wb); then the torque
 * limit at the flux reference into s->te_limit_Nm (N m). Context: ISR.
 */
void ctl_supervise_operating_point(ctl_state *s, const ctl_cfg *cfg, const hal_sample *x);

/**
 * Every tick: the torque shortfall summed for the supervision step, and the
 * flux reference (s->dtc_cmd.psi_ref_Wb, Wb) slew-limited towards its target
 * (psi_ramp_step_Wb per tick) so that magnetising does not trip. Context: ISR.
 */
void ctl_ramp_flux_reference(ctl_state *s, const ctl_cfg *cfg);

/**
 * One step of the stall windows (in the slots ctl_slot_stall, once per
 * speed-loop step of @p T s), on the command held since the last speed
 * command and this tick's filtered estimate; sets or clears
 * CTL_FAULT_STALL in s->monitor_faults. A command pinned at the limit while
 * the speed stays away from its reference, and does not come nearer, means
 * the loop cannot hold the speed it is asked for (overload, pull-out, or an
 * estimate that no longer moves with the shaft); so does braking at the limit
 * at low speed without the machine slowing. Off when stall_time_s is 0.
 * Context: ISR.
 */
void ctl_stall_step(ctl_state *s, const ctl_cfg *cfg, real_t T);

/**
 * One step of the speed-deviation supervision (in the slot ctl_slot_speed_dev,
 * once per slot cycle of @p T s, on the command held since the last speed
 * command): the error
 * |ramped reference - filtered estimate| beyond speed_dev_band_rad_s (rad/s)
 * is counted while the ramp stands still, in windows of 0.1 s; a window in
 * which the error shrank (a recovery, an acceleration at the limit) does not
 * count, a moving ramp holds the count, an error back inside the band clears
 * it. Half of speed_dev_time_s sets CTL_WARN_SPEED_DEV in s->warnings, all of
 * it CTL_FAULT_SPEED_DEV in s->monitor_faults. It only observes: nothing of
 * the control changes until the fault. Off when speed_dev_time_s is 0.
 * Context: ISR.
 */
void ctl_speed_dev_step(ctl_state *s, const ctl_cfg *cfg, real_t T);

/**
 * Every tick, with the actuation just latched (states @p a0, @p a1 after
 * @p prev_state, all 0..26): its leg changes summed; in the slot ctl_slot_fsw
 * their mean low-passed as a device switching frequency (s->fsw_hz, Hz) and
 * the torque bands' scale (s->dtc_cmd.band_scale, 1..band_scale_max)
 * stepped: wider above fsw_max_hz, back towards the configured bands below
 * it (integral action). The bands thereby follow speed and load: the torque
 * slopes, and with them the switching rate for a given band, grow with the
 * back-emf and the current. Context: ISR.
 */
void ctl_regulate_switching_frequency(ctl_state *s, const ctl_cfg *cfg, uint8_t prev_state, uint8_t a0, uint8_t a1);

#endif /* DTC_CTL_SUPERVISE_H */
