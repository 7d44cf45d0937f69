/**
 * @file npc_plan_leg.h
 * @brief Test oracle: the plan of one NPC leg for one PWM period as a
 *        struct (which set/reset events each complementary pair gets, the
 *        switching instant, the states applied), from a table of the
 *        planning rules per (prev, v0, v1) and the period's instants.
 *
 * The board's actuation writes the same plan as ready register words
 * (hal/stm32g4/npc_plan.h, npc_leg_words_table, npc_program_legs); the host
 * tests (tests/hal_stm32g4/test_npc_plan.cpp) hold this planner to the rules
 * written out step by step and the register words to this planner, for every
 * triple and instant. Test support only: not linked into any image.
 */
#ifndef DTC_ORACLES_NPC_PLAN_LEG_H
#define DTC_ORACLES_NPC_PLAN_LEG_H

#include <stdbool.h>
#include <stdint.h>

#include "npc_plan.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The programme of one leg for one period. */
typedef struct {
    uint32_t set[2];    /**< SETx1R event bits of pair 0 (S3/S1) and pair 1 (S2/S4) */
    uint32_t rst[2];    /**< RSTx1R event bits */
    uint32_t t;         /**< switching instant, counts; 0: second vector only, per: first only */
    uint8_t v0, v1;     /**< the leg states actually applied (after the P<->N guard) */
    uint8_t end;        /**< leg state at the end of the period */
    uint8_t fixups;     /**< number of P<->N steps replaced by O (0..2) */
} npc_leg_plan;

/** The leg-state part of a plan for one (prev, v0, v1): constants. */
typedef struct {
    uint8_t v0, v1;       /**< the states applied after the P<->N guard (prev -> v0 -> v1 via O) */
    uint8_t fixups;       /**< P<->N steps replaced by O (0..2) */
    uint8_t may_drop;     /**< 1: prev -> v1 is no P<->N step, so a too early instant may drop v0 */
    uint8_t set[3][2];    /**< SETx1R event bits per enum npc_instant_class and pair */
    uint8_t rst[3][2];    /**< RSTx1R event bits per enum npc_instant_class and pair */
} npc_leg_rule;

/** Rules for every (prev, v0, v1), index 9 prev + 3 v0 + v1 (each 0..NPC_P). */
extern const npc_leg_rule npc_leg_rules[27];

/**
 * Plan one leg with the period's instants @p in (npc_instants_of). @p prev is
 * the leg state at the end of the previous period, @p v0 / @p v1 the requested
 * states (each <= NPC_P, unchecked).
 */
void npc_plan_leg_at(const npc_timing *tm, const npc_instants *in, uint8_t prev, uint8_t v0, uint8_t v1,
                     npc_leg_plan *out);

/**
 * Plan one leg. @p prev is the leg state at the end of the previous period,
 * @p v0 / @p v1 the requested states (each <= NPC_P), @p t0 the requested
 * switching instant in counts (0..per).
 */
void npc_plan_leg(const npc_timing *tm, uint8_t prev, uint8_t v0, uint8_t v1, uint32_t t0, npc_leg_plan *out);

/** @return output-1 level of pair @p pair (0: S3 of S3/S1, 1: S2 of S2/S4) for leg state @p leg. */
bool npc_pair_level(unsigned pair, uint8_t leg);

#ifdef __cplusplus
}
#endif

#endif /* DTC_ORACLES_NPC_PLAN_LEG_H */
