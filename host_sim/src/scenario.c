/**
 * @file scenario.c
 * @brief Scenario defaults and the time-profile queries the engine and the
 *        metrics use (reference, disturbance, start-up end).
 */
#include "sim/scenario.h"

#include <math.h>
#include <string.h>

void scenario_default(scenario *sc)
{
    memset(sc, 0, sizeof *sc);
    strcpy(sc->source, "<scenario>");
    plant_default_config(&sc->plant);
    sc->supply_mode = (int)sc->plant.supply;
    sc->phase_rad = sc->plant.sine.phase_rad;
    sc->seed = (double)sc->plant.sensor.seed;
    /* The sine source defaults to the motor's nameplate supply. */
    sc->plant.sine.v_ll_rms_V = 220.0;
    sc->plant.sine.f_Hz = 60.0;
    /* Scenarios get a real inverter unless they say otherwise: 2 us dead time
     * without compensation (the paper's experiment) and 1 V per device. The
     * plant's own default stays ideal for its validation tests. */
    sc->plant.inverter.dead_time_s = 2e-6;
    sc->plant.inverter.v_on_V = 1.0;
    sc->duration_s = 1.0;
    sc->period_s = 200e-6;
    sc->trace_interval_s = 1e-3;
    sc->controller = SCENARIO_CTL_RBFN;
}

/* One step of a step/ramp profile whose entries are in time order and do
 * not overlap: @return false once @p t_s is before the entry (stop). */
static bool profile_step(double *v, bool ramp, double t0, double t1, double to, double t_s)
{
    if (t_s < t0)
        return false;
    if (!ramp || t_s >= t1) {
        *v = to;
        return true;
    }
    /* Inside a ramp: linear from the value at its start. */
    *v += (to - *v) * (t_s - t0) / (t1 - t0);
    return false;
}

double scenario_ref_rpm(const scenario *sc, double t_s)
{
    double v = 0.0;
    for (int i = 0; i < sc->n_ref; i++) {
        const scenario_ref_entry *e = &sc->ref[i];
        if (!profile_step(&v, e->ramp, e->t0_s, e->t1_s, e->rpm, t_s))
            break;
    }
    return v;
}

double scenario_load_nm(const scenario *sc, double t_s)
{
    double v = 0.0;
    for (int i = 0; i < sc->n_load; i++) {
        const scenario_load_entry *e = &sc->load[i];
        if (!profile_step(&v, e->ramp, e->t_s, e->t1_s, e->nm, t_s))
            break;
    }
    return v;
}

double scenario_param_factor(const scenario *sc, scenario_event_kind kind, double t_s)
{
    double v = 1.0;
    /* Entries of one kind are in time order and do not overlap (the parser
     * checks it); other kinds are skipped. */
    for (int i = 0; i < sc->n_events; i++) {
        const scenario_event *e = &sc->events[i];
        if (e->kind != kind)
            continue;
        if (!profile_step(&v, e->ramp, e->t_s, e->t1_s, e->factor, t_s))
            break;
    }
    return v;
}

bool scenario_disturbance(const scenario *sc, double *t_s)
{
    if (sc->has_disturbance) {
        *t_s = sc->disturbance_t_s;
        return true;
    }
    bool found = false;
    double t = 0.0;
    for (int i = 0; i < sc->n_load; i++)
        if (sc->load[i].t_s > 0.0 && (!found || sc->load[i].t_s < t)) {
            t = sc->load[i].t_s;
            found = true;
        }
    for (int i = 0; i < sc->n_events; i++)
        if (sc->events[i].t_s > 0.0 && (!found || sc->events[i].t_s < t)) {
            t = sc->events[i].t_s;
            found = true;
        }
    *t_s = t;
    return found;
}

double scenario_startup_end(const scenario *sc)
{
    if (sc->has_startup_end)
        return sc->startup_end_s;
    double t = 1.0;
    for (int i = 0; i < sc->n_ref; i++)
        if (sc->ref[i].ramp) {
            if (sc->ref[i].t1_s > t)
                t = sc->ref[i].t1_s;
            break;
        }
    return t;
}

bool scenario_last_ref_change(const scenario *sc, double *t_s, double *from_rpm, double *to_rpm)
{
    for (int i = sc->n_ref - 1; i >= 0; i--) {
        const scenario_ref_entry *e = &sc->ref[i];
        /* Entries are in time order and each completes before the next
         * starts, so the value before entry i is where entry i-1 ended. */
        double before = i > 0 ? sc->ref[i - 1].rpm : 0.0;
        if (before != e->rpm) {
            *t_s = e->t0_s;
            *from_rpm = before;
            *to_rpm = e->rpm;
            return true;
        }
    }
    return false;
}

static const char *const controller_names[] = { "ip", "nominal", "rbfn" };

const char *scenario_controller_name(int controller)
{
    if (controller < 0 || controller > 2)
        return NULL;
    return controller_names[controller];
}

int scenario_controller_parse(const char *name)
{
    for (int i = 0; i < 3; i++)
        if (strcmp(name, controller_names[i]) == 0)
            return i;
    return -1;
}
