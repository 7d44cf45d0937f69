/**
 * @file inverter_model.h
 * @brief The stator voltage the NPC inverter applies over one control
 *        period, for the observer and the loss-of-control monitor: the
 *        commanded leg levels mixed by the duty, and with a real inverter the
 *        devices' on-state drops and the dead time's late edges.
 *
 * Ideal inverter: the period's two states' voltages (dtc/npc.h) mixed by the
 * duty of the first.
 *
 * Real inverter, leg by leg, then one Clarke transform:
 *  - the commanded level, the duty's mix of the two states' levels;
 *  - the on-state drop of the two conducting devices, against the phase
 *    current: 2 v_drop_V x sat(i / INVERTER_DROP_BAND_A, -1, 1), a sign
 *    softened over +-INVERTER_DROP_BAND_A so that a current at zero does not
 *    toggle it. Written 4 v_drop_V x late_up - 2 v_drop_V with late_up =
 *    sat(0.5 + i / (2 INVERTER_DROP_BAND_A), 0, 1); the constant 2 v_drop_V,
 *    common to the three legs, drops out of the stator voltage;
 *  - the dead time: at a commutation between adjacent levels a -> b the
 *    incoming device turns on dead_time_s after the outgoing one turns off,
 *    and meanwhile the current picks the level through the diodes (into the
 *    motor the lower of a and b, out of it the upper one). The edge is late
 *    when the current flows the way of the step, on time otherwise, with the
 *    same softened sign late_up; a late edge costs (v_b - v_a) dead_time_s.
 *    The period's edges: from the state the period before ended on to the
 *    first state this period applies, then between its two states when it
 *    applies both (0 < duty0 < 1).
 * tests/unit/test_ctl_inverter_model.cpp holds this to a per-leg reference
 * (tests/oracles/dead_time_leg_error.c) and the drop's formula in double.
 *
 * Every function is pure; Context: ANY (the control step calls them in the ISR).
 */
#ifndef DTC_INVERTER_MODEL_H
#define DTC_INVERTER_MODEL_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/num.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Current over which the sign of the drops and of the dead time's edges is softened, A. */
#define INVERTER_DROP_BAND_A R(0.5)

/** One period as the inverter applies it: the actuation latched for it, with its states. */
typedef struct {
    hal_actuation act;  /**< the two vectors' leg codes and the first one's duty, 0..1 */
    uint8_t state[2];   /**< act's two vectors as state numbers 0..26 (their leg codes are act's) */
    uint8_t end_state;  /**< the state 0..26 the period before ended on: this period's first edges start there */
} inverter_period;

/** The inverter's constants, derived from its configuration (ctl_cfg_derive). */
typedef struct {
    real_t dead_time_per_T; /**< the dead time per control period, 0..0.5 (0: no dead time) */
    bool real;              /**< true: levels, drops and edges leg by leg (a drop or a dead time);
                                 false: the ideal inverter's voltage */
    real_t drop4_V;         /**< -4 x the on-state drop of one device, V (0: no drop) */
} inverter_consts;

/**
 * The state a period applying @p st0 for @p duty0 of it, then @p st1, ends on:
 * @p st1 unless @p duty0 is 1 (@p st0 alone; a NaN duty counts as 1, as
 * everywhere the duty is tested against 1).
 */
static inline uint8_t inverter_period_end_state(uint8_t st0, uint8_t st1, real_t duty0)
{
    return duty0 < R(1.0) ? st1 : st0;
}

/**
 * One dead-time edge of a leg between the levels @p from_V -> @p to_V (V):
 * @p v_V (V) less the late part of the step, (to_V - from_V) dt_per_T x the
 * late fraction (@p late_up, 0..1, when @p rising, 1 - late_up otherwise).
 */
static inline real_t inverter_dead_time_edge(bool rising, real_t late_up, real_t from_V, real_t to_V, real_t dt_per_T,
                                             real_t v_V)
{
    real_t late = rising ? late_up : R(1.0) - late_up;
    return num_mac(-num_mul(dt_per_T, late), to_V - from_V, v_V);
}

/**
 * The stator voltage (alpha, beta; isolated star) of the period @p p, V.
 * @param p       the period: its actuation, states (0..26, unchecked: the
 *                control step's own) and the state the one before ended on
 * @param level_V the leg voltage by leg code N, O, P over the period, V
 *                (-vc2, 0, vc1: the capacitors' mean voltages)
 * @param i_A     phase currents a, b, c into the motor over the period, A (finite)
 * @param k       the inverter's constants
 * @param v_ab    out: the stator voltage, V
 * @return the state the period ends on (inverter_period_end_state): the
 *         next period's first edges start there.
 */
uint8_t inverter_voltage(const inverter_period *p, const real_t level_V[3], const real_t i_A[3],
                         const inverter_consts *k, real_t v_ab[2]);

#ifdef __cplusplus
}
#endif

#endif /* DTC_INVERTER_MODEL_H */
