/**
 * @file dead_time.c
 * @brief Dead-time volt-seconds per leg and period (see dead_time.h).
 */
#include "dtc/dead_time.h"

static real_t leg_level_V(uint8_t leg, real_t vc1_V, real_t vc2_V)
{
    return leg == HAL_LEG_P ? vc1_V : (leg == HAL_LEG_N ? -vc2_V : R(0.0));
}

void dead_time_leg_error(const hal_actuation *prev, const hal_actuation *act, const real_t i_A[3], real_t vc1_V,
                         real_t vc2_V, real_t dt_per_T, real_t band_A, real_t dv_V[3])
{
    const hal_vector *seq[3];
    int n = 0;
    seq[n++] = prev->duty0 < R(1.0) ? &prev->vector[1] : &prev->vector[0];
    if (act->duty0 > R(0.0))
        seq[n++] = &act->vector[0];
    if (act->duty0 < R(1.0))
        seq[n++] = &act->vector[1];
    real_t half_per_A = num_div(R(0.5), band_A);
    for (int leg = 0; leg < 3; leg++) {
        dv_V[leg] = R(0.0);
        for (int e = 1; e < n; e++) {
            uint8_t la = seq[e - 1]->leg[leg], lb = seq[e]->leg[leg];
            if (la == lb)
                continue;
            real_t step_V = leg_level_V(lb, vc1_V, vc2_V) - leg_level_V(la, vc1_V, vc2_V);
            real_t toward_A = lb > la ? i_A[leg] : -i_A[leg];
            real_t late = num_sat(R(0.5) + num_mul(half_per_A, toward_A), R(0.0), R(1.0));
            dv_V[leg] -= num_mul(num_mul(dt_per_T, late), step_V);
        }
    }
}
