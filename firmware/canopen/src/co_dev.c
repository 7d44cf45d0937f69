/**
 * @file co_dev.c
 * @brief The CANopen device: start-up, frame dispatch, NMT resets and the
 *        periodic duties of a background pass.
 */
#include "dtc/canopen/co_dev.h"

#include <string.h>

#define COB_NMT 0x000u
#define COB_RPDO1 0x200u
#define COB_SDO_RX 0x600u

int co_dev_send(co_dev *c, uint16_t id, uint8_t dlc, const uint8_t *data)
{
    hal_can_frame f;
    memset(&f, 0, sizeof f);
    f.id = id;
    f.dlc = dlc;
    if (dlc > 0u)
        memcpy(f.data, data, dlc);
    return c->app->send(c->app->ctx, &f);
}

void co_dev_init(co_dev *c, const co_app *app)
{
    memset(c, 0, sizeof *c);
    c->app = app;
    c->node_id = app->default_node_id;
    co_dev_comm_defaults(c);
    co_nmt_init(&c->nmt, CO_NMT_INITIALISING, 0u);
    co_sdo_init(&c->sdo);
    co_emcy_init(&c->emcy);
    co_pdo_init(&c->pdo);
    co_cia402_init(&c->cia402);
}

void co_dev_comm_defaults(co_dev *c)
{
    for (uint32_t i = 0u; i < c->app->od.count; i++) {
        const co_param *p = &c->app->od.params[i];
        if (p->bind == CO_BIND_COMM) {
            co_num in = co_od_to_internal(p, &p->def);
            co_field_set(&c->comm, p, &in);
        }
    }
}

/* Boot-up (also after an NMT reset): node id and bit rate from the settings. */
static void start(co_dev *c)
{
    uint8_t id = c->comm.node_id;
    c->node_id = (id >= 1u && id <= 127u) ? id : c->app->default_node_id;
    (void)c->app->open(c->app->ctx, (uint32_t)c->comm.bitrate_kbps * 1000u);
    co_sdo_init(&c->sdo);
    co_pdo_init(&c->pdo);
    co_emcy_init(&c->emcy);
    (void)co_nmt_send_bootup(c);
    co_nmt_init(&c->nmt, c->comm.nmt_autostart != 0u ? CO_NMT_OPERATIONAL : CO_NMT_PRE_OPERATIONAL,
                c->pass.now_ms);
    c->started = true;
    c->reset_announced = false;
    c->app->booted(c->app->ctx);
}

/* A requested NMT reset is told to the application once, and carried out
 * when it says so: a machine that runs first reacts (for a CiA 402 drive
 * 0x6007, e.g. a quick stop) instead of being reset under way. */
static void service_reset(co_dev *c)
{
    if (c->nmt.reset_req == CO_NMT_RESET_NONE)
        return;
    if (!c->reset_announced) {
        c->reset_announced = true;
        c->app->event(c->app->ctx, CO_EVENT_RESET);
    }
    if (!c->app->reset_ready(c->app->ctx))
        return;
    if (c->nmt.reset_req == CO_NMT_RESET_NODE) {
        /* Application reset first: it stops and reloads what it stores. */
        c->app->reset_node(c->app->ctx);
        co_cia402_init(&c->cia402);
    }
    start(c);
}

/* A communication error's NMT state (0x1029), then the application's reaction. */
static void comm_error_reaction(co_dev *c, co_event ev)
{
    if (c->comm.error_behaviour == 0u && c->nmt.state == CO_NMT_OPERATIONAL)
        c->nmt.state = CO_NMT_PRE_OPERATIONAL;
    else if (c->comm.error_behaviour == 2u)
        c->nmt.state = CO_NMT_STOPPED;
    c->app->event(c->app->ctx, ev);
}

void co_dev_comm_error(co_dev *c, co_event ev, uint16_t emcy_code)
{
    const co_emcy_entry e = {0u, emcy_code, 4u}; /* error register bit 4: communication */
    co_emcy_event(c, &e, false);
    comm_error_reaction(c, ev);
}

/* Bus-off: nothing can be sent while off the bus, so the reaction comes at
 * once and the EMCY (0x8140, recovered from bus-off) when back on it. The
 * count, not the flag, tells a new entry: a bus-off shorter than a pass is
 * not missed, and a long one is reported once. */
static void watch_bus_off(co_dev *c)
{
    if (!c->bus_primed) {
        c->bus_primed = true;
        c->bus_off_count = c->pass.bus_off_count;
    }
    if (c->pass.bus_off_count != c->bus_off_count) {
        c->bus_off_count = c->pass.bus_off_count;
        c->bus_off_pending = true;
        comm_error_reaction(c, CO_EVENT_BUS_OFF);
    }
    if (c->bus_off_pending && !c->pass.bus_off) {
        const co_emcy_entry e = {0u, CO_EMCY_CODE_BUS_OFF_RECOVERED, 4u};
        c->bus_off_pending = false;
        co_emcy_event(c, &e, false);
    }
}

void co_dev_begin_pass(co_dev *c, const co_pass *pass)
{
    c->pass = *pass;
    if (c->pass.tick_hz == 0u)
        c->pass.tick_hz = 1u;
    if (!c->started)
        start(c);
    watch_bus_off(c);
}

void co_dev_rx(co_dev *c, const hal_can_frame *f)
{
    uint8_t st = c->nmt.state;
    c->rx_frames++;
    if (co_nmt_consume(c, f)) {
        /* the master's heartbeat: nothing else to do */
    } else if (f->id == COB_NMT) {
        co_nmt_rx(&c->nmt, c->node_id, f);
    } else if (f->id == COB_SDO_RX + c->node_id) {
        if (st == CO_NMT_PRE_OPERATIONAL || st == CO_NMT_OPERATIONAL)
            co_sdo_rx(c, f);
    } else if (f->id == COB_RPDO1 + c->node_id) {
        if (st == CO_NMT_OPERATIONAL)
            co_pdo_rx(c, 0u, f);
    }
    /* Everything else (other nodes, SYNC, TIME, our own COB-IDs) is not for us. */

    if (st != CO_NMT_STOPPED && c->nmt.state == CO_NMT_STOPPED)
        c->app->event(c->app->ctx, CO_EVENT_NMT_STOPPED);
    service_reset(c);
}

void co_dev_end_pass(co_dev *c)
{
    uint32_t now = c->pass.now_ms;
    service_reset(c);
    co_nmt_consumer_check(c, now);
    co_pdo_rx_check(c, now);
    co_sdo_poll(c);
    co_nmt_heartbeat(c, c->comm.heartbeat_ms, now);
    if (c->nmt.state != CO_NMT_STOPPED)
        co_emcy_poll(c);
    if (c->nmt.state == CO_NMT_OPERATIONAL)
        co_pdo_tx_poll(c);
    else
        c->pdo.primed = false; /* pacing restarts when operational again */
}
