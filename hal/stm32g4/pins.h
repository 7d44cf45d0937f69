/**
 * @file pins.h
 * @brief The board's pin map (docs/board.md, "Pin map"): every GPIO the
 *        firmware uses, and the gate drivers' fault line as the two pins it
 *        reaches. Private to hal/stm32g4.
 */
#ifndef HAL_STM32G4_PINS_H
#define HAL_STM32G4_PINS_H

#include <stdbool.h>
#include <stdint.h>

#include "stm32g474_regs.h"

/** The fault line's two inputs on port B: FLT3 (outer switches) and EEV6 (inner switches). */
#define PINS_FAULT_FLT3_PB 10u
#define PINS_FAULT_EEV6_PB 5u

/**
 * Clock GPIOA..C and put every pin of the map in its mode: pull and speed
 * first, then the alternate function, then the mode (RM0440 9.3.2). The
 * HRTIM outputs must be disabled before (their pins leave analog mode here).
 * Context: BG, once, from board_init().
 */
void pins_init(void);

/** The fault line as its two pins read it. */
typedef struct {
    bool flt3_low; /**< PB10 (HRTIM_FLT3) low: outer switches off */
    bool eev6_low; /**< PB5 (HRTIM_EEV6) low: inner switches off */
} pins_fault_line;

/** @return both pins of the fault line (active low), read at once. Context: ANY. */
static inline pins_fault_line pins_fault_line_read(void)
{
    uint32_t idr = GPIO_REG(GPIOB_BASE, GPIO_IDR_OFS);
    pins_fault_line l = {
        .flt3_low = (idr & (1u << PINS_FAULT_FLT3_PB)) == 0u,
        .eev6_low = (idr & (1u << PINS_FAULT_EEV6_PB)) == 0u,
    };
    return l;
}

#endif /* HAL_STM32G4_PINS_H */
