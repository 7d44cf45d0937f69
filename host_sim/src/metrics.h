/**
 * @file metrics.h
 * @brief Metric accumulators of the engine (private). Online where the
 *        window is known in advance; a ring of the last 0.5 s for the
 *        "final" means, so runs of unknown length (realtime) work too.
 */
#ifndef SIM_METRICS_H
#define SIM_METRICS_H

#include <stdbool.h>
#include <stddef.h>

#include "sim/scenario.h"
#include "sim/sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Runaway: |true speed| > FACTOR x the largest |reference| of the run + MARGIN at any tick. */
#define METRICS_RUNAWAY_FACTOR 1.5
#define METRICS_RUNAWAY_MARGIN_RPM 300.0

/** What the engine records at every tick (true plant values unless noted). */
typedef struct {
    double t_s;
    double speed_rpm;      /**< true mechanical speed */
    double ref_rpm;        /**< scenario reference */
    double est_rpm;        /**< telemetry estimate (firmware runs only) */
    double te_nm;          /**< true torque */
    double is_sq;          /**< ia^2 + ib^2 + ic^2, A^2 */
    double eps_hat;        /**< telemetry eps_hat */
    double eps_true;       /**< eq. 5 uncertainty from the plant's parameters */
    double np_dev_v;       /**< |vc1 - vc2| true */
    double w_norm;         /**< telemetry |W| */
    unsigned long switch_count; /**< plant switch counter at this tick */
} metrics_sample;

typedef struct {
    double period_s;
    bool has_dist;
    double t_dist;
    bool has_change;
    double t_change, from_rpm, to_rpm;
    double startup_end_s;
    int n_windows;
    scenario_window windows[SCENARIO_MAX_WINDOWS];

    metrics_sample *ring;
    size_t cap, head, count;

    /* disturbance recovery */
    bool exceeded;
    double last_exceed_t;
    double max_dip_rpm;
    bool last_exceeding;
    /* rise time */
    bool got10, got90;
    double t10, t90;
    /* steady window (after start-up) */
    bool steady;
    double steady_t0;
    unsigned long steady_sw0;
    double np_max;
    double w_norm_max;
    /* runaway: largest |true speed| and |reference| of the run */
    double speed_max_abs_rpm;
    double ref_max_abs_rpm;
    bool speed_nan;
    /* [metrics] windows */
    double win_speed[SCENARIO_MAX_WINDOWS];
    double win_is_sq[SCENARIO_MAX_WINDOWS];
    long win_n[SCENARIO_MAX_WINDOWS];

    metrics_sample last;
    bool any;
} metrics_acc;

/** Prepare for a run of @p sc at tick @p period_s. @return 0, or -1 (out of memory). */
int metrics_acc_init(metrics_acc *a, const scenario *sc, double period_s);

/** Record one tick. */
void metrics_acc_add(metrics_acc *a, const metrics_sample *s);

/** Fill the run-dependent fields of @p out (everything the samples determine). */
void metrics_acc_finish(const metrics_acc *a, sim_metrics *out);

void metrics_acc_free(metrics_acc *a);

#ifdef __cplusplus
}
#endif

#endif /* SIM_METRICS_H */
