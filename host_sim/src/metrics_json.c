/**
 * @file metrics_json.c
 * @brief The metrics JSON file (cJSON), written via PATH.partial + rename.
 *
 * Metrics that do not apply to a run (no disturbance, no reference change,
 * no firmware) are omitted rather than written as zeros.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "sim/sim.h"

static cJSON *build(const sim_metrics *m)
{
    cJSON *o = cJSON_CreateObject();
    if (o == NULL)
        return NULL;
    cJSON_AddStringToObject(o, "controller", m->controller);
    cJSON_AddNumberToObject(o, "sim_seconds", m->sim_seconds);
    cJSON_AddNumberToObject(o, "wall_seconds", m->wall_seconds);
    cJSON_AddNumberToObject(o, "speed_final_rad_s", m->speed_final_rad_s);
    cJSON_AddNumberToObject(o, "speed_final_rpm", m->speed_final_rpm);
    cJSON_AddNumberToObject(o, "te_final_nm", m->te_final_nm);
    cJSON_AddNumberToObject(o, "is_rms_final_a", m->is_rms_final_a);
    cJSON_AddNumberToObject(o, "speed_true_end_rpm", m->speed_true_end_rpm);
    cJSON_AddNumberToObject(o, "speed_true_max_abs_rpm", m->speed_true_max_abs_rpm);
    if (m->firmware) { /* a sine or open-loop run has no reference to run away from */
        cJSON_AddNumberToObject(o, "runaway_limit_rpm", m->runaway_limit_rpm);
        cJSON_AddBoolToObject(o, "runaway", m->runaway);
    }
    if (m->has_disturbance && m->firmware) { /* no reference to recover to without the firmware */
        cJSON_AddNumberToObject(o, "disturbance_t_s", m->disturbance_t_s);
        cJSON_AddNumberToObject(o, "recovery_time_s", m->recovery_time_s);
        cJSON_AddBoolToObject(o, "recovered", m->recovered);
        cJSON_AddNumberToObject(o, "max_dip_rpm", m->max_dip_rpm);
    }
    if (m->has_rise)
        cJSON_AddNumberToObject(o, "rise_time_s", m->rise_time_s);
    cJSON_AddNumberToObject(o, "eps_true", m->eps_true);
    if (m->firmware) {
        cJSON_AddNumberToObject(o, "steady_error_rpm", m->steady_error_rpm);
        cJSON_AddNumberToObject(o, "speed_est_error_rpm", m->speed_est_error_rpm);
        cJSON_AddNumberToObject(o, "eps_hat_final", m->eps_hat_final);
        cJSON_AddNumberToObject(o, "w_norm_max", m->w_norm_max);
        cJSON_AddNumberToObject(o, "m_w", m->m_w);
        cJSON_AddNumberToObject(o, "faults", (double)m->faults);
        cJSON_AddNumberToObject(o, "isr_max_us", m->isr_max_us);
        cJSON_AddNumberToObject(o, "isr_overruns", (double)m->isr_overruns);
    }
    cJSON_AddNumberToObject(o, "startup_end_s", m->startup_end_s);
    if (m->has_steady_window) {
        cJSON_AddNumberToObject(o, "np_dev_max_v", m->np_dev_max_v);
        cJSON_AddNumberToObject(o, "np_dev_limit_v", m->np_dev_limit_v);
        cJSON_AddNumberToObject(o, "switching_freq_hz", m->switching_freq_hz);
    }
    for (int i = 0; i < m->n_windows; i++) {
        const sim_window_result *w = &m->windows[i];
        if (!w->valid)
            continue;
        char key[SCENARIO_NAME_LEN + 32];
        snprintf(key, sizeof key, "window_%s_speed_rpm", w->name);
        cJSON_AddNumberToObject(o, key, w->speed_rpm);
        snprintf(key, sizeof key, "window_%s_is_rms_a", w->name);
        cJSON_AddNumberToObject(o, key, w->is_rms_a);
    }
    return o;
}

int sim_write_metrics_json(const sim_metrics *m, const char *path, char *err, size_t errlen)
{
    cJSON *o = build(m);
    char *text = o != NULL ? cJSON_Print(o) : NULL;
    cJSON_Delete(o);
    if (text == NULL) {
        snprintf(err, errlen, "%s: out of memory", path);
        return SIM_ERUNTIME;
    }
    size_t plen = strlen(path);
    char *partial = malloc(plen + 9u);
    int rc = SIM_ERUNTIME;
    if (partial == NULL) {
        snprintf(err, errlen, "%s: out of memory", path);
    } else {
        memcpy(partial, path, plen);
        memcpy(partial + plen, ".partial", 9u);
        FILE *f = fopen(partial, "wx"); /* x: never truncate a file this run did not create */
        if (f == NULL) {
            snprintf(err, errlen, "%s: cannot create: %s", partial, strerror(errno));
        } else {
            bool ok = fputs(text, f) >= 0 && fputc('\n', f) != EOF;
            ok = (fclose(f) == 0) && ok;
            if (ok && rename(partial, path) == 0) {
                rc = SIM_OK;
            } else {
                snprintf(err, errlen, "%s: write error: %s", path, strerror(errno));
                remove(partial);
            }
        }
        free(partial);
    }
    cJSON_free(text);
    return rc;
}
