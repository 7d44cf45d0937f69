/**
 * @file open_loop.h
 * @brief Open-loop vector sequence for the benchmark fallback (private).
 */
#ifndef SIM_OPEN_LOOP_H
#define SIM_OPEN_LOOP_H

#include <stdint.h>

#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * The actuation of period @p k at time @p t_s for a voltage rotating at
 * @p f_hz: the small vector nearest the rotating angle for 80 % of the
 * period, then the zero vector O,O,O. P-type and N-type redundant small
 * vectors alternate from period to period, so the neutral point stays
 * balanced; every leg passes through O, so there is no P<->N step.
 */
void open_loop_actuation(double t_s, double f_hz, uint64_t k, hal_actuation *act);

#ifdef __cplusplus
}
#endif

#endif /* SIM_OPEN_LOOP_H */
