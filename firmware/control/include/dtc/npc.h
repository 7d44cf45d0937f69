/**
 * @file npc.h
 * @brief Geometry of the three-level neutral-point-clamped (NPC) inverter:
 *        its leg codes, 27 switching states and 19 space vectors, the
 *        neutral-point current of each state, leg commutations, and the rule
 *        that no leg ever steps directly between P and N.
 *
 * Vocabulary
 *  - leg code: NPC_N (the leg at the negative rail, -vc2), NPC_O (clamped to
 *    the neutral point, 0 V), NPC_P (the positive rail, +vc1); the values of
 *    hal_leg_state.
 *  - state: one of the 27 switching states, numbered a*9 + b*3 + c with the
 *    leg codes a, b, c of the three legs.
 *  - space vector ("sv"): one of the 19 distinct voltage vectors:
 *      0       zero            (NNN, OOO, PPP)
 *      1..6    small  Vdc/3        at (sv-1)*60 deg  (two states: P-type, N-type)
 *      7..12   medium Vdc/sqrt(3)  at 30 + (sv-7)*60 deg (one state)
 *      13..18  large  2 Vdc/3      at (sv-13)*60 deg (one state)
 *  - neutral-point (NP) current: the current the legs at O draw from the
 *    neutral point, the sum of their phase currents; with C1 = C2 = C it moves
 *    the capacitors as d(vc1 - vc2)/dt = i_np / C.
 *  - P<->N step: a leg going directly from P to N or back, which the NPC leg
 *    must never do (it passes O); the P<->N-safe state of a transition holds
 *    every such leg at O.
 *
 * The facts about each state are const tables (flash, npc_states.c), so that
 * the interrupt looks a state up and never decomposes its index into base-3
 * digits. Each accessor comes twice: NAME_unchecked takes states 0..26 (and
 * vectors 0..18) only, for the control step's own states, which come from
 * these tables or were clamped once; NAME handles any value as documented.
 * Every function is pure and may be called from any context.
 * tests/unit/test_npc.cpp checks every entry against the plant's inverter
 * model and an independent base-3 decomposition.
 */
#ifndef DTC_NPC_H
#define DTC_NPC_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "dtc/num.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------- one leg */

#define NPC_N 0u /**< leg code: the negative rail, -vc2 (HAL_LEG_N) */
#define NPC_O 1u /**< leg code: the neutral point, 0 V (HAL_LEG_O) */
#define NPC_P 2u /**< leg code: the positive rail, +vc1 (HAL_LEG_P) */

/** True when a leg going from code @p a to code @p b steps directly between
 *  P and N. A constant expression for constant arguments (the board's leg
 *  planner builds its tables with it). */
#define NPC_LEG_PN(a, b) (((a) == NPC_P && (b) == NPC_N) || ((a) == NPC_N && (b) == NPC_P))

/** The leg code a leg going from @p a towards @p b takes without a P<->N
 *  step: @p b, or NPC_O when a -> b is one. A constant expression for
 *  constant arguments. */
#define NPC_LEG_SAFE(a, b) (NPC_LEG_PN(a, b) ? NPC_O : (b))

/* ---------------------------------------------------- states and vectors */

#define NPC_N_STATES 27u  /**< switching states */
#define NPC_N_VECTORS 19u /**< distinct space vectors */
#define NPC_STATE_OOO 13u /**< all legs at the neutral point */

/** Magnitude class of a space vector. */
typedef enum {
    NPC_CLASS_ZERO = 0,
    NPC_CLASS_SMALL = 1,
    NPC_CLASS_MEDIUM = 2,
    NPC_CLASS_LARGE = 3,
} npc_class;

extern const hal_vector npc_state_legs[NPC_N_STATES];       /**< leg codes of each state */
extern const uint32_t npc_state_legs_packed[NPC_N_STATES];  /**< the leg codes a | b << 8 | c << 16 */
extern const real_t npc_np_legs[NPC_N_STATES][3];           /**< 1 for a leg at O (its phase current
                                                                 flows from the neutral point), else 0 */
