/**
 * @file ctl_bringup.h
 * @brief The control step at bring-up levels 1-4 (dtc/bringup.h). Private to
 *        firmware/control (ctl.c calls it in place of the running step).
 */
#ifndef DTC_CTL_BRINGUP_H
#define DTC_CTL_BRINGUP_H

#include "dtc/ctl.h"

/**
 * One tick of a started core at bring-up level 1..4 (cfg->bringup_level):
 * no magnetising, no speed or torque control, no loss-of-control monitor;
 * the actuation is the gate-test pattern (level 1), nothing (level 2: gates
 * off, the samples in telemetry), or open-loop V/f with the observer running
 * (levels 3 and 4), behind the P<->N guard. The core reports RUNNING.
 * Context: ISR (from ctl_step, after the protection).
 */
void ctl_bringup_step(ctl_state *s, const ctl_cfg *cfg, const ctl_in *in, ctl_out *out);

#endif /* DTC_CTL_BRINGUP_H */
