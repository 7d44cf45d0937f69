/**
 * @file npc_plan.c
 * @brief One NPC leg's HRTIM programme per period (see npc_plan.h).
 */
#include "npc_plan.h"

#include "npc_plan_rules.h"

/* The rules (npc_plan_rules.h) as ready register words (npc_leg_words), written
 * out by the preprocessor. */
#define WORDS_C(c, p, a, b)                                                                           \
    {NPC_RULE_SET(0u, c, p, a, b), NPC_RULE_RST(0u, c, p, a, b) | NPC_RST_FAULT_EVENT,                \
     NPC_RULE_SET(1u, c, p, a, b), NPC_RULE_RST(1u, c, p, a, b) | NPC_RST_FAULT_EVENT}
/* a leg with one state (kind 0) leaves its timers holding that state's words: NPC_LEG_HELD on its end */
#define ONE_STATE(p, a, b) (NPC_RULE_V0(p, a) == NPC_RULE_V1(p, a, b))
#define END(c, p, a, b) \
    (uint8_t)(((c) == NPC_AT_PER ? NPC_RULE_V0(p, a) : NPC_RULE_V1(p, a, b)) | (ONE_STATE(p, a, b) ? NPC_LEG_HELD : 0u))
/* one state: always the first only; prev -> v1 no P<->N step: may drop v0; else keeps it;
 * h: the timers hold prev's one-state words, and the leg stays in prev: nothing to write */
#define KIND(h, p, a, b)                                                       \
    (uint8_t)((h) && (a) == (p) && (b) == (p)                                  \
                  ? NPC_HELD_SHIFT                                             \
                  : (ONE_STATE(p, a, b) ? 0u : (NPC_LEG_PN(p, NPC_RULE_V1(p, a, b)) ? 16u : 8u)))
/* not held: written; two states: timed; a P<->N step replaced: fixups */
#define FLAGS(h, p, a, b)                                                  \
    (uint8_t)((KIND(h, p, a, b) == NPC_HELD_SHIFT ? 0u : NPC_FLAG_WRITE) | \
              (ONE_STATE(p, a, b) ? 0u : NPC_FLAG_TIMED) |                 \
              (NPC_RULE_FIXUPS(p, a, b) != 0u ? NPC_FLAG_FIXUPS : 0u))
#define WORDS(h, p, a, b)                                                                       \
    {{WORDS_C(NPC_AT_ZERO, p, a, b), WORDS_C(NPC_AT_T, p, a, b), WORDS_C(NPC_AT_PER, p, a, b)}, \
     {END(NPC_AT_ZERO, p, a, b), END(NPC_AT_T, p, a, b), END(NPC_AT_PER, p, a, b)},             \
     KIND(h, p, a, b),                                                                          \
     (uint8_t)NPC_RULE_FIXUPS(p, a, b),                                                         \
     (uint8_t)(ONE_STATE(p, a, b) ? 0u : 1u),                                                   \
     FLAGS(h, p, a, b),                                                                         \
     {0u}}
#define WORDS_AT(h, p, a, b) [16u * ((p) | ((h) ? NPC_LEG_HELD : 0u)) + 4u * (a) + (b)] = WORDS(h, p, a, b)
#define WORDS_B(h, p, a) WORDS_AT(h, p, a, 0u), WORDS_AT(h, p, a, 1u), WORDS_AT(h, p, a, 2u)
#define WORDS_A(h, p) WORDS_B(h, p, 0u), WORDS_B(h, p, 1u), WORDS_B(h, p, 2u)

_Static_assert(sizeof(npc_leg_words) == 64u, "one shift per index");
const npc_leg_words npc_leg_words_table[NPC_LEG_WORDS_ENTRIES] = {
    WORDS_A(0, 0u), WORDS_A(0, 1u), WORDS_A(0, 2u), WORDS_A(1, 0u), WORDS_A(1, 1u), WORDS_A(1, 2u)};
