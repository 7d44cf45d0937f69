/**
 * @file hal_stm32g4.c
 * @brief Binding of hal/hal.h for the NUCLEO-G474RE control card driving a
 *        three-level NPC power stage (STM32G474RE at 170 MHz), composed of
 *        one driver per peripheral:
 *  - clock.c: HSE 24 MHz -> PLL -> 170 MHz, HSI16 fall-back, the DWT cycle
 *    counter and the 1 ms SysTick (RM0440 7.2, 6.1.5);
 *  - pins.c: the pin map (docs/board.md);
 *  - hrtim.c: the gates: HRTIM timers A..F, two complementary outputs each =
 *    the 12 switches, hardware dead time, preloaded compare/set/reset
 *    programmes transferred at the period start, the fault line on FLT3
 *    (PB10, outer switches) and external event 6 (PB5, filtered: inner
 *    switches) (RM0440 27.3);
 *  - adc.c: ADC1 + ADC2 injected simultaneous conversions and ADC3 (ic)
 *    triggered by the same HRTIM master compare at a fixed instant of the
 *    period (RM0440 21.4);
 *  - fdcan.c: FDCAN1 classic CAN, fixed message RAM layout (RM0440 44.3);
 *  - flash_nvm.c: two 2 KiB flash pages of bank 2 (RM0440 5.3);
 *  - iwdg.c: IWDG refreshed only when both the tick and the background have
 *    proven alive (RM0440 41.3);
 *  - reset_cause.c, board_faults.c: why the chip started, what went wrong.
 * This file brings the board up (board_init), runs the control tick (ADC1's
 * end-of-sequence interrupt) and maps each hal.h function onto its driver.
 * Pin map, analog scaling, priorities, the HRTIM scheme and the fault
 * sequence are documented for the hardware engineer in docs/board.md.
 *
 * The board is a singleton, so each driver keeps its state in one
 * file-level struct; the portable firmware keeps no such state (the rule
 * applies to firmware/).
 */
#include <stddef.h>

#include "adc.h"
#include "board.h"
#include "chip.h"
#include "clock.h"
#include "fdcan.h"
#include "flash_nvm.h"
#include "hal/hal.h"
#include "hrtim.h"
#include "iwdg.h"
#include "pins.h"
#include "reset_cause.h"

/* Interrupt priorities (4 bits, 0 = most urgent), docs/board.md. */
#define PRIO_HRTIM_FAULT 0u  /* runs once per trip: inner switches off */
#define PRIO_CONTROL_TICK 1u /* ADC1/2 end of injected sequence: the 200 us tick */
#define PRIO_SYSTICK 15u     /* 1 ms time base; CAN and flash are polled in the background (FDCAN1_IT0, also 15, only wakes it) */

/* Start of the vector table, from stm32g474.ld. */
extern const uint32_t __isr_vector_start[];

typedef struct {
    hal_tick_handler handler; /* control-tick callback */
    void *ctx;
    bool running;
    uint32_t reset_cause; /* enum hal_reset_cause, from RCC_CSR at board_init */
} board_tick;

static board_tick g_tick;

void board_init(void)
{
    SCB_VTOR = (uint32_t)(uintptr_t)__isr_vector_start;
    /* Separate fault handlers (all land in the safe state) and trap integer
     * division by zero instead of returning 0. */
    SCB_SHCSR |= SCB_SHCSR_MEMFAULTENA | SCB_SHCSR_BUSFAULTENA | SCB_SHCSR_USGFAULTENA;
    SCB_CCR |= SCB_CCR_DIV_0_TRP;

    g_tick.reset_cause = reset_cause_take();
    if (g_tick.reset_cause == HAL_RESET_WATCHDOG)
        board_fault_record(BOARD_FAULT_WDG_RESET);
    /* Option bytes this board depends on (docs/board.md, NUCLEO caveats):
     * boot not taken from PB8 (= CAN RX), flash in dual-bank mode. */
    if ((FLASH_OPTR & FLASH_OPTR_NSWBOOT0) != 0u)
        board_fault_record(BOARD_FAULT_BOOT0_PIN);
    if ((FLASH_OPTR & FLASH_OPTR_DBANK) == 0u)
        board_fault_record(BOARD_FAULT_NVM);

    clock_cycle_counter_start();
    (void)clock_init(); /* a failure leaves 16 MHz, recorded: every timing follows clock_sysclk_hz() */

    /* HRTIM before the pins: the outputs are disabled (idle, low) when the
     * pins switch from analog to the HRTIM alternate function. */
    hrtim_init();
    pins_init();
    hrtim_fault_arm(PRIO_HRTIM_FAULT);

    clock_systick_start(PRIO_SYSTICK); /* least urgent interrupt */
}

void board_safe_state(void) { hrtim_safe_state(); }

uint32_t hal_reset_cause(void) { return g_tick.reset_cause; }

/* ------------------------------------------------------- control tick */

/** ADC1/ADC2 end of the injected sequence: the control tick, synchronised to
 * the PWM. Context: interrupt, PRIO_CONTROL_TICK. */
