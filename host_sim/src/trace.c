/**
 * @file trace.c
 * @brief CSV trace writer: one header row, then one row per trace interval.
 */
#define _POSIX_C_SOURCE 200809L

#include "trace.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#define RPM_PER_RAD_S (60.0 / (2.0 * 3.14159265358979323846))

static const char header[] =
    "t_s,omega_m_rad_s,speed_rpm,te_nm,ia_a,ib_a,ic_a,vc1_v,vc2_v,t_load_nm,ref_cmd_rpm,"
    "speed_ref_rpm,speed_est_rpm,speed_err_true_rpm,te_ref_nm,te_est_nm,psi_s_wb,psi_ref_wb,"
    "eps_hat,eps_true,w_norm,zeta_bar,rs_est_ohm,vector,duty0,state,faults\n";

static char *concat(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b);
    char *s = malloc(la + lb + 1);
    if (s != NULL) {
        memcpy(s, a, la);
        memcpy(s + la, b, lb + 1);
    }
    return s;
}

int trace_open(sim_trace *t, const char *path, char *err, size_t errlen)
{
    memset(t, 0, sizeof *t);
    t->path = concat(path, "");
    t->partial = concat(path, ".partial");
    if (t->path == NULL || t->partial == NULL) {
        snprintf(err, errlen, "%s: out of memory", path);
        trace_close(t, false, NULL, 0);
        return -1;
    }
    t->f = fopen(t->partial, "wx"); /* x: never truncate a file this run did not create */
    if (t->f == NULL) {
        snprintf(err, errlen, "%s: cannot create: %s", t->partial, strerror(errno));
        trace_close(t, false, NULL, 0);
        return -1;
    }
    /* A large buffer: rows are small and many. */
    setvbuf(t->f, NULL, _IOFBF, 1u << 16);
    fputs(header, t->f);
    return 0;
}

void trace_write(sim_trace *t, const sim_trace_row *r)
{
    if (t->f == NULL)
        return;
    fprintf(t->f, "%.6f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g", r->t_s, r->omega_m_rad_s,
            r->omega_m_rad_s * RPM_PER_RAD_S, r->te_nm, r->ia_a, r->ib_a, r->ic_a, r->vc1_v, r->vc2_v,
            r->t_load_nm, r->ref_cmd_rpm);
    const drive_snapshot *s = r->snap;
    if (s == NULL) {
        /* No firmware (sine supply): controller columns stay empty. */
        fprintf(t->f, ",,,,,,,,,%.6g,,,,,,,\n", r->eps_true);
        return;
    }
    const ctl_telemetry *tel = &s->tel;
    double ref_rpm = (double)tel->speed_ref_rad_s * RPM_PER_RAD_S;
    fprintf(t->f, ",%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%u,%.4g,%u,%lu\n", ref_rpm,
            (double)tel->omega_est_rad_s * RPM_PER_RAD_S, ref_rpm - r->omega_m_rad_s * RPM_PER_RAD_S,
            (double)tel->te_ref_Nm, (double)tel->te_est_Nm, (double)tel->psi_s_est_Wb, (double)tel->psi_ref_Wb,
            (double)tel->eps_hat, r->eps_true, (double)tel->w_norm, (double)tel->zeta_bar,
            (double)tel->rs_est_ohm, (unsigned)tel->vector_index, (double)tel->duty0, (unsigned)tel->state,
            (unsigned long)tel->faults);
}

int trace_close(sim_trace *t, bool ok, char *err, size_t errlen)
{
    int rc = 0;
    if (t->f != NULL) {
        bool bad = ferror(t->f) != 0;
        if (fclose(t->f) != 0)
            bad = true;
        t->f = NULL;
        if (ok && bad) {
            if (err != NULL)
                snprintf(err, errlen, "%s: write error: %s", t->partial, strerror(errno));
            ok = false;
            rc = -1;
        }
        if (ok && rename(t->partial, t->path) != 0) {
            if (err != NULL)
                snprintf(err, errlen, "%s: cannot rename to %s: %s", t->partial, t->path, strerror(errno));
            ok = false;
            rc = -1;
        }
        if (!ok)
            remove(t->partial);
    }
    free(t->path);
    free(t->partial);
    t->path = t->partial = NULL;
    return rc;
}
