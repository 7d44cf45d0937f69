/**
 * @file npc_plan.h
 * @brief Pure planning of one NPC leg's HRTIM programme for one PWM period:
 *        which set/reset events each complementary pair gets, and when.
 *
 * Kept free of registers so the host tests (tests/hal_stm32g4) can check it
 * exhaustively: no S1+S4 / no direct P<->N step, keep-out of the sampling
 * window, minimum pulse. Private to hal/stm32g4 and its tests.
 *
 * Per leg two HRTIM timers drive complementary pairs: pair 0 = S3 (output 1)
 * / S1 (output 2), pair 1 = S2 (output 1) / S4 (output 2): output 1 is the
 * inner switch of both, so the fault line's delayed external event can reset
 * it in hardware (docs/board.md, "Fault"). Output 1 of a pair is set/reset by
 * two compare events: NPC_EV_START (CMP2, a few counts
 * after the period roll-over) gives the level of the first vector, NPC_EV_T
 * (CMP1 = t) the change to the second one.
 */
#ifndef HAL_STM32G4_NPC_PLAN_H
#define HAL_STM32G4_NPC_PLAN_H

#include <stdbool.h>
#include <stdint.h>

/** Event bits, equal to the HRTIM SETx1R/RSTx1R bits CMP2 and CMP1. */
#define NPC_EV_START (1u << 4)
#define NPC_EV_T (1u << 3)

/** Leg states (equal to hal_leg_state). */
#define NPC_N 0u
#define NPC_O 1u
#define NPC_P 2u

/** Timing of one PWM period, in timer counts. */
typedef struct {
    uint32_t per;       /**< period, counts (> keepout + min_pulse) */
    uint32_t keepout;   /**< no switching instant in [start event, keepout): sampling window */
    uint32_t min_pulse; /**< shortest second-vector pulse at the period end */
} npc_timing;

/** The programme of one leg for one period. */
typedef struct {
    uint32_t set[2];    /**< SETx1R event bits of pair 0 (S3/S1) and pair 1 (S2/S4) */
    uint32_t rst[2];    /**< RSTx1R event bits */
    uint32_t t;         /**< switching instant, counts; 0: second vector only, per: first only */
    uint8_t v0, v1;     /**< the leg states actually applied (after the P<->N guard) */
    uint8_t end;        /**< leg state at the end of the period */
    uint8_t fixups;     /**< number of P<->N steps replaced by O (0..2) */
} npc_leg_plan;

/**
 * Plan one leg. @p prev is the leg state at the end of the previous period,
 * @p v0 / @p v1 the requested states (each <= NPC_P), @p t0 the requested
 * switching instant in counts (0..per). Context: ANY (pure function).
 */
void npc_plan_leg(const npc_timing *tm, uint8_t prev, uint8_t v0, uint8_t v1, uint32_t t0, npc_leg_plan *out);

/** @return output-1 level of pair @p pair (0: S3 of S3/S1, 1: S2 of S2/S4) for leg state @p leg. */
bool npc_pair_level(unsigned pair, uint8_t leg);

#endif /* HAL_STM32G4_NPC_PLAN_H */
