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
    for (uint32_t i = 0u; i < SCOPE_CHANNELS; i++) {
        /* the channels not in use: read (the base's first word) but never shown */
        uint16_t at = i < n ? src[i].offset : 0u;
        uint8_t kind = i < n ? src[i].kind : (uint8_t)SCOPE_SRC_F32;
        /* a byte: the aligned word that holds it, the byte picked by the reader */
        uint8_t byte = kind == (uint8_t)SCOPE_SRC_U8 ? (uint8_t)(at & 3u) : 0u;
        s->word_at[i] = (uint16_t)(at - byte);
        s->kind[i] = kind;
        s->byte_in_word[i] = byte;
    }
    s->n_ch = n;
    s->trigger = s->cfg.trigger;
    s->pretrigger = s->cfg.pretrigger < SCOPE_SAMPLES ? s->cfg.pretrigger : (uint16_t)(SCOPE_SAMPLES - 1u);
    s->decimation = s->cfg.decimation >= 1u ? s->cfg.decimation : 1u;
    s->pos = 0u;
    s->pre_left = s->pretrigger;
    s->remaining = 0u;
    s->dec_left = s->decimation;
    s->start = 0u;
    s->pending = false;
    s->trigger_tick = 0u;
    publish_fence();
    s->state = SCOPE_ARMED;
}

void scope_trigger_now(scope *s) { s->pending = true; }

uint8_t scope_get_state(const scope *s) { return s->state; }

float scope_value(const scope *s, uint32_t ch, uint32_t j)
{
    if (s->state != SCOPE_DONE || ch >= s->n_ch || j >= SCOPE_SAMPLES)
        return 0.0f;
    uint32_t w = s->buf[(s->start + j) % SCOPE_SAMPLES][ch];
    switch (s->kind[ch]) {
    case SCOPE_SRC_U32:
        return (float)w;
    case SCOPE_SRC_U8: {
        uint8_t bytes[4]; /* the word as it lay in memory: the byte's place in it needs no byte order */
        memcpy(bytes, &w, sizeof bytes);
        return (float)bytes[s->byte_in_word[ch]];
    }
    default: {
        float f;
        memcpy(&f, &w, sizeof f);
        return f;
    }
    }
}

void scope_publish_done(scope *s)
{
    publish_fence(); /* the capture's stores before the state that publishes them */
    s->state = SCOPE_DONE;
}
