/**
 * @file co_dev.c
 * @brief The CANopen device: start-up, the background pass, NMT resets, and
 *        the handlers of the function-bound entries (speed reference, store,
 *        restore, CiA 402 words, scope, status).
 */
#include "dtc/canopen/co_dev.h"

#include <string.h>

#include "dtc/drive.h"
#include "dtc/param_table.h"
#include "dtc/persist.h"
#include "dtc/scope.h"
#include "hal/hal.h"

#define COB_NMT 0x000u
#define COB_RPDO1 0x200u
#define COB_SDO_RX 0x600u
#define SIGNATURE_SAVE 0x65766173u /* "save" */
#define SIGNATURE_LOAD 0x64616F6Cu /* "load" */

int co_dev_send(uint16_t id, uint8_t dlc, const uint8_t *data)
{
    hal_can_frame f;
    memset(&f, 0, sizeof f);
    f.id = id;
    f.dlc = dlc;
    if (dlc > 0u)
        memcpy(f.data, data, dlc);
    return hal_can_send(&f);
}

void co_dev_init(co_dev *c)
{
    memset(c, 0, sizeof *c);
    c->comm.node_id = (uint8_t)CO_DEFAULT_NODE_ID;
    c->node_id = (uint8_t)CO_DEFAULT_NODE_ID;
    co_nmt_init(&c->nmt, CO_NMT_INITIALISING, 0u);
    co_sdo_init(&c->sdo);
    co_emcy_init(&c->emcy);
    co_pdo_init(&c->pdo);
    co_cia402_init(&c->cia402);
}

void co_dev_defaults(struct drive *d)
{
    /* Communication and scope settings come from the table's defaults (the
     * control configuration from ctl_cfg_default, which a test keeps equal). */
    for (uint32_t i = 0u; i < CO_PARAM_COUNT; i++) {
        const co_param *p = &co_params[i];
        if (p->bind == CO_BIND_COMM || p->bind == CO_BIND_SCOPE)
            co_od_apply(d, p, &p->def, NULL);
    }
}

/* Boot-up (also after an NMT reset): node id and bit rate from the settings. */
static void start(struct drive *d, uint32_t now_ms)
{
    co_dev *c = &d->co;
    uint8_t id = c->comm.node_id;
    c->node_id = (id >= 1u && id <= 127u) ? id : (uint8_t)CO_DEFAULT_NODE_ID;
    (void)hal_can_open((uint32_t)c->comm.bitrate_kbps * 1000u);
    co_sdo_init(&c->sdo);
    co_pdo_init(&c->pdo);
    co_emcy_init(&c->emcy);
    (void)co_nmt_send_bootup(c->node_id);
    co_nmt_init(&c->nmt, c->comm.nmt_autostart != 0u ? CO_NMT_OPERATIONAL : CO_NMT_PRE_OPERATIONAL, now_ms);
    if (d->persist.status == PERSIST_CORRUPT)
        co_emcy_event(&c->emcy, c->node_id, CO_EMCY_PARAM_SET_LOST, d->bg_snap.tel.faults, true);
    c->started = true;
}

static void dispatch(struct drive *d, const hal_can_frame *f, uint32_t now_ms)
{
    co_dev *c = &d->co;
    uint8_t st = c->nmt.state;
    if (f->id == COB_NMT) {
        co_nmt_rx(&c->nmt, c->node_id, f);
    } else if (f->id == COB_SDO_RX + c->node_id) {
        if (st == CO_NMT_PRE_OPERATIONAL || st == CO_NMT_OPERATIONAL)
            co_sdo_rx(d, f, now_ms);
    } else if (f->id == COB_RPDO1 + c->node_id) {
        if (st == CO_NMT_OPERATIONAL)
            co_pdo_rx(d, 0u, f);
    }
    /* Everything else (other nodes, SYNC, TIME, our own COB-IDs) is not for us. */
}

void co_dev_process(struct drive *d)
{
    co_dev *c = &d->co;
    uint32_t now = hal_millis();
    drive_read_snapshot(d, &d->bg_snap);
    if (!c->started)
        start(d, now);

    hal_can_frame f;
    for (uint32_t i = 0u; i < CO_RX_BUDGET && hal_can_recv(&f) == HAL_OK; i++) {
        c->rx_frames++;
        dispatch(d, &f, now);
        if (c->nmt.reset_req != CO_NMT_RESET_NONE) {
            if (c->nmt.reset_req == CO_NMT_RESET_NODE) {
                /* Application reset: stop, then parameters as at power-on. */
                drive_set_run(d, false);
                (void)persist_load(d);
                scope_stop(&d->scope);
                co_cia402_init(&c->cia402);
            }
            start(d, now);
        }
    }

    co_sdo_poll(d, now);
    co_nmt_heartbeat(&c->nmt, c->node_id, c->comm.heartbeat_ms, now);
    if (c->nmt.state != CO_NMT_STOPPED)
        co_emcy_poll(&c->emcy, c->node_id, d->bg_snap.tel.faults);
    co_cia402_sync(d);
    if (c->nmt.state == CO_NMT_OPERATIONAL)
        co_pdo_tx_poll(d);
    else
        c->pdo.primed = false; /* pacing restarts when operational again */
}