extern const uint32_t npc_pn_step_mask[NPC_N_STATES];       /**< bit `to` set: from -> to steps a leg P<->N */
extern const uint8_t npc_changes[NPC_N_STATES][NPC_N_STATES];    /**< leg commutations from -> to */
extern const uint8_t npc_pn_safe_to[NPC_N_STATES][NPC_N_STATES]; /**< to with P<->N legs held at O */
extern const uint8_t npc_state_sv_of[NPC_N_STATES];         /**< space vector of each state */
extern const uint8_t npc_sv_state_list[NPC_N_VECTORS][3];   /**< states of each sv, preferred first
                                                                 (OOO; the P-type small one); 0xFF pads */
extern const uint8_t npc_sv_class_of[NPC_N_VECTORS];        /**< npc_class of each sv */

/** npc_legs for @p state 0..26 (unchecked). */
static inline void npc_legs_unchecked(uint8_t state, hal_vector *v) { *v = npc_state_legs[state]; }

/** Leg codes of @p state (0..26; others: OOO) into @p v. */
static inline void npc_legs(uint8_t state, hal_vector *v)
{
    npc_legs_unchecked(state < NPC_N_STATES ? state : NPC_STATE_OOO, v);
}

/** vector[0] and vector[1] of @p a: the leg codes of @p st0 and @p st1 (both
 *  0..26, unchecked), written as one word and one half-word from
 *  npc_state_legs_packed (the same six bytes as npc_legs_unchecked for each;
 *  the actuation is written every tick). @p a->duty0 is left as it is. */
static inline void npc_legs_pair_unchecked(uint8_t st0, uint8_t st1, hal_actuation *a)
{
    uint32_t w0 = npc_state_legs_packed[st0], w1 = npc_state_legs_packed[st1];
    uint32_t lo = w0 | w1 << 24;
    uint16_t hi = (uint16_t)(w1 >> 8);
    unsigned char *legs = (unsigned char *)a->vector;
    memcpy(legs, &lo, sizeof lo);
    memcpy(legs + sizeof lo, &hi, sizeof hi);
}

/** State number of @p v; 0xFF when a leg code is above NPC_P. */
static inline uint8_t npc_state_of(const hal_vector *v)
{
    if (v->leg[0] > NPC_P || v->leg[1] > NPC_P || v->leg[2] > NPC_P)
        return 0xFFu;
    return (uint8_t)(v->leg[0] * 9u + v->leg[1] * 3u + v->leg[2]);
}

/** npc_state_sv for @p state 0..26 (unchecked). */
static inline uint8_t npc_state_sv_unchecked(uint8_t state) { return npc_state_sv_of[state]; }

/** Space vector 0..18 of @p state (others: 0). */
static inline uint8_t npc_state_sv(uint8_t state) { return state < NPC_N_STATES ? npc_state_sv_unchecked(state) : 0u; }

/** npc_sv_class for @p sv 0..18 (unchecked): one load where npc_sv_class compares. */
static inline npc_class npc_sv_class_unchecked(uint8_t sv) { return (npc_class)npc_sv_class_of[sv]; }

/** Class of space vector @p sv (others: NPC_CLASS_ZERO). */
static inline npc_class npc_sv_class(uint8_t sv)
{
    if (sv == 0u || sv >= NPC_N_VECTORS)
        return NPC_CLASS_ZERO;
    if (sv <= 6u)
        return NPC_CLASS_SMALL;
    return sv <= 12u ? NPC_CLASS_MEDIUM : NPC_CLASS_LARGE;
}

/** States realising @p sv (others: the zero vector), preferred first (OOO;
 *  P-type small); returns the count 1..3. */
static inline uint8_t npc_sv_states(uint8_t sv, uint8_t states[3])
{
    const uint8_t *l = npc_sv_state_list[sv < NPC_N_VECTORS ? sv : 0u];
    states[0] = l[0];
    states[1] = l[1];
    states[2] = l[2];
    return (uint8_t)(sv == 0u || sv >= NPC_N_VECTORS ? 3u : (sv <= 6u ? 2u : 1u));
}

/* --------------------------------------------------------------- voltages */

/** npc_state_voltage for @p state 0..26 (unchecked). */
static inline void npc_state_voltage_unchecked(uint8_t state, real_t vc1_V, real_t vc2_V, real_t v_ab[2])
{
    const hal_vector *l = &npc_state_legs[state];
    real_t vn = -vc2_V; /* leg voltage by leg code N, O, P: -vc2, 0, vc1 */
    real_t va = l->leg[0] == NPC_P ? vc1_V : (l->leg[0] == NPC_N ? vn : R(0.0));
    real_t vb = l->leg[1] == NPC_P ? vc1_V : (l->leg[1] == NPC_N ? vn : R(0.0));
    real_t vc = l->leg[2] == NPC_P ? vc1_V : (l->leg[2] == NPC_N ? vn : R(0.0));
    /* Clarke of the leg voltages: the common mode drops out, as in an isolated star. */
    v_ab[0] = num_mul(R(0.333333333), R(2.0) * va - vb - vc);
    v_ab[1] = num_mul(NUM_INV_SQRT3, vb - vc);
}

