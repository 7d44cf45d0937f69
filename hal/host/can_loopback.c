/**
 * @file can_loopback.c
 * @brief In-memory CAN backend: two frame rings that tests read and write.
 *
 * Nothing here blocks: a full ring refuses the frame (HAL_EBUSY) and counts
 * it, as a full transmit mailbox would.
 */
#include "hal_host/hal_host.h"

#include <string.h>

static int queue_push(hal_host_can_queue *q, const hal_can_frame *f)
{
    if (q->count >= HAL_HOST_CAN_QUEUE_LEN) {
        q->dropped++;
        return HAL_EBUSY;
    }
    q->frame[(q->head + q->count) % HAL_HOST_CAN_QUEUE_LEN] = *f;
    q->count++;
    return HAL_OK;
}

static int queue_pop(hal_host_can_queue *q, hal_can_frame *f)
{
    if (q->count == 0u)
        return HAL_EAGAIN;
    *f = q->frame[q->head];
    q->head = (q->head + 1u) % HAL_HOST_CAN_QUEUE_LEN;
    q->count--;
    return HAL_OK;
}

/* Backend side: the drive sends into from_drive and receives from to_drive. */
static int loopback_send(void *ctx, const hal_can_frame *f)
{
    hal_host_can_loopback *q = ctx;
    if (q->bus_off)
        return HAL_EIO; /* off the bus: nothing can be sent */
    return queue_push(&q->from_drive, f);
}

static int loopback_recv(void *ctx, hal_can_frame *f)
{
    hal_host_can_loopback *q = ctx;
    while (q->bus_off && queue_pop(&q->to_drive, f) == HAL_OK)
        q->lost_bus_off++; /* sent while we were off the bus: never seen */
    return queue_pop(&q->to_drive, f);
}

static void loopback_state(void *ctx, hal_can_state *out)
{
    const hal_host_can_loopback *q = ctx;
    out->bus_off = q->bus_off;
    out->bus_off_count = q->bus_off_count;
}

void hal_host_can_loopback_init(hal_host_can_loopback *q, hal_host_can_backend *out)
{
    memset(q, 0, sizeof *q);
    out->ctx = q;
    out->send = loopback_send;
    out->recv = loopback_recv;
    out->wait_rx = NULL;
    out->state = loopback_state;
}

int hal_host_can_loopback_inject(hal_host_can_loopback *q, const hal_can_frame *f)
{
    if (f->id > 0x7FFu || f->dlc > 8u)
        return HAL_EINVAL;
    return queue_push(&q->to_drive, f);
}

int hal_host_can_loopback_take(hal_host_can_loopback *q, hal_can_frame *f)
{
    return queue_pop(&q->from_drive, f);
}

void hal_host_can_loopback_set_bus_off(hal_host_can_loopback *q, bool on)
{
    if (on && !q->bus_off)
        q->bus_off_count++;
    q->bus_off = on;
}
