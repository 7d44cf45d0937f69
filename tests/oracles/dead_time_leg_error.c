/**
 * @file dead_time_leg_error.c
 * @brief Test oracle: dead-time volt-seconds per leg and period (see dead_time_leg_error.h).
 */
#include "dead_time_leg_error.h"

#include <stdbool.h>

real_t dead_time_edge(uint32_t a, uint32_t b, real_t late_up, const real_t level_V[3], real_t dt_per_T, real_t v_V)
{
    if (a == b)
        return v_V;
    real_t late = b > a ? late_up : R(1.0) - late_up;
    return num_mac(-num_mul(dt_per_T, late), level_V[b] - level_V[a], v_V);
}

/* The vector the period after @p prev starts from: its last applied one. */
static const hal_vector *period_from(const hal_actuation *prev)
{
    return &prev->vector[prev->duty0 < R(1.0) ? 1 : 0];
}

/* The first vector @p act applies (vector[1] when duty0 is 0). */
static const hal_vector *period_first(const hal_actuation *act)
{
    return &act->vector[act->duty0 > R(0.0) ? 0 : 1];
}

/* True when @p act applies both of its vectors (0 < duty0 < 1). */
static bool period_split(const hal_actuation *act)
{
    return act->duty0 > R(0.0) && act->duty0 < R(1.0);
}

void dead_time_leg_error(const hal_actuation *prev, const hal_actuation *act, const real_t i_A[3], real_t vc1_V,
                         real_t vc2_V, real_t dt_per_T, real_t band_A, real_t dv_V[3])
{
    real_t half_per_A = num_div(R(0.5), band_A);
    const real_t level_V[3] = {-vc2_V, R(0.0), vc1_V};
    const uint8_t *from = period_from(prev)->leg, *first = period_first(act)->leg;
    const uint8_t *second = act->vector[1].leg;
    bool split = period_split(act);
    for (int k = 0; k < 3; k++) {
        /* the fraction of a rising edge that is late: sat(0.5 + i / (2 band), 0, 1) */
        real_t late_up = num_sat(num_mac(half_per_A, i_A[k], R(0.5)), R(0.0), R(1.0));
        real_t v = dead_time_edge(from[k], first[k], late_up, level_V, dt_per_T, R(0.0));
        if (split)
            v = dead_time_edge(first[k], second[k], late_up, level_V, dt_per_T, v);
        dv_V[k] = v;
    }
}
