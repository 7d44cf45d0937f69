/**
 * @file chip.h
 * @brief What every driver of the STM32G474 binding shares: bounded polls of
 *        a hardware flag, the NVIC, the execution context. Private to
 *        hal/stm32g4.
 */
#ifndef HAL_STM32G4_CHIP_H
#define HAL_STM32G4_CHIP_H

#include <stdbool.h>
#include <stdint.h>

#include "stm32g474_regs.h"

/** Bounded wait on a hardware flag, loop passes: about 1..6 ms depending on the bus. */
#define CHIP_WAIT_LOOPS 200000u

/**
 * Poll @p reg until (*reg & @p mask) == @p value, at most @p loops reads.
 * @return true when the value was seen, false on the time-out (the caller
 * records the fault: nothing waits forever on the hardware). Context: ANY.
 */
static inline bool chip_wait(volatile uint32_t *reg, uint32_t mask, uint32_t value, uint32_t loops)
{
    for (uint32_t n = 0u; n < loops; n++) {
        if ((*reg & mask) == value)
            return true;
    }
    return false;
}

/**
 * Enable interrupt @p irq (0..IRQN_COUNT-1) at priority @p prio (0..15,
 * 0 = most urgent), with any stale pending request cleared first. Context: BG.
 */
static inline void chip_nvic_enable(uint32_t irq, uint32_t prio)
{
    NVIC_IPR8(irq) = (uint8_t)(prio << NVIC_PRIO_SHIFT);
    NVIC_ICPR(irq >> 5) = 1u << (irq & 31u);
    NVIC_ISER(irq >> 5) = 1u << (irq & 31u);
}

/** Disable interrupt @p irq; no handler of it runs after the return. Context: BG. */
static inline void chip_nvic_disable(uint32_t irq)
{
    NVIC_ICER(irq >> 5) = 1u << (irq & 31u);
    __asm volatile("dsb\n\tisb" ::: "memory");
}

/** @return true when called from an exception handler (IPSR != 0). Context: ANY. */
static inline bool chip_in_interrupt(void)
{
    uint32_t ipsr;
    __asm volatile("mrs %0, ipsr" : "=r"(ipsr));
    return (ipsr & 0x1FFu) != 0u;
}

#endif /* HAL_STM32G4_CHIP_H */
