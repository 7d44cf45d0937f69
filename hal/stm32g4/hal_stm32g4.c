/**
 * @file hal_stm32g4.c
 * @brief Binding of hal/hal.h for the NUCLEO-G474RE control card driving a
 *        three-level NPC power stage (STM32G474RE at 170 MHz).
 *
 * Everything the contract asks for is real on this board:
 *  - clock: HSE 24 MHz -> PLL -> 170 MHz, HSI16 fall-back (RM0440 7.2, 6.1.5);
 *  - gates: HRTIM timers A..F, two complementary outputs each = the 12
 *    switches, hardware dead time, preloaded compare/set/reset programs
 *    transferred at the period start (RM0440 27.3);
 *  - fault: the gate drivers' active-low fault line on HRTIM FLT3 (PB10,
 *    outer switches) and external event 6 (PB5, filtered: inner switches);
 *  - sampling: ADC1 + ADC2 injected simultaneous conversions and ADC3
 *    (ic) triggered by the same HRTIM master compare at a fixed instant of
 *    the period; ADC1's end-of-sequence interrupt is the control tick
 *    (RM0440 21.4);
 *  - CAN: FDCAN1 classic CAN, fixed message RAM layout (RM0440 44.3);
 *  - NVM: two 2 KiB flash pages of bank 2 (RM0440 5.3);
 *  - watchdog: IWDG refreshed only when both the tick and the background have
 *    proven alive (RM0440 41.3).
 * Pin map, analog scaling, priorities, the HRTIM scheme and the fault
 * sequence are documented for the hardware engineer in docs/board.md.
 *
 * The board is a singleton, so its state is one file-level struct; the
 * portable firmware keeps no such state (the rule applies to firmware/).
 */
#include <stddef.h>
#include <string.h>

#include "board.h"
#include "hal/hal.h"
#include "npc_plan.h"
#include "stm32g474_regs.h"

/* ------------------------------------------------------------ board facts */

/* Sensor scaling of the power board (docs/motor-10hp.json "drive", docs/board.md). */
#define BOARD_ADC_FULL_CODE 4095.0f /* 12-bit converter, 0..3.3 V */
#define BOARD_I_FULL_SCALE_A 150.0f /* currents: code 0 = -150 A, 4095 = +150 A */
#define BOARD_V_FULL_SCALE_V 500.0f /* capacitor voltages: code 0 = 0 V, 4095 = 500 V */
#define BOARD_ADC_MID_CODE 2048u
#define BOARD_ADC_SAT_LOW 2u     /* codes at or beyond these are saturated */
#define BOARD_ADC_SAT_HIGH 4093u
#define BOARD_OFFSET_TOL_CODE 205u /* +-5 % of full scale accepted as a current offset */
#define BOARD_OFFSET_SAMPLES 64u

/* Interrupt priorities (4 bits, 0 = most urgent), docs/board.md. */
#define PRIO_HRTIM_FAULT 0u  /* runs once per trip: inner switches off */
#define PRIO_CONTROL_TICK 1u /* ADC1/2 end of injected sequence: the 200 us tick */
#define PRIO_SYSTICK 15u     /* 1 ms time base; CAN and flash are polled in the background */

/* Sampling instant and switching keep-out, ns after the period start. */
#define BOARD_SAMPLE_DELAY_NS 4000u  /* after the period-start edges and their dead time */
#define BOARD_KEEPOUT_END_NS 7000u   /* sampling (2 ranks x 0.87 us, to 5.74 us) is over by then */
#define BOARD_MIN_PULSE_NS 2000u     /* shortest second-vector pulse at the period end */
#define BOARD_START_EVENT_COUNTS 3u  /* CMP2: period-start event, 3 counts after roll-over */

/* Bounded waits on hardware flags. */
#define WAIT_LOOPS 200000u         /* about 1..6 ms depending on the bus */
#define WAIT_HSE_LOOPS 400000u     /* HSE start-up: a few ms at 16 MHz */
#define WAIT_FLASH_LOOPS 20000000u /* page erase: 40 ms max (datasheet), generous */
#define CAN_BUSOFF_RETRY_MS 100u

/* HRTIM outputs in OENR/ODISR: per leg, timer A-type = S3 (out 1) / S1
 * (out 2), timer B-type = S2 (out 1) / S4 (out 2): output 1 of every timer
 * is an inner switch, so one external event can reset all of them in
 * hardware. Outer switches S1, S4: TA2 TB2 .. TF2; inner S3, S2: TA1 .. TF1. */
#define HRTIM_OUT_OUTER 0xAAAu
#define HRTIM_OUT_INNER 0x555u

/* NVM area, from stm32g474.ld. */
extern const uint8_t __nvm_start[];
extern const uint8_t __nvm_size[];
#define NVM_PAGE_SIZE 2048u
#define FLASH_BANK2_START 0x08040000u

/* Start of the vector table, from stm32g474.ld. */
extern const uint32_t __isr_vector_start[];

/* ------------------------------------------------------------- pin map */

/* One GPIO the firmware configures; docs/board.md has the same table
 * (tools/svd/check_regs.py --board compares the two). */
typedef struct {
    uint32_t port_base;
    uint8_t pin;
    uint8_t mode; /* GPIO_MODE_* */
    uint8_t af;   /* alternate function when mode == GPIO_MODE_AF */
    uint8_t pupd; /* 0 none, 1 pull-up, 2 pull-down */
} board_pin;

#define PIN_AF(port, pin, af, pupd) {port, pin, GPIO_MODE_AF, af, pupd}
#define PIN_ANALOG(port, pin) {port, pin, GPIO_MODE_ANALOG, 0u, 0u}

static const board_pin g_pins[] = {
    /* HRTIM gate outputs (pull-downs hold the drivers off while the pins float). */
    PIN_AF(GPIOA_BASE, 8u, 13u, 2u),  /* CHA1 leg a S3 */
    PIN_AF(GPIOA_BASE, 9u, 13u, 2u),  /* CHA2 leg a S1 */
    PIN_AF(GPIOA_BASE, 10u, 13u, 2u), /* CHB1 leg a S2 */
    PIN_AF(GPIOA_BASE, 11u, 13u, 2u), /* CHB2 leg a S4 */
    PIN_AF(GPIOB_BASE, 12u, 13u, 2u), /* CHC1 leg b S3 */
    PIN_AF(GPIOB_BASE, 13u, 13u, 2u), /* CHC2 leg b S1 */
    PIN_AF(GPIOB_BASE, 14u, 13u, 2u), /* CHD1 leg b S2 */
    PIN_AF(GPIOB_BASE, 15u, 13u, 2u), /* CHD2 leg b S4 */
    PIN_AF(GPIOC_BASE, 8u, 3u, 2u),   /* CHE1 leg c S3 */
    PIN_AF(GPIOC_BASE, 9u, 3u, 2u),   /* CHE2 leg c S1 */
    PIN_AF(GPIOC_BASE, 6u, 13u, 2u),  /* CHF1 leg c S2 */
    PIN_AF(GPIOC_BASE, 7u, 13u, 2u),  /* CHF2 leg c S4 */
    /* Gate-driver fault line, active low, open drain: pull-up. */
    PIN_AF(GPIOB_BASE, 10u, 13u, 1u), /* HRTIM_FLT3: outer switches off */
    PIN_AF(GPIOB_BASE, 5u, 13u, 1u),  /* HRTIM_EEV6, the same line: inner switches off (filtered) */
    /* FDCAN1 to the transceiver. */
    PIN_AF(GPIOB_BASE, 8u, 9u, 1u), /* FDCAN1_RX */
    PIN_AF(GPIOB_BASE, 9u, 9u, 0u), /* FDCAN1_TX */
    /* Analog inputs. */
    PIN_ANALOG(GPIOA_BASE, 0u), /* ADC1_IN1 ia */
    PIN_ANALOG(GPIOA_BASE, 1u), /* ADC2_IN2 ib */
    PIN_ANALOG(GPIOB_BASE, 1u), /* ADC3_IN1 ic */
    PIN_ANALOG(GPIOC_BASE, 0u), /* ADC1_IN6 vc1 */
    PIN_ANALOG(GPIOC_BASE, 1u), /* ADC2_IN7 vc2 */
};

/* ADC channels: ADC1 ranks [ia, vc1], ADC2 ranks [ib, vc2] (dual injected
 * simultaneous), ADC3 rank [ic] on the same trigger: the three currents are
 * sampled at one instant, the two capacitor voltages at the next rank. */
#define ADC1_CH_IA 1u
#define ADC1_CH_VC1 6u
#define ADC2_CH_IB 2u
#define ADC2_CH_VC2 7u
#define ADC3_CH_IC 1u /* PB1 = ADC3_IN1 (datasheet pin table, LQFP64) */

/* ------------------------------------------------------------- state */

typedef struct {
    uint32_t sysclk_hz;       /* 170 MHz, or 16 MHz if the PLL failed to lock */
    volatile uint32_t faults; /* board_fault bits */
    hal_tick_handler handler; /* control-tick callback */
    void *ctx;
    bool tick_running;
    volatile uint32_t millis; /* written by SysTick only */
    uint32_t code[5];         /* this tick's ADC codes (ia, ib, ic, vc1, vc2), latched by the tick ISR */
    bool sample_fresh;        /* cleared by the one allowed read, which converts code[] */
    bool adc_ok;              /* calibration and offsets valid */
    uint32_t seq;             /* tick sequence number */
    float offset_code[3];     /* current-sensor zero, ADC codes (ia, ib, ic) */
    /* HRTIM timing, counts of the timer clock */
    uint32_t per_counts;
    uint32_t keepout_counts;
    uint32_t min_pulse_counts;
    float per_f;              /* per_counts as a float (exact: below 2^16), for the instant */
    npc_usual usual;          /* the period's usual instants (npc_usual_of) */
    uint8_t last_leg[4];      /* leg state at the end of the last latched period (with NPC_LEG_HELD: the timers hold its one-state words); [3] stays 0 (npc_leg_words_index3) */
    uint32_t pn_fixups;       /* P<->N steps replaced by O (diagnostics) */
    bool idle_held;           /* gates off: the preloaded registers hold idle_req's programme, which repeats itself */
    npc_request idle_req;     /* the last request programmed with the gates off */
    volatile bool gates_on;
    volatile bool fault_latched; /* set by the HRTIM fault ISR, reported once */
    uint32_t fault_inner_cycles; /* BOARD_FAULT_BACKUP_DELAY_NS in core cycles, set before the fault is armed */
    uint32_t fault_trips;
    /* watchdog and reset cause */
    uint32_t reset_cause;         /* enum hal_reset_cause, from RCC_CSR at board_init */
    bool wdg_started;
    volatile bool wdg_tick_alive; /* set by the tick ISR */
    /* NVM reads: a double ECC error there is an interrupted write, not a broken chip */
    volatile bool nvm_reading;    /* the background is reading the parameter pages */
    volatile bool nvm_ecc_hit;    /* the NMI saw FLASH_ECCR.ECCD meanwhile */
    uint32_t nvm_ecc_errors;
    /* CAN */
    bool can_open;
    uint32_t can_busoff_ms;
    bool can_busoff;
    uint32_t can_busoff_count;
    uint32_t can_rx_lost;
} board_state;

