/**
 * @file npc_plan.h
 * @brief Pure planning of one NPC leg's HRTIM programme for one PWM period:
 *        which set/reset events each complementary pair gets, and when.
 *
 * Kept free of registers so the host tests (tests/hal_stm32g4) can check it
 * exhaustively: no S1+S4 / no direct P<->N step, keep-out of the sampling
 * window, minimum pulse. Private to hal/stm32g4 and its tests (and the PIL
 * board, which runs the same planner).
 *
 * Per leg two HRTIM timers drive complementary pairs: pair 0 = S3 (output 1)
 * / S1 (output 2), pair 1 = S2 (output 1) / S4 (output 2): output 1 is the
 * inner switch of both, so the fault line's delayed external event can reset
 * it in hardware (docs/board.md, "Fault"). Output 1 of a pair is set/reset by
 * two compare events: NPC_EV_START (CMP2, a few counts
 * after the period roll-over) gives the level of the first vector, NPC_EV_T
 * (CMP1 = t) the change to the second one.
 *
 * Cost: the leg states' part of the plan (P<->N guard, event bits) depends
 * on the 27 triples (prev, v0, v1) only and is a constant table of ready
 * register words per triple and instant class (npc_leg_words_table, built
 * from the rules of npc_plan_rules.h); the switching instant's part depends
 * on the requested instant only and is worked out once per period for all
 * three legs (npc_instants_of). The actuation writes the words straight to
 * the timers, no plan struct in between; the host tests compare them with a
 * reference planner (tests/oracles/npc_plan_leg.c).
 */
#ifndef HAL_STM32G4_NPC_PLAN_H
#define HAL_STM32G4_NPC_PLAN_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "dtc/npc.h" /* the leg codes NPC_N, NPC_O, NPC_P and the P<->N rule of one leg */

