/**
 * @file drive_isr.c
 * @brief The drive's interrupt side: the 200 us tick (drive_isr) and the
 *        background's hand-over to it (the double-buffered configuration, the
 *        commands, the telemetry snapshot, arming the scope).
 *
 * It uses the control law, the scope and the HAL, and nothing of the CANopen
 * binding or the parameter store: those reach the interrupt only through the
 * functions below (tools/check_layers.py checks it on the built objects).
 */
#include "dtc/drive.h"

#include <stdatomic.h>
#include <stddef.h>
#include <string.h>

#include "dtc/ctl_ident.h"
#include "dtc/num.h"
#include "dtc/speed_ref.h"
#include "hal/hal.h"

/* A branch the tick takes only in a rare state: laid out off the common path,
 * which then runs straight on (one taken branch less per tick). */
#if defined(__GNUC__)
#define RARELY(c) __builtin_expect(!!(c), 0)
#else
#define RARELY(c) (c)
#endif

/* Compiler barrier: volatile orders only volatile accesses, so the plain
 * stores and loads of a published copy are fenced against the volatile word
 * that publishes it (single core: the interrupt only preempts). */
static inline void publish_fence(void) { atomic_signal_fence(memory_order_seq_cst); }

/* The control period in HAL cycles, for the overrun statistic (BG: keeps the
 * float-to-integer work out of the interrupt). Through uint32_t: a float ->
 * uint64 cast would pull in a software 64-bit float routine on the M4F. */
static uint32_t period_in_cycles(const ctl_cfg *cfg)
{
    uint32_t period_us = (uint32_t)(cfg->period_s * 1e6f + 0.5f);
    return (uint32_t)((uint64_t)hal_cycles_hz() * period_us / 1000000u);
}

void drive_isr_init(drive *d)
{
    ctl_cfg_default(&d->cfg[0]); /* derived too */
    d->cfg[1] = d->cfg[0];
    d->period_cycles[0] = d->period_cycles[1] = period_in_cycles(&d->cfg[0]);
    d->cfg_active = 0u;
    scope_init(&d->scope);
    /* the identification tick's arguments, fixed but for the configuration (set per tick) */
    d->ident_call = (ctl_ident_call){&d->ctl, &d->cfg[0], &d->ident, &d->ident_cfg, &d->snap.in, &d->out};
}

const ctl_cfg *drive_cfg(const drive *d) { return &d->cfg[d->cfg_active & 1u]; }

ctl_cfg *drive_cfg_edit(drive *d)
{
    uint32_t inactive = (d->cfg_active & 1u) ^ 1u;
    d->cfg[inactive] = d->cfg[inactive ^ 1u];
    return &d->cfg[inactive];
}

void drive_cfg_commit(drive *d)
{
    uint32_t inactive = (d->cfg_active & 1u) ^ 1u;
    (void)ctl_cfg_rederive(&d->cfg[inactive]);
    d->period_cycles[inactive] = period_in_cycles(&d->cfg[inactive]);
    publish_fence();
    /* One aligned word store: the ISR sees either the old or the new copy. */
    d->cfg_active = inactive;
}

void drive_set_speed_ref(drive *d, float speed_ref_rad_s)
{
    d->speed_ref_rad_s = speed_ref_declared(d->speed_ref_rad_s, speed_ref_rad_s);
}

void drive_set_run(drive *d, bool run)
{
    if (run)
        d->clear_faults_req = true;
    d->run = run;
}

/* A quick stop ends when the ramp is at 0 and the estimate has stayed below
 * 20 rpm for QS_HOLD_S: the speed loop holds the motor near standstill first,
 * so it does not coast on (a later start from a turning rotor is a flying
 * start, which the magnetising does not handle yet). */
#define QS_STOPPED_RAD_S 2.0943951f
#define QS_HOLD_S 0.2f

/*
 * Quick stop (ISR side): the speed reference ramps from the present estimate
 * to 0 at the configured deceleration; at 0 with the estimate below
 * QS_STOPPED_RAD_S for QS_HOLD_S (or when the control core is no longer
 * running) the gates go off and the snapshot says so, so the background ends
 * the run.
 * @return true when the quick stop is done.
 */
