/**
 * @file hal_pil.c
 * @brief HAL binding of the PIL programs (hal_pil.h).
 */
#include "hal_pil.h"

#include <string.h>

#include "npc_plan.h"

#define PIL_NVM_SIZE 4096u
/* The target's timer set-up (hal/stm32g4/hal_stm32g4.c): the HRTIM counts at
 * 170 MHz; switching keeps out of the sampling window and the last pulse of a
 * period is at least 2 us. */
#define PIL_COUNT_HZ 170000000u
#define PIL_KEEPOUT_END_NS 7000u
#define PIL_MIN_PULSE_NS 2000u

typedef struct {
    hal_tick_handler handler;
    void *ctx;
    bool tick_running;
    hal_sample next;       /* what the ADC converted for the coming tick; the one allowed read copies it */
    bool next_fresh;
    bool sample_pending;   /* latched by the tick interrupt, cleared by the one allowed read */
    uint32_t seq;
    bool gates_on;
    bool fault_input;
    bool tick_missed;
    uint32_t millis;
    npc_timing tm;            /* timer counts of the period, keep-out and minimum pulse */
    float per_f;              /* tm.per as a float (exact: below 2^24), for the instant */
    npc_usual usual;          /* the period's usual instants (npc_usual_of) */
    uint8_t last_leg[4];      /* leg states at the end of the programmed period (with NPC_LEG_HELD: the timers hold its one-state words); [3] stays 0 (npc_leg_words_index3) */
    uint32_t pn_fixups;       /* P<->N steps the planner replaced (a firmware bug if ever > 0) */
    bool pn_step_seen;        /* as the target's BOARD_FAULT_PN_STEP */
    bool idle_held;           /* gates off: the registers hold idle_req's programme, which repeats itself */
    npc_request idle_req;     /* the last request programmed with the gates off */
} pil_board;

/* Stand-ins for the six timers' SET/RST/CMP1 registers and the update-disable
 * bits: hal_actuate programs them as the target programs the HRTIM (with the
 * same whole-register writes of the update-disable bits and the same words,
 * the fault event in every reset word), so the bench counts the target's work. */
#define PIL_UDIS_ALL 0x7Fu           /* HRTIM_CR1 MUDIS, TAUDIS..TFUDIS */
static volatile uint32_t g_pil_timer[6][3];
static volatile uint32_t g_pil_update_disable;

static pil_board g_pil;

void hal_pil_board_reset(void) { memset(&g_pil, 0, sizeof g_pil); }

void hal_pil_set_inputs(const hal_sample *s, bool fresh, bool fault_input, bool tick_missed)
{
    g_pil.next = *s;
    g_pil.next_fresh = fresh;
    g_pil.fault_input = fault_input;
    g_pil.tick_missed = tick_missed;
    if (fault_input)
        g_pil.gates_on = false; /* the hardware path: the fault line turns the gates off */
}

void hal_pil_tick_irq(void)
{
    /* The target's sample_latch() takes the ADC results here and its
     * hal_sample_read converts them straight into the reader's buffer (one
     * copy of the sample, not two); the PIL board's read copies the
     * recorded, already converted sample. */
    g_pil.sample_pending = g_pil.next_fresh;
    g_pil.next_fresh = false;
    if (g_pil.handler != NULL)
        g_pil.handler(g_pil.ctx);
}

bool hal_pil_gates_on(void) { return g_pil.gates_on; }

/* ------------------------------------------------------------ the contract */

int hal_tick_start(hal_tick_handler handler, void *ctx, uint32_t period_us)
{
    if (handler == NULL || period_us < 50u || period_us > 1000u)
        return HAL_EINVAL;
    g_pil.handler = handler;
    g_pil.ctx = ctx;
    g_pil.tick_running = true;
    g_pil.tm.per = (uint32_t)((uint64_t)period_us * PIL_COUNT_HZ / 1000000u);
    g_pil.tm.keepout = (uint32_t)((uint64_t)PIL_KEEPOUT_END_NS * PIL_COUNT_HZ / 1000000000u);
    g_pil.tm.min_pulse = (uint32_t)((uint64_t)PIL_MIN_PULSE_NS * PIL_COUNT_HZ / 1000000000u);
    g_pil.per_f = (float)g_pil.tm.per;
    g_pil.usual = npc_usual_of(&g_pil.tm);
    for (unsigned leg = 0u; leg < 3u; leg++)
        g_pil.last_leg[leg] = (uint8_t)HAL_LEG_O;
    g_pil.last_leg[3] = 0u;
    g_pil.idle_held = false;
    return HAL_OK;
}

void hal_tick_stop(void)
{
    g_pil.gates_on = false;
    g_pil.tick_running = false;
    g_pil.handler = NULL;
}

/* The recorded deadline flag of this tick (hal_pil_set_inputs sets it every
 * tick), read as the target reads the timer's pending flag: without clearing
 * it. */
bool hal_tick_missed(void) { return g_pil.tick_missed; }

int hal_sample_read(hal_sample *out)
{
    if (out == NULL)
        return HAL_EINVAL;
    if (!g_pil.sample_pending)
        return HAL_EAGAIN;
    *out = g_pil.next;
    g_pil.sample_pending = false;
    return HAL_OK;
}

/* Leg @p leg's ready words of class @p c (not NPC_HELD) straight to its two
 * timers, CMP1 = @p t when @p cmp1 (no plan struct in between, as on the target). */
