/**
 * @file drive_ident.c
 * @brief The drive's identification run, background side (dtc/drive_ident.h):
 *        the start's checks, the fits, the results written to the active
 *        configuration at the end, nothing written after an abort.
 */
#include "dtc/drive_ident.h"

#include <stdatomic.h>
#include <string.h>

#include "dtc/drive.h"
#include "dtc/ident_apply.h"
#include "dtc/num.h"
#include "dtc/ratings.h"

/* as drive_isr.c: plain stores fenced against the volatile word that publishes them */
static inline void ident_fence(void) { atomic_signal_fence(memory_order_seq_cst); }

void drive_ident_plate_of(const ratings *r, ident_plate *p)
{
    p->p_W = r->P_W;
    p->v_ll_V = r->V_ll_V;
    p->i_A = r->I_A;
    p->f_Hz = r->f_Hz;
    p->speed_rpm = r->n_rpm;
    if (r->cos_phi > R(0.0)) {
        p->cos_phi = r->cos_phi;
    } else { /* not on the plate: the ratings' own estimate (ratings_base_of) */
        ratings_base b;
        ratings_base_of(r, &b);
        p->cos_phi = b.cos_phi;
    }
    p->cos_phi = num_sat(p->cos_phi, R(0.3), R(0.99)); /* ident_plate's range */
}

static int refuse(drive *d, int rc)
{
    d->ident_error = (int32_t)rc;
    d->ident_outcome = (uint8_t)DRIVE_IDENT_REFUSED;
    return rc;
}

int drive_ident_start(drive *d, const ident_plate *plate, bool rotating)
{
    if (d->ident_on)
        return refuse(d, IDENT_E_BUSY);
    if (rotating)
        return refuse(d, DRIVE_IDENT_E_ROTATING);
    const ctl_cfg *cfg = drive_cfg(d);
    ident_cfg *ic = &d->ident_cfg;
    memset(ic, 0, sizeof *ic);
    if (plate != NULL)
        ic->plate = *plate;
    else
        drive_ident_plate_of(&cfg->plate, &ic->plate); /* the motor the drive is configured for */
    ic->i_max_A = R(0.0); /* the rated peak */
    ic->period_s = cfg->period_s;
    ic->vdc_nom_V = cfg->vdc_nom_V;
    ic->vdc_min_V = cfg->vdc_min_V;
    ic->dead_time_s = cfg->dead_time_comp_s;
    ic->v_drop_V = cfg->v_drop_V;
    ic->rotating = false;
    ic->te_J_frac = R(0.0);
    int rc = ident_cfg_derive(ic);
    if (rc != IDENT_OK)
        return refuse(d, rc);

    drive_snapshot snap;
    drive_read_snapshot(d, &snap);
    ident_start_in si;
    si.drive_stopped = !d->run && !d->quick_stop_req && d->ctl.run_state == CTL_STOPPED && snap.tel.faults == 0u &&
                       snap.tel.state == (uint8_t)CTL_STOPPED;
    si.omega_m_rad_s = snap.tel.omega_est_rad_s;
    si.vdc_V = snap.vdc_V;
    ident_init(&d->ident);
    rc = ident_start(&d->ident, ic, &si);
    if (rc != IDENT_OK)
        return refuse(d, rc);
    memset(&d->ident_res, 0, sizeof d->ident_res);
    d->ident_error = 0;
    d->ident_applied = 0u;
    d->ident_outcome = (uint8_t)DRIVE_IDENT_RUNNING;
    d->ident_run = true;
    ident_fence();
    d->ident_on = true; /* the interrupt steps the run from its next tick */
    return 0;
}

void drive_ident_stop(drive *d)
{
    if (d->ident_on)
        d->ident_run = false;
}

bool drive_ident_running(const drive *d) { return d->ident_on; }

uint32_t drive_ident_progress(const drive *d)
{
    if (d->ident_outcome == (uint8_t)DRIVE_IDENT_DONE)
        return 100u;
    if (d->ident_outcome != (uint8_t)DRIVE_IDENT_RUNNING && d->ident_outcome != (uint8_t)DRIVE_IDENT_ABORTED)
        return 0u;
    return ident_progress(&d->ident, &d->ident_cfg);
}

void drive_ident_background(drive *d)
{
    if (!d->ident_on)
        return;
    (void)ident_background(&d->ident, &d->ident_cfg, &d->ident_res);
    ident_phase p = d->ident.phase;
    if (p == IDENT_DONE) {
        /* the interrupt is off the run now (done: gates off); the active copy is the one before */
        const ctl_cfg *from = drive_cfg(d);
        ctl_cfg *to = drive_cfg_edit(d);
        int rc = ident_apply(&d->ident, &d->ident_res, from, to);
        if (rc >= 0) {
            d->ident_applied = (uint8_t)rc;
            d->ident_outcome = (uint8_t)DRIVE_IDENT_DONE;
            if (rc != 0)
                drive_cfg_commit(d);
        } else {
            d->ident_outcome = (uint8_t)DRIVE_IDENT_REJECTED;
            d->ident_error = (int32_t)rc;
        }
        d->ident_run = false;
        ident_fence();
        d->ident_on = false;
    } else if (p == IDENT_ABORTED || p == IDENT_WAIT_APPLY) {
        /* aborted: nothing to write (the configuration was never changed); the
         * rotating part is never asked for, so WAIT_APPLY cannot come: ended as aborted */
        d->ident_outcome = (uint8_t)DRIVE_IDENT_ABORTED;
        d->ident_run = false;
        ident_fence();
        d->ident_on = false;
    }
}
