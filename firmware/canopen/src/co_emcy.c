/**
 * @file co_emcy.c
 * @brief Emergency producer and error register, driven by the application's
 *        table of fault bits and EMCY codes.
 */
#include "dtc/canopen/co_emcy.h"

#include <string.h>

#include "dtc/canopen/co_dev.h"

#define EMCY_BASE 0x080u
#define EMCY_GENERIC 0x1000u

void co_emcy_init(co_emcy *e) { memset(e, 0, sizeof *e); }

uint8_t co_emcy_error_register(const co_dev *c)
{
    const co_app *app = c->app;
    uint32_t faults = c->pass.faults;
    uint32_t reg = c->emcy.extra_reg;
    for (uint32_t i = 0u; i < app->n_emcy; i++)
        if ((app->emcy[i].fault_bit & faults) != 0u)
            reg |= 1u << app->emcy[i].reg_bit;
    if (reg != 0u || faults != 0u)
        reg |= 1u; /* generic error: set whenever any error is present */
    return (uint8_t)reg;
}

/* The inhibit time 0x1015 (100 us units) on the millisecond pass clock, rounded up. */
static bool inhibited(const co_dev *c)
{
    uint32_t inhibit_ms = ((uint32_t)c->comm.emcy_inhibit_100us + 9u) / 10u;
    return c->emcy.sent_once && c->pass.now_ms - c->emcy.last_ms < inhibit_ms;
}

int co_emcy_send(co_dev *c, uint16_t code, uint8_t error_register, uint32_t faults)
{
    if (inhibited(c))
        return -1;
    uint8_t b[8] = {(uint8_t)code, (uint8_t)(code >> 8), error_register, (uint8_t)faults,
                    (uint8_t)(faults >> 8), (uint8_t)(faults >> 16), (uint8_t)(faults >> 24), 0u};
    int rc = co_dev_send(c, (uint16_t)(EMCY_BASE + c->node_id), 8u, b);
    if (rc == 0) {
        c->emcy.sent_once = true;
        c->emcy.last_ms = c->pass.now_ms;
        if (code != 0x0000u) /* the return to no error is not an error */
            co_err_history_push(&c->err_history, code, error_register);
    }
    return rc;
}

/* An event's message: its own register bit is set in the error register it carries. */
static int send_event(co_dev *c, const co_emcy_entry *entry)
{
    uint8_t reg = (uint8_t)(co_emcy_error_register(c) | (1u << entry->reg_bit) | 1u);
    return co_emcy_send(c, entry->code, reg, c->pass.faults);
}

/* Send the oldest waiting event if the inhibit time allows. */
static void send_queued(co_dev *c)
{
    co_emcy *e = &c->emcy;
    if (e->n_queued == 0u || send_event(c, &e->queued[0]) != 0)
        return;
    e->n_queued--;
    for (uint32_t i = 0u; i < e->n_queued; i++)
        e->queued[i] = e->queued[i + 1u];
}

void co_emcy_poll(co_dev *c)
{
    co_emcy *e = &c->emcy;
    const co_app *app = c->app;
    uint32_t faults = c->pass.faults;
    send_queued(c);
    uint32_t fresh = faults & ~e->reported;
    uint32_t known = 0u;
    uint8_t reg = co_emcy_error_register(c);
    for (uint32_t i = 0u; i < app->n_emcy; i++) {
        uint32_t bit = app->emcy[i].fault_bit;
        known |= bit;
        if ((bit & fresh) != 0u && co_emcy_send(c, app->emcy[i].code, reg, faults) == 0)
            e->reported |= bit; /* a refused message is retried on the next pass */
    }
    /* Fault bits without a table entry are announced with the generic code. */
    uint32_t unknown = fresh & ~known;
    if (unknown != 0u && co_emcy_send(c, EMCY_GENERIC, reg, faults) == 0)
        e->reported |= unknown;
    if (faults == 0u) {
        if (e->reported != 0u && co_emcy_send(c, 0x0000u, reg, 0u) == 0)
            e->reported = 0u;
    } else {
        e->reported &= faults; /* a bit that cleared is announced again if it returns */
    }
}

void co_emcy_event(co_dev *c, const co_emcy_entry *entry, bool latch)
{
    co_emcy *e = &c->emcy;
    if (latch)
        e->extra_reg = (uint8_t)(e->extra_reg | (1u << entry->reg_bit) | 1u);
    for (uint32_t i = 0u; i < e->n_queued; i++)
        if (e->queued[i].code == entry->code)
            return; /* already waiting: one message per distinct error */
    if (e->n_queued == 0u && send_event(c, entry) == 0)
        return;
    if (e->n_queued < CO_EMCY_QUEUE)
        e->queued[e->n_queued++] = *entry;
}

void co_emcy_clear_extra(co_emcy *e) { e->extra_reg = 0u; }

void co_err_history_push(co_err_history *h, uint16_t code, uint8_t error_register)
{
    for (uint32_t i = CO_ERR_HISTORY - 1u; i > 0u; i--)
        h->entry[i] = h->entry[i - 1u];
    h->entry[0] = (uint32_t)code | ((uint32_t)error_register << 16);
    if (h->count < CO_ERR_HISTORY)
        h->count++;
}

uint32_t co_err_history_read(const co_err_history *h, uint8_t sub, uint32_t *value)
{
    *value = 0u;
    if (sub == 0u) {
        *value = h->count;
        return CO_ABORT_NONE;
    }
    if (sub > CO_ERR_HISTORY)
        return CO_ABORT_NO_SUB;
    *value = h->entry[sub - 1u]; /* above the count: 0 (cleared or never used) */
    return CO_ABORT_NONE;
}

void co_err_history_clear(co_err_history *h) { memset(h, 0, sizeof *h); }