/**
 * Stator voltage (alpha, beta; isolated star) of @p state (others: OOO) for
 * the capacitor voltages @p vc1_V (P to O) and @p vc2_V (O to N), V.
 */
static inline void npc_state_voltage(uint8_t state, real_t vc1_V, real_t vc2_V, real_t v_ab[2])
{
    npc_state_voltage_unchecked(state < NPC_N_STATES ? state : NPC_STATE_OOO, vc1_V, vc2_V, v_ab);
}

/**
 * Stator voltage (alpha, beta), V, of the leg codes @p l (each 0..2,
 * unchecked) with @p leg_V the leg voltage by leg code {-vc2, 0, vc1}: the
 * same values as npc_state_voltage, for a caller that has several states to
 * work out at the same capacitor voltages.
 */
static inline void npc_legs_voltage(const hal_vector *l, const real_t leg_V[3], real_t v_ab[2])
{
    real_t va = leg_V[l->leg[0]], vb = leg_V[l->leg[1]], vc = leg_V[l->leg[2]];
    v_ab[0] = num_mul(R(0.333333333), R(2.0) * va - vb - vc);
    v_ab[1] = num_mul(NUM_INV_SQRT3, vb - vc);
}

/* ---------------------------------------------------------- neutral point */

/** npc_np_current for @p state 0..26 (unchecked). */
static inline real_t npc_np_current_unchecked(uint8_t state, const real_t i_abc[3])
{
    const real_t *k = npc_np_legs[state];
    return num_mul(k[0], i_abc[0]) + num_mul(k[1], i_abc[1]) + num_mul(k[2], i_abc[2]);
}

/** Neutral-point current drawn by @p state (others: 0) with the phase
 *  currents @p i_abc (A, into the motor): the sum of the phase currents of
 *  its legs at O, A. */
static inline real_t npc_np_current(uint8_t state, const real_t i_abc[3])
{
    return state < NPC_N_STATES ? npc_np_current_unchecked(state, i_abc) : R(0.0);
}

/* ------------------------------------------------- transitions between states */

/** npc_pn_step for @p from and @p to 0..26 (unchecked). */
static inline bool npc_pn_step_unchecked(uint8_t from, uint8_t to) { return ((npc_pn_step_mask[from] >> to) & 1u) != 0u; }

/** True when going from @p from to @p to steps some leg directly between P and N
 *  (false when either is not a state). */
static inline bool npc_pn_step(uint8_t from, uint8_t to)
{
    return from < NPC_N_STATES && to < NPC_N_STATES && npc_pn_step_unchecked(from, to);
}

/** npc_leg_changes for @p from and @p to 0..26 (unchecked). */
static inline uint8_t npc_leg_changes_unchecked(uint8_t from, uint8_t to) { return npc_changes[from][to]; }

/** Number of leg commutations from @p from to @p to (N<->O and O<->P count 1;
 *  0 when either is not a state). */
static inline uint8_t npc_leg_changes(uint8_t from, uint8_t to)
{
    return from < NPC_N_STATES && to < NPC_N_STATES ? npc_leg_changes_unchecked(from, to) : 0u;
}

/** npc_pn_safe for @p from and @p to 0..26 (unchecked). */
static inline uint8_t npc_pn_safe_unchecked(uint8_t from, uint8_t to) { return npc_pn_safe_to[from][to]; }

/** @p to with every leg that would step between P and N from @p from held at O
 *  (NPC_LEG_SAFE leg by leg; OOO when either is not a state). */
static inline uint8_t npc_pn_safe(uint8_t from, uint8_t to)
{
    return from < NPC_N_STATES && to < NPC_N_STATES ? npc_pn_safe_unchecked(from, to) : (uint8_t)NPC_STATE_OOO;
}

#ifdef __cplusplus
}
#endif

#endif /* DTC_NPC_H */
