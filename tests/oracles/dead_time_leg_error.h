/**
 * @file dead_time_leg_error.h
 * @brief Test oracle: the volt-seconds the power stage's dead time takes from
 *        each leg in one control period, leg by leg as the edges happen.
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
 * The firmware works the same edges out inline on packed leg codes
 * (dtc/inverter_model.h); this plain per-leg version is the reference the unit
 * tests hold it to (tests/unit/test_ctl_inverter_model.cpp), itself checked
 * against cases worked out by hand (tests/unit/test_dead_time.cpp). Test
 * support only: not linked into any image.
 */
#ifndef DTC_ORACLES_DEAD_TIME_LEG_ERROR_H
#define DTC_ORACLES_DEAD_TIME_LEG_ERROR_H

#include <stdint.h>

#include "dtc/num.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * One edge a -> b (leg codes 0..2) of a leg: @p v_V (V) less the late part of
 * the step, (level_V[b] - level_V[a]) dt_per_T x the late fraction
 * (@p late_up when b > a, 1 - late_up otherwise); @p v_V itself when a == b.
 * @p level_V the levels of the leg codes N, O, P, V (-vc2, 0, vc1).
 */
real_t dead_time_edge(uint32_t a, uint32_t b, real_t late_up, const real_t level_V[3], real_t dt_per_T, real_t v_V);

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

#ifdef __cplusplus
}
#endif

#endif /* DTC_ORACLES_DEAD_TIME_LEG_ERROR_H */
