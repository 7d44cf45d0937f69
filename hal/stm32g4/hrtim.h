/**
 * @file hrtim.h
 * @brief HRTIM1 as the three-level NPC gate driver: timers A..F, two
 *        complementary outputs each = the 12 switches, hardware dead time,
 *        the per-period set/reset programmes (npc_plan.h) written to the
 *        preloaded registers, the fault line on FLT3 and external event 6,
 *        and master compare 1 as the ADC trigger. Private to hal/stm32g4.
 *
 * Outputs in OENR/ODISR: per leg, timer A-type = S3 (output 1) / S1
 * (output 2), timer B-type = S2 (output 1) / S4 (output 2): output 1 of every
 * timer is an inner switch, so one external event resets all of them in
 * hardware. docs/board.md, "HRTIM" and "Fault", has the scheme.
 */
#ifndef HAL_STM32G4_HRTIM_H
#define HAL_STM32G4_HRTIM_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_types.h"
#include "stm32g474_regs.h"

/** Outer switches S1, S4 (TA2 TB2 .. TF2) and inner S3, S2 (TA1 .. TF1) in OENR/ODISR. */
#define HRTIM_OUT_OUTER 0xAAAu
#define HRTIM_OUT_INNER 0x555u

/**
 * Static part, with the outputs disabled: clock on, output idle and fault
 * states, dead time BOARD_DEAD_TIME_NS from the present SYSCLK, FLT3 in every
 * timer, external event 6 (PB5, filtered). Context: BG, once, from
 * board_init(), before pins_init().
 */
void hrtim_init(void);

/**
 * Arm the fault input FLT3 (PB10, no filter, locked) and its interrupt at
 * priority @p prio; once PB10 is in its alternate function (after
 * pins_init(): in analog mode the input reads low = fault). Context: BG, once.
 */
void hrtim_fault_arm(uint32_t prio);

/**
 * Start the master and timers A..F together on a period of @p period_us
 * (counts below 0xFFDF, prescaler 5..7), every leg at O, master compare 1 =
 * the ADC trigger at BOARD_SAMPLE_DELAY_NS. Context: BG.
 * @return HAL_OK, HAL_EINVAL for a period the counters cannot hold.
 */
int hrtim_start(uint32_t period_us);

/** Outputs off, then every counter stopped. Context: BG. */
void hrtim_stop(void);

/**
 * Every output disabled, outer switches first, the full dead time before the
 * inner ones (RM0440 27.3.15: ODISR takes an output to its idle level
 * without waiting for the period); the gates count as off. Context: ANY.
 */
void hrtim_outputs_off(void);

/**
 * board_safe_state()'s part: the outputs off, outer first, with a fixed
 * delay that reads no RAM; nothing while the HRTIM is not clocked (the pins
 * are analog then, the drivers held off by their pull-downs). Context: ANY,
 * fault handlers included.
 */
void hrtim_safe_state(void);

/** Gates off (the outer-first sequence only when an output is on). Context: ANY. */
void hrtim_gates_disable(void);

/**
 * Gates on, refused (they stay off) unless @p ready (the control tick runs
 * on a valid calibration), the fault line has been high for
 * BOARD_FAULT_LINE_SETTLE_NS and no trip is latched. Each output 1 latch is
 * set to O first: after a trip external event 6 has left them reset, and
 * the outer switches (their complements) would come on together.
 * Context: ANY (the tick, or BG with the tick's interrupt masked).
 */
void hrtim_gates_enable(bool ready);

/** @return true while the gates are enabled (false after a trip). Context: ANY. */
bool hrtim_gates_enabled(void);

/**
 * @return true while the fault line is low on either pin, or a trip has not
 * been reported yet (it is reported once, then cleared when the line is
 * high). A difference between the two pins is recorded
 * (BOARD_FAULT_LINE_PINS). Context: ANY.
 */
bool hrtim_fault_input_active(void);

/**
 * Program the next period from @p act (applied at the next roll-over): each
 * leg's words from the planner, CMP1 = the switching instant, the six
 * programmes transferred together. With the gates off a request equal to
 * the last one writes nothing (the preloaded registers repeat it).
 * Context: ISR (the control tick).
 * @return HAL_OK, HAL_EINVAL for a NULL @p act, a leg state above HAL_LEG_P
 * or a duty outside 0..1 (NaN included).
 */
int hrtim_actuate(const hal_actuation *act);

/** @return P<->N steps replaced by O since start (a firmware bug if ever > 0). Context: ANY. */
uint32_t hrtim_pn_fixups(void);

/**
 * @return true when master compare 1 (the next sampling trigger) came again
 * since hrtim_tick_ack(): the next tick is already due. Context: ISR.
 */
static inline bool hrtim_tick_missed(void) { return (HRTIM_MISR & HRTIM_MISR_MCMP1) != 0u; }

/** Clear master compare 1's flag at the start of a tick. Context: ISR. */
static inline void hrtim_tick_ack(void) { HRTIM_MICR = HRTIM_MICR_MCMP1C; }

#endif /* HAL_STM32G4_HRTIM_H */
