/**
 * @file drive_co.c
 * @brief The drive's side of the CANopen interface: where each dictionary
 *        entry lives, how a write is applied (configuration through one
 *        edit/commit), the handlers of the function-bound entries, and the
 *        background pass that feeds the device.
 */
#include "dtc/drive_co.h"

#include <string.h>

#include "dtc/drive_ident.h"
#include "dtc/num.h"
#include "dtc/param_table.h"
#include "dtc/persist.h"
#include "dtc/ratings.h"
#include "dtc/scope.h"
#include "dtc/speed_ref.h"
#include "hal/hal.h"

#define SIGNATURE_SAVE 0x65766173u /* "save" */
#define SIGNATURE_LOAD 0x64616F6Cu /* "load" */

_Static_assert(CO_STRING_MAX <= CO_SDO_BUF, "a constant string does not fit the SDO buffer");

const co_dict drive_od = {co_params, (uint16_t)CO_PARAM_COUNT};

bool drive_co_running(const drive *d)
{
    ctl_run_state st = d->ctl.run_state; /* one aligned read of ISR state */
    return d->run || st == CTL_MAGNETISING || st == CTL_RUNNING || drive_ident_running(d);
}

/* A save for 0x1010:1 or 0x1011:1: the slot image is built on this frame,
 * sized by the table (the store itself knows no table). */
static int save_params(drive *d, persist_save_kind kind)
{
    uint8_t work[PERSIST_HEADER_SIZE + CO_PERSIST_BYTES];
    return persist_save(&d->persist, kind, work, sizeof work);
}

/* ------------------------------------------------------- bound C fields */

/* Where a bound entry lives for reading: the active configuration, the
 * scope settings, the background snapshot or the drive. */
static const void *read_base(const drive *d, const co_param *p)
{
    switch (p->bind) {
    case DRIVE_BIND_CFG:
        return drive_cfg(d);
    case DRIVE_BIND_SCOPE:
        return &d->scope.cfg;
    case DRIVE_BIND_APP:
        return &d->app;
    case DRIVE_BIND_SNAP:
        return &d->bg_snap;
    case DRIVE_BIND_DRIVE:
        return d;
    default:
        return NULL;
    }
}

/* Target reached (statusword bit 10): |e_x| below 1 % of the reference or 5 rpm. */
static bool target_reached(const drive *d)
{
    real_t ref = d->speed_ref_rad_s;
    real_t tol = num_abs(ref) * R(0.01);
    real_t min_tol = R(5.0) * R(0.104719755); /* 5 rpm in rad/s */
    if (tol < min_tol)
        tol = min_tol;
    return num_abs(ref - d->bg_snap.tel.omega_est_rad_s) <= tol;
}

/* ----------------------------------------------------------------- scope */

static uint32_t scope_arm_from_settings(drive *d)
{
    scope *s = &d->scope;
    scope_src src[SCOPE_CHANNELS];
    uint8_t n = 0u;
    for (uint32_t ch = 0u; ch < SCOPE_CHANNELS; ch++) {
        uint8_t sig = s->cfg.channel[ch];
        if (sig == 0u)
            continue;
        const co_param *p = co_od_find(&drive_od, (uint16_t)CO_TEL_INDEX, sig, NULL);
        if (p == NULL || p->bind != DRIVE_BIND_SNAP)
            return CO_ABORT_PARAM_INCOMPAT;
        src[n].offset = p->offset;
        src[n].kind = (uint8_t)(p->ckind == CO_CK_FLOAT ? SCOPE_SRC_F32
                                                       : (p->csize == 1u ? SCOPE_SRC_U8 : SCOPE_SRC_U32));
        n++;
    }
    if (s->cfg.decimation == 0u || s->cfg.pretrigger >= SCOPE_SAMPLES)
        return CO_ABORT_PARAM_INCOMPAT;
    drive_scope_arm(d, src, n);
    return CO_ABORT_NONE;
}

