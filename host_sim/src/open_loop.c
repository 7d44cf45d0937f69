/**
 * @file open_loop.c
 * @brief Rotating small-vector sequence (benchmark without the firmware).
 */
#include "open_loop.h"

#include <math.h>

/* Small vectors at 0, 60, ..., 300 degrees: P-type and N-type redundant pairs. */
static const uint8_t small_p[6][3] = { { 2, 1, 1 }, { 2, 2, 1 }, { 1, 2, 1 }, { 1, 2, 2 }, { 1, 1, 2 }, { 2, 1, 2 } };
static const uint8_t small_n[6][3] = { { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 1, 1 }, { 0, 0, 1 }, { 1, 0, 1 } };

void open_loop_actuation(double t_s, double f_hz, uint64_t k, hal_actuation *act)
{
    double turns = f_hz * t_s;
    double frac = turns - floor(turns);
    int sector = (int)floor(frac * 6.0 + 0.5) % 6;
    const uint8_t *v = (k & 1u) ? small_n[sector] : small_p[sector];
    for (int i = 0; i < 3; i++) {
        act->vector[0].leg[i] = v[i];
        act->vector[1].leg[i] = HAL_LEG_O;
    }
    act->duty0 = 0.8f;
}
