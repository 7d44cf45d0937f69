/**
 * @file dead_time.c
 * @brief Dead-time volt-seconds per leg and period (see dead_time.h).
 */
#include "dtc/dead_time.h"

#include <stddef.h>
#include <string.h>

/* The six leg bytes of an actuation are read as one word and one half-word. */
_Static_assert(sizeof(hal_vector) == 3u && offsetof(hal_actuation, vector) == 0u, "hal_actuation: six leg bytes first");
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "dead_time_leg_error unpacks the leg codes little-endian"
#endif

static real_t leg_level_V(uint32_t leg, real_t vc1_V, real_t vc2_V)
{
    return leg == HAL_LEG_P ? vc1_V : (leg == HAL_LEG_N ? -vc2_V : R(0.0));
}

/* vector[0] and vector[1] of @p a, each as a | b << 8 | c << 16 */
static void legs_packed(const hal_actuation *a, uint32_t *v0, uint32_t *v1)
{
    uint32_t lo;
    uint16_t hi;
    memcpy(&lo, (const unsigned char *)a->vector, sizeof lo);
    memcpy(&hi, (const unsigned char *)a->vector + sizeof lo, sizeof hi);
    *v0 = lo & 0xFFFFFFu;
    *v1 = lo >> 24 | (uint32_t)hi << 8;
}

/* Edge by edge, and within an edge only the legs that commute (most periods
 * commute none or one; issue 11): their bytes differ in from ^ to, so one
 * test per leg. The sums per leg run in the edges' order. */
void dead_time_leg_error(const hal_actuation *prev, const hal_actuation *act, const real_t i_A[3], real_t vc1_V,
                         real_t vc2_V, real_t dt_per_T, real_t band_A, real_t dv_V[3])
{
    uint32_t p0, p1, a0, a1, seq[3];
    legs_packed(prev, &p0, &p1);
    legs_packed(act, &a0, &a1);
    int n = 0;
    seq[n++] = prev->duty0 < R(1.0) ? p1 : p0;
    if (act->duty0 > R(0.0))
        seq[n++] = a0;
    if (act->duty0 < R(1.0))
        seq[n++] = a1;
    dv_V[0] = R(0.0);
    dv_V[1] = R(0.0);
    dv_V[2] = R(0.0);
    real_t half_per_A = num_div(R(0.5), band_A);
    for (int e = 1; e < n; e++) {
        uint32_t from = seq[e - 1], to = seq[e];
        uint32_t moved = from ^ to;
        if (moved == 0u)
            continue;
        for (int leg = 0; leg < 3; leg++) {
            unsigned sh = 8u * (unsigned)leg;
            if (((moved >> sh) & 0xFFu) == 0u)
                continue;
            uint32_t la = (from >> sh) & 0xFFu, lb = (to >> sh) & 0xFFu;
            real_t step_V = leg_level_V(lb, vc1_V, vc2_V) - leg_level_V(la, vc1_V, vc2_V);
            real_t toward_A = lb > la ? i_A[leg] : -i_A[leg];
            real_t late = num_sat(R(0.5) + num_mul(half_per_A, toward_A), R(0.0), R(1.0));
            dv_V[leg] -= num_mul(num_mul(dt_per_T, late), step_V);
        }
    }
}