static uint32_t domain_size(void *ctx, const co_param *p)
{
    const drive *d = ctx;
    if (p->offset != CO_FN_SCOPE_DATA || scope_get_state(&d->scope) != SCOPE_DONE)
        return 0u;
    return (uint32_t)d->scope.n_ch * SCOPE_SAMPLES * 4u;
}

static void domain_read(void *ctx, const co_param *p, uint32_t offset, uint8_t *buf, size_t n)
{
    const drive *d = ctx;
    memset(buf, 0, n);
    uint32_t size = domain_size(ctx, p);
    const scope *s = &d->scope;
    for (size_t i = 0u; i < n; i++) {
        uint32_t at = offset + (uint32_t)i;
        if (at >= size)
            return;
        uint32_t sample = at / 4u;
        uint32_t ch = sample / SCOPE_SAMPLES;
        uint32_t j = sample % SCOPE_SAMPLES;
        /* Convert to the telemetry signal's bus units (e.g. rpm) as REAL32. */
        const co_param *sig = co_od_find(&drive_od, (uint16_t)CO_TEL_INDEX, s->armed_channel[ch], NULL);
        co_num v;
        v.f = scope_value(s, ch, j) * (sig != NULL && sig->dtype == CO_DT_REAL32 ? sig->k : 1.0f);
        uint8_t b[4];
        co_num_encode(CO_DT_REAL32, &v, b);
        buf[i] = b[at % 4u];
    }
}

/* --------------------------------------------------------------- handlers */

static uint32_t fn_read(drive *d, const co_param *p, co_num *v)
{
    v->u = 0u;
    switch ((co_fn_id)p->offset) {
    case CO_FN_SPEED_REF:
        v->f = speed_ref_in_force(drive_cfg(d), d->speed_ref_rad_s);
        break;
    case CO_FN_VL_TARGET:
        v->f = d->target_rad_s;
        break;
    case CO_FN_VL_ACCEL: {
        float rpm_s = drive_cfg(d)->speed.ramp_rad_s2 * 9.549296586f;
        v->u = (uint32_t)(rpm_s + 0.5f);
        break;
    }
    case CO_FN_ERROR_REGISTER:
        v->u = co_emcy_error_register(&d->co);
        break;
    case CO_FN_STORE:
    case CO_FN_RESTORE:
        v->u = 1u; /* saves on command only */
        break;
    case CO_FN_CONTROLWORD:
        v->u = d->co.cia402.controlword;
        break;
    case CO_FN_STATUSWORD:
        v->u = co_cia402_statusword(&d->co.cia402, target_reached(d));
        break;
    case CO_FN_PERSIST_STATUS:
        v->u = d->persist.status;
        break;
    case CO_FN_TPDO_DROPPED:
        v->u = d->co.pdo.dropped;
        break;
    case CO_FN_TPDO_SEQ:
        v->u = d->co.pdo.seq;
        break;
    case CO_FN_CYCLES_HZ:
        v->u = hal_cycles_hz();
        break;
    case CO_FN_SCOPE_COMMAND:
        break;
    case CO_FN_SCOPE_STATE:
        v->u = scope_get_state(&d->scope);
        break;
    case CO_FN_SCOPE_TRIGGER_TICK:
        v->u = d->scope.trigger_tick;
        break;
    case CO_FN_IDENT_COMMAND:
        break;
    case CO_FN_IDENT_PROGRESS:
        v->u = drive_ident_progress(d);
        break;
    case CO_FN_SCOPE_DATA:
    case CO_FN_COUNT:
    default:
        return CO_ABORT_GENERAL;
    }
    return CO_ABORT_NONE;
}

/* The quick stop ramp in rad/s^2 from 0x6049 (rpm per s). */
static void derive_quick_stop(drive *d)
{
    uint32_t dt_s = d->app.qs_delta_s != 0u ? d->app.qs_delta_s : 1u;
    d->qs.decel_rad_s2 = (float)d->app.qs_delta_rpm * 0.104719755f / (float)dt_s;
}

