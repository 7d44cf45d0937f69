/**
 * @file co_pdo.c
 * @brief Telemetry TPDOs (paced on the application's control tick) and the command RPDO.
 */
#include "dtc/canopen/co_pdo.h"

#include <string.h>

#include "dtc/canopen/co_dev.h"
#include "dtc/canopen/co_od.h"

#define CIA402_CONTROLWORD 0x6040u

void co_pdo_init(co_pdo *p)
{
    p->acc = 0u;
    p->last_tick = 0u;
    p->primed = false;
    p->rpdo_seen = false;
    p->rpdo_timed_out = false;
    p->rpdo_last_ms = 0u;
}

static void send_telemetry(co_dev *c)
{
    const co_app *app = c->app;
    co_pdo *p = &c->pdo;
    for (uint32_t m = 0u; m < app->n_tpdo; m++) {
        const co_pdo_map *map = &app->tpdo[m];
        uint8_t b[8] = {0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u};
        uint32_t pos = 0u;
        for (uint32_t i = 0u; i < map->n; i++) {
            const co_param *e = &app->od.params[map->param[i]];
            co_num v;
            v.u = 0u;
            (void)co_od_read_num(c, e, &v);
            co_num_encode(e->dtype, &v, &b[pos]);
            pos += (uint32_t)co_dtype_size(e->dtype);
        }
        if (co_dev_send(c, (uint16_t)(map->cob_base + c->node_id), map->bytes, b) != 0)
            p->dropped++;
    }
    p->seq++;
}

void co_pdo_tx_poll(co_dev *c)
{
    co_pdo *p = &c->pdo;
    uint32_t tick = c->pass.tick;
    if (!p->primed) {
        p->primed = true;
        p->last_tick = tick;
        p->acc = 0u;
        return;
    }
    uint32_t hz = c->pass.tick_hz;
    uint32_t rate = c->comm.telemetry_hz;
    uint32_t elapsed = tick - p->last_tick;
    p->last_tick = tick;
    if (rate == 0u) {
        p->acc = 0u;
        return;
    }
    if (rate > hz)
        rate = hz;
    if (elapsed > hz)
        elapsed = hz; /* a long pause: no backlog beyond one second */
    p->acc += elapsed * rate;
    if (p->acc < hz)
        return;
    /* One telemetry cycle per pass; what a slow pass missed is dropped. */
    p->acc = (p->acc - hz) % hz;
    send_telemetry(c);
}

void co_pdo_rx(co_dev *c, uint32_t num, const hal_can_frame *f)
{
    const co_app *app = c->app;
    if (num >= app->n_rpdo || f->rtr)
        return;
    const co_pdo_map *map = &app->rpdo[num];
    if (f->dlc < map->bytes) {
        static const co_emcy_entry rpdo_length = {0u, CO_EMCY_CODE_RPDO_LENGTH, 0u};
        co_emcy_event(c, &rpdo_length, false);
        return;
    }
    if (num == 0u) {
        c->pdo.rpdo_seen = true;
        c->pdo.rpdo_timed_out = false;
        c->pdo.rpdo_last_ms = c->pass.now_ms;
    }
    /* Everything but the controlword first, so enabling starts with the new reference. */
    for (uint32_t pass = 0u; pass < 2u; pass++) {
        uint32_t pos = 0u;
        for (uint32_t i = 0u; i < map->n; i++) {
            const co_param *e = &app->od.params[map->param[i]];
            size_t n = co_dtype_size(e->dtype);
            bool is_cw = e->index == CIA402_CONTROLWORD;
            if ((pass == 0u) != is_cw)
                (void)co_od_write(c, e, &f->data[pos], n, CO_WR_PDO);
            pos += (uint32_t)n;
        }
    }
}

#define EMCY_RPDO_TIMEOUT 0x8250u /* CiA 301: RPDO timeout */

void co_pdo_rx_check(co_dev *c, uint32_t now_ms)
{
    co_pdo *p = &c->pdo;
    uint32_t timeout = c->comm.rpdo_timeout_ms;
    if (timeout == 0u || !p->rpdo_seen || p->rpdo_timed_out)
        return;
    if (now_ms - p->rpdo_last_ms > timeout) {
        p->rpdo_timed_out = true;
        co_dev_comm_error(c, CO_EVENT_RPDO_TIMEOUT, EMCY_RPDO_TIMEOUT);
    }
}
