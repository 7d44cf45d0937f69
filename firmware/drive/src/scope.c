/**
 * @file scope.c
 * @brief Triggered capture of telemetry signals: constant-time sampling in
 *        the interrupt, arming and reading in the background.
 */
#include "dtc/scope.h"

#include <stdatomic.h>
#include <string.h>

/* Compiler barrier: keeps plain stores on the right side of the state store
 * that publishes them (single core: the interrupt only preempts). */
static inline void publish_fence(void) { atomic_signal_fence(memory_order_seq_cst); }

void scope_init(scope *s)
{
    scope_cfg keep = s->cfg;
    memset(s, 0, sizeof *s);
    s->cfg = keep;
    s->decimation = 1u;
    s->state = SCOPE_IDLE;
}

void scope_stop(scope *s)
{
    s->state = SCOPE_IDLE;
    publish_fence();
}

void scope_arm(scope *s, const scope_src *src, uint8_t n_src)
{
    scope_stop(s); /* from here on the interrupt leaves everything below alone */
    uint8_t n = n_src <= SCOPE_CHANNELS ? n_src : (uint8_t)SCOPE_CHANNELS;
    uint8_t k = 0u;
    for (uint32_t ch = 0u; ch < SCOPE_CHANNELS; ch++) {
        if (s->cfg.channel[ch] != 0u && k < n)
            s->armed_channel[k++] = s->cfg.channel[ch];
    }
    for (uint32_t ch = k; ch < SCOPE_CHANNELS; ch++)
        s->armed_channel[ch] = 0u;
    bool all_f32 = true;
    for (uint32_t i = 0u; i < n; i++) {
        s->src[i] = src[i];
        all_f32 = all_f32 && src[i].kind == (uint8_t)SCOPE_SRC_F32;
    }
    for (uint32_t i = n; i < SCOPE_CHANNELS; i++) /* read (the base's first word) but never shown */
        s->src[i] = (scope_src){.offset = 0u, .kind = (uint8_t)SCOPE_SRC_F32};
    s->n_ch = n;
    s->all_f32 = all_f32;
    s->trigger = s->cfg.trigger;
    s->pretrigger = s->cfg.pretrigger < SCOPE_SAMPLES ? s->cfg.pretrigger : (uint16_t)(SCOPE_SAMPLES - 1u);
    s->decimation = s->cfg.decimation >= 1u ? s->cfg.decimation : 1u;
    s->pos = 0u;
    s->filled = 0u;
    s->remaining = 0u;
    s->dec_left = s->decimation;
    s->start = 0u;
    s->pending = false;
    s->trig_req = false;
    s->trigger_tick = 0u;
    publish_fence();
    s->state = SCOPE_ARMED;
}

void scope_trigger_now(scope *s) { s->trig_req = true; }

uint8_t scope_get_state(const scope *s) { return s->state; }

float scope_value(const scope *s, uint32_t ch, uint32_t j)
{
    if (s->state != SCOPE_DONE || ch >= s->n_ch || j >= SCOPE_SAMPLES)
        return 0.0f;
    return s->buf[(s->start + j) % SCOPE_SAMPLES][ch];
}

static inline float read_src(const uint8_t *base, scope_src src)
{
    switch (src.kind) {
    case SCOPE_SRC_U32: {
        uint32_t u;
        memcpy(&u, base + src.offset, sizeof u);
        return (float)u;
    }
    case SCOPE_SRC_U8:
        return (float)base[src.offset];
    default: {
        float f;
        memcpy(&f, base + src.offset, sizeof f);
        return f;
    }
    }
}

void scope_sample(scope *s, const void *base, real_t ref_cmd_rad_s, uint32_t faults, uint32_t tick)
{
    /* Trigger events are watched every tick, whatever the state, so that the
     * first tick after arming compares with a valid previous value: the
     * previous values are kept every tick, the edges worked out only where a
     * trigger can be taken. */
    real_t last_ref_rad_s = s->last_ref_rad_s;
    uint32_t last_faults = s->last_faults;
    bool primed = s->primed;
    s->last_ref_rad_s = ref_cmd_rad_s;
    s->last_faults = faults;
    s->primed = true;

    uint8_t st = s->state;
    if ((uint8_t)(st - (uint8_t)SCOPE_ARMED) > (uint8_t)(SCOPE_TRIGGERED - SCOPE_ARMED))
        return; /* neither ARMED nor TRIGGERED */
    if (st == SCOPE_ARMED && s->filled >= s->pretrigger) {
        bool manual = s->trig_req;
        if (manual)
            s->trig_req = false;
        uint8_t trigger = s->trigger;
        if (manual || (primed && ((trigger == SCOPE_TRIG_REF && ref_cmd_rad_s != last_ref_rad_s) ||
                                  (trigger == SCOPE_TRIG_FAULT && faults != 0u && last_faults == 0u))))
            s->pending = true;
    }
    /* a count down (issue 11: no compare with the decimation while it runs) */
    uint16_t dec_left = s->dec_left;
    if (dec_left > 1u) {
        s->dec_left = (uint16_t)(dec_left - 1u);
        return;
    }
    s->dec_left = s->decimation;

    const uint8_t *b = (const uint8_t *)base;
    uint16_t pos = s->pos;
    if (s->all_f32) {
        /* The usual case: the values as they are, every channel (scope_arm
         * points the unused ones at the base's first word; the reader never
         * reads their columns), no loop and no conversion to choose. */
        float f0, f1, f2, f3;
        memcpy(&f0, b + s->src[0].offset, sizeof f0);
        memcpy(&f1, b + s->src[1].offset, sizeof f1);
        memcpy(&f2, b + s->src[2].offset, sizeof f2);
        memcpy(&f3, b + s->src[3].offset, sizeof f3);
        /* one sample's channels side by side: one address for the four stores */
        float *row = s->buf[pos];
        row[0] = f0;
        row[1] = f1;
        row[2] = f2;
        row[3] = f3;
    } else {
        uint32_t n_ch = s->n_ch; /* read once: the stores below are float stores, which cannot change it */
        for (uint32_t ch = 0u; ch < n_ch; ch++) /* at most SCOPE_CHANNELS stores */
            s->buf[pos][ch] = read_src(b, s->src[ch]);
    }
    s->pos = (uint16_t)((pos + 1u) % SCOPE_SAMPLES);
    if (s->filled < SCOPE_SAMPLES)
        s->filled++;

    if (st == SCOPE_ARMED) {
        if (!s->pending)
            return;
        s->pending = false;
        s->trigger_tick = tick;
        s->start = (uint16_t)((pos + SCOPE_SAMPLES - s->pretrigger) % SCOPE_SAMPLES);
        s->remaining = (uint16_t)(SCOPE_SAMPLES - 1u - s->pretrigger);
        if (s->remaining > 0u) {
            s->state = SCOPE_TRIGGERED;
            return;
        }
    } else if (--s->remaining > 0u) {
        return;
    }
    publish_fence();
    s->state = SCOPE_DONE;
}