/* Quick stop per the option code 0x605A: ramp down (2) or coast (0). */
static void quick_stop(drive *d)
{
    if (d->app.quick_stop_option == 0) {
        drive_set_run(d, false);
        co_cia402_quick_stop_done(&d->co.cia402);
        return;
    }
    if (d->run)
        d->quick_stop_req = true;
    else
        co_cia402_quick_stop_done(&d->co.cia402);
}

static bool same_bits(float a, float b)
{
    uint32_t x, y;
    memcpy(&x, &a, sizeof x);
    memcpy(&y, &b, sizeof y);
    return x == y;
}

/* The bus's target velocity under the vl limits 0x6046 (step 1 of the rule
 * in dtc/speed_ref.h), rad/s: a non-zero magnitude at least @p min_rpm, then
 * at most @p max_rpm, so the maximum wins even over a pair stored before the
 * pair was checked; the halt bit holds it at 0 (the speed ramp slows the
 * motor, operation stays enabled). */
static float vl_limited(const drive *d, uint32_t min_rpm, uint32_t max_rpm)
{
    const float rpm_per_rad_s = 9.549296586f;
    float t = d->target_rad_s;
    float mag = (t < 0.0f ? -t : t) * rpm_per_rad_s;
    if (mag > 0.0f && mag < (float)min_rpm)
        mag = (float)min_rpm;
    if (mag > (float)max_rpm)
        mag = (float)max_rpm;
    float ref = (t < 0.0f ? -mag : mag) / rpm_per_rad_s;
    return d->halt ? 0.0f : ref;
}

/* The bus's target into the speed reference: the vl limits, then the
 * declared range (drive_set_speed_ref). */
static void apply_target(drive *d)
{
    drive_set_speed_ref(d, vl_limited(d, d->app.vl_min_rpm, d->app.vl_max_rpm));
}

/* Whether the reference in force is the bus's target under the present vl
 * limits: one set by the board itself (e.g. a SIL scenario) is not a vl
 * target, and a change of the limits leaves it as it is. */
static bool ref_is_bus_target(const drive *d)
{
    float from_bus = speed_ref_declared(d->speed_ref_rad_s, vl_limited(d, d->app.vl_min_rpm, d->app.vl_max_rpm));
    return same_bits(from_bus, d->speed_ref_rad_s);
}

/* A write of 0x6046:1 (vl_velocity_min) or :2 (vl_velocity_max): refused when
 * it would put the minimum above the maximum; else applied, and a reference
 * that came from the bus is worked out again under the new limits. */
static uint32_t vl_limits_write(drive *d, const co_param *p, const co_num *v)
{
    uint32_t min_rpm = d->app.vl_min_rpm, max_rpm = d->app.vl_max_rpm;
    if (p == &co_params[CO_P_VL_VELOCITY_MIN])
        min_rpm = v->u;
    else
        max_rpm = v->u;
    if (min_rpm > max_rpm)
        return CO_ABORT_MAX_BELOW_MIN;
    bool bus_ref = ref_is_bus_target(d);
    co_field_set(&d->app, p, v);
    if (bus_ref)
        apply_target(d);
    return CO_ABORT_NONE;
}

static void apply_cia402(drive *d, co_cia402_action a)
{
    /* a run lasts in "Switched on" only: a disable, a shutdown, a quick stop, an enable end it */
    if (a != CO_CIA402_KEEP || d->co.cia402.state != CO_CIA402_SWITCHED_ON)
        drive_ident_stop(d);
    switch (a) {
    case CO_CIA402_QUICK_STOP:
        quick_stop(d);
        break;
    case CO_CIA402_RUN:
        drive_set_run(d, true);
        break;
    case CO_CIA402_STOP:
        d->quick_stop_req = false;
        drive_set_run(d, false);
        break;
    case CO_CIA402_FAULT_RESET:
        d->quick_stop_req = false;
        drive_set_run(d, false);
        d->drive_faults = 0u;
        d->clear_faults_req = true; /* the ISR clears what is no longer active */
        break;
    case CO_CIA402_KEEP:
    default:
        break;
    }
}

