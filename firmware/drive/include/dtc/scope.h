/**
 * @file scope.h
 * @brief A triggered capture of up to 4 telemetry signals x 1024 samples,
 *        sampled in the control interrupt in constant time.
 *
 * The background arms it (scope_arm) with the channels resolved to byte
 * offsets in the telemetry snapshot; the interrupt (scope_sample) stores one
 * value per channel every `decimation` ticks into a ring, watches the
 * trigger (a change of the commanded speed reference, a new fault, or a
 * manual request) and, pretrigger samples after arming at the earliest,
 * captures the rest of the record and freezes it (state DONE). The background
 * reads a frozen record only (scope_value); arming again discards it.
 *
 * Sharing rule: the background writes the capture settings only while the
 * interrupt ignores them (state IDLE or DONE) and publishes them with the
 * state store; the interrupt writes the buffer only in ARMED or TRIGGERED
 * and publishes DONE after its last store.
 */
#ifndef DTC_SCOPE_H
#define DTC_SCOPE_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SCOPE_CHANNELS 4u
#define SCOPE_SAMPLES 1024u

/** Settings (parameters 0x2600), used at the next scope_arm. */
typedef struct {
    uint8_t channel[SCOPE_CHANNELS]; /**< telemetry signal numbers (0x3000 subindex), 0 = off */
    uint8_t trigger;                 /**< scope_trigger */
    uint16_t pretrigger;             /**< samples kept before the trigger, 0..SCOPE_SAMPLES-1 */
    uint16_t decimation;             /**< one sample every N ticks, >= 1 */
} scope_cfg;

typedef enum {
    SCOPE_IDLE = 0,
    SCOPE_ARMED = 1,      /**< filling the pretrigger part, waiting for the trigger */
    SCOPE_TRIGGERED = 2,  /**< capturing after the trigger */
    SCOPE_DONE = 3,       /**< record frozen, ready to read */
} scope_state;

typedef enum {
    SCOPE_TRIG_MANUAL = 0,
    SCOPE_TRIG_REF = 1,   /**< the commanded speed reference changed */
    SCOPE_TRIG_FAULT = 2, /**< a fault bit latched (0 -> non-zero) */
} scope_trigger;

/** What one channel's snapshot field holds (the reader converts it: the interrupt copies words). */
typedef enum {
    SCOPE_SRC_F32 = 0,
    SCOPE_SRC_U32 = 1,
    SCOPE_SRC_U8 = 2,
} scope_src_kind;

typedef struct {
    uint16_t offset; /**< byte offset in the snapshot */
    uint8_t kind;    /**< scope_src_kind */
} scope_src;

typedef struct {
    scope_cfg cfg;                      /**< settings (BG only) */

    /* capture settings: written by BG in IDLE/DONE, read by the ISR */
    uint16_t word_at[SCOPE_CHANNELS];   /**< byte offset of the 4-byte word the ISR copies per channel (a U8
                                             source's aligned word; 0 for the channels not in use) */
    uint8_t trigger;                    /**< scope_trigger of the capture */
    uint16_t pretrigger;
    uint16_t decimation;
    /* the capture's description, for the reader (BG) */
    uint8_t kind[SCOPE_CHANNELS];       /**< scope_src_kind of each channel (F32 for those not in use) */
    uint8_t byte_in_word[SCOPE_CHANNELS]; /**< a U8 source's byte within its word, 0..3 */
    uint8_t armed_channel[SCOPE_CHANNELS]; /**< signal numbers of the capture */
    uint8_t n_ch;                       /**< channels in use */

    /* hand-over */
    volatile uint8_t state;             /**< scope_state */
    volatile bool pending;              /**< a trigger to take at the next stored sample once the pretrigger
                                             part is full: set by the ISR on a trigger event or by BG for a
                                             manual trigger (one flag for both, so the ISR tests no separate
                                             request every tick), cleared by the ISR when it takes it and by
                                             scope_arm */

    /* interrupt-owned */
    uint16_t pos;                       /**< next ring index */
    uint16_t pre_left;                  /**< samples still to store (ARMED) before a trigger may be taken */
    uint16_t remaining;                 /**< samples still to take after the trigger */
    uint16_t dec_left;                  /**< ticks until the next stored sample (1: this one) */
    uint16_t start;                     /**< ring index of the oldest sample (DONE) */
    bool primed;                        /**< last_ref/last_faults valid */
    real_t last_ref_rad_s;
    uint32_t last_faults;
    uint32_t trigger_tick;              /**< tick counter at the trigger sample */
    uint32_t buf[SCOPE_SAMPLES][SCOPE_CHANNELS]; /**< ring of samples, the channels of one side by side, each
                                                      the source's word as it was (scope_value converts it) */
} scope;

