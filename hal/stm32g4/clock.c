/**
 * @file clock.c
 * @brief The clock tree (RCC, PWR, flash latency) and the core's time bases
 *        (DWT cycle counter, SysTick) of the STM32G474.
 */
#include "clock.h"

#include "board.h"
#include "chip.h"
#include "hal/hal_types.h"

/* HSE start-up: a few ms at 16 MHz. */
#define CLOCK_WAIT_HSE_LOOPS 400000u

typedef struct {
    uint32_t sysclk_hz;       /* 0 before clock_init, then 16 MHz or 170 MHz */
    volatile uint32_t millis; /* written by SysTick only */
} clock_state;

static clock_state g_clock;

uint32_t clock_sysclk_hz(void) { return g_clock.sysclk_hz; }

uint32_t clock_millis(void) { return g_clock.millis; }

void clock_cycle_counter_start(void)
{
    DEMCR |= DEMCR_TRCENA;
    DWT_CYCCNT = 0u;
    DWT_CTRL |= DWT_CTRL_CYCCNTENA;
}

void clock_delay_ns(uint32_t ns)
{
    uint32_t hz = g_clock.sysclk_hz != 0u ? g_clock.sysclk_hz : CLOCK_HSI16_HZ;
    uint32_t cycles = (uint32_t)(((uint64_t)ns * hz + 999999999u) / 1000000000u);
    uint32_t t0 = DWT_CYCCNT;
    /* If the counter does not run (no DEMCR), fall back to a loop of the same length. */
    for (uint32_t n = 0u; n < cycles; n++) {
        if (DWT_CYCCNT - t0 >= cycles)
            break;
    }
}

/*
 * RM0440 order of operations (6.1.5 range 1 boost, 5.3.3 wait states, 7.2.4
 * PLL, 7.2.7 clock switch): PWR clock on; 4 wait states before the clock
 * rises; AHB / 2 while switching above 80 MHz; R1MODE = 0 (boost); HSE on
 * (bounded wait); PLL from HSE (or HSI16) to 340 MHz VCO / 2; switch; after
 * at least 1 us AHB back to / 1. APB1/APB2 stay / 1 (PCLK = 170 MHz).
 */