/* Every value the commit derived (not set by the user) within the range its
 * dictionary entry declares: a write whose derivation would leave one (an
 * i_trip_A so low that the derived torque limit falls below te_max_Nm's
 * minimum) is refused, so a read-back never shows a value the entry could not
 * take. Context: BG. */
static bool derived_within_ranges(const ctl_cfg *e)
{
    for (uint32_t i = 0u; i < CO_PARAM_COUNT; i++) {
        const co_param *q = &co_params[i];
        if (q->bind != DRIVE_BIND_CFG || (q->flags & CO_F_LIMITS) == 0u)
            continue;
        ratings_id id = ratings_id_at(q->offset);
        if (id == RATINGS_ID_COUNT || ratings_mask_has(&e->set, id))
            continue;
        co_num raw = co_od_to_raw(q, co_field_get(e, q));
        uint8_t bytes[4] = {0u, 0u, 0u, 0u};
        co_num_encode(q->dtype, &raw, bytes);
        co_num back;
        if (co_od_check(q, bytes, co_dtype_size(q->dtype), CO_WR_LOAD, &back) != CO_ABORT_NONE)
            return false;
    }
    return true;
}

static uint32_t fn_write(drive *d, const co_param *p, const co_num *v)
{
    switch ((co_fn_id)p->offset) {
    case CO_FN_SPEED_REF:
    case CO_FN_VL_TARGET:
        d->target_rad_s = v->f;
        apply_target(d);
        return CO_ABORT_NONE;
    case CO_FN_VL_ACCEL: {
        bool was_ok = ctl_cfg_check(drive_cfg(d)) == CTL_CFG_OK;
        /* rpm/s -> rad/s^2, held to ramp_rad_s2's range: the top of this entry's
         * (its maximum rounded to whole rpm/s) lies a little above it */
        const co_param *ramp = &co_params[CO_P_RAMP_RAD_S2];
        float rad_s2 = (float)v->u * 0.104719755f;
        if (rad_s2 > ramp->max.f)
            rad_s2 = ramp->max.f;
        ctl_cfg *e = drive_cfg_edit(d);
        e->speed.ramp_rad_s2 = rad_s2;
        ratings_mask_set(&e->set, RATINGS_ID_SPEED_RAMP);
        (void)ctl_cfg_rederive(e);
        if ((was_ok && ctl_cfg_check(e) != CTL_CFG_OK) || !derived_within_ranges(e))
            return CO_ABORT_PARAM_INCOMPAT;
        drive_cfg_commit(d);
        return CO_ABORT_NONE;
    }
    case CO_FN_STORE:
        if (v->u != SIGNATURE_SAVE)
            return CO_ABORT_STORE;
        if (save_params(d, PERSIST_SAVE_VALUES) != HAL_OK)
            return CO_ABORT_STORE;
        co_emcy_clear_extra(&d->co.emcy);
        return CO_ABORT_NONE;
    case CO_FN_RESTORE:
        if (v->u != SIGNATURE_LOAD)
            return CO_ABORT_STORE;
        if (drive_co_running(d))
            return CO_ABORT_STATE;
        /* Store the empty set first: if the NVM fails nothing has changed. */
        if (save_params(d, PERSIST_SAVE_EMPTY) != HAL_OK)
            return CO_ABORT_STORE;
        bool bus_ref = ref_is_bus_target(d);
        (void)persist_load(&d->persist);
        if (bus_ref)
            apply_target(d); /* under the default vl limits */
        co_emcy_clear_extra(&d->co.emcy);
        return CO_ABORT_NONE;
    case CO_FN_CONTROLWORD: {
        bool halt = (v->u & 0x0100u) != 0u; /* bit 8: halt (option 1: slow down on the speed ramp) */
        if (halt != d->halt) {
            d->halt = halt;
            apply_target(d);
        }
        apply_cia402(d, co_cia402_controlword(&d->co.cia402, (uint16_t)v->u));
        return CO_ABORT_NONE;
    }
    case CO_FN_SCOPE_COMMAND:
        if (v->u == 0u) {
            scope_stop(&d->scope);
            return CO_ABORT_NONE;
        }
        if (v->u == 1u)
            return scope_arm_from_settings(d);
        if (scope_get_state(&d->scope) != SCOPE_ARMED)
            return CO_ABORT_STATE;
        scope_trigger_now(&d->scope);
        return CO_ABORT_NONE;
    case CO_FN_IDENT_COMMAND:
        /* 0 aborts (nothing is written); 1 starts the standstill run on the plate the drive holds,
         * 2 the run with its rotating part; only in CiA 402 "Switched on" (voltage on, operation
         * not enabled); a refusal leaves its reason in ident_error (0x2800:6) */
        if (v->u == 0u) {
            drive_ident_stop(d);
            return CO_ABORT_NONE;
        }
        if (d->co.cia402.state != CO_CIA402_SWITCHED_ON && !drive_ident_running(d)) {
            d->ident_error = DRIVE_IDENT_E_CIA402;
            d->ident_outcome = (uint8_t)DRIVE_IDENT_REFUSED;
            return CO_ABORT_STATE;
        }
        return drive_ident_start(d, NULL, v->u == 2u) == 0 ? CO_ABORT_NONE : CO_ABORT_STATE;
    case CO_FN_IDENT_PROGRESS:
    case CO_FN_ERROR_REGISTER:
    case CO_FN_STATUSWORD:
    case CO_FN_PERSIST_STATUS:
    case CO_FN_TPDO_DROPPED:
    case CO_FN_TPDO_SEQ:
    case CO_FN_CYCLES_HZ:
    case CO_FN_SCOPE_STATE:
    case CO_FN_SCOPE_TRIGGER_TICK:
    case CO_FN_SCOPE_DATA:
    case CO_FN_COUNT:
    default:
        return CO_ABORT_READ_ONLY;
    }
}

