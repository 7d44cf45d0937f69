/**
 * @file hal_stm32g4.c
 * @brief Minimal binding of hal/hal.h for an STM32G474 at 170 MHz.
 *
 * What is real: clocks (HSI16 -> PLL -> 170 MHz), the DWT cycle counter, the
 * 1 ms SysTick, the control-tick interrupt (TIM6 at the requested period),
 * the one-read-per-tick sample discipline, actuation checking and double
 * buffering, the independent watchdog, reading the NVM area of flash.
 *
 * What is a placeholder, each marked "PORT:" below, for the full board port:
 *  - ADC: the injected conversions (ADC1/ADC2, triggered by the HRTIM at the
 *    period start) are not configured, so every sample is refused (HAL_EAGAIN)
 *    and the firmware stays in its safe state; the code that reads the
 *    injected data registers and scales them is in place behind
 *    BOARD_ADC_PORTED.
 *  - HRTIM: the 12 gate outputs are not driven; hal_gate_enable(true) is
 *    refused (the gates stay off) and the latched actuation is not output.
 *  - Fault input: HRTIM fault lines not wired; reads inactive.
 *  - FDCAN: classic frames are not ported; open/send return HAL_EIO.
 *  - Flash programming for NVM writes: returns HAL_EIO.
 *
 * The board is a singleton, so its state is one file-level struct; the
 * portable firmware keeps no such state (the rule applies to firmware/).
 */
#include <stddef.h>
#include <string.h>

#include "board.h"
#include "hal/hal.h"
#include "stm32g474_regs.h"

/* Set to 1 by the ADC port, once ADC1/ADC2 injected groups are configured. */
#define BOARD_ADC_PORTED 0

/* Sensor scaling of the power board (docs/motor-10hp.json, "drive"). */
#define BOARD_ADC_FULL_CODE 4095.0f   /* 12-bit converter */
#define BOARD_I_FULL_SCALE_A 150.0f   /* currents: code 0 = -150 A, 4095 = +150 A */
#define BOARD_V_FULL_SCALE_V 500.0f   /* capacitor voltages: 0..500 V */

/* Interrupt priorities (4 bits, 0 = most urgent). */
#define PRIO_CONTROL_TICK 0u
#define PRIO_SYSTICK 15u

/* Bounded waits on hardware flags: about 1 ms at 170 MHz and never forever. */
#define WAIT_LOOPS 200000u

/* NVM area, from stm32g474.ld. */
extern const uint8_t __nvm_start[];
extern const uint8_t __nvm_size[];

/* Start of the vector table, from stm32g474.ld. */
extern const uint32_t __isr_vector_start[];

typedef struct {
    uint32_t sysclk_hz;          /* 170 MHz, or 16 MHz if the PLL failed to lock */
    hal_tick_handler handler;    /* control-tick callback */
    void *ctx;
    bool tick_running;
    volatile uint32_t millis;    /* written by SysTick only */
    hal_sample sample;           /* this tick's sample, written by the tick ISR */
    bool sample_fresh;           /* cleared by the one allowed read */
    uint32_t seq;                /* tick sequence number */
    hal_actuation pending;       /* written during tick k, applied from period k+1 */
    hal_actuation applied;       /* what the HRTIM outputs during this period */
    volatile bool gates_on;
} board_state;

static board_state g_board;

/* ----------------------------------------------------------- helpers */

static bool wait_set(volatile uint32_t *reg, uint32_t mask, uint32_t value)
{
    for (uint32_t n = 0u; n < WAIT_LOOPS; n++) {
        if ((*reg & mask) == value)
            return true;
    }
    return false;
}

static void nvic_enable(uint32_t irq, uint32_t prio)
{
    NVIC_IPR8(irq) = (uint8_t)(prio << NVIC_PRIO_SHIFT);
    NVIC_ICPR(irq >> 5) = 1u << (irq & 31u);
    NVIC_ISER(irq >> 5) = 1u << (irq & 31u);
}

static void nvic_disable(uint32_t irq)
{
    NVIC_ICER(irq >> 5) = 1u << (irq & 31u);
    __asm volatile("dsb\n\tisb" ::: "memory");
}