/** Idle, no channels; settings untouched. Context: BG. */
void scope_init(scope *s);

/**
 * Arm a capture with the present settings and the given sources (one per
 * cfg.channel that is not 0, in channel order; @p n_src of them); a running
 * capture is discarded. A source's word (a U8 source's: the aligned word that
 * holds it) must lie inside the snapshot scope_sample is given: F32 and U32
 * fields are whole words, and a struct with a float member is a whole number
 * of 4-byte words. Context: BG.
 */
void scope_arm(scope *s, const scope_src *src, uint8_t n_src);

/** Trigger now (honoured once pretrigger samples are stored). Context: BG. */
void scope_trigger_now(scope *s);

/** Stop and discard any capture. Context: BG. */
void scope_stop(scope *s);

/** @return the scope_state. Context: BG. */
uint8_t scope_get_state(const scope *s);

/**
 * Sample j (0 = oldest) of capture channel @p ch of a DONE record, converted
 * from the stored word by the channel's kind (SI units, or the integer's
 * value); 0 when not DONE or out of range. Context: BG.
 */
float scope_value(const scope *s, uint32_t ch, uint32_t j);

/** Publish the record: DONE after every store of the capture (once per capture). Context: ISR. */
void scope_publish_done(scope *s);

/**
 * Interrupt part: trigger detection and one store per channel every
 * decimation ticks. Constant time, the same whatever the channels' kinds (each
 * channel's word copied as it is; the reader converts). @p base is the
 * telemetry snapshot the source offsets refer to (at least 4 bytes: the
 * unused channels read its first word), @p ref_cmd_rad_s the commanded (not ramped) speed
 * reference, @p faults the latched fault bits, @p tick the tick counter.
 * Inline: the interrupt's one call site pays no call, no argument set-up
 * and no register saves. Context: ISR.
 */
static inline void scope_sample(scope *s, const void *base, real_t ref_cmd_rad_s, uint32_t faults, uint32_t tick)
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
    if (!primed) /* once: no store every tick */
        s->primed = true;

    uint8_t st = s->state;
    if (st == (uint8_t)SCOPE_ARMED) {
        if (s->pre_left == 0u) { /* the pretrigger part is full (a manual trigger is pending already) */
            uint8_t trigger = s->trigger;
            if (primed && ((trigger == SCOPE_TRIG_REF && ref_cmd_rad_s != last_ref_rad_s) ||
                           (trigger == SCOPE_TRIG_FAULT && faults != 0u && last_faults == 0u)))
                s->pending = true;
        }
    } else if (st != (uint8_t)SCOPE_TRIGGERED) {
        return;
    }
    /* a count down: no compare with the decimation while it runs */
    uint16_t dec_left = s->dec_left;
    if (dec_left > 1u) {
        s->dec_left = (uint16_t)(dec_left - 1u);
        return;
    }
    s->dec_left = s->decimation;

    uint16_t pos = s->pos;
    uint32_t *row = s->buf[pos]; /* one sample's channels side by side: one address for the stores */
    /* Every channel's word as it is (the unused ones read the base's first
     * word; the reader never reads their columns): no conversion and no
     * per-kind path here, so an integer channel costs what a float one does
     * and the tick's cost does not depend on the channels' kinds. */
    const uint8_t *b = (const uint8_t *)base;
    uint32_t w0, w1, w2, w3;
    memcpy(&w0, b + s->word_at[0], sizeof w0);
    memcpy(&w1, b + s->word_at[1], sizeof w1);
    memcpy(&w2, b + s->word_at[2], sizeof w2);
    memcpy(&w3, b + s->word_at[3], sizeof w3);
    row[0] = w0;
    row[1] = w1;
    row[2] = w2;
    row[3] = w3;
    s->pos = (uint16_t)((pos + 1u) % SCOPE_SAMPLES);

    if (st == (uint8_t)SCOPE_ARMED) {
        uint16_t pre_left = s->pre_left;
        if (pre_left != 0u) { /* (a pending manual trigger waits for the pretrigger part) */
            s->pre_left = (uint16_t)(pre_left - 1u);
            return;
        }
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
    scope_publish_done(s);
}

#ifdef __cplusplus
}
#endif

#endif /* DTC_SCOPE_H */
