/**
 * @file board.h
 * @brief What the STM32G474 startup code (and a debugger) needs from the board
 *        binding, plus the board's own diagnostics. Private to hal/stm32g4.
 *
 * The pin map, analog scaling and interrupt priorities are in docs/board.md.
 */
#ifndef HAL_STM32G4_BOARD_H
#define HAL_STM32G4_BOARD_H

#include <stdint.h>

/** System clock after board_init(), Hz: HSE 24 MHz -> PLL (M 6, N 85, R 2). */
#define BOARD_SYSCLK_HZ 170000000u

/** HSE crystal of the NUCLEO-G474RE (X3, ST-LINK MCO not used), Hz. */
#define BOARD_HSE_HZ 24000000u

/** Dead time inserted on each complementary pair (S1/S3, S2/S4), ns. Range 100..10000. */
#define BOARD_DEAD_TIME_NS 1000u

/**
 * Hardware delay from the fault line to the inner switches (S2, S3) going off,
 * ns (nominal): the line's second input, HRTIM_EEV6 (PB5), passes a digital
 * filter of N = 8 samples at fHRTIM / 16 (8 x 16 / 170 MHz = 753 ns; with the
 * sampling phase and the input synchronisation 0.68-0.77 us), then resets
 * output 1 (the inner switch) of every timer. The outer switches (S1, S4) go
 * off through FLT3 within a few tHRTIM. See docs/board.md, "Fault".
 */
#define BOARD_FAULT_INNER_DELAY_NS 753u

/**
 * Software back-up of the inner stage, ns after the fault interrupt's entry:
 * later than the hardware stage, so it only matters if that one failed (PB5
 * not wired to the fault line, for instance).
 */
#define BOARD_FAULT_BACKUP_DELAY_NS 1000u

/**
 * Before enabling the gates the fault line must have been high at least this
 * long, ns: longer than the external event 6 filter (<= 0.77 us), so its reset
 * request is over when the output-1 latches are set to O.
 */
#define BOARD_FAULT_LINE_SETTLE_NS 1000u

/** Board fault bits recorded by the binding (board_faults()). */
enum board_fault {
    BOARD_FAULT_HSE = 1u << 0,        /**< HSE did not start: running from HSI16 -> PLL */
    BOARD_FAULT_PLL = 1u << 1,        /**< PLL did not lock: running from HSI16 at 16 MHz */
    BOARD_FAULT_ADC_CAL = 1u << 2,    /**< ADC regulator, calibration or enable timed out */
    BOARD_FAULT_ADC_OFFSET = 1u << 3, /**< current offset at start-up outside +-5 % of mid-scale */
    BOARD_FAULT_ADC_RANGE = 1u << 4,  /**< a conversion was saturated (code <= 2 or >= 4093) */
    BOARD_FAULT_HRTIM = 1u << 5,      /**< HRTIM fault input tripped (desat/over-current) */
    BOARD_FAULT_CAN_BUSOFF = 1u << 6, /**< FDCAN1 went bus-off (recovered automatically) */
    BOARD_FAULT_NVM = 1u << 7,        /**< flash erase/program error, or single-bank flash (seen at boot) */
    BOARD_FAULT_WDG_RESET = 1u << 8,  /**< the last reset came from the independent watchdog */
    BOARD_FAULT_PN_STEP = 1u << 9,    /**< an actuation asked for a direct P<->N step (O inserted) */
    BOARD_FAULT_BOOT0_PIN = 1u << 10, /**< option bytes still boot from the PB8/BOOT0 pin (CAN RX!) */
    BOARD_FAULT_ADC_SYNC = 1u << 11,  /**< ADC3 (ic) had not converted when ADC1/2 ended: sample refused */
    BOARD_FAULT_LINE_PINS = 1u << 12, /**< PB5 (EEV6) and PB10 (FLT3), one fault line, read differently */
};

/**
 * Bring the chip to its run configuration: 170 MHz from HSE via the PLL
 * (range 1 boost mode, 4 flash wait states, caches and prefetch on; HSI16 as
 * the PLL source if HSE does not start), fault exceptions enabled, DWT cycle
 * counter and 1 ms SysTick, GPIO per docs/board.md, HRTIM outputs configured
 * but disabled, the HRTIM fault input armed. The gate outputs stay off.
 * Context: reset handler, once, after .data/.bss are set up.
 */
void board_init(void);

/**
 * Force the safe state: all twelve HRTIM outputs disabled (outer switches
 * first, then the inner ones). Safe to call from any context, including
 * fault handlers (touches no RAM state beyond one flag).
 */
void board_safe_state(void);

/**
 * Every exception nobody claimed ends here (startup_stm32g474.c): the safe
 * state, then wait for the watchdog. The NMI handler calls it for every NMI
 * that is not a flash ECC error of a parameter read. Context: exception.
 */
void Default_Handler(void);

/**
 * What the background has been woken for so far: a count that moves with
 * every interrupt that can give it work (the control tick, whose counter is
 * @p tick_count, the SysTick's milliseconds, an FDCAN frame received or sent).
 * Take it before a background pass and hand it to board_idle() after it.
 * Context: BG.
 */
uint32_t board_idle_mark(const volatile uint32_t *tick_count);

/**
 * Sleep (WFI) until the next interrupt, unless one that can give the
 * background work came since @p mark was taken (then return at once). The
 * check and the WFI run with interrupts masked (PRIMASK): an interrupt that
 * arrives in between stays pending, wakes the core all the same (ARMv7-M) and
 * is taken when this returns, so no wake-up is lost. The longest sleep is one
 * control tick (200 us) while the tick runs, 1 ms (SysTick) otherwise; with
 * every interrupt dead the core sleeps for good and the watchdog, no longer
 * refreshed, resets the chip. Context: BG.
 */
void board_idle(const volatile uint32_t *tick_count, uint32_t mark);

/** @return the board_fault bits recorded since reset. Context: ANY. */
uint32_t board_faults(void);

/**
 * The board_fault bits recorded since reset (board_faults.c). A word of its
 * own, named, so a debugger or the emulated board reads it by symbol.
 */
extern volatile uint32_t g_board_faults;

/**
 * Record the board_fault bits @p bits (kept until reset). Every driver
 * records its own faults here. Context: ANY.
 */
static inline void board_fault_record(uint32_t bits) { g_board_faults |= bits; }

#endif /* HAL_STM32G4_BOARD_H */