/* HSI16 / M 4 * N 85 / R 2 = 170 MHz (RM0440 7.2.4: VCO 340 MHz within 96..344). */
static bool clock_init_170mhz(void)
{
    RCC_APB1ENR1 |= RCC_APB1ENR1_PWREN;
    (void)RCC_APB1ENR1; /* read back: the clock is on before PWR is touched */

    /* Range 1 boost mode is required above 150 MHz (RM0440 6.1.5). */
    PWR_CR5 &= ~PWR_CR5_R1MODE;

    /* 4 wait states at 170 MHz in boost mode (RM0440 table 9), set before the
     * clock rises; prefetch and caches on. */
    FLASH_ACR = (FLASH_ACR & ~FLASH_ACR_LATENCY_MASK) | 4u | FLASH_ACR_PRFTEN | FLASH_ACR_ICEN |
                FLASH_ACR_DCEN;
    if (!wait_set(&FLASH_ACR, FLASH_ACR_LATENCY_MASK, 4u))
        return false;

    RCC_CR |= RCC_CR_HSION;
    if (!wait_set(&RCC_CR, RCC_CR_HSIRDY, RCC_CR_HSIRDY))
        return false;

    RCC_CR &= ~RCC_CR_PLLON;
    if (!wait_set(&RCC_CR, RCC_CR_PLLRDY, 0u))
        return false;
    RCC_PLLCFGR = RCC_PLLCFGR_PLLSRC_HSI16 | ((4u - 1u) << RCC_PLLCFGR_PLLM_SHIFT) |
                  (85u << RCC_PLLCFGR_PLLN_SHIFT) | RCC_PLLCFGR_PLLREN | (0u << RCC_PLLCFGR_PLLR_SHIFT);
    RCC_CR |= RCC_CR_PLLON;
    if (!wait_set(&RCC_CR, RCC_CR_PLLRDY, RCC_CR_PLLRDY))
        return false;

    /* Going above 80 MHz: switch with AHB / 2, then back to / 1 after at
     * least 1 us (RM0440 7.2.7), so the core current steps in two halves. */
    RCC_CFGR = (RCC_CFGR & ~(RCC_CFGR_HPRE_MASK | RCC_CFGR_SW_MASK | RCC_CFGR_PPRE1_MASK |
                             RCC_CFGR_PPRE2_MASK)) |
               RCC_CFGR_HPRE_DIV2 | RCC_CFGR_SW_PLL;
    if (!wait_set(&RCC_CFGR, RCC_CFGR_SWS_MASK, RCC_CFGR_SWS_PLL))
        return false;
    for (volatile uint32_t n = 0u; n < 200u; n++) {
        /* >= 1 us at 85 MHz: each pass is several cycles */
    }
    RCC_CFGR &= ~RCC_CFGR_HPRE_MASK;
    return true;
}

/* --------------------------------------------------------- board_init */

void board_init(void)
{
    SCB_VTOR = (uint32_t)(uintptr_t)__isr_vector_start;
    /* Separate fault handlers (all land in the safe state) and trap integer
     * division by zero instead of returning 0. */
    SCB_SHCSR |= SCB_SHCSR_MEMFAULTENA | SCB_SHCSR_BUSFAULTENA | SCB_SHCSR_USGFAULTENA;
    SCB_CCR |= SCB_CCR_DIV_0_TRP;

    board_safe_state();
    g_board.sysclk_hz = clock_init_170mhz() ? BOARD_SYSCLK_HZ : 16000000u;

    DEMCR |= DEMCR_TRCENA;
    DWT_CYCCNT = 0u;
    DWT_CTRL |= DWT_CTRL_CYCCNTENA;

    /* SysTick: 1 ms, least urgent interrupt. */
    SCB_SHPR3 = (SCB_SHPR3 & 0x00FFFFFFu) | ((PRIO_SYSTICK << NVIC_PRIO_SHIFT) << 24);
    SYST_RVR = g_board.sysclk_hz / 1000u - 1u;
    SYST_CVR = 0u;
    SYST_CSR = SYST_CSR_CLKSOURCE | SYST_CSR_TICKINT | SYST_CSR_ENABLE;
}

void board_safe_state(void)
{
    /* PORT: disable all twelve HRTIM outputs (HRTIM_ODISR) and drop the
     * gate-driver enable pin here; until the HRTIM port no output is driven. */
    g_board.gates_on = false;
}

/** SysTick: milliseconds since start. Context: interrupt, lowest priority. */
void SysTick_Handler(void) { g_board.millis++; }

/* ------------------------------------------------------- control tick */

/* Scale raw converter codes to engineering units (ADC1: ia, ib, vc1;
 * ADC2: ic, vc2), the same scaling the plant model's ADC uses. */