static inline void write_leg(uint32_t leg, const npc_leg_words *w, uint32_t c, bool cmp1, uint32_t t)
{
    const uint32_t *reg = w->reg[c];
    uint32_t tim = 2u * leg;
    g_pil_timer[tim][0] = reg[0];
    g_pil_timer[tim][1] = reg[1];
    if (cmp1)
        g_pil_timer[tim][2] = t;
    g_pil_timer[tim + 1u][0] = reg[2];
    g_pil_timer[tim + 1u][1] = reg[3];
    if (cmp1)
        g_pil_timer[tim + 1u][2] = t;
    g_pil.last_leg[leg] = w->end[c];
}

/* The target's work (hal_stm32g4.c program_period): plan each leg's
 * switching events for the period and write them to the timers. */
static __attribute__((noinline)) int program_period(const hal_actuation *act)
{
    _Static_assert(sizeof(hal_vector) == 3u && HAL_LEG_P == NPC_P, "two vectors: six leg codes, NPC numbering");
    if (!npc_legs_valid((const uint8_t *)act->vector)) /* any leg code above HAL_LEG_P */
        return HAL_EINVAL;
    if (!npc_duty_valid(act->duty0)) /* 0..1; also refuses NaN */
        return HAL_EINVAL;
    if (g_pil.tm.per == 0u)
        return HAL_OK; /* tick not started: nothing to program */
    /* the legs' words first: the instants only when a leg has two states */
    const npc_leg_words *w3[3];
    uint32_t legs = npc_legs_words((const uint8_t *)act->vector, g_pil.last_leg, w3);
    if (legs == 0u)
        return HAL_OK; /* every leg alone in its held state again: the timers hold its words */
    g_pil_update_disable = PIL_UDIS_ALL; /* as the target: CR1 holds nothing else */
    npc_program_legs(w3, legs, act->duty0, g_pil.per_f, &g_pil.usual, &g_pil.tm, write_leg);
    if ((legs & NPC_FLAG_FIXUPS) != 0u) { /* one test per period (a firmware bug if ever true) */
        g_pil.pn_fixups += npc_legs_fixups(w3);
        g_pil.pn_step_seen = true;
    }
    g_pil_update_disable = 0u;
    return HAL_OK;
}

/* Gates off (as the target's actuate_gates_off): the request repeats (the
 * zero vector); once a programme has left the legs where it found them, the
 * preloaded registers hold what the same request would write again. */
static __attribute__((noinline)) int actuate_gates_off(const hal_actuation *act)
{
    npc_request req = npc_request_of((const uint8_t *)act->vector, act->duty0);
    if (g_pil.idle_held && npc_request_same(&req, &g_pil.idle_req))
        return HAL_OK;
    uint32_t prev = npc_legs_word(g_pil.last_leg);
    int rc = program_period(act);
    g_pil.idle_held = rc == HAL_OK && g_pil.tm.per != 0u && npc_legs_word(g_pil.last_leg) == prev;
    g_pil.idle_req = req;
    return rc;
}

int hal_actuate(const hal_actuation *act)
{
    if (act == NULL)
        return HAL_EINVAL;
    if (!g_pil.gates_on)
        return actuate_gates_off(act);
    return program_period(act);
}

void hal_gate_enable(bool enable)
{
    if (enable)
        g_pil.idle_held = false; /* the running programmes will overwrite the held one */
    g_pil.gates_on = enable && !g_pil.fault_input && g_pil.tick_running;
}

bool hal_gate_enabled(void) { return g_pil.gates_on; }

bool hal_fault_input_active(void) { return g_pil.fault_input; }

/* No cycle counter on this QEMU (DWT CYCCNT reads 0): the drive's timing
 * statistic stays 0; the bench counts instructions with SysTick instead. */
uint32_t hal_cycles(void) { return 0u; }

uint32_t hal_cycles_hz(void) { return 170000000u; }

uint32_t hal_millis(void) { return g_pil.millis; }

int hal_can_open(uint32_t bitrate_bps)
{
    return (bitrate_bps == 125000u || bitrate_bps == 250000u || bitrate_bps == 500000u || bitrate_bps == 1000000u)
               ? HAL_OK
               : HAL_EINVAL;
}

int hal_can_send(const hal_can_frame *frame)
{
    if (frame == NULL || frame->id > 0x7FFu || frame->dlc > 8u)
        return HAL_EINVAL;
    return HAL_OK; /* no bus: dropped */
}

int hal_can_recv(hal_can_frame *frame)
{
    (void)frame;
    return HAL_EAGAIN;
}

uint32_t hal_nvm_size(void) { return PIL_NVM_SIZE; }

int hal_nvm_read(uint32_t offset, void *buf, size_t len)
{
    if (offset > PIL_NVM_SIZE || len > PIL_NVM_SIZE - offset)
        return HAL_ENOSPC;
    memset(buf, 0xFF, len); /* erased: the drive starts from its defaults */
    return HAL_OK;
}

int hal_nvm_write(uint32_t offset, const void *buf, size_t len)
{
    (void)buf;
    if (offset > PIL_NVM_SIZE || len > PIL_NVM_SIZE - offset)
        return HAL_ENOSPC;
    return HAL_EIO; /* the replay never stores parameters */
}

int hal_watchdog_start(uint32_t timeout_ms) { return (timeout_ms >= 1u && timeout_ms <= 4000u) ? HAL_OK : HAL_EINVAL; }

void hal_watchdog_kick(void) {}

/* The bench starts from a power-on reset every time (QEMU -kernel). */
uint32_t hal_reset_cause(void) { return HAL_RESET_POWER_ON; }