static bool quick_stop_step(drive *d, const ctl_cfg *cfg, ctl_in *in)
{
    drive_quick_stop *q = &d->qs;
    if (!d->quick_stop_req) {
        q->active = false;
        return false;
    }
    real_t w = d->out.tel.omega_est_rad_s;
    if (!q->active) {
        q->active = true;
        q->ref_rad_s = w;
        q->held_s = R(0.0);
    }
    real_t step = q->decel_rad_s2 * cfg->period_s;
    if (q->ref_rad_s > step)
        q->ref_rad_s -= step;
    else if (q->ref_rad_s < -step)
        q->ref_rad_s += step;
    else
        q->ref_rad_s = R(0.0);
    in->speed_ref_rad_s = q->ref_rad_s;
    ctl_run_state st = d->ctl.run_state;
    bool still = q->ref_rad_s == R(0.0) && num_abs(w) < QS_STOPPED_RAD_S;
    q->held_s = still ? q->held_s + cfg->period_s : R(0.0);
    bool done = q->held_s >= QS_HOLD_S || st == CTL_STOPPED || st == CTL_FAULTED;
    if (done)
        in->run = false;
    return done;
}

/* The derived fields of @p s selected by @p which (DRIVE_SNAP_*), from its raw
 * fields. Inline: the interrupt's call with the scope's constant-per-capture
 * mask and the background's with all of them. */
static inline void snapshot_derive(drive_snapshot *s, uint32_t which)
{
    if ((which & DRIVE_SNAP_SPEED_ERR) != 0u)
        s->speed_err_rad_s = s->tel.speed_ref_rad_s - s->tel.omega_est_rad_s;
    if ((which & DRIVE_SNAP_VDC_DIFF) != 0u)
        s->vdc_diff_V = s->vc1_V - s->vc2_V;
    if ((which & DRIVE_SNAP_I_PEAK) != 0u)
        s->i_peak_A = num_sqrt(R(0.6666667) * (s->ia_A * s->ia_A + s->ib_A * s->ib_A + s->ic_A * s->ic_A));
    if ((which & DRIVE_SNAP_VDC) != 0u)
        s->vdc_V = s->vc1_V + s->vc2_V;
}

/* The scope copies whole 4-byte words of the snapshot (a byte signal's: the aligned
 * word that holds it, scope_arm), so the snapshot must be whole words. */
_Static_assert(sizeof(drive_snapshot) % 4u == 0u, "the snapshot is a whole number of words");
#define SNAP_AT(f) offsetof(drive_snapshot, f)
#define SAMPLE_AT(f) (offsetof(drive_snapshot, in) + offsetof(ctl_in, sample) + offsetof(hal_sample, f))
_Static_assert(SNAP_AT(ia_A) == SAMPLE_AT(ia_A) && SNAP_AT(ib_A) == SAMPLE_AT(ib_A) &&
                   SNAP_AT(ic_A) == SAMPLE_AT(ic_A) && SNAP_AT(vc1_V) == SAMPLE_AT(vc1_V) &&
                   SNAP_AT(vc2_V) == SAMPLE_AT(vc2_V) && SNAP_AT(omega_meas_rad_s) == SAMPLE_AT(speed_meas_rad_s),
               "the snapshot's sample fields are its in.sample's first six floats");
_Static_assert(offsetof(drive, out) == offsetof(drive, snap) + offsetof(drive_snapshot, out) &&
                   offsetof(drive_snapshot, tel) == offsetof(drive_snapshot, out) + offsetof(ctl_out, tel) &&
                   offsetof(drive_snapshot, out_act_) == offsetof(drive_snapshot, out) + offsetof(ctl_out, act) &&
                   offsetof(drive_snapshot, out_gate_enable_) ==
                       offsetof(drive_snapshot, out) + offsetof(ctl_out, gate_enable),
               "d->out is d->snap.out, and snap.tel its telemetry");

/* The snapshot is being written (odd): from before the sample is read into
 * it and ctl_step writes its telemetry in place (d->out is d->snap.out). */
static inline void snapshot_open(drive_snapshot *s)
{
    s->seq++;
    publish_fence();
}

/* The rest of the snapshot (the telemetry is in place). */
static inline void snapshot_fill(drive *d, bool quick_stop_done)
{
    drive_snapshot *s = &d->snap;
    s->tick = d->tick;
    s->quick_stop_done = quick_stop_done;
    uint32_t which = d->snap_derived;
    if (which != 0u) /* only what the armed scope reads */
        snapshot_derive(s, which);
}

/* Even: consistent. */
static inline void snapshot_close(drive_snapshot *s)
{
    publish_fence();
    s->seq++;
}

