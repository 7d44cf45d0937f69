/**
 * @file npc_plan_rules.h
 * @brief The planning rules of one NPC leg for one PWM period, as macros
 *        that are constant expressions, so that the tables built from them
 *        (npc_plan.c's register words, the host tests' reference planner in
 *        tests/oracles/npc_plan_leg.c) are constants and cannot disagree
 *        with them. Private to the leg planner and its tests.
 *
 * p is the leg state at the end of the previous period, a and b the requested
 * states of the two vectors (leg codes NPC_N, NPC_O, NPC_P of dtc/npc.h), k a
 * complementary pair (0: S3/S1, 1: S2/S4), c an enum npc_instant_class.
 */
#ifndef HAL_STM32G4_NPC_PLAN_RULES_H
#define HAL_STM32G4_NPC_PLAN_RULES_H

#include "npc_plan.h"

/* Never a direct P<->N step (dtc/npc.h): O inserted, prev -> v0, then v0 -> v1. */
#define NPC_RULE_V0(p, a) NPC_LEG_SAFE(p, a)
#define NPC_RULE_V1(p, a, b) NPC_LEG_SAFE(NPC_RULE_V0(p, a), b)
/* P<->N steps the two vectors' states replace by O (0..2) */
#define NPC_RULE_FIXUPS(p, a, b) ((NPC_LEG_PN(p, a) ? 1u : 0u) + (NPC_LEG_PN(NPC_RULE_V0(p, a), b) ? 1u : 0u))
/* Output 1 of pair k: S3 (k = 0) on in O and N, S2 (k = 1) on in P and O. */
#define NPC_RULE_LEVEL(k, s) ((k) == 0u ? (s) != NPC_P : (s) != NPC_N)
/* Level of pair k after the start event in instant class c (at t = 0 the second vector only). */
#define NPC_RULE_L_START(k, c, p, a, b) NPC_RULE_LEVEL(k, (c) == NPC_AT_ZERO ? NPC_RULE_V1(p, a, b) : NPC_RULE_V0(p, a))
#define NPC_RULE_L_END(k, p, a, b) NPC_RULE_LEVEL(k, NPC_RULE_V1(p, a, b))
/* Event bits of pair k: the start level on the start event, the change (only
 * for 0 < t < per and only when the level changes) on the t event. */
#define NPC_RULE_CHANGES(k, c, p, a, b) ((c) == NPC_AT_T && NPC_RULE_L_END(k, p, a, b) != NPC_RULE_L_START(k, c, p, a, b))
#define NPC_RULE_SET(k, c, p, a, b)                                 \
    (uint8_t)((NPC_RULE_L_START(k, c, p, a, b) ? NPC_EV_START : 0u) | \
              (NPC_RULE_CHANGES(k, c, p, a, b) && NPC_RULE_L_END(k, p, a, b) ? NPC_EV_T : 0u))
#define NPC_RULE_RST(k, c, p, a, b)                                 \
    (uint8_t)((NPC_RULE_L_START(k, c, p, a, b) ? 0u : NPC_EV_START) | \
              (NPC_RULE_CHANGES(k, c, p, a, b) && !NPC_RULE_L_END(k, p, a, b) ? NPC_EV_T : 0u))

#endif /* HAL_STM32G4_NPC_PLAN_RULES_H */
