/**
 * @file clock.h
 * @brief The STM32G474's clock tree (HSE 24 MHz -> PLL -> 170 MHz, HSI16
 *        fall-back) and the core's time bases: the DWT cycle counter and the
 *        1 ms SysTick. Private to hal/stm32g4.
 */
#ifndef HAL_STM32G4_CLOCK_H
#define HAL_STM32G4_CLOCK_H

#include <stdint.h>

#include "stm32g474_regs.h"

/** SYSCLK after reset and whenever the PLL is not running, Hz. */
#define CLOCK_HSI16_HZ 16000000u

/**
 * Bring SYSCLK (= HCLK = PCLK1 = PCLK2) to BOARD_SYSCLK_HZ: range 1 boost
 * mode, 4 flash wait states, caches and prefetch on, the PLL from HSE, or from
 * HSI16 when HSE does not start (BOARD_FAULT_HSE recorded). The clock security
 * system is armed when HSE runs. The DWT cycle counter must run (it times the
 * 1 us wait of the switch). Context: BG, once, from reset.
 * @return HAL_OK at 170 MHz (from HSE or HSI16), HAL_EIO when the PLL did not
 * lock or the switch failed: SYSCLK stays HSI16 at 16 MHz and BOARD_FAULT_PLL
 * is recorded.
 */
int clock_init(void);

/** @return SYSCLK, Hz: 0 before clock_init(), 16 MHz while on HSI16, 170 MHz after it succeeded. Context: ANY. */
uint32_t clock_sysclk_hz(void);

/** Start the DWT cycle counter (CYCCNT from 0). Context: BG, once, from reset. */
void clock_cycle_counter_start(void);

/** @return the DWT cycle counter, SYSCLK cycles (wraps at 2^32). Context: ANY. */
static inline uint32_t clock_cycles(void) { return DWT_CYCCNT; }

/**
 * Busy wait of at least @p ns (0..25e6) from the cycle counter at the present
 * SYSCLK; bounded by its own loop count should the counter not run.
 * Context: ANY (blocks the caller).
 */
void clock_delay_ns(uint32_t ns);

/**
 * Start the 1 ms SysTick interrupt at priority @p prio (0..15) from the
 * present SYSCLK (after clock_init()). Context: BG, once.
 */
void clock_systick_start(uint32_t prio);

/** @return milliseconds since clock_systick_start() (wraps at 2^32). Context: ANY. */
uint32_t clock_millis(void);

#endif /* HAL_STM32G4_CLOCK_H */