void ADC1_2_IRQHandler(void)
{
    hrtim_tick_ack();
    if (!adc_tick_pending())
        return; /* spurious */
#ifdef BOARD_TEST_STALL_TICK_MS
    /* TEST BUILD ONLY (dtc-fw-stalltest.elf, never dtc-fw.elf): BOARD_TEST_STALL_TICK_MS
     * after a start that was not a watchdog reset, the control tick stops itself for good
     * (its interrupt disabled, as a hung sampling chain would leave it); the background keeps
     * running and asking for watchdog refreshes, which the two-flag scheme must refuse. */
    if (g_tick.reset_cause != HAL_RESET_WATCHDOG && clock_millis() >= BOARD_TEST_STALL_TICK_MS) {
        NVIC_ICER(IRQN_ADC1_2 >> 5) = 1u << (IRQN_ADC1_2 & 31u);
        return;
    }
#endif
    adc_latch();
    iwdg_tick_alive();
    if (g_tick.handler != NULL)
        g_tick.handler(g_tick.ctx);
}

int hal_tick_start(hal_tick_handler handler, void *ctx, uint32_t period_us)
{
    if (handler == NULL || period_us < 50u || period_us > 1000u)
        return HAL_EINVAL;
    if (g_tick.running)
        return HAL_EBUSY;

    g_tick.handler = handler;
    g_tick.ctx = ctx;

    /* Gates off during the offset calibration. */
    hrtim_outputs_off();
    int rc = adc_init();
    if (rc != HAL_OK) {
        adc_stop();
        return rc;
    }
    rc = hrtim_start(period_us);
    if (rc != HAL_OK) {
        adc_stop();
        return rc;
    }
    (void)adc_calibrate_offsets(); /* a failure is recorded; the samples are refused: the drive stays safe */

    adc_tick_irq_enable();
    g_tick.running = true;
    iwdg_expect_tick(true);
    chip_nvic_enable(IRQN_ADC1_2, PRIO_CONTROL_TICK);
    return HAL_OK;
}

void hal_tick_stop(void)
{
    hal_gate_enable(false);
    chip_nvic_disable(IRQN_ADC1_2);
    adc_stop();
    hrtim_stop();
    g_tick.running = false;
    iwdg_expect_tick(false);
}

bool hal_tick_missed(void) { return hrtim_tick_missed(); }

/* ------------------------------------------------ sample and actuation */

int hal_sample_read(hal_sample *out) { return adc_sample_read(out); }

int hal_actuate(const hal_actuation *act) { return hrtim_actuate(act); }

/* ------------------------------------------------------ gates and faults */

void hal_gate_enable(bool enable)
{
    if (!enable)
        hrtim_gates_disable();
    else
        hrtim_gates_enable(g_tick.running && adc_calibrated());
}

bool hal_gate_enabled(void) { return hrtim_gates_enabled(); }

bool hal_fault_input_active(void) { return hrtim_fault_input_active(); }

/* ------------------------------------------------------------------ time */

uint32_t hal_cycles(void) { return clock_cycles(); }

uint32_t hal_cycles_hz(void) { return clock_sysclk_hz(); }

uint32_t hal_millis(void) { return clock_millis(); }

/* ------------------------------------------------------------------ idle */

uint32_t board_idle_mark(const volatile uint32_t *tick_count)
{
    return *tick_count + clock_millis() + fdcan_wakeups();
}

void board_idle(const volatile uint32_t *tick_count, uint32_t mark)
{
    __asm volatile("cpsid i" ::: "memory");
    if (board_idle_mark(tick_count) == mark)
        __asm volatile("dsb\n\twfi" ::: "memory"); /* wakes on a pending interrupt, masked or not */
    __asm volatile("cpsie i" ::: "memory");          /* the interrupt that woke the core is taken here */
}

/* ------------------------------------------------------------------- CAN */

int hal_can_open(uint32_t bitrate_bps) { return fdcan_open(bitrate_bps); }

void hal_can_get_state(hal_can_state *out) { fdcan_get_state(out); }

int hal_can_send(const hal_can_frame *frame) { return fdcan_send(frame); }

int hal_can_recv(hal_can_frame *frame) { return fdcan_recv(frame); }

/* ---------------------------------------------------------- non-volatile */

uint32_t hal_nvm_size(void) { return flash_nvm_size(); }

int hal_nvm_read(uint32_t offset, void *buf, size_t len) { return flash_nvm_read(offset, buf, len); }

int hal_nvm_write(uint32_t offset, const void *buf, size_t len) { return flash_nvm_write(offset, buf, len); }

/* -------------------------------------------------------------- watchdog */

int hal_watchdog_start(uint32_t timeout_ms) { return iwdg_start(timeout_ms); }

/* hal.h: refresh the watchdog. Here the refresh happens only if the control
 * tick has also run since the last refresh (two-flag scheme, docs/board.md),
 * so neither a stuck background nor a dead tick keeps the chip alive. */
void hal_watchdog_kick(void) { iwdg_service(); }
