/**
 * @file metrics.c
 * @brief Metric accumulators: recovery, dip, rise time, steady errors,
 *        neutral-point deviation, switching frequency, windows.
 */
#include "metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int metrics_acc_init(metrics_acc *a, const scenario *sc, double period_s)
{
    memset(a, 0, sizeof *a);
    a->period_s = period_s;
    a->has_dist = scenario_disturbance(sc, &a->t_dist);
    a->has_change = scenario_last_ref_change(sc, &a->t_change, &a->from_rpm, &a->to_rpm);
    a->startup_end_s = scenario_startup_end(sc);
    a->n_windows = sc->n_windows;
    memcpy(a->windows, sc->windows, sizeof a->windows);
    /* The ring holds the longest "last X s" window (0.5 s) plus one. */
    a->cap = (size_t)floor(0.5 / period_s + 0.5) + 1u;
    a->ring = calloc(a->cap, sizeof *a->ring);
    return a->ring != NULL ? 0 : -1;
}

void metrics_acc_free(metrics_acc *a)
{
    free(a->ring);
    a->ring = NULL;
}

/* Tick times are k * T; compare with half a tick of slack. */
static bool at_or_after(const metrics_acc *a, double t, double t_event)
{
    return t >= t_event - 0.5 * a->period_s;
}

void metrics_acc_add(metrics_acc *a, const metrics_sample *s)
{
    a->ring[(a->head + a->count) % a->cap] = *s;
    if (a->count < a->cap)
        a->count++;
    else
        a->head = (a->head + 1u) % a->cap;
    a->last = *s;
    a->any = true;

    if (s->w_norm > a->w_norm_max)
        a->w_norm_max = s->w_norm;

    /* Runaway (judged in metrics_acc_finish): the largest |true speed| of
     * the run against the largest |reference| of the run. A NaN speed
     * counts as a runaway. */
    if (fabs(s->ref_rpm) > a->ref_max_abs_rpm)
        a->ref_max_abs_rpm = fabs(s->ref_rpm);
    if (fabs(s->speed_rpm) > a->speed_max_abs_rpm)
        a->speed_max_abs_rpm = fabs(s->speed_rpm);
    if (isnan(s->speed_rpm))
        a->speed_nan = true;

    if (a->has_dist && at_or_after(a, s->t_s, a->t_dist)) {
        double err = fabs(s->ref_rpm - s->speed_rpm);
        if (err > a->max_dip_rpm)
            a->max_dip_rpm = err;
        a->last_exceeding = err > 0.01 * fabs(s->ref_rpm);
        if (a->last_exceeding) {
            a->exceeded = true;
            a->last_exceed_t = s->t_s;
        }
    }

    if (a->has_change && at_or_after(a, s->t_s, a->t_change) && !a->got90) {
        double frac = (s->speed_rpm - a->from_rpm) / (a->to_rpm - a->from_rpm);
        if (!a->got10 && frac >= 0.1) {
            a->got10 = true;
            a->t10 = s->t_s;
        }
        if (a->got10 && frac >= 0.9) {
            a->got90 = true;
            a->t90 = s->t_s;
        }
    }

    if (at_or_after(a, s->t_s, a->startup_end_s)) {
        if (!a->steady) {
            a->steady = true;
            a->steady_t0 = s->t_s;
            a->steady_sw0 = s->switch_count;
        }
        if (s->np_dev_v > a->np_max)
            a->np_max = s->np_dev_v;
    }

    for (int i = 0; i < a->n_windows; i++) {
        if (at_or_after(a, s->t_s, a->windows[i].t0_s) && !at_or_after(a, s->t_s, a->windows[i].t1_s)) {
            a->win_speed[i] += s->speed_rpm;
            a->win_is_sq[i] += s->is_sq;
            a->win_n[i]++;
        }
    }
}

/* Index range of the last @p window_s seconds in the ring. */
static size_t last_n(const metrics_acc *a, double window_s)
{
    size_t n = (size_t)floor(window_s / a->period_s + 0.5);
    if (n < 1u)
        n = 1u;
    return n < a->count ? n : a->count;
}