int clock_init(void)
{
    g_clock.sysclk_hz = CLOCK_HSI16_HZ; /* HSI16 after reset */

    RCC_APB1ENR1 |= RCC_APB1ENR1_PWREN;
    (void)RCC_APB1ENR1; /* read back: the clock is on before PWR is touched */
    RCC_AHB1ENR |= RCC_AHB1ENR_FLASHEN;

    /* Voltage scaling range 1 (reset value; made explicit), then boost. */
    PWR_CR1 = (PWR_CR1 & ~PWR_CR1_VOS_MASK) | PWR_CR1_VOS_RANGE1;
    (void)chip_wait(&PWR_SR2, PWR_SR2_VOSF, 0u, CHIP_WAIT_LOOPS);

    FLASH_ACR = (FLASH_ACR & ~FLASH_ACR_LATENCY_MASK) | FLASH_ACR_LATENCY_4WS | FLASH_ACR_PRFTEN |
                FLASH_ACR_ICEN | FLASH_ACR_DCEN;
    if (!chip_wait(&FLASH_ACR, FLASH_ACR_LATENCY_MASK, FLASH_ACR_LATENCY_4WS, CHIP_WAIT_LOOPS)) {
        board_fault_record(BOARD_FAULT_PLL); /* cannot raise the clock safely */
        return HAL_EIO;
    }

    /* AHB / 2 first, then range 1 boost (RM0440 6.1.5: the core current steps in halves). */
    RCC_CFGR = (RCC_CFGR & ~(RCC_CFGR_HPRE_MASK | RCC_CFGR_PPRE1_MASK | RCC_CFGR_PPRE2_MASK)) |
               RCC_CFGR_HPRE_DIV2;
    PWR_CR5 &= ~PWR_CR5_R1MODE;

    /* HSE: 24 MHz crystal; bounded start-up, clean fall-back to HSI16. */
    uint32_t pllsrc = RCC_PLLCFGR_PLLSRC_HSE;
    uint32_t pllm = 6u; /* 24 MHz / 6 = 4 MHz VCO input */
    bool hse = true;
    RCC_CR |= RCC_CR_HSEON;
    if (!chip_wait(&RCC_CR, RCC_CR_HSERDY, RCC_CR_HSERDY, CLOCK_WAIT_HSE_LOOPS)) {
        RCC_CR &= ~RCC_CR_HSEON;
        board_fault_record(BOARD_FAULT_HSE);
        hse = false;
        pllsrc = RCC_PLLCFGR_PLLSRC_HSI16;
        pllm = 4u; /* 16 MHz / 4 = 4 MHz */
    }
    RCC_CR |= RCC_CR_HSION;
    if (!chip_wait(&RCC_CR, RCC_CR_HSIRDY, RCC_CR_HSIRDY, CHIP_WAIT_LOOPS)) {
        board_fault_record(BOARD_FAULT_PLL);
        return HAL_EIO;
    }

    RCC_CR &= ~RCC_CR_PLLON;
    if (!chip_wait(&RCC_CR, RCC_CR_PLLRDY, 0u, CHIP_WAIT_LOOPS)) {
        board_fault_record(BOARD_FAULT_PLL);
        return HAL_EIO;
    }
    /* 4 MHz x N 85 = 340 MHz VCO (96..344), / R 2 = 170 MHz. */
    RCC_PLLCFGR = pllsrc | ((pllm - 1u) << RCC_PLLCFGR_PLLM_SHIFT) | (85u << RCC_PLLCFGR_PLLN_SHIFT) |
                  RCC_PLLCFGR_PLLREN | (0u << RCC_PLLCFGR_PLLR_SHIFT);
    RCC_CR |= RCC_CR_PLLON;
    if (!chip_wait(&RCC_CR, RCC_CR_PLLRDY, RCC_CR_PLLRDY, CHIP_WAIT_LOOPS)) {
        RCC_CR &= ~RCC_CR_PLLON;
        RCC_CFGR &= ~RCC_CFGR_HPRE_MASK; /* stay on HSI16, AHB / 1 */
        board_fault_record(BOARD_FAULT_PLL);
        return HAL_EIO;
    }

    RCC_CFGR = (RCC_CFGR & ~RCC_CFGR_SW_MASK) | RCC_CFGR_SW_PLL;
    if (!chip_wait(&RCC_CFGR, RCC_CFGR_SWS_MASK, RCC_CFGR_SWS_PLL, CHIP_WAIT_LOOPS)) {
        RCC_CFGR = (RCC_CFGR & ~(RCC_CFGR_SW_MASK | RCC_CFGR_HPRE_MASK)) | RCC_CFGR_SW_HSI16;
        board_fault_record(BOARD_FAULT_PLL);
        return HAL_EIO;
    }
    g_clock.sysclk_hz = BOARD_SYSCLK_HZ / 2u;
    clock_delay_ns(1000u); /* >= 1 us at AHB / 2 (RM0440 7.2.7) */
    RCC_CFGR &= ~RCC_CFGR_HPRE_MASK;
    g_clock.sysclk_hz = BOARD_SYSCLK_HZ;

    /* Clock security: an HSE failure now raises NMI -> Default_Handler -> safe state. */
    if (hse)
        RCC_CR |= RCC_CR_CSSON;
    return HAL_OK;
}

void clock_systick_start(uint32_t prio)
{
    SCB_SHPR3 = (SCB_SHPR3 & 0x00FFFFFFu) | ((prio << NVIC_PRIO_SHIFT) << 24);
    SYST_RVR = g_clock.sysclk_hz / 1000u - 1u;
    SYST_CVR = 0u;
    SYST_CSR = SYST_CSR_CLKSOURCE | SYST_CSR_TICKINT | SYST_CSR_ENABLE;
}

/** SysTick: milliseconds since start. Context: interrupt, lowest priority. */
void SysTick_Handler(void) { g_clock.millis++; }
