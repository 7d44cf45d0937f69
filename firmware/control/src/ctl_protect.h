/**
 * @file ctl_protect.h
 * @brief The control step's protection: this tick's fault conditions from the
 *        inputs, the sample's limits, the estimated speed and the slow
 *        monitors' verdicts; the current sensors' plausibility; the latch.
 *        Private to firmware/control (ctl.c runs it first in every tick).
 *
 * Detection and reaction of each fault: docs/faults.md. A latched fault holds
 * the core FAULTED, gates off, until ctl_clear_faults() finds its cause gone.
 */
#ifndef DTC_CTL_PROTECT_H
#define DTC_CTL_PROTECT_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/ctl.h"

/**
 * This tick's fault conditions but the sensors' plausibility (enum ctl_fault
 * bits): the hardware fault input, an overrun, a stale sample; on a fresh
 * sample its limits (SAMPLE_INVALID alone when a value is not a number), then
 * while magnetising or running the estimated speed against overspeed_rad_s
 * and the slow monitors' last verdicts (s->monitor_faults).
 * @param judged out: true when the sample was judged (fresh, every value a
 *               number): then the tick's slot advances and
 *               ctl_protect_plausibility() follows.
 * Context: ISR.
 */
uint32_t ctl_protect_detect(const ctl_state *s, const ctl_cfg *cfg, const ctl_in *in, bool *judged);

/**
 * The current sensors' plausibility on a judged sample @p x (plaus_check:
 * CURRENT_SENSOR, PHASE_LOSS, DC_DIVIDER bits), its current checks in this
 * tick's slot of s->slow_slot (ctl_slot_plaus). Context: ISR.
 */
uint32_t ctl_protect_plausibility(ctl_state *s, const ctl_cfg *cfg, const hal_sample *x);

/**
 * Latch this tick's fault conditions @p f (enum ctl_fault bits): kept as the
 * conditions present (s->faults_active), added to the latched faults; any
 * latched fault makes the core FAULTED. @return true when the gates must be
 * off in this tick. Context: ISR.
 */
bool ctl_protect_latch(ctl_state *s, uint32_t f);

#endif /* DTC_CTL_PROTECT_H */
