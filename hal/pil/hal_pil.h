/**
 * @file hal_pil.h
 * @brief The HAL binding of the PIL programs (QEMU mps2-an386): a board whose
 *        "ADC" converts what the bench hands it (recorded SIL samples) and
 *        whose control tick is a real NVIC interrupt.
 *
 * The semantics follow the host binding (hal/host): a sample can be read once
 * per tick, hal_actuate validates and latches, an active fault input keeps the
 * gates off, hal_tick_missed reports the injected miss of the tick (until the
 * next hal_pil_set_inputs, as the target's timer flag until the next tick). Like the
 * target, hal_actuate also plans every leg's switching events for the period
 * (hal/stm32g4/npc_plan.c, the target's own planner) and writes them to
 * stand-in timer registers, so the bench counts that work too.
 * The tick interrupt (hal_pil_tick_irq, in the vector table as IRQ
 * HAL_PIL_TICK_IRQ) does what ADC1_2_IRQHandler does on the target: latch the
 * sample (the one allowed read copies it, where the target's converts its ADC
 * codes), then call the registered handler (drive_isr). The bench
 * triggers it by pending the IRQ in the NVIC.
 */
#ifndef PIL_HAL_PIL_H
#define PIL_HAL_PIL_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal.h"

/** External interrupt number of the control tick on mps2-an386 (not wired to a device). */
#define HAL_PIL_TICK_IRQ 31u

/** Power-on state: no tick, gates off, erased NVM, no CAN. Context: thread. */
void hal_pil_board_reset(void);

/**
 * What the board presents at the next tick: the converted sample (@p fresh
 * false: the ADC did not convert, the tick finds no new sample), the fault
 * input and an injected missed deadline. Context: thread, between ticks.
 */
void hal_pil_set_inputs(const hal_sample *s, bool fresh, bool fault_input, bool tick_missed);

/** The control-tick interrupt handler. Context: interrupt. */
void hal_pil_tick_irq(void);

/** @return true while the gates are enabled. */
bool hal_pil_gates_on(void);

#endif /* PIL_HAL_PIL_H */