static board_state g_board;

/* ------------------------------------------------------------ helpers */

static bool wait_set(volatile uint32_t *reg, uint32_t mask, uint32_t value, uint32_t loops)
{
    for (uint32_t n = 0u; n < loops; n++) {
        if ((*reg & mask) == value)
            return true;
    }
    return false;
}

/* Busy wait of at least @p ns, from the DWT cycle counter (bounded by itself). */
static void delay_ns(uint32_t ns)
{
    uint32_t hz = g_board.sysclk_hz != 0u ? g_board.sysclk_hz : 16000000u;
    uint32_t cycles = (uint32_t)(((uint64_t)ns * hz + 999999999u) / 1000000000u);
    uint32_t t0 = DWT_CYCCNT;
    /* If the counter does not run (no DEMCR), fall back to a loop of the same length. */
    for (uint32_t n = 0u; n < cycles; n++) {
        if (DWT_CYCCNT - t0 >= cycles)
            break;
    }
}

static uint32_t ns_to_counts(uint32_t ns, uint32_t count_hz)
{
    return (uint32_t)(((uint64_t)ns * count_hz + 500000000u) / 1000000000u);
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

static bool in_interrupt(void)
{
    uint32_t ipsr;
    __asm volatile("mrs %0, ipsr" : "=r"(ipsr));
    return (ipsr & 0x1FFu) != 0u;
}

uint32_t board_faults(void) { return g_board.faults; }

/* --------------------------------------------------------------- clock */

/*
 * RM0440 order of operations (6.1.5 range 1 boost, 5.3.3 wait states, 7.2.4
 * PLL, 7.2.7 clock switch): PWR clock on; 4 wait states before the clock
 * rises; AHB / 2 while switching above 80 MHz; R1MODE = 0 (boost); HSE on
 * (bounded wait); PLL from HSE (or HSI16) to 340 MHz VCO / 2; switch; after
 * at least 1 us AHB back to / 1. APB1/APB2 stay / 1 (PCLK = 170 MHz).
 */
static void clock_init_170mhz(void)
{
    g_board.sysclk_hz = 16000000u; /* HSI16 after reset */

    RCC_APB1ENR1 |= RCC_APB1ENR1_PWREN;
    (void)RCC_APB1ENR1; /* read back: the clock is on before PWR is touched */
    RCC_AHB1ENR |= RCC_AHB1ENR_FLASHEN;

    /* Voltage scaling range 1 (reset value; made explicit), then boost. */
    PWR_CR1 = (PWR_CR1 & ~PWR_CR1_VOS_MASK) | PWR_CR1_VOS_RANGE1;
    (void)wait_set(&PWR_SR2, PWR_SR2_VOSF, 0u, WAIT_LOOPS);

    FLASH_ACR = (FLASH_ACR & ~FLASH_ACR_LATENCY_MASK) | FLASH_ACR_LATENCY_4WS | FLASH_ACR_PRFTEN |
                FLASH_ACR_ICEN | FLASH_ACR_DCEN;
    if (!wait_set(&FLASH_ACR, FLASH_ACR_LATENCY_MASK, FLASH_ACR_LATENCY_4WS, WAIT_LOOPS)) {
        g_board.faults |= BOARD_FAULT_PLL; /* cannot raise the clock safely */
        return;
    }

    /* AHB / 2 first, then range 1 boost (RM0440 6.1.5: the core current steps in halves). */
    RCC_CFGR = (RCC_CFGR & ~(RCC_CFGR_HPRE_MASK | RCC_CFGR_PPRE1_MASK | RCC_CFGR_PPRE2_MASK)) |
               RCC_CFGR_HPRE_DIV2;
    PWR_CR5 &= ~PWR_CR5_R1MODE;

    /* HSE: 24 MHz crystal; bounded start-up, clean fall-back to HSI16. */
    uint32_t pllsrc = RCC_PLLCFGR_PLLSRC_HSE;
    uint32_t pllm = 6u; /* 24 MHz / 6 = 4 MHz VCO input */
    RCC_CR |= RCC_CR_HSEON;
    if (!wait_set(&RCC_CR, RCC_CR_HSERDY, RCC_CR_HSERDY, WAIT_HSE_LOOPS)) {
        RCC_CR &= ~RCC_CR_HSEON;
        g_board.faults |= BOARD_FAULT_HSE;
        pllsrc = RCC_PLLCFGR_PLLSRC_HSI16;
        pllm = 4u; /* 16 MHz / 4 = 4 MHz */
    }
    RCC_CR |= RCC_CR_HSION;
    if (!wait_set(&RCC_CR, RCC_CR_HSIRDY, RCC_CR_HSIRDY, WAIT_LOOPS)) {
        g_board.faults |= BOARD_FAULT_PLL;
        return;
    }

    RCC_CR &= ~RCC_CR_PLLON;
    if (!wait_set(&RCC_CR, RCC_CR_PLLRDY, 0u, WAIT_LOOPS)) {
        g_board.faults |= BOARD_FAULT_PLL;
        return;
    }
    /* 4 MHz x N 85 = 340 MHz VCO (96..344), / R 2 = 170 MHz. */
    RCC_PLLCFGR = pllsrc | ((pllm - 1u) << RCC_PLLCFGR_PLLM_SHIFT) | (85u << RCC_PLLCFGR_PLLN_SHIFT) |
                  RCC_PLLCFGR_PLLREN | (0u << RCC_PLLCFGR_PLLR_SHIFT);
    RCC_CR |= RCC_CR_PLLON;
    if (!wait_set(&RCC_CR, RCC_CR_PLLRDY, RCC_CR_PLLRDY, WAIT_LOOPS)) {
        RCC_CR &= ~RCC_CR_PLLON;
        RCC_CFGR &= ~RCC_CFGR_HPRE_MASK; /* stay on HSI16, AHB / 1 */
        g_board.faults |= BOARD_FAULT_PLL;
        return;
    }

    RCC_CFGR = (RCC_CFGR & ~RCC_CFGR_SW_MASK) | RCC_CFGR_SW_PLL;
    if (!wait_set(&RCC_CFGR, RCC_CFGR_SWS_MASK, RCC_CFGR_SWS_PLL, WAIT_LOOPS)) {
        RCC_CFGR = (RCC_CFGR & ~(RCC_CFGR_SW_MASK | RCC_CFGR_HPRE_MASK)) | RCC_CFGR_SW_HSI16;
        g_board.faults |= BOARD_FAULT_PLL;
        return;
    }
    g_board.sysclk_hz = BOARD_SYSCLK_HZ / 2u;
    delay_ns(1000u); /* >= 1 us at AHB / 2 (RM0440 7.2.7) */
    RCC_CFGR &= ~RCC_CFGR_HPRE_MASK;
    g_board.sysclk_hz = BOARD_SYSCLK_HZ;

    /* Clock security: an HSE failure now raises NMI -> Default_Handler -> safe state. */
    if ((g_board.faults & BOARD_FAULT_HSE) == 0u)
        RCC_CR |= RCC_CR_CSSON;
}

/* ---------------------------------------------------------------- GPIO */

static void gpio_init(void)
{
    RCC_AHB2ENR |= RCC_AHB2ENR_GPIOAEN | RCC_AHB2ENR_GPIOBEN | RCC_AHB2ENR_GPIOCEN;
    (void)RCC_AHB2ENR;
    for (size_t i = 0u; i < sizeof g_pins / sizeof g_pins[0]; i++) {
        const board_pin *p = &g_pins[i];
        uint32_t b = p->port_base;
        uint32_t pin = p->pin;
        /* Pull and speed first, then the AF number, then the mode (RM0440 9.3.2). */
        GPIO_REG(b, GPIO_PUPDR_OFS) =
            (GPIO_REG(b, GPIO_PUPDR_OFS) & ~(3u << (2u * pin))) | ((uint32_t)p->pupd << (2u * pin));
        if (p->mode == GPIO_MODE_AF) {
            GPIO_REG(b, GPIO_OSPEEDR_OFS) |= 2u << (2u * pin); /* high speed: clean gate edges */
            uint32_t ofs = pin < 8u ? GPIO_AFRL_OFS : GPIO_AFRH_OFS;
            uint32_t sh = 4u * (pin & 7u);
            GPIO_REG(b, ofs) = (GPIO_REG(b, ofs) & ~(GPIO_AFR_MASK0 << sh)) | ((uint32_t)p->af << sh);
        }
        GPIO_REG(b, GPIO_MODER_OFS) = (GPIO_REG(b, GPIO_MODER_OFS) & ~(GPIO_MODER_MASK0 << (2u * pin))) |
                                      ((uint32_t)p->mode << (2u * pin));
    }
}

/* --------------------------------------------------------------- HRTIM */

/* Outputs off, outer switches first (RM0440 27.3.15: ODISR takes an output
 * to its idle level, inactive here, without waiting for the period). */
static void hrtim_outputs_off(void)
{
    HRTIM_ODISR = HRTIM_OUT_OUTER;
    delay_ns(BOARD_DEAD_TIME_NS); /* not urgent here: the full dead time between outer and inner */
    HRTIM_ODISR = HRTIM_OUT_INNER;
}

/*
 * Static part of the HRTIM, done at reset with the outputs disabled:
 * output idle/fault states, dead time, fault input FLT3 (RM0440 27.3.15-17).
 * The outputs are in their idle (inactive, low) level until OENR.
 */
static void hrtim_init_static(void)
{
    RCC_APB2ENR |= RCC_APB2ENR_HRTIM1EN;
    (void)RCC_APB2ENR;
    HRTIM_ODISR = HRTIM_OUT_ALL;

    /* Dead time: tDTG = 2^DTPRSC x tHRTIM / 8 (RM0440, HRTIM dead-time
     * generator), 9-bit count. Prescalers below 3 (finer than tHRTIM) use the
     * high-resolution delay line, which needs the DLL; this port runs the
     * HRTIM in low resolution, so the search starts at DTPRSC = 3 (5.88 ns). */
    uint32_t dt_prsc = 3u;
    uint32_t dt_counts = 0u;
    for (dt_prsc = 3u; dt_prsc < 8u; dt_prsc++) {
        uint64_t tdtg_hz = ((uint64_t)g_board.sysclk_hz * 8u) >> dt_prsc;
        dt_counts = (uint32_t)(((uint64_t)BOARD_DEAD_TIME_NS * tdtg_hz + 999999999u) / 1000000000u);
        if (dt_counts <= 511u)
            break;
    }
    uint32_t dtr = (dt_counts << HRTIM_DTxR_DTR_SHIFT) | (dt_prsc << HRTIM_DTxR_DTPRSC_SHIFT) |
                   (dt_counts << HRTIM_DTxR_DTF_SHIFT);

    for (uint32_t t = 0u; t < 6u; t++) {
        /* Fault states, NPC order: output 2 (the outer switch, S1 or S4) goes
         * to its inactive level through FLT3 at once; output 1 (the inner
         * switch, S3 or S2) keeps its waveform until the filtered external
         * event 6 resets it BOARD_FAULT_INNER_DELAY_NS later (RSTx1R). */
        uint32_t fault = HRTIM_OUTxR_FAULT1_NONE | HRTIM_OUTxR_FAULT2_INACTIVE;
        /* Complementary pair with dead time on both edges; POL = 0 (active
         * high), idle level inactive (IDLES = 0). */
        HRTIM_TIM_REG(t, HRTIM_OUTxR_OFS) = HRTIM_OUTxR_DTEN | fault;
        HRTIM_TIM_REG(t, HRTIM_DTxR_OFS) = dtr;
        HRTIM_TIM_REG(t, HRTIM_FLTxR_OFS) = HRTIM_FLTxR_FLT3EN | HRTIM_FLTxR_FLTLCK;
    }

    /* External event 6 = the fault line's second pin (PB5): active low,
     * level-sensitive, digital filter of 8 samples at fHRTIM / 16. Written
     * before any counter runs (RM0440, HRTIM_EECRx: not to be changed once a
     * timer using the event is enabled). As a reset source of output 1 it
     * holds the inner switches off while the line is low: a reset request has
     * priority over a simultaneous set (RM0440 27.3.7). */
    HRTIM_EECR2 = (HRTIM_EECR2 & ~HRTIM_EECR2_EE6_MASK) | HRTIM_EECR2_EE6SRC_PIN | HRTIM_EECR2_EE6POL_LOW |
                  HRTIM_EECR2_EE6SNS_LEVEL;
    HRTIM_EECR3 = (HRTIM_EECR3 & ~(HRTIM_EECR3_EE6F_MASK | HRTIM_EECR3_EEVSD_MASK)) | HRTIM_EECR3_EEVSD_DIV1 |
                  (HRTIM_EEF_DIV16_N8 << HRTIM_EECR3_EE6F_SHIFT);
}

/* Arm the fault input once PB10 is in its HRTIM alternate function (in
 * analog mode the input would read low = fault). */
static void hrtim_arm_fault(void)
{
    /* FLT3 = PB10 pin, active low, no digital filter: the fastest response
     * (a few tHRTIM of input synchronisation). The comparators on the power
     * board filter the desaturation glitches. Locked until reset. */
    /* Polarity, source and filter may change only while FLT3E = 0, so: configure,
     * enable, then lock (RM0440, HRTIM chapter, HRTIM_FLTINR1 description). */
    HRTIM_FLTINR1 = (HRTIM_FLTINR1 & ~(0xFFu << 16)) | (0u << HRTIM_FLTINR1_FLT3F_SHIFT);
    HRTIM_FLTINR1 |= HRTIM_FLTINR1_FLT3E;
    HRTIM_FLTINR1 |= HRTIM_FLTINR1_FLT3LCK;
    HRTIM_ICR = HRTIM_ICR_FLT3C;
    HRTIM_IER |= HRTIM_IER_FLT3IE;
    /* The back-up stage's delay, precomputed: no division in the handler. */
    g_board.fault_inner_cycles =
        (uint32_t)(((uint64_t)BOARD_FAULT_BACKUP_DELAY_NS * g_board.sysclk_hz + 999999999u) / 1000000000u);
    nvic_enable(IRQN_HRTIM1_FLT, PRIO_HRTIM_FAULT);
}

/** HRTIM fault interrupt, the software back-up: the outer switches are off
 * through FLT3 and the inner ones go off through the filtered external event
 * 6, both in hardware. BOARD_FAULT_BACKUP_DELAY_NS after the handler's entry
 * (after the hardware inner stage) every output is disabled, so the inner
 * switches are off even if the second input is not wired; then the trip is
 * latched. The first action is the time stamp, the wait a precomputed cycle
 * count (bounded by its own loop count should the cycle counter stop), the
 * second a single store of a constant. Context: interrupt, most urgent
 * (priority 0: pre-empts the control tick; nothing in the firmware masks it). */
void HRTIM1_FLT_IRQHandler(void)
{
    const uint32_t t0 = DWT_CYCCNT;
    const uint32_t wait = g_board.fault_inner_cycles;
    for (uint32_t n = 0u; n < wait && DWT_CYCCNT - t0 < wait; n++) {
    }
    HRTIM_ODISR = HRTIM_OUT_ALL;
    /* One interrupt per trip: a line held low must not starve the tick.
     * hal_gate_enable(true) re-arms it once the line is high again. */
    HRTIM_IER &= ~HRTIM_IER_FLT3IE;
    HRTIM_ICR = HRTIM_ICR_FLT3C;
    g_board.gates_on = false;
    g_board.fault_latched = true;
    g_board.fault_trips++;
    g_board.faults |= BOARD_FAULT_HRTIM;
}

/*
 * Dynamic part: the period. Master and timers A..F share prescaler and
 * period and are started by one MCR write, so their counters are aligned.
 * Every timer register written by hal_actuate is preloaded (PREEN) and
 * transferred at the roll-over (TxREPU with REP = 0, RM0440 27.3.8).
 * Master compare 1 is the ADC trigger (ADC trigger 2, RM0440 27.3.19).
 */
static int hrtim_start(uint32_t period_us)
{
    /* fCOUNTER = fHRTIM x 32 / 2^CKPSC; CKPSC >= 5 (low resolution, no DLL needed). */
    uint32_t ckpsc = 5u;
    uint32_t count_hz = g_board.sysclk_hz;
    uint32_t per = (uint32_t)(((uint64_t)period_us * count_hz) / 1000000u);
    while (per > 0xFFDFu && ckpsc < 7u) {
        ckpsc++;
        count_hz /= 2u;
        per /= 2u;
    }
    if (per > 0xFFDFu || per < 64u)
        return HAL_EINVAL;
    g_board.per_counts = per;
    g_board.keepout_counts = ns_to_counts(BOARD_KEEPOUT_END_NS, count_hz);
    g_board.min_pulse_counts = ns_to_counts(BOARD_MIN_PULSE_NS, count_hz);
    g_board.per_f = (float)per;
    const npc_timing tm = {per, g_board.keepout_counts, g_board.min_pulse_counts};
    g_board.usual = npc_usual_of(&tm);

    HRTIM_MCR = (ckpsc << HRTIM_MCR_CK_PSC_SHIFT) | HRTIM_MCR_CONT | HRTIM_MCR_PREEN | HRTIM_MCR_MREPU;
    HRTIM_MPER = per;
    HRTIM_MREP = 0u;
    HRTIM_MCMP1R = ns_to_counts(BOARD_SAMPLE_DELAY_NS, count_hz);

    for (uint32_t t = 0u; t < 6u; t++) {
        HRTIM_TIM_REG(t, HRTIM_TIMxCR_OFS) =
            (ckpsc << HRTIM_TIMxCR_CK_PSC_SHIFT) | HRTIM_TIMxCR_CONT | HRTIM_TIMxCR_PREEN | HRTIM_TIMxCR_TREPU;
        HRTIM_TIM_REG(t, HRTIM_PERxR_OFS) = per;
        HRTIM_TIM_REG(t, HRTIM_REPxR_OFS) = 0u;
        HRTIM_TIM_REG(t, HRTIM_CMP1xR_OFS) = per / 2u;
        HRTIM_TIM_REG(t, HRTIM_CMP2xR_OFS) = BOARD_START_EVENT_COUNTS;
        /* Every leg starts clamped to the neutral point (O): output 1 (S3,
         * S2) high in both pairs. External event 6 resets output 1 (fault). */
        HRTIM_TIM_REG(t, HRTIM_SETx1R_OFS) = HRTIM_SET_CMP2;
        HRTIM_TIM_REG(t, HRTIM_RSTx1R_OFS) = HRTIM_RST_EXTEVNT6;
    }
    for (uint32_t leg = 0u; leg < 3u; leg++)
        g_board.last_leg[leg] = (uint8_t)HAL_LEG_O;
    g_board.last_leg[3] = 0u;
    g_board.idle_held = false;

    /* The ADC trigger's update source stays the master timer (HRTIM_CR1 ADxUSRC at reset):
     * program_period writes CR1 whole, so an update source set in CR1 would be cleared there. */
    HRTIM_ADC2R = HRTIM_ADC2R_AD2MC1;
    HRTIM_MICR = HRTIM_MICR_MCMP1C;
    HRTIM_CR2 = HRTIM_CR2_SWU_ALL; /* preload -> active now, before the counters run */
    HRTIM_MCR |= HRTIM_MCR_MCEN | HRTIM_MCR_TACEN | HRTIM_MCR_TBCEN | HRTIM_MCR_TCCEN | HRTIM_MCR_TDCEN |
                 HRTIM_MCR_TECEN | HRTIM_MCR_TFCEN;
    return HAL_OK;
}

static void hrtim_stop(void)
{
    hrtim_outputs_off();
    HRTIM_MCR &= ~(HRTIM_MCR_MCEN | HRTIM_MCR_TACEN | HRTIM_MCR_TBCEN | HRTIM_MCR_TCCEN | HRTIM_MCR_TDCEN |
                   HRTIM_MCR_TECEN | HRTIM_MCR_TFCEN);
}

/* ----------------------------------------------------------------- ADC */

static bool adc_power_up(uint32_t base)
{
    /* Exit deep power-down, start the regulator, wait tADCVREG_STUP (20 us,
     * datasheet), calibrate single-ended (RM0440 21.4.6, 21.4.8). */
    ADC_REG(base, ADC_CR_OFS) = 0u; /* DEEPPWD = 0 */
    ADC_REG(base, ADC_CR_OFS) = ADC_CR_ADVREGEN;
    delay_ns(20000u);
    ADC_REG(base, ADC_CR_OFS) = ADC_CR_ADVREGEN | ADC_CR_ADCAL; /* ADCALDIF = 0: single-ended */
    if (!wait_set(&ADC_REG(base, ADC_CR_OFS), ADC_CR_ADCAL, 0u, WAIT_LOOPS))
        return false;
    delay_ns(1000u); /* 4 ADC clocks between ADCAL = 0 and ADEN = 1 */
    ADC_REG(base, ADC_ISR_OFS) = ADC_ISR_ADRDY;
    ADC_REG(base, ADC_CR_OFS) = ADC_CR_ADVREGEN | ADC_CR_ADEN;
    if (!wait_set(&ADC_REG(base, ADC_ISR_OFS), ADC_ISR_ADRDY, ADC_ISR_ADRDY, WAIT_LOOPS))
        return false;
    ADC_REG(base, ADC_ISR_OFS) = ADC_ISR_ADRDY;
    return true;
}

static uint32_t smp_bits(uint32_t ch) { return ADC_SMP_24C5 << (ADC_SMPR_BITS * (ch % 10u)); }

static void adc_set_sampling(uint32_t base, uint32_t ch)
{
    uint32_t ofs = ch < 10u ? ADC_SMPR1_OFS : ADC_SMPR2_OFS;
    uint32_t sh = ADC_SMPR_BITS * (ch % 10u);
    ADC_REG(base, ofs) = (ADC_REG(base, ofs) & ~(7u << sh)) | smp_bits(ch);
}

/*
 * ADC1 (master) + ADC2 (slave), dual injected simultaneous mode, 2 ranks
 * each, and ADC3 (independent, 1 rank), all three triggered by HRTIM ADC
 * trigger 2 (master compare 1) on the rising edge: JEXTSEL 19 is
 * hrtim_adc_trg2 in both the ADC1/2 and the ADC3/4/5 injected trigger tables
 * (RM0440, ADC chapter). Both ADC pairs are clocked HCLK / 4 = 42.5 MHz,
 * synchronous with the HRTIM, so the sampling instants have no jitter
 * (RM0440 21.4.3, 21.4.31). 24.5 + 12.5 ADC cycles = 0.87 us per rank:
 * ia, ib and ic are sampled at the trigger (rank 1), vc1 and vc2 one rank
 * later; ADC3's single rank ends one rank before ADC1's sequence.
 */
static bool adc_init(void)
{
    RCC_CCIPR = (RCC_CCIPR & ~(RCC_CCIPR_ADC12SEL_MASK | RCC_CCIPR_ADC345SEL_MASK)) | RCC_CCIPR_ADC12SEL_SYSCLK |
                RCC_CCIPR_ADC345SEL_SYSCLK;
    RCC_AHB2ENR |= RCC_AHB2ENR_ADC12EN | RCC_AHB2ENR_ADC345EN;
    (void)RCC_AHB2ENR;
    /* Clock mode and dual mode may be written only while the ADCs of the
     * pair are disabled (RM0440, ADC chapter, ADC_CCR description). */
    ADC12_CCR = (ADC12_CCR & ~(ADC12_CCR_CKMODE_MASK | ADC12_CCR_DUAL_MASK)) | ADC12_CCR_CKMODE_HCLK_DIV4 |
                ADC12_CCR_DUAL_INJ_SIMULT;
    ADC345_CCR = (ADC345_CCR & ~(ADC345_CCR_CKMODE_MASK | ADC345_CCR_DUAL_MASK)) | ADC345_CCR_CKMODE_HCLK_DIV4;

    if (!adc_power_up(ADC1_BASE) || !adc_power_up(ADC2_BASE) || !adc_power_up(ADC3_BASE))
        return false;

    ADC_REG(ADC1_BASE, ADC_CFGR_OFS) |= ADC_CFGR_JQDIS;
    ADC_REG(ADC2_BASE, ADC_CFGR_OFS) |= ADC_CFGR_JQDIS;
    ADC_REG(ADC3_BASE, ADC_CFGR_OFS) |= ADC_CFGR_JQDIS;
    adc_set_sampling(ADC1_BASE, ADC1_CH_IA);
    adc_set_sampling(ADC1_BASE, ADC1_CH_VC1);
    adc_set_sampling(ADC2_BASE, ADC2_CH_IB);
    adc_set_sampling(ADC2_BASE, ADC2_CH_VC2);
    adc_set_sampling(ADC3_BASE, ADC3_CH_IC);

    ADC_REG(ADC1_BASE, ADC_JSQR_OFS) = (1u << ADC_JSQR_JL_SHIFT) | (ADC_JEXTSEL_HRTIM_TRG2 << ADC_JSQR_JEXTSEL_SHIFT) |
                                      ADC_JSQR_JEXTEN_RISING | (ADC1_CH_IA << ADC_JSQR_JSQ1_SHIFT) |
                                      (ADC1_CH_VC1 << ADC_JSQR_JSQ2_SHIFT);
    /* The slave follows the master's trigger: its own trigger stays off. */
    ADC_REG(ADC2_BASE, ADC_JSQR_OFS) =
        (1u << ADC_JSQR_JL_SHIFT) | (ADC2_CH_IB << ADC_JSQR_JSQ1_SHIFT) | (ADC2_CH_VC2 << ADC_JSQR_JSQ2_SHIFT);
    ADC3_JSQR = (0u << ADC_JSQR_JL_SHIFT) | (ADC345_JEXTSEL_HRTIM_TRG2 << ADC_JSQR_JEXTSEL_SHIFT) |
                ADC_JSQR_JEXTEN_RISING | (ADC3_CH_IC << ADC_JSQR_JSQ1_SHIFT);

    ADC_REG(ADC1_BASE, ADC_ISR_OFS) = ADC_ISR_JEOS | ADC_ISR_JEOC;
    ADC_REG(ADC2_BASE, ADC_ISR_OFS) = ADC_ISR_JEOS | ADC_ISR_JEOC;
    ADC3_ISR = ADC_ISR_JEOS | ADC_ISR_JEOC;
    /* ADC3 armed first: both wait for the same HRTIM trigger edge. */
    ADC_REG(ADC3_BASE, ADC_CR_OFS) |= ADC_CR_JADSTART;
    ADC_REG(ADC1_BASE, ADC_CR_OFS) |= ADC_CR_JADSTART; /* the master starts both of its pair */
    return true;
}

/* Stop the injected conversions and disable the three ADCs (JADSTP, then ADDIS,
 * RM0440, ADC chapter, "Stopping an ongoing conversion" / "ADC on-off
 * control"), so a later adc_init() finds them disabled as it must. */
static void adc_stop(void)
{
    ADC_REG(ADC1_BASE, ADC_IER_OFS) = 0u;
    const uint32_t masters[2] = {ADC1_BASE, ADC3_BASE};
    for (unsigned k = 0u; k < 2u; k++) {
        if ((ADC_REG(masters[k], ADC_CR_OFS) & ADC_CR_JADSTART) != 0u) {
            ADC_REG(masters[k], ADC_CR_OFS) |= ADC_CR_JADSTP;
            (void)wait_set(&ADC_REG(masters[k], ADC_CR_OFS), ADC_CR_JADSTART, 0u, WAIT_LOOPS);
        }
    }
    const uint32_t bases[3] = {ADC1_BASE, ADC2_BASE, ADC3_BASE};
    for (unsigned k = 0u; k < 3u; k++) {
        if ((ADC_REG(bases[k], ADC_CR_OFS) & ADC_CR_ADEN) != 0u) {
            ADC_REG(bases[k], ADC_CR_OFS) |= ADC_CR_ADDIS;
            (void)wait_set(&ADC_REG(bases[k], ADC_CR_OFS), ADC_CR_ADEN, 0u, WAIT_LOOPS);
        }
    }
}

/*
 * Read the five injected results (ia, ib, ic, vc1, vc2) once ADC1's sequence
 * has ended. ADC3's single rank ends one rank (0.87 us) before ADC1's two on
 * the same trigger, but its result is taken only with its own JEOS set: a
 * missed or late ADC3 conversion is refused, never read stale.
 * @return ADC_CODES_OK, or why the sample must be refused.
 */
enum adc_codes { ADC_CODES_OK, ADC_CODES_SATURATED, ADC_CODES_IC_MISSING };

static enum adc_codes adc_read_codes(uint32_t code[5])
{
    bool ic_done = (ADC3_ISR & ADC_ISR_JEOS) != 0u;
    code[0] = ADC_JDR(ADC1_BASE, 0u) & 0xFFFu; /* ia */
    code[1] = ADC_JDR(ADC2_BASE, 0u) & 0xFFFu; /* ib */
    code[2] = ADC3_JDR1 & 0xFFFu;               /* ic */
    code[3] = ADC_JDR(ADC1_BASE, 1u) & 0xFFFu; /* vc1 */
    code[4] = ADC_JDR(ADC2_BASE, 1u) & 0xFFFu; /* vc2 */
    ADC_REG(ADC1_BASE, ADC_ISR_OFS) = ADC_ISR_JEOS | ADC_ISR_JEOC;
    ADC_REG(ADC2_BASE, ADC_ISR_OFS) = ADC_ISR_JEOS | ADC_ISR_JEOC;
    ADC3_ISR = ADC_ISR_JEOS | ADC_ISR_JEOC;
    if (!ic_done)
        return ADC_CODES_IC_MISSING;
    for (unsigned k = 0u; k < 5u; k++) {
        if (k < 3u && (code[k] <= BOARD_ADC_SAT_LOW || code[k] >= BOARD_ADC_SAT_HIGH))
            return ADC_CODES_SATURATED; /* a current at the rail: the sensor or the converter is saturated */
        if (k >= 3u && code[k] >= BOARD_ADC_SAT_HIGH)
            return ADC_CODES_SATURATED; /* a capacitor voltage at full scale (0 V is a valid reading) */
    }
    return ADC_CODES_OK;
}

/* Current offsets with the gates off: average BOARD_OFFSET_SAMPLES periods. */
static bool adc_calibrate_offsets(void)
{
    uint32_t sum[3] = {0u, 0u, 0u};
    for (uint32_t n = 0u; n < BOARD_OFFSET_SAMPLES; n++) {
        if (!wait_set(&ADC_REG(ADC1_BASE, ADC_ISR_OFS), ADC_ISR_JEOS, ADC_ISR_JEOS, WAIT_LOOPS))
            return false;
        uint32_t code[5];
        if (adc_read_codes(code) == ADC_CODES_IC_MISSING)
            return false; /* ADC3 did not convert with ADC1/2: no offset for ic */
        for (unsigned k = 0u; k < 3u; k++)
            sum[k] += code[k];
    }
    bool ok = true;
    for (unsigned k = 0u; k < 3u; k++) {
        uint32_t mean = (sum[k] + BOARD_OFFSET_SAMPLES / 2u) / BOARD_OFFSET_SAMPLES;
        uint32_t dev = mean > BOARD_ADC_MID_CODE ? mean - BOARD_ADC_MID_CODE : BOARD_ADC_MID_CODE - mean;
        if (dev > BOARD_OFFSET_TOL_CODE)
            ok = false;
        g_board.offset_code[k] = (float)sum[k] / (float)BOARD_OFFSET_SAMPLES;
    }
    return ok;
}

/* ------------------------------------------------------------ board_init */

/*
 * RCC_CSR reset flags -> one cause (RM0440, RCC chapter, RCC_CSR). An internal
 * reset also drives NRST, so PINRSTF comes with every other flag; a power-on
 * sets BORRSTF and PINRSTF. The most specific flag wins.
 */
static uint32_t reset_cause_from_csr(uint32_t csr)
{
    if ((csr & RCC_CSR_IWDGRSTF) != 0u)
        return HAL_RESET_WATCHDOG;
    if ((csr & RCC_CSR_WWDGRSTF) != 0u)
        return HAL_RESET_WINDOW_WATCHDOG;
    if ((csr & RCC_CSR_SFTRSTF) != 0u)
        return HAL_RESET_SOFTWARE;
    if ((csr & RCC_CSR_LPWRRSTF) != 0u)
        return HAL_RESET_LOW_POWER;
    if ((csr & RCC_CSR_OBLRSTF) != 0u)
        return HAL_RESET_OPTION_LOAD;
    if ((csr & RCC_CSR_BORRSTF) != 0u)
        return HAL_RESET_POWER_ON;
    if ((csr & RCC_CSR_PINRSTF) != 0u)
        return HAL_RESET_PIN;
    return HAL_RESET_UNKNOWN;
}

uint32_t hal_reset_cause(void) { return g_board.reset_cause; }

void board_init(void)
{
    SCB_VTOR = (uint32_t)(uintptr_t)__isr_vector_start;
    /* Separate fault handlers (all land in the safe state) and trap integer
     * division by zero instead of returning 0. */
    SCB_SHCSR |= SCB_SHCSR_MEMFAULTENA | SCB_SHCSR_BUSFAULTENA | SCB_SHCSR_USGFAULTENA;
    SCB_CCR |= SCB_CCR_DIV_0_TRP;

    g_board.reset_cause = reset_cause_from_csr(RCC_CSR);
    RCC_CSR |= RCC_CSR_RMVF; /* clear the flags: the next start reports its own cause */
    if (g_board.reset_cause == HAL_RESET_WATCHDOG)
        g_board.faults |= BOARD_FAULT_WDG_RESET;
    /* Option bytes this board depends on (docs/board.md, NUCLEO caveats):
     * boot not taken from PB8 (= CAN RX), flash in dual-bank mode. */
    if ((FLASH_OPTR & FLASH_OPTR_NSWBOOT0) != 0u)
        g_board.faults |= BOARD_FAULT_BOOT0_PIN;
    if ((FLASH_OPTR & FLASH_OPTR_DBANK) == 0u)
        g_board.faults |= BOARD_FAULT_NVM;

    DEMCR |= DEMCR_TRCENA;
    DWT_CYCCNT = 0u;
    DWT_CTRL |= DWT_CTRL_CYCCNTENA;

    clock_init_170mhz();

    /* HRTIM before the pins: the outputs are disabled (idle, low) when the
     * pins switch from analog to the HRTIM alternate function. */
    hrtim_init_static();
    gpio_init();
    hrtim_arm_fault();

    /* SysTick: 1 ms, least urgent interrupt. */
    SCB_SHPR3 = (SCB_SHPR3 & 0x00FFFFFFu) | ((PRIO_SYSTICK << NVIC_PRIO_SHIFT) << 24);
    SYST_RVR = g_board.sysclk_hz / 1000u - 1u;
    SYST_CVR = 0u;
    SYST_CSR = SYST_CSR_CLKSOURCE | SYST_CSR_TICKINT | SYST_CSR_ENABLE;
}

void board_safe_state(void)
{
    /* Before board_init the HRTIM is not clocked and the pins are still
     * analog (gate drivers held off by the pull-downs): nothing to do. */
    if ((RCC_APB2ENR & RCC_APB2ENR_HRTIM1EN) != 0u) {
        HRTIM_ODISR = HRTIM_OUT_OUTER;
        for (volatile uint32_t n = 0u; n < 60u; n++) {
            /* >= 1 us at 170 MHz without relying on any RAM state */
        }
        HRTIM_ODISR = HRTIM_OUT_INNER;
    }
    g_board.gates_on = false;
}

/** SysTick: milliseconds since start. Context: interrupt, lowest priority. */
void SysTick_Handler(void) { g_board.millis++; }

/* ------------------------------------------------------- control tick */

static void sample_latch(void)
{
    enum adc_codes got = adc_read_codes(g_board.code);
    g_board.seq++;
    if (got == ADC_CODES_SATURATED)
        g_board.faults |= BOARD_FAULT_ADC_RANGE;
    if (got == ADC_CODES_IC_MISSING)
        g_board.faults |= BOARD_FAULT_ADC_SYNC;
    /* No trustworthy measurement: refuse it (the control core then sees a
     * stale sample and goes to its safe state). A good one is converted by
     * the one allowed read, straight into the reader's buffer (issue 11: one
     * copy of the sample, not two). */
    g_board.sample_fresh = g_board.adc_ok && got == ADC_CODES_OK;
}

bool hal_tick_missed(void)
{
    /* Master compare 1 (the next sampling trigger) came again while the
     * handler still runs: the next tick is already due. */
    return (HRTIM_MISR & HRTIM_MISR_MCMP1) != 0u;
}

/** ADC1/ADC2 end of the injected sequence: the control tick, synchronised to
 * the PWM. Context: interrupt, PRIO_CONTROL_TICK. */
void ADC1_2_IRQHandler(void)
{
    HRTIM_MICR = HRTIM_MICR_MCMP1C;
    if ((ADC_REG(ADC1_BASE, ADC_ISR_OFS) & ADC_ISR_JEOS) == 0u)
        return; /* spurious */
#ifdef BOARD_TEST_STALL_TICK_MS
    /* TEST BUILD ONLY (dtc-fw-stalltest.elf, never dtc-fw.elf): BOARD_TEST_STALL_TICK_MS
     * after a start that was not a watchdog reset, the control tick stops itself for good
     * (its interrupt disabled, as a hung sampling chain would leave it); the background keeps
     * running and asking for watchdog refreshes, which the two-flag scheme must refuse. */
    if (g_board.reset_cause != HAL_RESET_WATCHDOG && g_board.millis >= BOARD_TEST_STALL_TICK_MS) {
        NVIC_ICER(IRQN_ADC1_2 >> 5) = 1u << (IRQN_ADC1_2 & 31u);
        return;
    }
#endif
    sample_latch();
    g_board.wdg_tick_alive = true;
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

    /* Gates off during the offset calibration. */
    hrtim_outputs_off();
    g_board.gates_on = false;
    g_board.adc_ok = false;
    if (!adc_init()) {
        adc_stop();
        g_board.faults |= BOARD_FAULT_ADC_CAL;
        return HAL_EIO;
    }
    int rc = hrtim_start(period_us);
    if (rc != HAL_OK) {
        adc_stop();
        return rc;
    }
    if (adc_calibrate_offsets())
        g_board.adc_ok = true;
    else
        g_board.faults |= BOARD_FAULT_ADC_OFFSET; /* samples refused: the drive stays safe */

    ADC_REG(ADC1_BASE, ADC_ISR_OFS) = ADC_ISR_JEOS | ADC_ISR_JEOC;
    ADC_REG(ADC1_BASE, ADC_IER_OFS) = ADC_IER_JEOSIE;
    g_board.tick_running = true;
    nvic_enable(IRQN_ADC1_2, PRIO_CONTROL_TICK);
    return HAL_OK;
}

void hal_tick_stop(void)
{
    hal_gate_enable(false);
    nvic_disable(IRQN_ADC1_2);
    adc_stop();
    hrtim_stop();
    g_board.tick_running = false;
}

/* ------------------------------------------------ sample and actuation */

int hal_sample_read(hal_sample *out)
{
    if (out == NULL)
        return HAL_EINVAL;
    if (!g_board.sample_fresh)
        return HAL_EAGAIN;
    g_board.sample_fresh = false;
    const float i_scale = 2.0f * BOARD_I_FULL_SCALE_A / BOARD_ADC_FULL_CODE;
    const float v_scale = BOARD_V_FULL_SCALE_V / BOARD_ADC_FULL_CODE;
    const uint32_t *code = g_board.code;
    out->ia_A = ((float)code[0] - g_board.offset_code[0]) * i_scale;
    out->ib_A = ((float)code[1] - g_board.offset_code[1]) * i_scale;
    out->ic_A = ((float)code[2] - g_board.offset_code[2]) * i_scale;
    out->vc1_V = (float)code[3] * v_scale;
    out->vc2_V = (float)code[4] * v_scale;
    out->speed_meas_rad_s = 0.0f;
    out->speed_meas_valid = false; /* no speed sensor on the board */
    out->seq = g_board.seq;
    return HAL_OK;
}

/* The planner's event bits are the HRTIM's CMP2/CMP1 set/reset bits. */
_Static_assert(NPC_EV_START == HRTIM_SET_CMP2 && NPC_EV_START == HRTIM_RST_CMP2, "CMP2 event bit");
_Static_assert(NPC_EV_T == HRTIM_SET_CMP1 && NPC_EV_T == HRTIM_RST_CMP1, "CMP1 event bit");
_Static_assert(NPC_RST_FAULT_EVENT == HRTIM_RST_EXTEVNT6, "the fault event in every reset word");
_Static_assert(NPC_P == (unsigned)HAL_LEG_P && NPC_O == (unsigned)HAL_LEG_O && NPC_N == (unsigned)HAL_LEG_N,
               "leg states");

/* Leg @p leg's ready words of class @p c (not NPC_HELD) straight to the
 * preloaded registers of its two timers, CMP1 = @p t when @p cmp1 (issue 11:
 * no plan struct in between). */
static inline void write_leg(uint32_t leg, const npc_leg_words *w, uint32_t c, bool cmp1, uint32_t t)
{
    const uint32_t *reg = w->reg[c];
    uint32_t tim = 2u * leg; /* A/B: leg a, C/D: leg b, E/F: leg c */
    HRTIM_TIM_REG(tim, HRTIM_SETx1R_OFS) = reg[0];
    HRTIM_TIM_REG(tim, HRTIM_RSTx1R_OFS) = reg[1]; /* with EXTEVNT6: inner off on a fault */
    if (cmp1)
        HRTIM_TIM_REG(tim, HRTIM_CMP1xR_OFS) = t;
    HRTIM_TIM_REG(tim + 1u, HRTIM_SETx1R_OFS) = reg[2];
    HRTIM_TIM_REG(tim + 1u, HRTIM_RSTx1R_OFS) = reg[3];
    if (cmp1)
        HRTIM_TIM_REG(tim + 1u, HRTIM_CMP1xR_OFS) = t;
    g_board.last_leg[leg] = w->end[c];
}

/* Plan each leg's switching events for the period and write them to the
 * timers' preloaded registers. */
static __attribute__((noinline)) int program_period(const hal_actuation *act)
{
    _Static_assert(sizeof(hal_vector) == 3u, "the two vectors: six contiguous leg codes");
    if (!npc_legs_valid((const uint8_t *)act->vector)) /* any leg code above HAL_LEG_P */
        return HAL_EINVAL;
    if (!npc_duty_valid(act->duty0)) /* 0..1; also refuses NaN */
        return HAL_EINVAL;
    if (g_board.per_counts == 0u)
        return HAL_OK; /* tick not started: nothing to program */

    const npc_timing tm = {g_board.per_counts, g_board.keepout_counts, g_board.min_pulse_counts};
    /* the legs' words first: the instants only when a leg has two states */
    const npc_leg_words *w3[3];
    uint32_t legs = npc_legs_words((const uint8_t *)act->vector, g_board.last_leg, w3);
    if (legs == 0u)
        return HAL_OK; /* every leg alone in its held state again: the timers hold its words (issue 11) */

    /* RM0440, HRTIM chapter, HRTIM_CR1 TxUDIS: hold the preload transfer
     * while the six programmes are written, so a period never starts with
     * half of them. The binding uses no other CR1 bit (the ADC triggers'
     * update sources ADxUSRC keep their reset value 0, written nowhere), so
     * the register is written whole (issue 11: no read-modify-write). */
    HRTIM_CR1 = HRTIM_CR1_UDIS_ALL;
    npc_program_legs(w3, legs, act->duty0, g_board.per_f, &g_board.usual, &tm, write_leg);
    if ((legs & NPC_FLAG_FIXUPS) != 0u) { /* one test per period (a firmware bug if ever true) */
        g_board.pn_fixups += npc_legs_fixups(w3);
        g_board.faults |= BOARD_FAULT_PN_STEP;
    }
    HRTIM_CR1 = 0u;
    return HAL_OK;
}

/* Gates off (stopped, faulted: issue 11): the control asks for the same
 * request every period (the zero vector). Once a programme has left the legs
 * where it found them, the preloaded registers (transferred again at every
 * roll-over, RM0440 HRTIM TxREPU) hold exactly what the same request would
 * write, so nothing is written. Only here: with the gates on the request
 * changes nearly every period and the test would cost. */
static __attribute__((noinline)) int actuate_gates_off(const hal_actuation *act)
{
    npc_request req = npc_request_of((const uint8_t *)act->vector, act->duty0);
    if (g_board.idle_held && npc_request_same(&req, &g_board.idle_req))
        return HAL_OK;
    uint32_t prev = npc_legs_word(g_board.last_leg);
    int rc = program_period(act);
    g_board.idle_held = rc == HAL_OK && g_board.per_counts != 0u && npc_legs_word(g_board.last_leg) == prev;
    g_board.idle_req = req;
    return rc;
}

int hal_actuate(const hal_actuation *act)
{
    if (act == NULL)
        return HAL_EINVAL;
    if (!g_board.gates_on)
        return actuate_gates_off(act);
    return program_period(act);
}

/* ------------------------------------------------------ gates and faults */

/* The fault line reaches two pins, PB10 (FLT3: outer switches) and PB5 (EEV6:
 * inner switches). Either low is a fault: a PB5 held low by a broken link or a
 * stuck pin holds every inner switch off, and the outer ones would come on as
 * their complements at the next gate enable (refused here) while the core
 * stops on CTL_FAULT_HW. A difference between the two is recorded. */
static bool fault_pin_active(void)
{
    uint32_t idr = GPIO_REG(GPIOB_BASE, GPIO_IDR_OFS);
    bool flt3_low = (idr & (1u << 10)) == 0u;
    bool eev6_low = (idr & (1u << 5)) == 0u;
    if (flt3_low != eev6_low)
        g_board.faults |= BOARD_FAULT_LINE_PINS;
    return flt3_low || eev6_low;
}

void hal_gate_enable(bool enable)
{
    if (!enable) {
        if ((HRTIM_OENR & HRTIM_OUT_ALL) != 0u)
            hrtim_outputs_off(); /* the 1 us outer-first sequence only when something is on */
        g_board.gates_on = false;
        return;
    }
    g_board.idle_held = false; /* the running programmes will overwrite the held one */
    /* Refused (gates stay off) without a running tick, a valid calibration,
     * or while the fault line is low. */
    if (!g_board.tick_running || !g_board.adc_ok || fault_pin_active() || g_board.fault_latched)
        return;
    /* After a trip the fault line's external event 6 has left every output-1
     * latch reset (inner switch off): enabled as they are, the outer switches
     * (their complements) would come on together. So, once the line has been
     * high for longer than the event's filter, set the latches to O (S3, S2
     * on; a software set, not preloaded: RM0440, HRTIM_SETx1R.SST) for the
     * rest of this period: no programme has a P<->N step from O. */
    delay_ns(BOARD_FAULT_LINE_SETTLE_NS);
    if (fault_pin_active())
        return;
    for (uint32_t t = 0u; t < 6u; t++)
        HRTIM_TIM_REG(t, HRTIM_SETx1R_OFS) |= HRTIM_SET_SST; /* the preloaded programme is written back as read */
    HRTIM_ICR = HRTIM_ICR_FLT3C;
    HRTIM_IER |= HRTIM_IER_FLT3IE;
    HRTIM_OENR = HRTIM_OUT_ALL;
    /* Reading OENR gives the outputs' enable status (RM0440, HRTIM chapter, HRTIM_OENR description). */
    g_board.gates_on = (HRTIM_OENR & HRTIM_OUT_ALL) == HRTIM_OUT_ALL;
    if ((HRTIM_ISR & HRTIM_ISR_FLT3) != 0u) /* tripped meanwhile */
        g_board.gates_on = false;
}

bool hal_gate_enabled(void) { return g_board.gates_on; }

bool hal_fault_input_active(void)
{
    /* The pin's level, or a trip not yet reported: a glitch shorter than one
     * tick is still seen once by the control core (CTL_FAULT_HW). */
    bool pin = fault_pin_active();
    bool latched = g_board.fault_latched;
    if (latched && !pin)
        g_board.fault_latched = false;
    return pin || latched;
}

/* ------------------------------------------------------------------ time */

uint32_t hal_cycles(void) { return DWT_CYCCNT; }

uint32_t hal_cycles_hz(void) { return g_board.sysclk_hz; }

uint32_t hal_millis(void) { return g_board.millis; }

/* ------------------------------------------------------------------- CAN */

/*
 * Nominal bit timing from the FDCAN kernel clock (PCLK1 = SYSCLK): the
 * prescaler and number of time quanta (8..80) whose sample point is closest
 * to 87.5 % (CiA 301 recommendation), SJW = phase segment 2 (RM0440, FDCAN chapter, FDCAN_NBTP description).
 */
static bool can_bit_timing(uint32_t clk_hz, uint32_t bitrate, uint32_t *nbtp)
{
    uint32_t best_err = 1000u, best = 0u;
    for (uint32_t brp = 1u; brp <= 32u; brp++) {
        if (clk_hz % (brp * bitrate) != 0u)
            continue;
        uint32_t ntq = clk_hz / (brp * bitrate);
        if (ntq < 8u || ntq > 80u)
            continue;
        uint32_t sp_tq = (ntq * 875u + 500u) / 1000u; /* sync + tseg1 */
        uint32_t tseg1 = sp_tq - 1u;
        uint32_t tseg2 = ntq - sp_tq;
        if (tseg2 < 2u || tseg1 > 256u || tseg2 > 128u)
            continue;
        uint32_t sp = sp_tq * 1000u / ntq;
        uint32_t err = sp > 875u ? sp - 875u : 875u - sp;
        if (err < best_err) {
            best_err = err;
            best = ((tseg2 - 1u) << FDCAN_NBTP_NSJW_SHIFT) | ((brp - 1u) << FDCAN_NBTP_NBRP_SHIFT) |
                   ((tseg1 - 1u) << FDCAN_NBTP_NTSEG1_SHIFT) | ((tseg2 - 1u) << FDCAN_NBTP_NTSEG2_SHIFT);
        }
    }
    *nbtp = best;
    return best_err < 1000u;
}

/* Standard filter element (RM0440, FDCAN chapter, "Standard message ID filter element"):
 * SFT range (0) or dual (1), SFEC 1 = store in Rx FIFO 0. */
static uint32_t can_filter(uint32_t type, uint32_t id1, uint32_t id2)
{
    return (type << 30) | (1u << 27) | (id1 << 16) | id2;
}

int hal_can_open(uint32_t bitrate_bps)
{
    if (bitrate_bps != 125000u && bitrate_bps != 250000u && bitrate_bps != 500000u &&
        bitrate_bps != 1000000u)
        return HAL_EINVAL;
    uint32_t nbtp;
    if (!can_bit_timing(g_board.sysclk_hz, bitrate_bps, &nbtp))
        return HAL_EIO;

    RCC_CCIPR = (RCC_CCIPR & ~RCC_CCIPR_FDCANSEL_MASK) | RCC_CCIPR_FDCANSEL_PCLK1;
    RCC_APB1ENR1 |= RCC_APB1ENR1_FDCANEN;
    (void)RCC_APB1ENR1;

    /* Initialisation mode, then configuration change enable (RM0440, FDCAN chapter, FDCAN_CCCR description). */
    FDCAN1_CCCR |= FDCAN_CCCR_INIT;
    if (!wait_set(&FDCAN1_CCCR, FDCAN_CCCR_INIT, FDCAN_CCCR_INIT, WAIT_LOOPS))
        return HAL_EIO;
    FDCAN1_CCCR |= FDCAN_CCCR_CCE;
    /* Classic CAN: no FD operation, no bit-rate switching; automatic
     * retransmission on (DAR = 0). */
    FDCAN1_CCCR &= ~(FDCAN_CCCR_FDOE | FDCAN_CCCR_BRSE | FDCAN_CCCR_DAR);
    FDCAN1_NBTP = nbtp;

    /* Message RAM: clear it, then the filters of this node's function codes
     * (the node id is the firmware's, so the exact match is in software). */
    for (uint32_t ofs = 0u; ofs < SRAMCAN_SIZE; ofs += 4u)
        SRAMCAN_WORD(ofs) = 0u;
    SRAMCAN_WORD(SRAMCAN_FLSSA + 0u) = can_filter(1u, 0x000u, 0x080u); /* NMT, SYNC */
    SRAMCAN_WORD(SRAMCAN_FLSSA + 4u) = can_filter(0u, 0x200u, 0x57Fu); /* RPDO1..4 */
    SRAMCAN_WORD(SRAMCAN_FLSSA + 8u) = can_filter(0u, 0x600u, 0x67Fu); /* SDO requests */
    SRAMCAN_WORD(SRAMCAN_FLSSA + 12u) = can_filter(0u, 0x700u, 0x77Fu); /* heartbeats, node guarding */
    /* 4 standard filters; everything else and every extended or remote
     * extended frame is rejected. */
    FDCAN1_RXGFC = (4u << FDCAN_RXGFC_LSS_SHIFT) | FDCAN_RXGFC_ANFS_REJECT | FDCAN_RXGFC_ANFE_REJECT |
                   FDCAN_RXGFC_RRFE;
    FDCAN1_TXBC = 0u; /* TFQM = 0: Tx FIFO (3 elements, fixed) */
    FDCAN1_IE = 0u;   /* polled from the background: never interrupts the tick */
    FDCAN1_IR = 0xFFFFFFFFu;

    FDCAN1_CCCR &= ~FDCAN_CCCR_INIT; /* joins after 11 recessive bits */
    g_board.can_open = true;
    g_board.can_busoff = false;
    return HAL_OK;
}

/* Bus-off: the controller sets INIT by itself; after CAN_BUSOFF_RETRY_MS
 * clearing INIT starts the recovery (128 x 11 recessive bits; RM0440, FDCAN chapter, bus-off recovery).
 * @return true while the controller is usable. Context: BG. */
static bool can_service(void)
{
    if (!g_board.can_open)
        return false;
    /* PSR.BO stays set from bus-off until the recovery sequence completes. */
    if ((FDCAN1_PSR & FDCAN_PSR_BO) != 0u) {
        if (!g_board.can_busoff) {
            g_board.can_busoff = true;
            g_board.can_busoff_ms = g_board.millis;
            g_board.can_busoff_count++;
            g_board.faults |= BOARD_FAULT_CAN_BUSOFF;
        } else if ((FDCAN1_CCCR & FDCAN_CCCR_INIT) != 0u &&
                   g_board.millis - g_board.can_busoff_ms >= CAN_BUSOFF_RETRY_MS) {
            FDCAN1_CCCR &= ~FDCAN_CCCR_INIT; /* start the recovery */
            g_board.can_busoff_ms = g_board.millis;
        }
        return false;
    }
    g_board.can_busoff = false;
    return true;
}

/* PSR.BO (RM0440, FDCAN_PSR) is read through can_service, which also starts
 * the recovery, so a caller that only polls the state still recovers. */
void hal_can_get_state(hal_can_state *out)
{
    (void)can_service();
    out->bus_off = g_board.can_open && g_board.can_busoff;
    out->bus_off_count = g_board.can_busoff_count;
}

int hal_can_send(const hal_can_frame *frame)
{
    if (frame == NULL || frame->id > 0x7FFu || frame->dlc > 8u)
        return HAL_EINVAL;
    if (!can_service())
        return HAL_EIO;
    uint32_t fqs = FDCAN1_TXFQS;
    if ((fqs & FDCAN_TXFQS_TFQF) != 0u)
        return HAL_EBUSY; /* never waits: the caller retries later */
    uint32_t idx = (fqs & FDCAN_TXFQS_TFQPI_MASK) >> FDCAN_TXFQS_TFQPI_SHIFT;
    uint32_t e = SRAMCAN_TBSA + idx * SRAMCAN_ELEM_SIZE;
    uint8_t d[8] = {0};
    memcpy(d, frame->data, frame->dlc);
    /* T0: RTR [29], standard id [28:18]; T1: DLC [19:16] (classic, no EFC). */
    SRAMCAN_WORD(e + 0u) = ((uint32_t)frame->id << 18) | (frame->rtr ? (1u << 29) : 0u);
    SRAMCAN_WORD(e + 4u) = (uint32_t)frame->dlc << 16;
    SRAMCAN_WORD(e + 8u) = (uint32_t)d[0] | ((uint32_t)d[1] << 8) | ((uint32_t)d[2] << 16) | ((uint32_t)d[3] << 24);
    SRAMCAN_WORD(e + 12u) = (uint32_t)d[4] | ((uint32_t)d[5] << 8) | ((uint32_t)d[6] << 16) | ((uint32_t)d[7] << 24);
    FDCAN1_TXBAR = 1u << idx;
    return HAL_OK;
}

int hal_can_recv(hal_can_frame *frame)
{
    if (frame == NULL)
        return HAL_EINVAL;
    (void)can_service();
    if (!g_board.can_open)
        return HAL_EAGAIN;
    if ((FDCAN1_IR & FDCAN_IR_RF0L) != 0u) {
        FDCAN1_IR = FDCAN_IR_RF0L;
        g_board.can_rx_lost++;
    }
    for (;;) {
        uint32_t s = FDCAN1_RXF0S;
        if ((s & FDCAN_RXF0S_F0FL_MASK) == 0u)
            return HAL_EAGAIN;
        uint32_t idx = (s & FDCAN_RXF0S_F0GI_MASK) >> FDCAN_RXF0S_F0GI_SHIFT;
        uint32_t e = SRAMCAN_RF0SA + idx * SRAMCAN_ELEM_SIZE;
        uint32_t r0 = SRAMCAN_WORD(e + 0u);
        uint32_t r1 = SRAMCAN_WORD(e + 4u);
        uint32_t w[2] = {SRAMCAN_WORD(e + 8u), SRAMCAN_WORD(e + 12u)};
        FDCAN1_RXF0A = idx;
        if ((r0 & (1u << 30)) != 0u || (r1 & (1u << 21)) != 0u)
            continue; /* extended or FD frame: not ours (filters reject them anyway) */
        uint32_t dlc = (r1 >> 16) & 0xFu;
        frame->id = (uint16_t)((r0 >> 18) & 0x7FFu);
        frame->rtr = (r0 & (1u << 29)) != 0u;
        frame->dlc = (uint8_t)(dlc > 8u ? 8u : dlc);
        for (unsigned k = 0u; k < 8u; k++)
            frame->data[k] = (uint8_t)(w[k / 4u] >> (8u * (k % 4u)));
        return HAL_OK;
    }
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

/*
 * Reads of the parameter pages go between these two: a power loss during an
 * erase or a program leaves double words whose ECC does not match, and reading
 * one raises the NMI with FLASH_ECCR.ECCD (RM0440, FLASH chapter, "Error code
 * correction"). Inside the window the NMI handler takes that as "this copy is
 * unreadable" instead of a fatal error. @return false if an ECC error was seen.
 * Context: BG.
 */
static void nvm_read_begin(void)
{
    g_board.nvm_ecc_hit = false;
    g_board.nvm_reading = true;
    __asm volatile("" ::: "memory");
}

static bool nvm_read_end(void)
{
    __asm volatile("dsb\n\tisb" ::: "memory"); /* the last read's NMI is taken by now */
    g_board.nvm_reading = false;
    return !g_board.nvm_ecc_hit;
}

/** NMI: a double ECC error while the background reads the parameter pages is
 * cleared and reported to that read (the data are unusable, the persist layer
 * falls back to the other slot); any other cause (clock security system, an
 * ECC error in code or constants) forces the safe state. Context: NMI. */
void NMI_Handler(void)
{
    uint32_t ecc = FLASH_ECCR;
    if ((ecc & FLASH_ECCR_ECCD) != 0u && g_board.nvm_reading) {
        FLASH_ECCR = (ecc & FLASH_ECCR_ECCCIE) | FLASH_ECCR_ECCD; /* rc_w1 */
        g_board.nvm_ecc_hit = true;
        g_board.nvm_ecc_errors++;
        g_board.faults |= BOARD_FAULT_NVM;
        return;
    }
    Default_Handler();
}

int hal_nvm_read(uint32_t offset, void *buf, size_t len)
{
    int rc = nvm_check(offset, buf, len);
    if (rc != HAL_OK)
        return rc;
    /* Flash is memory-mapped: reading is a copy (erased bytes read 0xFF). */
    if (len == 0u)
        return HAL_OK;
    nvm_read_begin();
    memcpy(buf, __nvm_start + offset, len);
    return nvm_read_end() ? HAL_OK : HAL_EIO;
}

/* Let the watchdog through during long flash operations: the caller is the
 * background, so only the tick still has to prove itself. Context: BG. */
static void wdg_service_bg(void);

#define FLASH_SR_ERRORS                                                                                  \
    (FLASH_SR_OPERR | FLASH_SR_PROGERR | FLASH_SR_WRPERR | FLASH_SR_PGAERR | FLASH_SR_SIZERR |          \
     FLASH_SR_PGSERR | FLASH_SR_MISSERR | FLASH_SR_FASTERR | FLASH_SR_RDERR | FLASH_SR_OPTVERR)

/* The flash data cache may hold a page's old contents after an erase or a
 * program: reset it (RM0440, FLASH chapter, FLASH_ACR DCRST: only while DCEN = 0). */
static void flash_dcache_reset(void)
{
    uint32_t acr = FLASH_ACR;
    FLASH_ACR = acr & ~FLASH_ACR_DCEN;
    FLASH_ACR = (acr & ~FLASH_ACR_DCEN) | FLASH_ACR_DCRST;
    FLASH_ACR = acr & ~(FLASH_ACR_DCEN | FLASH_ACR_DCRST);
    FLASH_ACR = acr & ~FLASH_ACR_DCRST;
}

static bool flash_wait(void)
{
    for (uint32_t n = 0u; n < WAIT_FLASH_LOOPS; n++) {
        if ((FLASH_SR & FLASH_SR_BSY) == 0u)
            break;
        if ((n & 0xFFFFu) == 0u)
            wdg_service_bg();
    }
    uint32_t sr = FLASH_SR;
    FLASH_SR = sr & (FLASH_SR_ERRORS | FLASH_SR_EOP); /* rc_w1 */
    return (sr & (FLASH_SR_BSY | FLASH_SR_ERRORS)) == 0u;
}

static bool flash_unlock(void)
{
    if ((FLASH_CR & FLASH_CR_LOCK) != 0u) {
        FLASH_KEYR = FLASH_KEY1; /* RM0440 5.3.5 */
        FLASH_KEYR = FLASH_KEY2;
    }
    return (FLASH_CR & FLASH_CR_LOCK) == 0u;
}

static bool flash_erase_page(uint32_t addr)
{
    /* Dual-bank mode: 2 KiB pages, bank 2 from 0x08040000 (RM0440 5.3.8). */
    uint32_t bank2 = addr >= FLASH_BANK2_START ? 1u : 0u;
    uint32_t page = ((addr - (bank2 ? FLASH_BANK2_START : 0x08000000u)) / NVM_PAGE_SIZE) & 0x7Fu;
    if (!flash_wait())
        return false;
    FLASH_CR = FLASH_CR_PER | (bank2 ? FLASH_CR_BKER : 0u) | (page << FLASH_CR_PNB_SHIFT);
    FLASH_CR |= FLASH_CR_STRT;
    bool ok = flash_wait();
    FLASH_CR &= ~(FLASH_CR_PER | FLASH_CR_BKER | FLASH_CR_PNB_MASK);
    return ok;
}

static bool flash_program_dword(uint32_t addr, uint32_t lo, uint32_t hi)
{
    if (!flash_wait())
        return false;
    FLASH_CR = FLASH_CR_PG;
    REG32(addr) = lo; /* double word: two 32-bit writes, low word first (RM0440 5.3.7) */
    REG32(addr + 4u) = hi;
    bool ok = flash_wait();
    FLASH_CR &= ~FLASH_CR_PG;
    return ok;
}

static uint8_t g_page_buf[NVM_PAGE_SIZE] __attribute__((aligned(8)));

/* Write one page: program in place if every changed double word is erased,
 * otherwise read-modify-erase-write the whole page. */
static bool nvm_write_page(uint32_t page_addr, uint32_t from, const uint8_t *src, uint32_t n)
{
    const uint8_t *flash = (const uint8_t *)(uintptr_t)page_addr;
    flash_dcache_reset();
    nvm_read_begin();
    memcpy(g_page_buf, flash, NVM_PAGE_SIZE);
    memcpy(g_page_buf + from, src, n);

    bool need_erase = false;
    for (uint32_t dw = from & ~7u; dw < from + n; dw += 8u) {
        if (memcmp(flash + dw, g_page_buf + dw, 8u) == 0)
            continue;
        for (uint32_t k = 0u; k < 8u; k++) {
            if (flash[dw + k] != 0xFFu)
                need_erase = true;
        }
    }
    /* A double word with a broken ECC (an interrupted write) may even read as
     * erased but cannot be programmed: only an erase makes the page usable. */
    if (!nvm_read_end())
        need_erase = true;
    uint32_t lo = need_erase ? 0u : from & ~7u;
    uint32_t hi = need_erase ? NVM_PAGE_SIZE : from + n;
    if (need_erase && !flash_erase_page(page_addr))
        return false;
    for (uint32_t dw = lo; dw < hi; dw += 8u) {
        uint32_t w[2];
        memcpy(w, g_page_buf + dw, 8u);
        if (w[0] == 0xFFFFFFFFu && w[1] == 0xFFFFFFFFu)
            continue; /* erased already */
        if (!need_erase && memcmp(flash + dw, g_page_buf + dw, 8u) == 0)
            continue;
        if (!flash_program_dword(page_addr + dw, w[0], w[1])) {
            flash_dcache_reset();
            return false;
        }
    }
    flash_dcache_reset();
    nvm_read_begin();
    bool same = memcmp(flash + from, src, n) == 0; /* read back through the bus */
    return nvm_read_end() && same;
}

/*
 * hal.h contract, with this board's reading of "a power loss may leave any
 * prefix written": a write that needs an erase rewrites its whole 2 KiB page,
 * so a power loss in the middle can leave that page partly erased. The
 * persist layer keeps each of its two slots in its own page (slot size =
 * hal_nvm_size() / 2 = one page) and writes the header last, so the other
 * slot is never touched and a reset at any point leaves one valid slot.
 * Blocks the background for up to about 2 x 40 ms (two page erases) plus
 * 90 us per double word. Context: BG only (refused from an interrupt).
 */
int hal_nvm_write(uint32_t offset, const void *buf, size_t len)
{
    int rc = nvm_check(offset, buf, len);
    if (rc != HAL_OK)
        return rc;
    if (len == 0u)
        return HAL_OK;
    /* Never from an interrupt (erase takes tens of ms); single-bank mode
     * (4 KiB pages) would put both slots in one page: refused. */
    if (in_interrupt() || (FLASH_OPTR & FLASH_OPTR_DBANK) == 0u) {
        g_board.faults |= BOARD_FAULT_NVM;
        return HAL_EIO;
    }
    if (!flash_unlock()) {
        g_board.faults |= BOARD_FAULT_NVM;
        return HAL_EIO;
    }
    bool ok = true;
    const uint8_t *src = (const uint8_t *)buf;
    uint32_t base = (uint32_t)(uintptr_t)__nvm_start;
    uint32_t at = offset;
    uint32_t left = (uint32_t)len;
    while (ok && left > 0u) {
        uint32_t page = (base + at) & ~(NVM_PAGE_SIZE - 1u);
        uint32_t from = (base + at) - page;
        uint32_t n = NVM_PAGE_SIZE - from < left ? NVM_PAGE_SIZE - from : left;
        ok = nvm_write_page(page, from, src, n);
        src += n;
        at += n;
        left -= n;
    }
    FLASH_CR |= FLASH_CR_LOCK;
    if (!ok) {
        g_board.faults |= BOARD_FAULT_NVM;
        return HAL_EIO;
    }
    return HAL_OK;
}

/* -------------------------------------------------------------- watchdog */

int hal_watchdog_start(uint32_t timeout_ms)
{
    if (timeout_ms < 1u || timeout_ms > 4000u)
        return HAL_EINVAL;
    /* Stop the watchdog while the core is halted by a debugger. */
    DBGMCU_APB1L_FZ |= DBGMCU_APB1L_FZ_IWDG;
    /* LSI (about 32 kHz, +-several %) / 32 = one reload count per ms. The
     * start key also switches the LSI on; once started it cannot be stopped. */
    IWDG_KR = IWDG_KEY_START;
    IWDG_KR = IWDG_KEY_UNLOCK;
    IWDG_PR = IWDG_PR_DIV32;
    IWDG_RLR = timeout_ms;
    if (!wait_set(&IWDG_SR, IWDG_SR_BUSY_MASK, 0u, WAIT_LOOPS))
        return HAL_EIO;
    IWDG_KR = IWDG_KEY_REFRESH;
    g_board.wdg_started = true;
    return HAL_OK;
}

/* The tick proves itself by setting wdg_tick_alive; the caller is the
 * background. Refresh only if both have run since the last refresh. */
static void wdg_service_bg(void)
{
    if (!g_board.wdg_started)
        return;
    if (g_board.tick_running && !g_board.wdg_tick_alive)
        return; /* the tick has not run since the last refresh: let it bite */
    g_board.wdg_tick_alive = false;
    IWDG_KR = IWDG_KEY_REFRESH;
}

/* hal.h: refresh the watchdog. Here the refresh happens only if the control
 * tick has also run since the last refresh (two-flag scheme, docs/board.md),
 * so neither a stuck background nor a dead tick keeps the chip alive.
 * Context: BG. */
void hal_watchdog_kick(void) { wdg_service_bg(); }