/* ------------------------------------------------------ the co_app hooks */

static uint32_t app_read(void *ctx, const co_param *p, co_num *internal)
{
    drive *d = ctx;
    if (p->bind == DRIVE_BIND_FN)
        return fn_read(d, p, internal);
    const void *base = read_base(d, p);
    if (base == NULL)
        return CO_ABORT_GENERAL;
    *internal = co_field_get(base, p);
    return CO_ABORT_NONE;
}

static uint32_t app_write(void *ctx, const co_param *p, const co_num *internal)
{
    drive *d = ctx;
    switch (p->bind) {
    case DRIVE_BIND_FN:
        return fn_write(d, p, internal);
    case DRIVE_BIND_SCOPE:
        co_field_set(&d->scope.cfg, p, internal);
        return CO_ABORT_NONE;
    case DRIVE_BIND_APP:
        if (p == &co_params[CO_P_VL_VELOCITY_MIN] || p == &co_params[CO_P_VL_VELOCITY_MAX])
            return vl_limits_write(d, p, internal);
        co_field_set(&d->app, p, internal);
        derive_quick_stop(d);
        return CO_ABORT_NONE;
    case DRIVE_BIND_CFG: {
        /* Edit the inactive copy, refuse a change that makes a consistent
         * configuration inconsistent (ctl_cfg_check: e.g. a width of 0 for a
         * node in use, vdc_min above vdc_max) -- the copy is then simply not
         * published -- else publish it with one store. */
        bool was_ok = ctl_cfg_check(drive_cfg(d)) == CTL_CFG_OK;
        ctl_cfg *e = drive_cfg_edit(d);
        co_field_set(e, p, internal);
        /* A derivable value written is the user's from now on (the read-back
         * says "set"); what is derived from it follows at the commit. */
        ratings_id id = ratings_id_at(p->offset);
        if (id != RATINGS_ID_COUNT)
            ratings_mask_set(&e->set, id);
        /* the configuration judged is the derived one */
        (void)ctl_cfg_rederive(e);
        if ((was_ok && ctl_cfg_check(e) != CTL_CFG_OK) || !derived_within_ranges(e))
            return CO_ABORT_PARAM_INCOMPAT;
        drive_cfg_commit(d);
        return CO_ABORT_NONE;
    }
    default:
        return CO_ABORT_READ_ONLY; /* snapshot and drive fields are read only */
    }
}

