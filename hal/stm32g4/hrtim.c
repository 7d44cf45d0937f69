/**
 * @file hrtim.c
 * @brief HRTIM1 driving the three-level NPC power stage (RM0440 27): the
 *        static set-up, the period, the per-period programmes, the gates and
 *        the fault line's hardware and software stages.
 */
#include "hrtim.h"

#include <stddef.h>

#include "board.h"
#include "chip.h"
#include "clock.h"
#include "npc_plan.h"
#include "pins.h"

/* Sampling instant and switching keep-out, ns after the period start. */
#define BOARD_SAMPLE_DELAY_NS 4000u  /* after the period-start edges and their dead time */
#define BOARD_KEEPOUT_END_NS 7000u   /* sampling (2 ranks x 0.87 us, to 5.74 us) is over by then */
#define BOARD_MIN_PULSE_NS 2000u     /* shortest second-vector pulse at the period end */
#define BOARD_START_EVENT_COUNTS 3u  /* CMP2: period-start event, 3 counts after roll-over */

typedef struct {
    /* timing, counts of the timer clock */
    uint32_t per_counts;       /* 0 until hrtim_start */
    uint32_t keepout_counts;
    uint32_t min_pulse_counts;
    float per_f;               /* per_counts as a float (exact: below 2^16), for the instant */
    npc_usual usual;           /* the period's usual instants (npc_usual_of) */
    uint8_t last_leg[4];       /* leg state at the end of the last latched period (with NPC_LEG_HELD: the timers hold its one-state words); [3] stays 0 (npc_leg_words_index3) */
    uint32_t pn_fixups;        /* P<->N steps replaced by O (diagnostics) */
    bool idle_held;            /* gates off: the preloaded registers hold idle_req's programme, which repeats itself */
    npc_request idle_req;      /* the last request programmed with the gates off */
    volatile bool gates_on;
    volatile bool fault_latched;  /* set by the HRTIM fault ISR, reported once */
    uint32_t fault_inner_cycles;  /* BOARD_FAULT_BACKUP_DELAY_NS in core cycles, set before the fault is armed */
    uint32_t fault_trips;
} hrtim_driver;

static hrtim_driver g_hrtim;

static uint32_t ns_to_counts(uint32_t ns, uint32_t count_hz)
{
    return (uint32_t)(((uint64_t)ns * count_hz + 500000000u) / 1000000000u);
}

void hrtim_outputs_off(void)
{
    HRTIM_ODISR = HRTIM_OUT_OUTER;
    clock_delay_ns(BOARD_DEAD_TIME_NS); /* not urgent here: the full dead time between outer and inner */
    HRTIM_ODISR = HRTIM_OUT_INNER;
    g_hrtim.gates_on = false;
}

/*
 * Static part, done at reset with the outputs disabled: output idle/fault
 * states, dead time, fault input FLT3 (RM0440 27.3.15-17). The outputs are in
 * their idle (inactive, low) level until OENR.
 */
void hrtim_init(void)
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
        uint64_t tdtg_hz = ((uint64_t)clock_sysclk_hz() * 8u) >> dt_prsc;
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

void hrtim_fault_arm(uint32_t prio)
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
    g_hrtim.fault_inner_cycles =
        (uint32_t)(((uint64_t)BOARD_FAULT_BACKUP_DELAY_NS * clock_sysclk_hz() + 999999999u) / 1000000000u);
    chip_nvic_enable(IRQN_HRTIM1_FLT, prio);
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
    const uint32_t wait = g_hrtim.fault_inner_cycles;
    for (uint32_t n = 0u; n < wait && DWT_CYCCNT - t0 < wait; n++) {
    }
    HRTIM_ODISR = HRTIM_OUT_ALL;
    /* One interrupt per trip: a line held low must not starve the tick.
     * hal_gate_enable(true) re-arms it once the line is high again. */
    HRTIM_IER &= ~HRTIM_IER_FLT3IE;
    HRTIM_ICR = HRTIM_ICR_FLT3C;
    g_hrtim.gates_on = false;
    g_hrtim.fault_latched = true;
    g_hrtim.fault_trips++;
    board_fault_record(BOARD_FAULT_HRTIM);
}

/*
 * Dynamic part: the period. Master and timers A..F share prescaler and
 * period and are started by one MCR write, so their counters are aligned.
 * Every timer register written by hrtim_actuate is preloaded (PREEN) and
 * transferred at the roll-over (TxREPU with REP = 0, RM0440 27.3.8).
 * Master compare 1 is the ADC trigger (ADC trigger 2, RM0440 27.3.19).
 */
