/**
 * @file ctl_schedule.h
 * @brief The slots in which the control step's slow tasks take turns.
 *
 * Tick k has slot k mod CTL_SLOW_SLOTS (an 8-tick cycle, 1.6 ms at 200 us),
 * and each slow task does its heavy part in its own slots only, so that no
 * tick carries two heavy ones (the RBFN's learning, the supervision and the
 * regulation are lighter than the speed command or a monitor):
 *
 *   slot   0      1        2        3           4      5        6        7
 *          guard  speed    plaus    RBFN learn  guard  speed    plaus    RBFN learn
 *                 command  + stall  + supervise        command  + stall  + FSW + level
 *                                                                        + speed dev
 *
 *  - guard: the loss-of-control monitor closes its window and judges
 *    (dtc/ctl_guard.h; it sums its inputs every tick), every
 *    CTL_GUARD_WINDOW_MAX ticks;
 *  - plaus: the current plausibility checks (dtc/plausibility.h), every
 *    PLAUS_CHECK_TICKS ticks: the monitors' windows and latencies are those
 *    of a 4-tick cycle;
 *  - speed command: the speed loop steps every CTL_RBFN_TICKS ticks (800 us,
 *    1.25 kHz), whatever the controller, never with a monitor;
 *  - RBFN learn: the RBFN's weight and bound updates of that command, before
 *    the next command (the same updates wherever they sit in between; only the
 *    telemetry's |W| and zeta_bar wait for them; docs/speed_control.md, "Rate");
 *  - stall: the stall windows step once per speed-loop step, on the command
 *    held since its slot, with the plausibility checks (the lightest slots);
 *  - supervise: the supervision of the operating point (flux target with
 *    field weakening, the lowered flux while regenerating near zero stator
 *    frequency, the torque limit) steps once per cycle on what the ticks in
 *    between summed, beside neither a monitor nor the speed command (the flux
 *    reference ramps to its target every tick);
 *  - FSW: the switching-frequency regulation steps the band scale once per
 *    cycle on the mean of the leg changes summed every tick;
 *  - level: the DTC decides its voltage level (the back-emf against the link
 *    voltage, with hysteresis; a division and two compares, beside the
 *    RBFN's learning, the lightest of the slow tasks);
 *  - speed dev: the speed-deviation supervision steps once per cycle (its
 *    0.1 s windows need no more), in the slot of the lightest tasks.
 *
 * The slot advances once per tick that judges a sample (ctl_step: a fresh
 * sample whose values are all numbers), by ctl_schedule_next; the predicates
 * below are the only tests of a slot. Every function is pure; Context: ANY.
 */
#ifndef DTC_CTL_SCHEDULE_H
#define DTC_CTL_SCHEDULE_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/ctl_guard.h"
#include "dtc/plausibility.h"

#ifdef __cplusplus
extern "C" {
#endif

#define CTL_SLOW_SLOTS 8u    /**< slots of the cycle: ticks 0..7 */
#define CTL_MONITOR_SLOTS 4u /**< the monitors' cycle: CTL_GUARD_WINDOW_MAX = PLAUS_CHECK_TICKS */
#define CTL_SLOT_GUARD 0u    /**< modulo CTL_MONITOR_SLOTS: slots 0 and 4 */
#define CTL_SLOT_PLAUS 2u    /**< modulo CTL_MONITOR_SLOTS: slots 2 and 6 */
#define CTL_RBFN_TICKS 4u    /**< ticks per speed-loop step, every controller's (a power of 2) */
#define CTL_SLOT_RBFN 1u     /**< modulo CTL_RBFN_TICKS: the speed command, slots 1 and 5 */
#define CTL_SLOT_RBFN_LEARN 3u /**< modulo CTL_RBFN_TICKS: the RBFN's learning, slots 3 and 7 */
#define CTL_SLOT_STALL 2u    /**< modulo CTL_RBFN_TICKS: the stall windows, slots 2 and 6 */
#define CTL_SLOT_SUPERVISE 3u /**< the supervision of the operating point */
#define CTL_SLOT_FSW 7u      /**< the switching-frequency regulation */
#define CTL_SLOT_LEVEL 7u    /**< the DTC's voltage level */
#define CTL_SLOT_SPEED_DEV 7u /**< the speed-deviation supervision (beside the lightest tasks) */

#ifndef __cplusplus
_Static_assert(CTL_GUARD_WINDOW_MAX == CTL_MONITOR_SLOTS && PLAUS_CHECK_TICKS == CTL_MONITOR_SLOTS &&
                   CTL_SLOW_SLOTS % CTL_MONITOR_SLOTS == 0u && CTL_SLOW_SLOTS % CTL_RBFN_TICKS == 0u &&
                   CTL_SLOT_RBFN < CTL_RBFN_TICKS && CTL_SLOT_RBFN_LEARN < CTL_RBFN_TICKS &&
                   CTL_SLOT_STALL < CTL_RBFN_TICKS && CTL_SLOT_STALL != CTL_SLOT_RBFN &&
                   CTL_SLOT_STALL != CTL_SLOT_RBFN_LEARN,
               "the slow tasks' own rates are the schedule's");
#endif

/** The slot of the tick after one in slot @p slot (0..CTL_SLOW_SLOTS - 1). */
static inline uint8_t ctl_schedule_next(uint8_t slot) { return (uint8_t)((slot + 1u) & (CTL_SLOW_SLOTS - 1u)); }

/** True in the slots where the loss-of-control monitor closes its window and judges. */
static inline bool ctl_slot_guard(uint8_t slot) { return (slot & (CTL_MONITOR_SLOTS - 1u)) == CTL_SLOT_GUARD; }

/** True in the slots of the current plausibility checks. */
static inline bool ctl_slot_plaus(uint8_t slot) { return (slot & (CTL_MONITOR_SLOTS - 1u)) == CTL_SLOT_PLAUS; }

/** True in the slots where the speed loop commands (every controller). */
static inline bool ctl_slot_speed_command(uint8_t slot) { return (slot & (CTL_RBFN_TICKS - 1u)) == CTL_SLOT_RBFN; }

/** True in the slots where the RBFN learns from its last command. */
static inline bool ctl_slot_rbfn_learn(uint8_t slot)
{
    return (slot & (CTL_RBFN_TICKS - 1u)) == CTL_SLOT_RBFN_LEARN;
}

/** True in the slots where the stall windows step. */
static inline bool ctl_slot_stall(uint8_t slot) { return (slot & (CTL_RBFN_TICKS - 1u)) == CTL_SLOT_STALL; }

/** True in the slot of the supervision of the operating point. */
static inline bool ctl_slot_supervise(uint8_t slot) { return slot == CTL_SLOT_SUPERVISE; }

/** True in the slot of the switching-frequency regulation's step. */
static inline bool ctl_slot_fsw(uint8_t slot) { return slot == CTL_SLOT_FSW; }

/** True in the slot of the speed-deviation supervision's step. */
static inline bool ctl_slot_speed_dev(uint8_t slot) { return slot == CTL_SLOT_SPEED_DEV; }

/** True in the slot where the DTC decides its voltage level. */
static inline bool ctl_slot_level(uint8_t slot) { return slot == CTL_SLOT_LEVEL; }

#ifdef __cplusplus
}
#endif

#endif /* DTC_CTL_SCHEDULE_H */
