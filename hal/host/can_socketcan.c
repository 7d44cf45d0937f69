/**
 * @file can_socketcan.c
 * @brief SocketCAN backend for the host HAL (Linux raw CAN socket).
 *
 * Classic 11-bit frames only (CANopen uses no extended identifiers). The
 * socket is non-blocking: send and receive return HAL_EBUSY / HAL_EAGAIN
 * instead of waiting, as the background loop must never block. The owner
 * may sleep in socketcan_wait_rx() (ppoll) between ticks; from then on an
 * empty receive queue is remembered, and recv() skips the read() system call
 * (which would only say EAGAIN) until the next wait sees a frame.
 * The controller's error frames (CAN_RAW_ERR_FILTER: bus-off, restarted)
 * arrive on the same socket; recv consumes them and state() reports them.
 */
#define _GNU_SOURCE /* ppoll */

#include "hal_host/hal_host.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

typedef struct {
    int fd;
    bool waited;  /* wait_rx has been used: trust rx_ready */
    bool rx_ready; /* a frame may be waiting (unknown counts as yes) */
    bool bus_off;  /* the last controller error frame said bus-off (until one says restarted) */
    uint32_t bus_off_count; /* CAN_ERR_BUSOFF error frames received */
} socketcan_ctx;

/* A controller error frame (linux/can/error.h): bus-off, or the restart that ends it. */
static void socketcan_error_frame(socketcan_ctx *c, canid_t id)
{
    if ((id & CAN_ERR_BUSOFF) != 0u) {
        if (!c->bus_off)
            c->bus_off_count++;
        c->bus_off = true;
    } else if ((id & CAN_ERR_RESTARTED) != 0u) {
        c->bus_off = false;
    }
}

static void socketcan_state(void *ctx, hal_can_state *out)
{
    const socketcan_ctx *c = ctx;
    out->bus_off = c->bus_off;
    out->bus_off_count = c->bus_off_count;
}

static int socketcan_send(void *ctx, const hal_can_frame *f)
{
    const socketcan_ctx *c = ctx;
    if (f->id > 0x7FFu || f->dlc > 8u)
        return HAL_EINVAL;
    struct can_frame cf;
    memset(&cf, 0, sizeof cf);
    cf.can_id = f->id | (f->rtr ? CAN_RTR_FLAG : 0u);
    cf.can_dlc = f->dlc;
    if (!f->rtr)
        memcpy(cf.data, f->data, f->dlc);
    ssize_t n = write(c->fd, &cf, sizeof cf);
    if (n == (ssize_t)sizeof cf)
        return HAL_OK;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS))
        return HAL_EBUSY; /* transmit queue full */
    return HAL_EIO;
}

static int socketcan_recv(void *ctx, hal_can_frame *f)
{
    socketcan_ctx *c = ctx;
    if (c->waited && !c->rx_ready)
        return HAL_EAGAIN; /* the last read found the queue empty and no wait saw a frame since */
    for (;;) {
        struct can_frame cf;
        ssize_t n = read(c->fd, &cf, sizeof cf);
        if (n < 0) {
            if (errno == EAGAIN || errno == EWOULDBLOCK) {
                c->rx_ready = false;
                return HAL_EAGAIN;
            }
            return errno == EINTR ? HAL_EAGAIN : HAL_EIO;
        }
        if (n != (ssize_t)sizeof cf)
            continue; /* not a classic frame */
        if (cf.can_id & CAN_ERR_FLAG) {
            socketcan_error_frame(c, cf.can_id);
            continue; /* the controller's condition, not a frame for the caller */
        }
        if (cf.can_id & CAN_EFF_FLAG)
            continue; /* extended frames are not ours */
        memset(f, 0, sizeof *f);
        f->id = (uint16_t)(cf.can_id & CAN_SFF_MASK);
        f->rtr = (cf.can_id & CAN_RTR_FLAG) != 0u;
        f->dlc = cf.can_dlc > 8u ? 8u : cf.can_dlc;
        memcpy(f->data, cf.data, 8u);
        return HAL_OK;
    }
}

static int socketcan_wait_rx(void *ctx, const struct timespec *timeout)
{
    socketcan_ctx *c = ctx;
    c->waited = true;
    if (c->rx_ready)
        return 1; /* frames left from the last pass: no need to ask */
    struct pollfd p = { .fd = c->fd, .events = POLLIN, .revents = 0 };
    int n = ppoll(&p, 1, timeout, NULL);
    if (n < 0)
        return errno == EINTR ? HAL_EAGAIN : HAL_EIO;
    if (n == 0)
        return 0;
    /* POLLIN, or an error condition that the next read() reports. */
    c->rx_ready = true;
    return 1;
}

int hal_host_socketcan_open(const char *iface, hal_host_can_backend *out)
{
    memset(out, 0, sizeof *out);
    if (iface == NULL || iface[0] == '\0' || strlen(iface) >= IFNAMSIZ)
        return -EINVAL;
    int fd = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (fd < 0)
        return -errno;
    int err = 0;
    unsigned int ifindex = if_nametoindex(iface);
    if (ifindex == 0u)
        err = ENODEV;
    int on = 1, off = 0;
    can_err_mask_t errs = CAN_ERR_BUSOFF | CAN_ERR_RESTARTED;
    if (err == 0 && (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_LOOPBACK, &on, sizeof on) != 0 ||
                     setsockopt(fd, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &off, sizeof off) != 0 ||
                     setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &errs, sizeof errs) != 0))
        err = errno;
    if (err == 0) {
        struct sockaddr_can addr;
        memset(&addr, 0, sizeof addr);
        addr.can_family = AF_CAN;
        addr.can_ifindex = (int)ifindex;
        if (bind(fd, (struct sockaddr *)&addr, sizeof addr) != 0)
            err = errno;
    }
    socketcan_ctx *c = NULL;
    if (err == 0) {
        c = malloc(sizeof *c);
        if (c == NULL)
            err = ENOMEM;
    }
    if (err != 0) {
        close(fd);
        return -err;
    }
    c->fd = fd;
    c->waited = false;
    c->rx_ready = true;
    c->bus_off = false;
    c->bus_off_count = 0u;
    out->ctx = c;
    out->send = socketcan_send;
    out->recv = socketcan_recv;
    out->wait_rx = socketcan_wait_rx;
    out->state = socketcan_state;
    return 0;
}

void hal_host_socketcan_close(hal_host_can_backend *b)
{
    if (b->send == socketcan_send && b->ctx != NULL) {
        socketcan_ctx *c = b->ctx;
        close(c->fd);
        free(c);
    }
    memset(b, 0, sizeof *b);
}