int hrtim_start(uint32_t period_us)
{
    /* fCOUNTER = fHRTIM x 32 / 2^CKPSC; CKPSC >= 5 (low resolution, no DLL needed). */
    uint32_t ckpsc = 5u;
    uint32_t count_hz = clock_sysclk_hz();
    uint32_t per = (uint32_t)(((uint64_t)period_us * count_hz) / 1000000u);
    while (per > 0xFFDFu && ckpsc < 7u) {
        ckpsc++;
        count_hz /= 2u;
        per /= 2u;
    }
    if (per > 0xFFDFu || per < 64u)
        return HAL_EINVAL;
    g_hrtim.per_counts = per;
    g_hrtim.keepout_counts = ns_to_counts(BOARD_KEEPOUT_END_NS, count_hz);
    g_hrtim.min_pulse_counts = ns_to_counts(BOARD_MIN_PULSE_NS, count_hz);
    g_hrtim.per_f = (float)per;
    const npc_timing tm = {per, g_hrtim.keepout_counts, g_hrtim.min_pulse_counts};
    g_hrtim.usual = npc_usual_of(&tm);

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
        g_hrtim.last_leg[leg] = (uint8_t)HAL_LEG_O;
    g_hrtim.last_leg[3] = 0u;
    g_hrtim.idle_held = false;

    /* The ADC trigger's update source stays the master timer (HRTIM_CR1 ADxUSRC at reset):
     * program_period writes CR1 whole, so an update source set in CR1 would be cleared there. */
    HRTIM_ADC2R = HRTIM_ADC2R_AD2MC1;
    HRTIM_MICR = HRTIM_MICR_MCMP1C;
    HRTIM_CR2 = HRTIM_CR2_SWU_ALL; /* preload -> active now, before the counters run */
    HRTIM_MCR |= HRTIM_MCR_MCEN | HRTIM_MCR_TACEN | HRTIM_MCR_TBCEN | HRTIM_MCR_TCCEN | HRTIM_MCR_TDCEN |
                 HRTIM_MCR_TECEN | HRTIM_MCR_TFCEN;
    return HAL_OK;
}

void hrtim_stop(void)
{
    hrtim_outputs_off();
    HRTIM_MCR &= ~(HRTIM_MCR_MCEN | HRTIM_MCR_TACEN | HRTIM_MCR_TBCEN | HRTIM_MCR_TCCEN | HRTIM_MCR_TDCEN |
                   HRTIM_MCR_TECEN | HRTIM_MCR_TFCEN);
}

void hrtim_safe_state(void)
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
    g_hrtim.gates_on = false;
}

/* ------------------------------------------------ per-period programmes */

/* The planner's event bits are the HRTIM's CMP2/CMP1 set/reset bits. */
_Static_assert(NPC_EV_START == HRTIM_SET_CMP2 && NPC_EV_START == HRTIM_RST_CMP2, "CMP2 event bit");
_Static_assert(NPC_EV_T == HRTIM_SET_CMP1 && NPC_EV_T == HRTIM_RST_CMP1, "CMP1 event bit");
_Static_assert(NPC_RST_FAULT_EVENT == HRTIM_RST_EXTEVNT6, "the fault event in every reset word");
_Static_assert(NPC_P == (unsigned)HAL_LEG_P && NPC_O == (unsigned)HAL_LEG_O && NPC_N == (unsigned)HAL_LEG_N,
               "leg states");

/* Leg @p leg's ready words of class @p c (not NPC_HELD) straight to the
 * preloaded registers of its two timers, CMP1 = @p t when @p cmp1: no plan
 * struct in between. */
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
    g_hrtim.last_leg[leg] = w->end[c];
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
    if (g_hrtim.per_counts == 0u)
        return HAL_OK; /* tick not started: nothing to program */

    const npc_timing tm = {g_hrtim.per_counts, g_hrtim.keepout_counts, g_hrtim.min_pulse_counts};
    /* the legs' words first: the instants only when a leg has two states */
    const npc_leg_words *w3[3];
    uint32_t legs = npc_legs_words((const uint8_t *)act->vector, g_hrtim.last_leg, w3);
    if (legs == 0u)
        return HAL_OK; /* every leg alone in its held state again: the timers hold its words */

    /* RM0440, HRTIM chapter, HRTIM_CR1 TxUDIS: hold the preload transfer
     * while the six programmes are written, so a period never starts with
     * half of them. The binding uses no other CR1 bit (the ADC triggers'
     * update sources ADxUSRC keep their reset value 0, written nowhere), so
     * the register is written whole, without a read. */
    HRTIM_CR1 = HRTIM_CR1_UDIS_ALL;
    npc_program_legs(w3, legs, act->duty0, g_hrtim.per_f, &g_hrtim.usual, &tm, write_leg);
    if ((legs & NPC_FLAG_FIXUPS) != 0u) { /* one test per period (a firmware bug if ever true) */
        g_hrtim.pn_fixups += npc_legs_fixups(w3);
        board_fault_record(BOARD_FAULT_PN_STEP);
    }
    HRTIM_CR1 = 0u;
    return HAL_OK;
}