static int app_send(void *ctx, const hal_can_frame *f)
{
    (void)ctx;
    return hal_can_send(f);
}

static int app_open(void *ctx, uint32_t bitrate_bps)
{
    (void)ctx;
    return hal_can_open(bitrate_bps);
}

static bool app_running(void *ctx) { return drive_co_running(ctx); }

/* CiA 402 abort connection option 0x6007: what losing the master (heartbeat,
 * RPDO timeout), a bus-off, or an NMT stop or reset does to a drive whose
 * operation is enabled. The device reports each event once (a bus-off once
 * per entry), and a reaction under way is not restarted. */
static void app_event(void *ctx, co_event ev)
{
    drive *d = ctx;
    (void)ev; /* every connection event gets the same reaction */
    drive_ident_stop(d); /* a lost master ends an identification run, whatever 0x6007 says */
    bool enabled = d->co.cia402.state == CO_CIA402_OPERATION_ENABLED || d->run;
    if (!enabled || d->quick_stop_req)
        return;
    switch (d->app.abort_option) {
    case 1: /* fault: coast and show the fault state until a fault reset */
        d->drive_faults |= DRIVE_FAULT_COMM;
        drive_set_run(d, false);
        break;
    case 2: /* disable voltage: coast */
        drive_set_run(d, false);
        co_cia402_disable_voltage(&d->co.cia402);
        break;
    case 3: /* quick stop */
        (void)co_cia402_quick_stop(&d->co.cia402);
        quick_stop(d);
        break;
    default: /* 0: no action */
        break;
    }
}

/* An NMT reset waits for a quick stop in progress to end. */
static bool app_reset_ready(void *ctx)
{
    const drive *d = ctx;
    return !d->quick_stop_req;
}

/* NMT reset node: stop, then parameters as at power-on. */
static void app_reset_node(void *ctx)
{
    drive *d = ctx;
    d->quick_stop_req = false;
    drive_set_run(d, false);
    bool bus_ref = ref_is_bus_target(d);
    (void)persist_load(&d->persist);
    if (bus_ref)
        apply_target(d); /* under the stored vl limits */
    scope_stop(&d->scope);
}

static void app_booted(void *ctx)
{
    drive *d = ctx;
    if (d->persist.status == PERSIST_CORRUPT || d->persist.status == PERSIST_OLD_FORMAT)
        co_emcy_event(&d->co, &co_emcy_table[CO_EMCY_PARAM_SET_LOST], true);
    /* After a watchdog reset, once per start (not after NMT resets): an event, not latched. */
    if (d->reset_cause == HAL_RESET_WATCHDOG && !d->reset_cause_sent) {
        d->reset_cause_sent = true;
        co_emcy_event(&d->co, &co_emcy_table[CO_EMCY_WATCHDOG_RESET], false);
    }
}

/* ------------------------------------------------------------ public */