static void sample_from_codes(const uint32_t code[5], hal_sample *out)
{
    const float i_scale = 2.0f * BOARD_I_FULL_SCALE_A / BOARD_ADC_FULL_CODE;
    const float v_scale = BOARD_V_FULL_SCALE_V / BOARD_ADC_FULL_CODE;
    out->ia_A = (float)code[0] * i_scale - BOARD_I_FULL_SCALE_A;
    out->ib_A = (float)code[1] * i_scale - BOARD_I_FULL_SCALE_A;
    out->ic_A = (float)code[3] * i_scale - BOARD_I_FULL_SCALE_A;
    out->vc1_V = (float)code[2] * v_scale;
    out->vc2_V = (float)code[4] * v_scale;
}

static void sample_latch(void)
{
    g_board.seq++;
    if (BOARD_ADC_PORTED) {
        /* PORT: the HRTIM triggers both injected sequences at the period start;
         * by the time this interrupt runs they have converted (JEOS set). */
        uint32_t code[5];
        code[0] = ADC_JDR(ADC1_BASE, 0u) & 0xFFFu;
        code[1] = ADC_JDR(ADC1_BASE, 1u) & 0xFFFu;
        code[2] = ADC_JDR(ADC1_BASE, 2u) & 0xFFFu;
        code[3] = ADC_JDR(ADC2_BASE, 0u) & 0xFFFu;
        code[4] = ADC_JDR(ADC2_BASE, 1u) & 0xFFFu;
        sample_from_codes(code, &g_board.sample);
        g_board.sample.speed_meas_rad_s = 0.0f;
        g_board.sample.speed_meas_valid = false; /* no speed sensor on the board */
        g_board.sample.seq = g_board.seq;
        g_board.sample_fresh = true;
    } else {
        /* PORT: no ADC yet, so there is no measurement to give: refuse it. */
        g_board.sample_fresh = false;
    }
}

bool hal_tick_missed(void)
{
    /* UIF set again while the handler still runs: the next period has begun. */
    return (TIM6_SR & TIM_SR_UIF) != 0u;
}

/** TIM6 update: start of a control period. Context: interrupt, most urgent. */
void TIM6_DAC_IRQHandler(void)
{
    TIM6_SR = ~TIM_SR_UIF; /* rc_w0: clears only UIF */

    /* The period has started: what was latched during the last tick applies now.
     * PORT: the HRTIM preload transfer does this in hardware at the period start. */
    g_board.applied = g_board.pending;

    sample_latch();
    if (g_board.handler != NULL)
        g_board.handler(g_board.ctx);
}

int hal_tick_start(hal_tick_handler handler, void *ctx, uint32_t period_us)
{
    if (handler == NULL || period_us < 50u || period_us > 1000u)
        return HAL_EINVAL;
    if (g_board.tick_running)
        return HAL_EBUSY;

    g_board.handler = handler;
    g_board.ctx = ctx;

    RCC_APB1ENR1 |= RCC_APB1ENR1_TIM6EN;
    (void)RCC_APB1ENR1;

    /* TIM6 runs from the APB1 timer clock (= SYSCLK with APB1 / 1). Pick the
     * smallest prescaler that fits 16 bits and divides the period exactly. */
    uint32_t counts = (g_board.sysclk_hz / 1000000u) * period_us;
    uint32_t div = 1u;
    while (counts / div > 65536u || counts % div != 0u)
        div++;

    TIM6_CR1 = TIM_CR1_URS;
    TIM6_PSC = div - 1u;
    TIM6_ARR = counts / div - 1u;
    TIM6_CNT = 0u;
    TIM6_EGR = TIM_EGR_UG; /* load PSC now; URS keeps this from interrupting */
    TIM6_SR = 0u;
    TIM6_DIER = TIM_DIER_UIE;
    nvic_enable(IRQN_TIM6_DAC, PRIO_CONTROL_TICK);
    g_board.tick_running = true;
    TIM6_CR1 = TIM_CR1_URS | TIM_CR1_ARPE | TIM_CR1_CEN;
    return HAL_OK;
}

void hal_tick_stop(void)
{
    hal_gate_enable(false);
    TIM6_CR1 &= ~TIM_CR1_CEN;
    TIM6_DIER = 0u;
    nvic_disable(IRQN_TIM6_DAC);
    TIM6_SR = 0u;
    g_board.tick_running = false;
}

/* ------------------------------------------------ sample and actuation */

int hal_sample_read(hal_sample *out)
{
    if (out == NULL)
        return HAL_EINVAL;
    if (!g_board.sample_fresh)
        return HAL_EAGAIN;
    *out = g_board.sample;
    g_board.sample_fresh = false;
    return HAL_OK;
}