void drive_isr(void *ctx)
{
    drive *d = (drive *)ctx;
    uint32_t t0 = hal_cycles();
    uint32_t active = d->cfg_active & 1u; /* one read: cfg and period_cycles from the same copy */
    const ctl_cfg *cfg = &d->cfg[active];

    if (d->clear_faults_req) {
        d->clear_faults_req = false;
        (void)ctl_clear_faults(&d->ctl);
    }

    /* The inputs are read in place into the snapshot (d->snap.in), inside
     * its sequence window. Every member is set below (no memset of the
     * struct in the tick); a refused read leaves a zero sample, which the
     * snapshot then shows. */
    snapshot_open(&d->snap);
    ctl_in *in = &d->snap.in;
    in->sample_fresh = (hal_sample_read(&in->sample) == HAL_OK);
    if (!in->sample_fresh)
        in->sample = (hal_sample){.ia_A = R(0.0)};
    in->run = d->run;
    in->speed_ref_rad_s = d->speed_ref_rad_s;
    bool qs_done = quick_stop_step(d, cfg, in);
    in->fault_input = hal_fault_input_active();
    in->overrun = d->tick_missed;

    if (RARELY(d->ident_on)) { /* the identification run state (dtc/drive_ident.h) */
        in->run = d->ident_run;
        d->ident_call.cfg = cfg; /* the rest points into d (drive_isr_init) */
        ctl_ident_step(&d->ident_call);
    } else {
        ctl_step(&d->ctl, cfg, in, &d->out);
    }

    /* Protection acts in the same tick: gates off before anything else. */
    if (!d->out.gate_enable) {
        hal_gate_enable(false);
    } else {
        if (!hal_gate_enabled())
            hal_gate_enable(true);
    }
    (void)hal_actuate(&d->out.act);

    d->tick++;
    snapshot_fill(d, qs_done);
    /* The scope reads the filled snapshot before it is closed: with the
     * closing fence after the scope, its inputs need not be read again. */
    scope_sample(&d->scope, &d->snap, in->speed_ref_rad_s, d->out.tel.faults, d->tick);
    snapshot_close(&d->snap);

    /* Judged by the board's timer, so it latches CTL_FAULT_OVERRUN next tick. */
    d->tick_missed = hal_tick_missed();

    uint32_t dt = hal_cycles() - t0;
    d->timing.last_cycles = dt;
    if (dt > d->timing.max_cycles)
        d->timing.max_cycles = dt;
    if (dt > d->period_cycles[active])
        d->timing.overruns++;
}

void drive_read_snapshot(const drive *d, drive_snapshot *out)
{
    uint32_t s0, s1;
    do {
        s0 = d->snap.seq;
        publish_fence();
        memcpy(out, (const void *)&d->snap, sizeof *out);
        publish_fence();
        s1 = d->snap.seq;
    } while (s0 != s1 || (s0 & 1u));
    snapshot_derive(out, DRIVE_SNAP_SPEED_ERR | DRIVE_SNAP_VDC_DIFF | DRIVE_SNAP_I_PEAK | DRIVE_SNAP_VDC);
}

void drive_scope_arm(drive *d, const scope_src *src, uint8_t n_src)
{
    static const struct {
        uint16_t offset;
        uint8_t bit;
    } derived[] = {
        {(uint16_t)offsetof(drive_snapshot, speed_err_rad_s), (uint8_t)DRIVE_SNAP_SPEED_ERR},
        {(uint16_t)offsetof(drive_snapshot, vdc_diff_V), (uint8_t)DRIVE_SNAP_VDC_DIFF},
        {(uint16_t)offsetof(drive_snapshot, i_peak_A), (uint8_t)DRIVE_SNAP_I_PEAK},
        {(uint16_t)offsetof(drive_snapshot, vdc_V), (uint8_t)DRIVE_SNAP_VDC},
    };
    uint32_t which = 0u;
    for (uint32_t i = 0u; i < n_src && i < SCOPE_CHANNELS; i++)
        for (uint32_t k = 0u; k < sizeof derived / sizeof derived[0]; k++)
            if (src[i].offset == derived[k].offset)
                which |= derived[k].bit;
    scope_stop(&d->scope); /* the interrupt stops reading the old sources before their fields may go stale */
    d->snap_derived = (uint8_t)which;
    publish_fence();
    scope_arm(&d->scope, src, n_src);
}
