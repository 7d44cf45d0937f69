/**
 * @file npc_plan.c
 * @brief One NPC leg's HRTIM programme per period (see npc_plan.h).
 */
#include "npc_plan.h"

/* The rules, written out by the preprocessor from the planning rules below so
 * that the table is a constant (flash) and cannot disagree with them.
 * a, b are leg states 0..2 (N, O, P). */

/* a -> b is a direct P<->N step (dtc/npc.h) */
#define PN(a, b) NPC_LEG_PN(a, b)
/* Never a direct P<->N step: insert O (prev -> v0, then v0 -> v1). */
#define V0(p, a) NPC_LEG_SAFE(p, a)
#define V1(p, a, b) NPC_LEG_SAFE(V0(p, a), b)
/* Output 1 of pair k: S3 (k = 0) on in O and N, S2 (k = 1) on in P and O. */
#define LVL(k, s) ((k) == 0u ? (s) != NPC_P : (s) != NPC_N)
/* Level of pair k after the start event in instant class c (at t = 0 the second vector only). */
#define L_START(k, c, p, a, b) LVL(k, (c) == NPC_AT_ZERO ? V1(p, a, b) : V0(p, a))
#define L_END(k, p, a, b) LVL(k, V1(p, a, b))
/* Event bits of pair k: the start level on the start event, the change (only
 * for 0 < t < per and only when the level changes) on the t event. */
#define CHG(k, c, p, a, b) ((c) == NPC_AT_T && L_END(k, p, a, b) != L_START(k, c, p, a, b))
#define SET(k, c, p, a, b) \
    (uint8_t)((L_START(k, c, p, a, b) ? NPC_EV_START : 0u) | (CHG(k, c, p, a, b) && L_END(k, p, a, b) ? NPC_EV_T : 0u))
#define RST(k, c, p, a, b) \
    (uint8_t)((L_START(k, c, p, a, b) ? 0u : NPC_EV_START) | (CHG(k, c, p, a, b) && !L_END(k, p, a, b) ? NPC_EV_T : 0u))
#define EV(F, p, a, b)                                          \
    {{F(0u, NPC_AT_ZERO, p, a, b), F(1u, NPC_AT_ZERO, p, a, b)}, \
     {F(0u, NPC_AT_T, p, a, b), F(1u, NPC_AT_T, p, a, b)},       \
     {F(0u, NPC_AT_PER, p, a, b), F(1u, NPC_AT_PER, p, a, b)}}
#define RULE(p, a, b)                                                                                  \
    {(uint8_t)V0(p, a), (uint8_t)V1(p, a, b), (uint8_t)((PN(p, a) ? 1u : 0u) + (PN(V0(p, a), b) ? 1u : 0u)), \
     (uint8_t)(PN(p, V1(p, a, b)) ? 0u : 1u), EV(SET, p, a, b), EV(RST, p, a, b)}
#define RULES_B(p, a) RULE(p, a, 0u), RULE(p, a, 1u), RULE(p, a, 2u)
#define RULES_A(p) RULES_B(p, 0u), RULES_B(p, 1u), RULES_B(p, 2u)

const npc_leg_rule npc_leg_rules[27] = {RULES_A(0u), RULES_A(1u), RULES_A(2u)};

/* The same rules as ready register words (npc_leg_words). */
#define WORDS_C(c, p, a, b)                                                                    \
    {SET(0u, c, p, a, b), RST(0u, c, p, a, b) | NPC_RST_FAULT_EVENT, SET(1u, c, p, a, b), \
     RST(1u, c, p, a, b) | NPC_RST_FAULT_EVENT}
/* a leg with one state (kind 0) leaves its timers holding that state's words: NPC_LEG_HELD on its end */
#define ONE_STATE(p, a, b) (V0(p, a) == V1(p, a, b))
#define END(c, p, a, b) \
    (uint8_t)(((c) == NPC_AT_PER ? V0(p, a) : V1(p, a, b)) | (ONE_STATE(p, a, b) ? NPC_LEG_HELD : 0u))
/* one state: always the first only; prev -> v1 no P<->N step: may drop v0; else keeps it;
 * h: the timers hold prev's one-state words, and the leg stays in prev: nothing to write */
#define KIND(h, p, a, b) \
    (uint8_t)((h) && (a) == (p) && (b) == (p) ? NPC_HELD_SHIFT : (ONE_STATE(p, a, b) ? 0u : (PN(p, V1(p, a, b)) ? 16u : 8u)))
/* not held: written; two states: timed; a P<->N step replaced: fixups */
#define FLAGS(h, p, a, b)                                                                   \
    (uint8_t)((KIND(h, p, a, b) == NPC_HELD_SHIFT ? 0u : NPC_FLAG_WRITE) |                  \
              (ONE_STATE(p, a, b) ? 0u : NPC_FLAG_TIMED) |                                  \
              (PN(p, a) || PN(V0(p, a), b) ? NPC_FLAG_FIXUPS : 0u))
#define WORDS(h, p, a, b)                                                                                       \
    {{WORDS_C(NPC_AT_ZERO, p, a, b), WORDS_C(NPC_AT_T, p, a, b), WORDS_C(NPC_AT_PER, p, a, b)},                 \
     {END(NPC_AT_ZERO, p, a, b), END(NPC_AT_T, p, a, b), END(NPC_AT_PER, p, a, b)},                             \
     KIND(h, p, a, b),                                                                                          \
     (uint8_t)((PN(p, a) ? 1u : 0u) + (PN(V0(p, a), b) ? 1u : 0u)),                                            \
     (uint8_t)(ONE_STATE(p, a, b) ? 0u : 1u),                                                                   \
     FLAGS(h, p, a, b),                                                                                         \
     {0u}}
#define WORDS_AT(h, p, a, b) [16u * ((p) | ((h) ? NPC_LEG_HELD : 0u)) + 4u * (a) + (b)] = WORDS(h, p, a, b)
#define WORDS_B(h, p, a) WORDS_AT(h, p, a, 0u), WORDS_AT(h, p, a, 1u), WORDS_AT(h, p, a, 2u)
#define WORDS_A(h, p) WORDS_B(h, p, 0u), WORDS_B(h, p, 1u), WORDS_B(h, p, 2u)

_Static_assert(sizeof(npc_leg_words) == 64u, "one shift per index");
const npc_leg_words npc_leg_words_table[NPC_LEG_WORDS_ENTRIES] = {
    WORDS_A(0, 0u), WORDS_A(0, 1u), WORDS_A(0, 2u), WORDS_A(1, 0u), WORDS_A(1, 1u), WORDS_A(1, 2u)};

bool npc_pair_level(unsigned pair, uint8_t leg) { return LVL(pair, leg); }

void npc_plan_leg(const npc_timing *tm, uint8_t prev, uint8_t v0, uint8_t v1, uint32_t t0, npc_leg_plan *out)
{
    npc_instants in;
    npc_instants_of(tm, t0, &in);
    npc_plan_leg_at(tm, &in, prev, v0, v1, out);
}
