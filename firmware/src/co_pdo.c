/**
 * @file co_pdo.c
 * @brief Telemetry TPDOs (paced on the control tick) and the command RPDO.
 */
#include "dtc/canopen/co_pdo.h"

#include <string.h>

#include "dtc/canopen/co_dev.h"
#include "dtc/canopen/co_od.h"
#include "dtc/drive.h"
#include "dtc/param_table.h"

void co_pdo_init(co_pdo *p)
{
    p->acc = 0u;
    p->last_tick = 0u;
    p->primed = false;
}

/* Control ticks per second from the configured period (5000 at 200 us). */
static uint32_t tick_hz(const struct drive *d)
{
    float period = drive_cfg(d)->period_s;
    if (!(period > 1e-6f && period < 1.0f))
        return CO_TICK_HZ;
    return (uint32_t)(1.0f / period + 0.5f);
}

static void send_telemetry(struct drive *d)
{
    co_pdo *p = &d->co.pdo;
    for (uint32_t m = 0u; m < CO_TPDO_COUNT; m++) {
        const co_pdo_map *map = &co_tpdo_maps[m];
        uint8_t b[8] = {0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u};
        uint32_t pos = 0u;
        for (uint32_t i = 0u; i < map->n; i++) {
            const co_param *e = &co_params[map->param[i]];
            co_num v;
            v.u = 0u;
            (void)co_od_read_num(d, e, &v);
            co_num_encode(e->dtype, &v, &b[pos]);
            pos += (uint32_t)co_dtype_size(e->dtype);
        }
        if (co_dev_send((uint16_t)(map->cob_base + d->co.node_id), map->bytes, b) != 0)
            p->dropped++;
    }
    p->seq++;
}

void co_pdo_tx_poll(struct drive *d)
{
    co_pdo *p = &d->co.pdo;
    uint32_t tick = d->bg_snap.tick;
    if (!p->primed) {
        p->primed = true;
        p->last_tick = tick;
        p->acc = 0u;
        return;
    }
    uint32_t hz = tick_hz(d);
    uint32_t rate = d->co.comm.telemetry_hz;
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
    send_telemetry(d);
}

void co_pdo_rx(struct drive *d, uint32_t num, const hal_can_frame *f)
{
    if (num >= CO_RPDO_COUNT || f->rtr)
        return;
    const co_pdo_map *map = &co_rpdo_maps[num];
    if (f->dlc < map->bytes) {
        co_emcy_event(&d->co.emcy, d->co.node_id, CO_EMCY_RPDO_LENGTH, d->bg_snap.tel.faults, false);
        return;
    }
    /* Everything but the controlword first, so enabling starts with the new reference. */
    for (uint32_t pass = 0u; pass < 2u; pass++) {
        uint32_t pos = 0u;
        for (uint32_t i = 0u; i < map->n; i++) {
            const co_param *e = &co_params[map->param[i]];
            size_t n = co_dtype_size(e->dtype);
            bool is_cw = map->param[i] == CO_P_CONTROLWORD;
            if ((pass == 0u) != is_cw)
                (void)co_od_write(d, e, &f->data[pos], n, CO_WR_PDO);
            pos += (uint32_t)n;
        }
    }
}
