/**
 * @file dead_time.h
 * @brief The volt-seconds the power stage's dead time takes from each leg in
 *        one control period, for the voltage model of the observer and the
 *        loss-of-control monitor.
 *
 * At a commutation of an NPC leg between adjacent levels a -> b the incoming
 * device turns on dead_time_s after the outgoing one turns off. Meanwhile the
 * current picks the level through the diodes: into the motor (i > 0) the lower
 * of a and b, out of it the upper one. So the edge is dead_time_s late when the
 * current flows the way of the step (sign(i) = sign(b - a)) and on time
 * otherwise: a late edge costs (v_b - v_a) dead_time_s. The edges of one period
 * are: the vector the previous period ended with -> vector[0] -> vector[1],
 * each vector counted only when it is applied for a part of the period. The
 * current's sign is softened over +-band_A (at zero current the leg floats
 * between the two levels during the blanking).
 *
 * Context: any (a pure function). ctl_step works the same edges out inline, leg by
 * leg (ctl.c apply_real_inverter); this function is the reference the unit tests
 * hold the model to.
 */
#ifndef DTC_DEAD_TIME_H
#define DTC_DEAD_TIME_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/num.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Mean voltage error of each leg over the period that applies @p act, V
 * (true leg voltage minus the commanded one; add it to the commanded voltage).
 *
 * @param prev        the actuation of the period before (its last applied vector starts this one)
 * @param act         the actuation of this period (vectors, duty0 0..1)
 * @param i_A         phase currents a, b, c into the motor, A
 * @param vc1_V       upper capacitor voltage, V (>= 0)
 * @param vc2_V       lower capacitor voltage, V (>= 0)
 * @param dt_per_T    dead time divided by the period (0..0.05); 0 gives zeros
 * @param band_A      current over which the sign is softened, A (> 0)
 * @param dv_V        out: per-leg mean voltage error, V
 */
void dead_time_leg_error(const hal_actuation *prev, const hal_actuation *act, const real_t i_A[3], real_t vc1_V,
                         real_t vc2_V, real_t dt_per_T, real_t band_A, real_t dv_V[3]);

/**
 * One edge of a leg between the levels @p from_V -> @p to_V (V): @p v_V (V) less
 * the late part of the step, (to_V - from_V) dt_per_T x the late fraction
 * (@p late_up when @p rising, 1 - late_up otherwise). For a caller that has the
 * levels read already (ctl.c). Context: ANY (pure).
 */
static inline real_t dead_time_edge_levels(bool rising, real_t late_up, real_t from_V, real_t to_V, real_t dt_per_T,
                                           real_t v_V)
{
    real_t late = rising ? late_up : R(1.0) - late_up;
    return num_mac(-num_mul(dt_per_T, late), to_V - from_V, v_V);
}

/** One edge a -> b (leg codes 0..2, a != b) of a leg, on the codes' levels
 *  @p level_V (V): dead_time_edge_levels. Context: ANY (pure). */
static inline real_t dead_time_edge_moving(uint32_t a, uint32_t b, real_t late_up, const real_t level_V[3],
                                           real_t dt_per_T, real_t v_V)
{
    return dead_time_edge_levels(b > a, late_up, level_V[a], level_V[b], dt_per_T, v_V);
}

/* One edge a -> b of a leg: subtracts the late part of the step from @p v_V. */
static inline real_t dead_time_edge_(uint32_t a, uint32_t b, real_t late_up, const real_t level_V[3], real_t dt_per_T,
                                     real_t v_V)
{
    if (a == b)
        return v_V;
    return dead_time_edge_moving(a, b, late_up, level_V, dt_per_T, v_V);
}

#ifdef __cplusplus
}
#endif

#endif
