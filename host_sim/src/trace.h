/**
 * @file trace.h
 * @brief CSV trace writer (private to the engine). The file is written as
 *        PATH.partial and renamed to PATH only when the run succeeds, so a
 *        failed run never leaves a half-written trace under the real name.
 */
#ifndef SIM_TRACE_H
#define SIM_TRACE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "dtc/drive.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    FILE *f;
    char *path;
    char *partial;
} sim_trace;

/** One row: true plant values at t_s plus the drive's telemetry (NULL: no firmware). */
typedef struct {
    double t_s;
    double omega_m_rad_s, te_nm;
    double ia_a, ib_a, ic_a;
    double vc1_v, vc2_v;
    double ref_cmd_rpm;     /**< scenario reference (before the firmware's ramp) */
    double t_load_nm;
    double eps_true;
    const drive_snapshot *snap;
} sim_trace_row;

/** Create PATH.partial and write the header. @return 0, or -1 with @p err set. */
int trace_open(sim_trace *t, const char *path, char *err, size_t errlen);

/** Append one row (errors are caught by trace_close). */
void trace_write(sim_trace *t, const sim_trace_row *r);

/** @p ok: flush, close and rename to PATH (0, or -1 with @p err). !ok: close and delete. */
int trace_close(sim_trace *t, bool ok, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif /* SIM_TRACE_H */