static const metrics_sample *ring_at(const metrics_acc *a, size_t from_end, size_t n)
{
    /* from_end in 0..n-1 over the last n samples, oldest first. */
    size_t idx = a->head + (a->count - n) + from_end;
    return &a->ring[idx % a->cap];
}

void metrics_acc_finish(const metrics_acc *a, sim_metrics *out)
{
    if (!a->any)
        return;
    const double rad_per_rpm = 2.0 * 3.14159265358979323846 / 60.0;
    double t_end = a->last.t_s;

    size_t n = last_n(a, 0.1);
    double spd = 0.0, te = 0.0, is_sq = 0.0;
    for (size_t i = 0; i < n; i++) {
        const metrics_sample *s = ring_at(a, i, n);
        spd += s->speed_rpm;
        te += s->te_nm;
        is_sq += s->is_sq;
    }
    out->speed_final_rpm = spd / (double)n;
    out->speed_final_rad_s = out->speed_final_rpm * rad_per_rpm;
    out->te_final_nm = te / (double)n;
    out->is_rms_final_a = sqrt(is_sq / (3.0 * (double)n));
    out->speed_true_end_rpm = a->last.speed_rpm;
    out->speed_true_max_abs_rpm = a->speed_max_abs_rpm;
    out->runaway_limit_rpm = METRICS_RUNAWAY_FACTOR * a->ref_max_abs_rpm + METRICS_RUNAWAY_MARGIN_RPM;
    out->runaway = a->speed_nan || a->speed_max_abs_rpm > out->runaway_limit_rpm;

    n = last_n(a, 0.5);
    double e_ref = 0.0, e_est = 0.0, eh = 0.0, et = 0.0;
    for (size_t i = 0; i < n; i++) {
        const metrics_sample *s = ring_at(a, i, n);
        e_ref += fabs(s->ref_rpm - s->speed_rpm);
        e_est += fabs(s->est_rpm - s->speed_rpm);
        eh += s->eps_hat;
        et += s->eps_true;
    }
    out->steady_error_rpm = e_ref / (double)n;
    out->speed_est_error_rpm = e_est / (double)n;
    out->eps_hat_final = eh / (double)n;
    out->eps_true = et / (double)n;

    out->has_disturbance = a->has_dist && t_end >= a->t_dist;
    out->disturbance_t_s = a->t_dist;
    if (out->has_disturbance) {
        out->recovery_time_s = a->exceeded ? a->last_exceed_t - a->t_dist : 0.0;
        if (out->recovery_time_s < 0.0)
            out->recovery_time_s = 0.0;
        out->recovered = !a->last_exceeding;
        out->max_dip_rpm = a->max_dip_rpm;
    }

    out->has_rise = a->got90;
    out->rise_time_s = a->got90 ? a->t90 - a->t10 : 0.0;

    out->startup_end_s = a->startup_end_s;
    out->has_steady_window = a->steady && t_end > a->steady_t0;
    if (out->has_steady_window) {
        out->np_dev_max_v = a->np_max;
        /* Leg transitions per leg per second; a device pair commutes once per
         * transition, and a device switches on and off once per period: / 2. */
        out->switching_freq_hz =
            (double)(a->last.switch_count - a->steady_sw0) / (3.0 * (t_end - a->steady_t0)) / 2.0;
    }
    out->w_norm_max = a->w_norm_max;

    out->n_windows = a->n_windows;
    for (int i = 0; i < a->n_windows; i++) {
        sim_window_result *w = &out->windows[i];
        memcpy(w->name, a->windows[i].name, sizeof w->name);
        w->valid = a->win_n[i] > 0;
        if (w->valid) {
            w->speed_rpm = a->win_speed[i] / (double)a->win_n[i];
            w->is_rms_a = sqrt(a->win_is_sq[i] / (3.0 * (double)a->win_n[i]));
        }
    }
}