int hal_actuate(const hal_actuation *act)
{
    if (act == NULL)
        return HAL_EINVAL;
    for (unsigned v = 0u; v < 2u; v++) {
        for (unsigned leg = 0u; leg < 3u; leg++) {
            if (act->vector[v].leg[leg] > (uint8_t)HAL_LEG_P)
                return HAL_EINVAL;
        }
    }
    if (!(act->duty0 >= 0.0f && act->duty0 <= 1.0f)) /* also refuses NaN */
        return HAL_EINVAL;
    /* PORT: write the HRTIM timers' compare (duty split) and output set/reset
     * sources into their preload registers here; the master period event
     * transfers them at the start of the next period. */
    g_board.pending = *act;
    return HAL_OK;
}

/* ------------------------------------------------------ gates and faults */

void hal_gate_enable(bool enable)
{
    if (!enable) {
        board_safe_state();
        return;
    }
    /* PORT: enable the HRTIM outputs (HRTIM_OENR) and the gate-driver enable
     * pin, then set gates_on. Until the HRTIM port the request is refused and
     * hal_gate_enabled() keeps reporting the truth: off. */
}

bool hal_gate_enabled(void) { return g_board.gates_on; }

bool hal_fault_input_active(void)
{
    /* PORT: return the HRTIM fault-input flags (desaturation, over-current
     * comparator). With no output driven there is nothing to protect yet. */
    return false;
}

/* ------------------------------------------------------------------ time */

uint32_t hal_cycles(void) { return DWT_CYCCNT; }

uint32_t hal_cycles_hz(void) { return g_board.sysclk_hz; }

uint32_t hal_millis(void) { return g_board.millis; }

/* ------------------------------------------------------------------- CAN */

int hal_can_open(uint32_t bitrate_bps)
{
    if (bitrate_bps != 125000u && bitrate_bps != 250000u && bitrate_bps != 500000u &&
        bitrate_bps != 1000000u)
        return HAL_EINVAL;
    /* PORT: FDCAN1 in classic mode (bit timing from the 170 MHz kernel clock,
     * message RAM filters and FIFOs). Not ported yet. */
    return HAL_EIO;
}

int hal_can_send(const hal_can_frame *frame)
{
    if (frame == NULL || frame->id > 0x7FFu || frame->dlc > 8u)
        return HAL_EINVAL;
    return HAL_EIO; /* PORT: FDCAN1 transmit FIFO */
}

int hal_can_recv(hal_can_frame *frame)
{
    if (frame == NULL)
        return HAL_EINVAL;
    return HAL_EAGAIN; /* PORT: FDCAN1 receive FIFO 0; nothing can arrive yet */
}

/* ---------------------------------------------------------- non-volatile */

uint32_t hal_nvm_size(void) { return (uint32_t)(uintptr_t)__nvm_size; }

static int nvm_check(uint32_t offset, const void *buf, size_t len)
{
    uint32_t size = hal_nvm_size();
    if (buf == NULL && len != 0u)
        return HAL_EINVAL;
    if (offset > size || len > (size_t)(size - offset))
        return HAL_ENOSPC;
    return HAL_OK;
}

int hal_nvm_read(uint32_t offset, void *buf, size_t len)
{
    int rc = nvm_check(offset, buf, len);
    if (rc != HAL_OK)
        return rc;
    /* Flash is memory-mapped: reading is a copy (erased bytes read 0xFF). */
    if (len != 0u)
        memcpy(buf, __nvm_start + offset, len);
    return HAL_OK;
}

int hal_nvm_write(uint32_t offset, const void *buf, size_t len)
{
    int rc = nvm_check(offset, buf, len);
    if (rc != HAL_OK)
        return rc;
    /* PORT: unlock FLASH_KEYR, erase the 2 KiB page(s), program double words.
     * Not ported yet: nothing is written. */
    return HAL_EIO;
}

/* -------------------------------------------------------------- watchdog */

int hal_watchdog_start(uint32_t timeout_ms)
{
    if (timeout_ms < 1u || timeout_ms > 4000u)
        return HAL_EINVAL;
    /* LSI (about 32 kHz, +-several %) / 32 = one reload count per ms. The
     * start key also switches the LSI on; once started it cannot be stopped. */
    IWDG_KR = IWDG_KEY_START;
    IWDG_KR = IWDG_KEY_UNLOCK;
    IWDG_PR = IWDG_PR_DIV32;
    IWDG_RLR = timeout_ms;
    if (!wait_set(&IWDG_SR, IWDG_SR_BUSY_MASK, 0u))
        return HAL_EIO;
    IWDG_KR = IWDG_KEY_REFRESH;
    return HAL_OK;
}

void hal_watchdog_kick(void) { IWDG_KR = IWDG_KEY_REFRESH; }
