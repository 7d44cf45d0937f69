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
 * Context: any (a pure function). ctl_step works the edges out inline, leg by
 * leg (ctl.c apply_real_inverter); tests/oracles/dead_time_leg_error.c is the
 * reference the unit tests hold it to.
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

#ifdef __cplusplus
}
#endif

#endif