#ifdef __cplusplus
extern "C" {
#endif

/** Event bits, equal to the HRTIM SETx1R/RSTx1R bits CMP2 and CMP1. */
#define NPC_EV_START (1u << 4)
#define NPC_EV_T (1u << 3)

/**
 * True when each of the six leg codes at @p legs (the two vectors of an
 * actuation, three legs each, contiguous bytes) is a leg state (<= NPC_P).
 * Word-wide (one test in place of six compares and branches): a
 * byte b below 0x80 is above NPC_P exactly when b + 0x7D sets its bit 7; a
 * byte with bit 7 set fails through the OR with the word itself (only such a
 * byte carries into the next one, so the carries change nothing).
 * Context: ANY (pure).
 */
static inline bool npc_legs_valid(const uint8_t legs[6])
{
    uint32_t w;
    uint16_t h;
    memcpy(&w, legs, sizeof w);
    memcpy(&h, legs + 4, sizeof h);
    uint32_t hw = h; /* its bytes 2 and 3 are 0: + 0x7D leaves their bit 7 clear (one constant for both words) */
    uint32_t bad = ((w + 0x7D7D7D7Du) | w | (hw + 0x7D7D7D7Du) | hw) & 0x80808080u;
    return bad == 0u;
}

/**
 * True when @p duty0 is in [0, 1] (NaN refused): as integers (an unsigned
 * compare of the bits in place of two float compares; +0..1 are the
 * bits 0..0x3F800000, and -0 is accepted as the float compare accepts it).
 * Context: ANY (pure).
 */
static inline bool npc_duty_valid(float duty0)
{
    uint32_t b;
    memcpy(&b, &duty0, sizeof b);
    return b <= 0x3F800000u || b == 0x80000000u;
}

/**
 * An actuation's request as the gates-off repeat compares it: the
 * six leg codes and the duty's bits (no padding byte compared).
 */
typedef struct {
    uint32_t legs_0123; /**< leg codes 0..3 of the two vectors, as stored */
    uint32_t legs_45;   /**< leg codes 4 and 5 */
    uint32_t duty_bits; /**< the duty's float bits */
} npc_request;

/** @return the request of leg codes @p legs (six contiguous bytes) and duty @p duty0. Context: ANY (pure). */
static inline npc_request npc_request_of(const uint8_t legs[6], float duty0)
{
    npc_request r;
    uint16_t h;
    memcpy(&r.legs_0123, legs, sizeof r.legs_0123);
    memcpy(&h, legs + 4, sizeof h);
    r.legs_45 = h;
    memcpy(&r.duty_bits, &duty0, sizeof r.duty_bits);
    return r;
}

/** @return true when @p a and @p b are the same request. Context: ANY (pure). */
static inline bool npc_request_same(const npc_request *a, const npc_request *b)
{
    return ((a->legs_0123 ^ b->legs_0123) | (a->legs_45 ^ b->legs_45) | (a->duty_bits ^ b->duty_bits)) == 0u;
}

/** @return the three leg states @p leg packed as one word, for an equality test. Context: ANY (pure). */
static inline uint32_t npc_legs_word(const uint8_t leg[3])
{
    return (uint32_t)leg[0] | ((uint32_t)leg[1] << 8) | ((uint32_t)leg[2] << 16);
}

/** Timing of one PWM period, in timer counts. */
typedef struct {
    uint32_t per;       /**< period, counts (> keepout + min_pulse) */
    uint32_t keepout;   /**< no switching instant in [start event, keepout): sampling window */
    uint32_t min_pulse; /**< shortest second-vector pulse at the period end */
} npc_timing;

/** Where a leg's switching instant falls; indexes npc_leg_rule's event bits. */
enum npc_instant_class {
    NPC_AT_ZERO = 0, /**< t = 0: the second vector only */
    NPC_AT_T = 1,    /**< 0 < t < per: both vectors, a change at t */
    NPC_AT_PER = 2   /**< t = per: the first vector only */
};

/** The switching instant of a period, counts, for the two kinds of leg that have two vectors. */
typedef struct {
    uint32_t keep; /**< a leg that must keep v0 (prev -> v1 is a P<->N step) */
    uint32_t drop; /**< a leg that may drop v0 when the instant is in the first half of the keep-out */
} npc_instants;

/**
 * The switching instants of a period from the requested instant @p t0
 * (counts, 0..per; larger is taken as per): out of the keep-out [0, keepout),
 * the second pulse at least min_pulse, else per. Context: ANY (pure; inline for
 * the actuation in the control interrupt).
 */
static inline void npc_instants_of(const npc_timing *tm, uint32_t t0, npc_instants *out)
{
    /* Switching instant out of [0, keepout); second pulse >= min_pulse.
     * Dropping v0 (t = 0) only if prev -> v1 is not a P<->N step. */
    uint32_t t = t0 > tm->per ? tm->per : t0;
    uint32_t keep = t, drop = t;
    if (t < tm->keepout) {
        keep = tm->keepout;
        drop = t < tm->keepout / 2u ? 0u : tm->keepout;
    }
    out->keep = keep + tm->min_pulse > tm->per ? tm->per : keep;
    out->drop = drop + tm->min_pulse > tm->per ? tm->per : drop;
}

/**
 * The fault line's reset event ORed into every RSTx1R word (HRTIM RSTx1R
 * EXTEVNT6: the delayed fault event resets the inner switch; docs/board.md).
 */
#define NPC_RST_FAULT_EVENT (1u << 26)

/**
 * The register words of one leg for one (prev, v0, v1), ready to write
 * (the actuation writes them straight to the timers, no plan struct in
 * between; a host test requires them to agree with the reference planner,
 * tests/oracles/npc_plan_leg.c, for every triple and instant).
 */
typedef struct {
    /** per enum npc_instant_class: SETx1R and RSTx1R (with NPC_RST_FAULT_EVENT) of pair 0, then of pair 1 */
    uint32_t reg[3][4];
    uint8_t end[3];     /**< leg state at the end of the period, per enum npc_instant_class, with
                             NPC_LEG_HELD when the words are that state's one-state words */
    uint8_t kind_shift; /**< where its class is in npc_period_classes' word: 0 one state, 8 may drop v0,
                             16 keeps v0, 24 the timers already hold these words (NPC_HELD) */
    uint8_t fixups;     /**< P<->N steps replaced by O (0..2) */
    uint8_t timed;      /**< 1: two states (kind_shift 8 or 16), its class depends on the period's instants */
    uint8_t flags;      /**< NPC_FLAG_WRITE unless held (kind_shift 24), | NPC_FLAG_TIMED when timed,
                             | NPC_FLAG_FIXUPS with fixups */
    uint8_t pad[9];     /**< 64 bytes: the index is one shift */
} npc_leg_words;

/**
 * A flag on a leg's recorded state (the actuation's prev): the leg's timers
 * hold the one-state words of that state (written when the leg last had one
 * state for a whole period). A period asking for that state again, alone,
 * writes nothing: the preloaded registers hold what it would write (RM0440
 * HRTIM preload; about three legs in five in the bench's runs).
 * The words table has a row for each flagged state too; npc_leg_words.end
 * sets the flag after a one-state period. The state is (prev & NPC_LEG_STATE).
 */
#define NPC_LEG_HELD 4u
#define NPC_LEG_STATE 3u

/** The instant class of a leg whose timers hold its words already: nothing to write. */
#define NPC_HELD 3u

/** Entries of npc_leg_words_table: prev up to NPC_P | NPC_LEG_HELD. */
#define NPC_LEG_WORDS_ENTRIES (16u * (NPC_P | NPC_LEG_HELD) + 4u * NPC_P + NPC_P + 1u)

/**
 * Words for every (prev, v0, v1), index 16 prev + 4 v0 + v1 (v0, v1 0..NPC_P;
 * prev 0..NPC_P, optionally with NPC_LEG_HELD): the index is two ORs of
 * shifted states (no multiplications as for 9 prev + 3 v0 + v1), the
 * indices with a 3 are never used. A flagged prev's row equals the
 * plain one, but for (prev, prev, prev), whose class is always NPC_HELD.
 */
extern const npc_leg_words npc_leg_words_table[NPC_LEG_WORDS_ENTRIES];

/** @return the instant class of instant @p t (counts, 0..per) of a period of @p per counts. Context: ANY (pure). */
static inline uint32_t npc_class_at(uint32_t per, uint32_t t)
{
    return t == 0u ? (uint32_t)NPC_AT_ZERO : (t == per ? (uint32_t)NPC_AT_PER : (uint32_t)NPC_AT_T);
}

/**
 * The period's instant classes of the three kinds of leg in one word (byte 0:
 * a leg with one state, always NPC_AT_PER; byte 1: a leg that may drop v0;
 * byte 2: a leg that keeps v0; byte 3: a leg whose timers hold its words,
 * NPC_HELD), indexed by npc_leg_words.kind_shift. A leg
 * whose class is NPC_AT_T changes at @p in->keep: the drop instant is either
 * 0 or the keep instant (npc_instants_of). Context: ANY (pure).
 */
static inline uint32_t npc_period_classes(const npc_timing *tm, const npc_instants *in)
{
    return (uint32_t)NPC_AT_PER | (npc_class_at(tm->per, in->drop) << 8) | (npc_class_at(tm->per, in->keep) << 16) |
           ((uint32_t)NPC_HELD << 24);
}

/**
 * The period's instant classes (as npc_period_classes of npc_instants_of) and
 * the instant @p t_out (counts) at which its legs of class NPC_AT_T change
 * (npc_instants.keep), from the requested instant @p t0 (counts). An instant
 * out of the keep-out and before the last minimum pulse, the usual one, is
 * taken as it is: both kinds of two-state leg change at it (no clamps and no
 * class tests; only the other instants take the general way).
 * Context: ANY (pure).
 */
static inline uint32_t npc_period_classes_at(const npc_timing *tm, uint32_t t0, uint32_t *t_out)
{
    if (t0 >= tm->keepout && t0 != 0u && t0 + tm->min_pulse < tm->per) {
        *t_out = t0;
        return (uint32_t)NPC_AT_PER | ((uint32_t)NPC_AT_T << 8) | ((uint32_t)NPC_AT_T << 16) |
               ((uint32_t)NPC_HELD << 24);
    }
    npc_instants in;
    npc_instants_of(tm, t0, &in);
    *t_out = in.keep;
    return npc_period_classes(tm, &in);
}

/**
 * The usual instants of a period, [lo, lo + span) counts: out of the keep-out
 * (and not 0) and before the last minimum pulse, the instants
 * npc_period_classes_at takes as they are. Worked out once when the period is
 * set up (npc_usual_of), so a period's test is one subtraction and one
 * unsigned compare.
 */
typedef struct {
    uint32_t lo;   /**< first usual instant, counts: the keep-out's end, at least 1 */
    uint32_t span; /**< number of usual instants (0: none) */
} npc_usual;

/** @return the usual instants of periods of timing @p tm. Context: ANY (pure). */
static inline npc_usual npc_usual_of(const npc_timing *tm)
{
    uint32_t lo = tm->keepout != 0u ? tm->keepout : 1u;
    uint32_t end = tm->per > tm->min_pulse ? tm->per - tm->min_pulse : 0u; /* first instant whose last pulse is too short */
    npc_usual u = {lo, end > lo ? end - lo : 0u};
    return u;
}

/**
 * @return true when the requested instant @p t0 (counts) is usual (@p u of
 * npc_usual_of): then every leg with two states changes at @p t0 (class
 * NPC_AT_T), every other leg that is not held has class NPC_AT_PER, whose
 * words are its NPC_AT_T row too. Context: ANY (pure).
 */
static inline bool npc_instant_usual(const npc_usual *u, uint32_t t0)
{
    return t0 - u->lo < u->span; /* below lo wraps to more than any span */
}

/**
 * The instant classes of a period none of whose legs has two states (no
 * npc_leg_words.timed): every such leg's class is NPC_AT_PER or NPC_HELD
 * whatever the instants, so the actuation need not work them out (three
 * periods in four apply one vector for the whole period).
 */
#define NPC_UNTIMED_CLASSES ((uint32_t)NPC_AT_PER | ((uint32_t)NPC_HELD << 24))

/** @return the words of leg states @p prev (<= NPC_P, optionally | NPC_LEG_HELD), @p v0, @p v1 (each <= NPC_P, unchecked). Context: ANY (pure). */
static inline const npc_leg_words *npc_leg_words_of(uint8_t prev, uint8_t v0, uint8_t v1)
{
    return &npc_leg_words_table[((uint32_t)prev << 4) | ((uint32_t)v0 << 2) | v1];
}

/**
 * The npc_leg_words_table indices of the three legs at once, one per byte
 * (byte k: leg k's 16 prev + 4 v0 + v1, as npc_leg_words_of): @p legs are the
 * six leg codes of an actuation (two vectors, each <= NPC_P: check with
 * npc_legs_valid first), @p prev4 the three recorded leg states (each <=
 * NPC_P | NPC_LEG_HELD) and a fourth byte that must be 0. Word-wide (issue
 * 11: two loads and a few ORs instead of nine byte loads and six ORs; byte k
 * of a word is the k-th byte in memory on both little-endian builds): no byte
 * exceeds 16 * 6 + 4 * 2 + 2 = 106, so nothing carries into the next one.
 * Context: ANY (pure).
 */
static inline uint32_t npc_leg_words_index3(const uint8_t legs[6], const uint8_t prev4[4])
{
    uint32_t w, p;
    uint16_t h;
    memcpy(&w, legs, sizeof w);       /* v0 of legs 0..2, v1 of leg 0 */
    memcpy(&h, legs + 4, sizeof h);   /* v1 of legs 1, 2 */
    memcpy(&p, prev4, sizeof p);
    uint32_t v0 = w & 0x00FFFFFFu;
    uint32_t v1 = (w >> 24) | ((uint32_t)h << 8);
    return (p << 4) | (v0 << 2) | v1;
}

/** npc_leg_words.flags: the leg is not held, the period writes its words */
#define NPC_FLAG_WRITE 1u
/** npc_leg_words.flags: the leg has two states (npc_leg_words.timed) */
#define NPC_FLAG_TIMED 2u
/** npc_leg_words.flags: the entry replaces a P<->N step (npc_leg_words.fixups > 0) */
#define NPC_FLAG_FIXUPS 4u

/**
 * The three legs' entries of npc_leg_words_table for an actuation (@p legs,
 * @p prev4 as npc_leg_words_index3) into @p w3; @return the OR of their
 * npc_leg_words.flags: 0 when every leg stays alone in its held state (the
 * period writes nothing, no update-disable writes either),
 * NPC_FLAG_TIMED when a leg has two states (the period then needs its
 * instants), NPC_FLAG_FIXUPS when a leg replaces a P<->N step (then count
 * them with npc_legs_fixups: no sum per written leg). Both boards'
 * programme writers start here. Context: ANY.
 */
static inline uint32_t npc_legs_words(const uint8_t legs[6], const uint8_t prev4[4], const npc_leg_words *w3[3])
{
    uint32_t flags = 0u;
    uint32_t index3 = npc_leg_words_index3(legs, prev4);
    for (uint32_t leg = 0u; leg < 3u; leg++) {
        w3[leg] = &npc_leg_words_table[(index3 >> (8u * leg)) & 0xFFu];
        flags |= w3[leg]->flags;
    }
    return flags;
}

/**
 * @return the P<->N fixups of the three legs' entries @p w3 (npc_legs_words):
 * those of the legs a period writes, a held leg's being 0. Context: ANY (pure).
 */
static inline uint32_t npc_legs_fixups(const npc_leg_words *const w3[3])
{
    return (uint32_t)w3[0]->fixups + w3[1]->fixups + w3[2]->fixups;
}

/** npc_leg_words.kind_shift of an entry whose timers hold its words already (class NPC_HELD in every period) */
#define NPC_HELD_SHIFT 24u

/**
 * @return true when the entry @p w's timers hold its words already (class
 * NPC_HELD whatever the period). In a period none of whose legs has two
 * states (no npc_leg_words.timed), every other leg's class is NPC_AT_PER
 * (such a period needs no class word). Context: ANY (pure).
 */
static inline bool npc_leg_held(const npc_leg_words *w)
{
    /* the flags byte npc_legs_words loaded, not kind_shift: the first leg's
     * test reuses the load */
    return (w->flags & NPC_FLAG_WRITE) == 0u;
}

/** @return the instant class of the leg @p w in a period of classes @p classes (npc_period_classes). Context: ANY (pure). */
static inline uint32_t npc_leg_class(const npc_leg_words *w, uint32_t classes)
{
    return (classes >> w->kind_shift) & 0xFFu;
}

/**
 * Writes one leg's words of class @p c (not NPC_HELD) to its timers, and CMP1 =
 * @p t when @p cmp1; records the leg's end state. Each board's own.
 */
typedef void (*npc_write_leg_fn)(uint32_t leg, const npc_leg_words *w, uint32_t c, bool cmp1, uint32_t t);

/**
 * The programme of a period for the three legs, the same on both boards (the
 * PIL board counts the target's work): @p w3 and @p legs from npc_legs_words
 * (legs != 0), @p duty0 the checked split (npc_duty_valid), @p per_f the period
 * in counts as a float, @p u and @p tm the period's usual instants and timing.
 * A period without two-state legs writes each leg that is not held for the
 * whole period; a timed one at a usual instant writes every such leg's
 * NPC_AT_T row with CMP1 = t0 (a one-state leg's words use no CMP1 event:
 * no class work); any other instant takes the classes of the
 * instants. Inline with @p write a constant, so the board's writer is inlined
 * too. Context: ISR (the board's actuation).
 */
static inline __attribute__((always_inline)) void npc_program_legs(const npc_leg_words *w3[3], uint32_t legs,
                                                                    float duty0, float per_f, const npc_usual *u,
                                                                    const npc_timing *tm, npc_write_leg_fn write)
{
    if ((legs & NPC_FLAG_TIMED) == 0u) {
        /* one state per leg (three periods in four) */
        for (uint32_t leg = 0u; leg < 3u; leg++) {
            const npc_leg_words *w = w3[leg];
            if (npc_leg_held(w))
                continue; /* a held leg: the timers hold its words */
            write(leg, w, NPC_AT_PER, false, 0u);
        }
    } else {
        uint32_t t0 = (uint32_t)(duty0 * per_f + 0.5f);
        if (npc_instant_usual(u, t0)) {
            for (uint32_t leg = 0u; leg < 3u; leg++) {
                const npc_leg_words *w = w3[leg];
                if (npc_leg_held(w))
                    continue;
                write(leg, w, NPC_AT_T, true, t0);
            }
        } else {
            /* in or near the keep-out, or too short a last pulse */
            uint32_t t; /* CMP1 of every leg that changes inside the period */
            uint32_t classes = npc_period_classes_at(tm, t0, &t); /* once for the three legs */
            for (uint32_t leg = 0u; leg < 3u; leg++) {
                const npc_leg_words *w = w3[leg];
                uint32_t c = npc_leg_class(w, classes);
                if (c == NPC_HELD)
                    continue;
                write(leg, w, c, c == (uint32_t)NPC_AT_T, t);
            }
        }
    }
}

#ifdef __cplusplus
}
#endif

#endif /* HAL_STM32G4_NPC_PLAN_H */