/* ----------------------------------------------------------------- scope */

static uint32_t scope_arm_from_settings(struct drive *d)
{
    scope *s = &d->scope;
    scope_src src[SCOPE_CHANNELS];
    uint8_t n = 0u;
    for (uint32_t ch = 0u; ch < SCOPE_CHANNELS; ch++) {
        uint8_t sig = s->cfg.channel[ch];
        if (sig == 0u)
            continue;
        const co_param *p = co_od_find((uint16_t)CO_TEL_INDEX, sig, NULL);
        if (p == NULL || p->bind != CO_BIND_SNAP)
            return CO_ABORT_PARAM_INCOMPAT;
        src[n].offset = p->offset;
        src[n].kind = (uint8_t)(p->ckind == CO_CK_FLOAT ? SCOPE_SRC_F32
                                                       : (p->csize == 1u ? SCOPE_SRC_U8 : SCOPE_SRC_U32));
        n++;
    }
    if (s->cfg.decimation == 0u || s->cfg.pretrigger >= SCOPE_SAMPLES)
        return CO_ABORT_PARAM_INCOMPAT;
    scope_arm(s, src, n);
    return CO_ABORT_NONE;
}

uint32_t co_fn_domain_size(struct drive *d, const co_param *p)
{
    if (p->offset != CO_FN_SCOPE_DATA || scope_get_state(&d->scope) != SCOPE_DONE)
        return 0u;
    return (uint32_t)d->scope.n_ch * SCOPE_SAMPLES * 4u;
}

void co_fn_domain_read(struct drive *d, const co_param *p, uint32_t offset, uint8_t *buf, size_t n)
{
    memset(buf, 0, n);
    uint32_t size = co_fn_domain_size(d, p);
    const scope *s = &d->scope;
    for (size_t i = 0u; i < n; i++) {
        uint32_t at = offset + (uint32_t)i;
        if (at >= size)
            return;
        uint32_t sample = at / 4u;
        uint32_t ch = sample / SCOPE_SAMPLES;
        uint32_t j = sample % SCOPE_SAMPLES;
        /* Convert to the telemetry signal's bus units (e.g. rpm) as REAL32. */
        const co_param *sig = co_od_find((uint16_t)CO_TEL_INDEX, s->armed_channel[ch], NULL);
        co_num v;
        v.f = scope_value(s, ch, j) * (sig != NULL && sig->dtype == CO_DT_REAL32 ? sig->k : 1.0f);
        uint8_t b[4];
        co_num_encode(CO_DT_REAL32, &v, b);
        buf[i] = b[at % 4u];
    }
}

/* --------------------------------------------------------------- handlers */

uint32_t co_fn_read(struct drive *d, const co_param *p, co_num *v)
{
    v->u = 0u;
    switch ((co_fn_id)p->offset) {
    case CO_FN_SPEED_REF:
        v->f = d->speed_ref_rad_s;
        break;
    case CO_FN_ERROR_REGISTER:
        v->u = co_emcy_error_register(&d->co.emcy, d->bg_snap.tel.faults);
        break;
    case CO_FN_STORE:
    case CO_FN_RESTORE:
        v->u = 1u; /* saves on command only */
        break;
    case CO_FN_CONTROLWORD:
        v->u = d->co.cia402.controlword;
        break;
    case CO_FN_STATUSWORD:
        v->u = co_cia402_statusword(d);
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
    case CO_FN_SCOPE_DATA:
    case CO_FN_COUNT:
    default:
        return CO_ABORT_GENERAL;
    }
    return CO_ABORT_NONE;
}

uint32_t co_fn_write(struct drive *d, const co_param *p, const co_num *v)
{
    switch ((co_fn_id)p->offset) {
    case CO_FN_SPEED_REF:
        drive_set_speed_ref(d, v->f);
        return CO_ABORT_NONE;
    case CO_FN_STORE:
        if (v->u != SIGNATURE_SAVE)
            return CO_ABORT_STORE;
        if (persist_save(d) != HAL_OK)
            return CO_ABORT_STORE;
        co_emcy_clear_extra(&d->co.emcy);
        return CO_ABORT_NONE;
    case CO_FN_RESTORE:
        if (v->u != SIGNATURE_LOAD)
            return CO_ABORT_STORE;
        if (co_od_running(d))
            return CO_ABORT_STATE;
        /* Store the empty set first: if the NVM fails nothing has changed. */
        if (persist_save_defaults(d) != HAL_OK)
            return CO_ABORT_STORE;
        (void)persist_load(d);
        co_emcy_clear_extra(&d->co.emcy);
        return CO_ABORT_NONE;
    case CO_FN_CONTROLWORD:
        co_cia402_controlword(d, (uint16_t)v->u);
        return CO_ABORT_NONE;
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