void drive_co_init(drive *d)
{
    co_app *a = &d->co_app;
    memset(a, 0, sizeof *a);
    a->od = drive_od;
    a->tpdo = co_tpdo_maps;
    a->n_tpdo = (uint8_t)CO_TPDO_COUNT;
    a->rpdo = co_rpdo_maps;
    a->n_rpdo = (uint8_t)CO_RPDO_COUNT;
    a->emcy = co_emcy_table;
    a->n_emcy = (uint8_t)CO_EMCY_COUNT;
    a->default_node_id = (uint8_t)CO_DEFAULT_NODE_ID;
    a->ctx = d;
    a->send = app_send;
    a->open = app_open;
    a->read = app_read;
    a->write = app_write;
    a->domain_size = domain_size;
    a->domain_read = domain_read;
    a->running = app_running;
    a->event = app_event;
    a->reset_ready = app_reset_ready;
    a->reset_node = app_reset_node;
    a->booted = app_booted;
    co_dev_init(&d->co, a);
}

void drive_co_defaults(drive *d)
{
    /* Communication and scope settings come from the table's defaults (the
     * control configuration from ctl_cfg_default, which a test keeps equal). */
    co_dev_comm_defaults(&d->co);
    for (uint32_t i = 0u; i < CO_PARAM_COUNT; i++) {
        const co_param *p = &co_params[i];
        if (p->bind == DRIVE_BIND_SCOPE || p->bind == DRIVE_BIND_APP)
            drive_co_apply(d, p, &p->def, NULL);
    }
}

void drive_co_apply(drive *d, const co_param *p, const co_num *raw, ctl_cfg *edit)
{
    co_num in = co_od_to_internal(p, raw);
    switch (p->bind) {
    case DRIVE_BIND_FN:
        (void)fn_write(d, p, &in);
        break;
    case DRIVE_BIND_CFG:
        if (edit != NULL)
            co_field_set(edit, p, &in);
        break;
    case DRIVE_BIND_SCOPE:
        co_field_set(&d->scope.cfg, p, &in);
        break;
    case DRIVE_BIND_APP:
        co_field_set(&d->app, p, &in);
        derive_quick_stop(d);
        break;
    case CO_BIND_COMM:
        co_field_set(&d->co.comm, p, &in);
        break;
    default:
        break;
    }
}

/* Control ticks per second from the configured period (5000 at 200 us). */
static uint32_t tick_hz(const drive *d)
{
    float period = drive_cfg(d)->period_s;
    if (!(period > 1e-6f && period < 1.0f))
        return CO_TICK_HZ;
    return (uint32_t)(1.0f / period + 0.5f);
}

void drive_co_process(drive *d)
{
    drive_read_snapshot(d, &d->bg_snap);
    if (d->quick_stop_req && d->bg_snap.quick_stop_done) {
        d->quick_stop_req = false;
        drive_set_run(d, false);
        co_cia402_quick_stop_done(&d->co.cia402);
    }
    hal_can_state bus;
    hal_can_get_state(&bus);
    co_pass pass = {hal_millis(), d->bg_snap.tick, tick_hz(d), d->bg_snap.tel.faults | d->drive_faults,
                    bus.bus_off, bus.bus_off_count};
    co_dev_begin_pass(&d->co, &pass);
    /* a warning rising: one EMCY, not latched (the fault word and the error register stay as they are) */
    uint32_t warn = d->bg_snap.tel.warnings;
    if ((warn & ~d->warnings_seen & (uint32_t)CTL_WARN_SPEED_DEV) != 0u)
        co_emcy_event(&d->co, &co_emcy_table[CO_EMCY_SPEED_DEV_WARNING], false);
    d->warnings_seen = warn;

    hal_can_frame f;
    for (uint32_t i = 0u; i < CO_RX_BUDGET && hal_can_recv(&f) == HAL_OK; i++)
        co_dev_rx(&d->co, &f);

    bool faulted = d->bg_snap.tel.state == (uint8_t)CTL_FAULTED || d->drive_faults != 0u;
    co_cia402_sync(&d->co.cia402, faulted, d->run);
    co_dev_end_pass(&d->co);
}
