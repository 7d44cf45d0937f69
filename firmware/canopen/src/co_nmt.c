/**
 * @file co_nmt.c
 * @brief NMT slave: command handling, boot-up message, heartbeat producer.
 */
#include "dtc/canopen/co_nmt.h"

#include "dtc/canopen/co_dev.h"

#define HEARTBEAT_BASE 0x700u

void co_nmt_init(co_nmt *n, uint8_t state, uint32_t now_ms)
{
    n->state = state;
    n->reset_req = CO_NMT_RESET_NONE;
    n->hb_last_ms = now_ms;
    n->hbc_state = CO_HBC_WAITING;
    n->hbc_last_ms = now_ms;
}

void co_nmt_rx(co_nmt *n, uint8_t node_id, const hal_can_frame *f)
{
    if (f->rtr || f->dlc != 2u)
        return;
    if (f->data[1] != 0u && f->data[1] != node_id)
        return;
    switch (f->data[0]) {
    case CO_NMT_CMD_START:
        n->state = CO_NMT_OPERATIONAL;
        break;
    case CO_NMT_CMD_STOP:
        n->state = CO_NMT_STOPPED;
        break;
    case CO_NMT_CMD_PRE_OPERATIONAL:
        n->state = CO_NMT_PRE_OPERATIONAL;
        break;
    case CO_NMT_CMD_RESET_NODE:
        n->reset_req = CO_NMT_RESET_NODE;
        break;
    case CO_NMT_CMD_RESET_COMM:
        /* A node reset already pending includes the communication reset. */
        if (n->reset_req != CO_NMT_RESET_NODE)
            n->reset_req = CO_NMT_RESET_COMM;
        break;
    default:
        break; /* unknown command: ignored, as CiA 301 has no response to give */
    }
}

int co_nmt_send_bootup(struct co_dev *c)
{
    uint8_t b = 0u;
    return co_dev_send(c, (uint16_t)(HEARTBEAT_BASE + c->node_id), 1u, &b);
}

void co_nmt_heartbeat(struct co_dev *c, uint16_t period_ms, uint32_t now_ms)
{
    co_nmt *n = &c->nmt;
    if (period_ms == 0u) {
        n->hb_last_ms = now_ms; /* the first beat comes one period after switching on */
        return;
    }
    uint32_t since = now_ms - n->hb_last_ms;
    if (since < period_ms)
        return;
    /* Keep the beat on its grid; after a pause of two periods or more, restart it. */
    n->hb_last_ms = since >= 2u * (uint32_t)period_ms ? now_ms : n->hb_last_ms + period_ms;
    uint8_t b = n->state;
    (void)co_dev_send(c, (uint16_t)(HEARTBEAT_BASE + c->node_id), 1u, &b);
}

#define EMCY_HEARTBEAT_LOST 0x8130u /* CiA 301: life guard or heartbeat error */

bool co_nmt_consume(struct co_dev *c, const hal_can_frame *f)
{
    uint32_t cfg = c->comm.hb_consumer;
    uint32_t node = (cfg >> 16) & 0xFFu;
    if ((cfg & 0xFFFFu) == 0u || node == 0u || node > 127u || f->id != HEARTBEAT_BASE + node)
        return false;
    if (f->rtr || f->dlc != 1u)
        return true; /* the master's COB-ID, but not a heartbeat: no proof of life */
    c->nmt.hbc_state = CO_HBC_ACTIVE;
    c->nmt.hbc_last_ms = c->pass.now_ms;
    return true;
}

void co_nmt_consumer_check(struct co_dev *c, uint32_t now_ms)
{
    co_nmt *n = &c->nmt;
    uint32_t time_ms = c->comm.hb_consumer & 0xFFFFu;
    if (time_ms == 0u || n->hbc_state != CO_HBC_ACTIVE)
        return;
    if (now_ms - n->hbc_last_ms > time_ms) {
        n->hbc_state = CO_HBC_LOST;
        co_dev_comm_error(c, CO_EVENT_HEARTBEAT_LOST, EMCY_HEARTBEAT_LOST);
    }
}
