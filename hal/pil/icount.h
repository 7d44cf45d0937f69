/**
 * @file icount.h
 * @brief Exact instruction counting on QEMU mps2-an386 with -icount shift=7.
 *
 * With -icount shift=7 every executed instruction advances QEMU's virtual
 * clock by 2^7 = 128 ns. SysTick, clocked from the 25 MHz processor clock of
 * this machine, then counts 40 ns per tick, i.e. 3.2 ticks per instruction, so
 * instructions = round(ticks * 40 / 128) = round(ticks * 5 / 16) is exact for
 * any interval. A 24-bit down-counter at 3.2 ticks per instruction wraps after
 * about 5.2 M instructions: intervals must stay below that (one wrap is
 * handled by the mask). Without -icount the counter follows host time and the
 * figures are noise; icount_selftest() detects that.
 * DWT CYCCNT is not implemented by this QEMU (reads 0), hence SysTick.
 */
#ifndef PIL_ICOUNT_H
#define PIL_ICOUNT_H

#include <stdint.h>

#define ICOUNT_SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define ICOUNT_SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define ICOUNT_SYST_CVR (*(volatile uint32_t *)0xE000E018u)

/** Start SysTick free-running from the processor clock, no interrupt. */
static inline void icount_start(void)
{
    ICOUNT_SYST_CSR = 0u;
    ICOUNT_SYST_RVR = 0xFFFFFFu;
    ICOUNT_SYST_CVR = 0u;
    ICOUNT_SYST_CSR = 5u; /* ENABLE | CLKSOURCE = processor clock */
}

/** Current SysTick value (counts down). */
static inline uint32_t icount_now(void)
{
    __asm volatile("" ::: "memory");
    uint32_t v = ICOUNT_SYST_CVR;
    __asm volatile("" ::: "memory");
    return v;
}

/** Instructions between two icount_now() readings, t0 taken first. */
static inline uint32_t icount_between(uint32_t t0, uint32_t t1)
{
    uint32_t ticks = (t0 - t1) & 0xFFFFFFu;
    return (ticks * 5u + 8u) / 16u;
}

#endif /* PIL_ICOUNT_H */
