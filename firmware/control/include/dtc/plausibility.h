/**
 * @file plausibility.h
 * @brief Sensor plausibility checks of the control tick: the current sum of
 *        three sensors, stuck current readings, an open motor phase, and the
 *        capacitor-voltage dividers while the drive is stopped.
 *
 * What each check can and cannot see (docs/faults.md has the table):
 *  - current sum: with a star-connected motor and no neutral, ia + ib + ic = 0.
 *    An offset or gain error on ONE sensor shows as a sum; the same error on
 *    all three, or a gain error during zero current, does not.
 *  - stuck: a reading that repeats bit for bit for PLAUS_STUCK_TICKS while
 *    current flows (the switching ripple always moves a live sensor).
 *  - phase loss: one phase near 0 A for longer than half an electrical period
 *    while the others carried current (the magnitude exceeded
 *    PLAUS_CURRENT_A meanwhile); not judged below PLAUS_PHASE_MIN_HZ, where a
 *    healthy phase may sit near zero for long.
 *  - DC dividers: while stopped (no neutral-point current) the two capacitors
 *    share the link equally, so |vc1 - vc2| beyond PLAUS_DIVIDER_REL of the
 *    link is a divider or sensor error. A common error of both dividers keeps
 *    them balanced and is visible only against the supply (over/under-voltage).
 *
 * Rate: the current checks judge every PLAUS_CHECK_TICKS-th tick (the
 * control step's schedule of the slow tasks, dtc/ctl_schedule.h) and count in ticks, PLAUS_CHECK_TICKS
 * per check: the sum trips on the third implausible check in a row (12 ticks,
 * within 11 ticks of the first implausible sample), a stuck reading is
 * compared with the one PLAUS_CHECK_TICKS ticks before; the divider check
 * runs every tick while stopped (a start must not slip through between checks).
 * Context: ISR (called from ctl_step).
 */
#ifndef DTC_PLAUSIBILITY_H
#define DTC_PLAUSIBILITY_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/num.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PLAUS_CHECK_TICKS 4u        /**< the current checks run every this many ticks */
#define PLAUS_SUM_ABS_A R(5.0)      /**< current-sum tolerance: 5 A ... */
#define PLAUS_SUM_REL R(0.05)       /**< ... + 5 % of the current magnitude */
#define PLAUS_SUM_TICKS 10u         /**< ... for this many ticks in a row (2 ms at 200 us) */
#define PLAUS_STUCK_TICKS 100u      /**< identical current readings in a row while current flows (20 ms) */
#define PLAUS_CURRENT_A R(3.0)      /**< "current flows": magnitude above this, A */
#define PLAUS_OPEN_A R(0.5)         /**< a phase below this while the others flow is "open", A */
#define PLAUS_PHASE_MIN_HZ R(2.0)   /**< phase loss is judged above this electrical frequency, Hz */
#define PLAUS_OPEN_MIN_TICKS 50u    /**< and for at least this many ticks (10 ms) */
#define PLAUS_DIVIDER_REL R(0.03)   /**< |vc1 - vc2| / (vc1 + vc2) allowed while stopped */

/** Caller-owned state of the checks. */
typedef struct {
    uint16_t sum_ticks;       /**< ticks in a row with an implausible current sum */
    uint16_t stuck_ticks[3];  /**< ticks in a row with a repeated reading, per phase */
    uint16_t open_ticks[3];   /**< ticks in a row with a phase near 0 A */
    float open_peak_A[3];     /**< largest current magnitude seen meanwhile, A */
    float last_A[3];          /**< the readings of the previous check, A */
    bool cleared;             /**< the history is plaus_reset()'s and no check ran since: a stopped
                                   or faulted tick need not write it again */
} plaus_state;

/** Forget the history (at every start). Context: ISR or BG. */
void plaus_reset(plaus_state *p);

/**
 * Check this tick's sample.
 * @param active the drive is magnetising or running (current checks apply)
 * @param stopped the drive is stopped (the divider check applies)
 * @param omega_e_rad_s electrical frequency of the stator quantities, rad/s
 * @param period_s the control period, s
 * @param check this is a tick of the current checks (every PLAUS_CHECK_TICKS-th)
 * @return CTL_FAULT_CURRENT_SENSOR, CTL_FAULT_PHASE_LOSS, CTL_FAULT_DC_DIVIDER bits
 *         (dtc/ctl.h), 0 when plausible. Context: ISR.
 */
uint32_t plaus_check(plaus_state *p, const hal_sample *x, bool active, bool stopped, real_t omega_e_rad_s,
                     real_t period_s, bool check);

#ifdef __cplusplus
}
#endif

#endif /* DTC_PLAUSIBILITY_H */
