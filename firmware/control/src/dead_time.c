/**
 * @file dead_time.c
 * @brief Dead-time volt-seconds per leg and period (see dead_time.h).
 */
#include "dtc/dead_time.h"

/* The per-leg core (dead_time_leg_add) on zeros, with the softened signs
 * worked out here; the observer's reconstruction (ctl.c) calls the core
 * itself. */
void dead_time_leg_error(const hal_actuation *prev, const hal_actuation *act, const real_t i_A[3], real_t vc1_V,
                         real_t vc2_V, real_t dt_per_T, real_t band_A, real_t dv_V[3])
{
    real_t half_per_A = num_div(R(0.5), band_A);
    const real_t level_V[3] = {-vc2_V, R(0.0), vc1_V};
    const uint8_t *from = dead_time_from(prev)->leg, *first = dead_time_first(act)->leg;
    const uint8_t *second = act->vector[1].leg;
    bool split = dead_time_split(act);
    for (int k = 0; k < 3; k++) {
        real_t late_up = num_sat(num_mac(half_per_A, i_A[k], R(0.5)), R(0.0), R(1.0));
        dv_V[k] = dead_time_leg_add(from[k], first[k], second[k], split, late_up, level_V, dt_per_T, R(0.0));
    }
}
