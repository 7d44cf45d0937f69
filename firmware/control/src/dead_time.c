/**
 * @file dead_time.c
 * @brief Dead-time volt-seconds per leg and period (see dead_time.h).
 */
#include "dtc/dead_time.h"

#include <stdbool.h>

/*
 * One leg: @p v_V (V) plus the leg's mean voltage error over the period.
 *
 * @param from       the leg's code in the vector the last period ended on
 * @param first      its code in the first vector applied in this period
 * @param second     its code in vector[1] (used when @p split)
 * @param split      both vectors of the period are applied (0 < duty0 < 1)
 * @param late_up    the fraction of a rising edge that is late:
 *                   sat(0.5 + i_A / (2 band_A), 0, 1) (a falling edge: 1 - that)
 * @param level_V    the levels of the leg codes N, O, P, V (-vc2, 0, vc1)
 * @param dt_per_T   dead time divided by the period (0..0.05)
 * Context: ANY (pure).
 */
static real_t leg_add(uint32_t from, uint32_t first, uint32_t second, bool split, real_t late_up,
                      const real_t level_V[3], real_t dt_per_T, real_t v_V)
{
    v_V = dead_time_edge_(from, first, late_up, level_V, dt_per_T, v_V);
    if (split)
        v_V = dead_time_edge_(first, second, late_up, level_V, dt_per_T, v_V);
    return v_V;
}

/* The vector the period before @p prev's successor starts from: its last applied one. Context: ANY. */
static const hal_vector *period_from(const hal_actuation *prev)
{
    return &prev->vector[prev->duty0 < R(1.0) ? 1 : 0];
}

/* The first vector @p act applies (vector[1] when duty0 is 0). Context: ANY. */
static const hal_vector *period_first(const hal_actuation *act)
{
    return &act->vector[act->duty0 > R(0.0) ? 0 : 1];
}

/* True when @p act applies both of its vectors (0 < duty0 < 1). Context: ANY. */
static bool period_split(const hal_actuation *act)
{
    return act->duty0 > R(0.0) && act->duty0 < R(1.0);
}

/* Leg by leg (leg_add) on zeros, with the softened signs worked out here; the
 * observer's reconstruction (ctl.c apply_real_inverter) works the same edges out
 * inline with dead_time_edge_levels. */
void dead_time_leg_error(const hal_actuation *prev, const hal_actuation *act, const real_t i_A[3], real_t vc1_V,
                         real_t vc2_V, real_t dt_per_T, real_t band_A, real_t dv_V[3])
{
    real_t half_per_A = num_div(R(0.5), band_A);
    const real_t level_V[3] = {-vc2_V, R(0.0), vc1_V};
    const uint8_t *from = period_from(prev)->leg, *first = period_first(act)->leg;
    const uint8_t *second = act->vector[1].leg;
    bool split = period_split(act);
    for (int k = 0; k < 3; k++) {
        real_t late_up = num_sat(num_mac(half_per_A, i_A[k], R(0.5)), R(0.0), R(1.0));
        dv_V[k] = leg_add(from[k], first[k], second[k], split, late_up, level_V, dt_per_T, R(0.0));
    }
}