/* Gates off (stopped, faulted): the control asks for the same request every
 * period (the zero vector). Once a programme has left the legs where it found
 * them, the preloaded registers (transferred again at every roll-over, RM0440
 * HRTIM TxREPU) hold exactly what the same request would write, so nothing is
 * written. Only here: with the gates on the request changes nearly every
 * period and the test would cost. */
static __attribute__((noinline)) int actuate_gates_off(const hal_actuation *act)
{
    npc_request req = npc_request_of((const uint8_t *)act->vector, act->duty0);
    if (g_hrtim.idle_held && npc_request_same(&req, &g_hrtim.idle_req))
        return HAL_OK;
    uint32_t prev = npc_legs_word(g_hrtim.last_leg);
    int rc = program_period(act);
    g_hrtim.idle_held = rc == HAL_OK && g_hrtim.per_counts != 0u && npc_legs_word(g_hrtim.last_leg) == prev;
    g_hrtim.idle_req = req;
    return rc;
}

int hrtim_actuate(const hal_actuation *act)
{
    if (act == NULL)
        return HAL_EINVAL;
    if (!g_hrtim.gates_on)
        return actuate_gates_off(act);
    return program_period(act);
}

uint32_t hrtim_pn_fixups(void) { return g_hrtim.pn_fixups; }

/* ------------------------------------------------------ gates and faults */

/* The fault line reaches two pins, PB10 (FLT3: outer switches) and PB5 (EEV6:
 * inner switches). Either low is a fault: a PB5 held low by a broken link or a
 * stuck pin holds every inner switch off, and the outer ones would come on as
 * their complements at the next gate enable (refused here) while the core
 * stops on CTL_FAULT_HW. A difference between the two is recorded. */
static bool fault_pin_active(void)
{
    pins_fault_line l = pins_fault_line_read();
    if (l.flt3_low != l.eev6_low)
        board_fault_record(BOARD_FAULT_LINE_PINS);
    return l.flt3_low || l.eev6_low;
}

void hrtim_gates_disable(void)
{
    if ((HRTIM_OENR & HRTIM_OUT_ALL) != 0u)
        hrtim_outputs_off(); /* the 1 us outer-first sequence only when something is on */
    g_hrtim.gates_on = false;
}

void hrtim_gates_enable(bool ready)
{
    g_hrtim.idle_held = false; /* the running programmes will overwrite the held one */
    if (!ready || fault_pin_active() || g_hrtim.fault_latched)
        return;
    /* After a trip the fault line's external event 6 has left every output-1
     * latch reset (inner switch off): enabled as they are, the outer switches
     * (their complements) would come on together. So, once the line has been
     * high for longer than the event's filter, set the latches to O (S3, S2
     * on; a software set, not preloaded: RM0440, HRTIM_SETx1R.SST) for the
     * rest of this period: no programme has a P<->N step from O. */
    clock_delay_ns(BOARD_FAULT_LINE_SETTLE_NS);
    if (fault_pin_active())
        return;
    for (uint32_t t = 0u; t < 6u; t++)
        HRTIM_TIM_REG(t, HRTIM_SETx1R_OFS) |= HRTIM_SET_SST; /* the preloaded programme is written back as read */
    HRTIM_ICR = HRTIM_ICR_FLT3C;
    HRTIM_IER |= HRTIM_IER_FLT3IE;
    HRTIM_OENR = HRTIM_OUT_ALL;
    /* Reading OENR gives the outputs' enable status (RM0440, HRTIM chapter, HRTIM_OENR description). */
    g_hrtim.gates_on = (HRTIM_OENR & HRTIM_OUT_ALL) == HRTIM_OUT_ALL;
    if ((HRTIM_ISR & HRTIM_ISR_FLT3) != 0u) /* tripped meanwhile */
        g_hrtim.gates_on = false;
}

bool hrtim_gates_enabled(void) { return g_hrtim.gates_on; }

bool hrtim_fault_input_active(void)
{
    /* The pin's level, or a trip not yet reported: a glitch shorter than one
     * tick is still seen once by the control core (CTL_FAULT_HW). */
    bool pin = fault_pin_active();
    bool latched = g_hrtim.fault_latched;
    if (latched && !pin)
        g_hrtim.fault_latched = false;
    return pin || latched;
}
