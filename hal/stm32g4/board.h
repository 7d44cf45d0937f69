/**
 * @file board.h
 * @brief What the STM32G474 startup code needs from the board binding.
 * Private to hal/stm32g4.
 */
#ifndef HAL_STM32G4_BOARD_H
#define HAL_STM32G4_BOARD_H

/** System clock after board_init(), Hz: HSI16 -> PLL (M 4, N 85, R 2). */
#define BOARD_SYSCLK_HZ 170000000u

/**
 * Bring the chip to its run configuration: 170 MHz from the PLL (range 1
 * boost mode, 4 flash wait states, caches and prefetch on), fault exceptions
 * enabled, DWT cycle counter and the 1 ms SysTick started. The gate outputs
 * stay off. Context: reset handler, once, after .data/.bss are set up.
 */
void board_init(void);

/**
 * Force the safe state: all gate outputs off. Safe to call from any context,
 * including fault handlers (touches no RAM state beyond one flag).
 */
void board_safe_state(void);

#endif /* HAL_STM32G4_BOARD_H */
