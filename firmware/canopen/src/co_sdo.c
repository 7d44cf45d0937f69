/**
 * @file co_sdo.c
 * @brief SDO server: expedited and segmented transfers, CiA 301 aborts.
 *
 * Byte 0 of a request holds the client command specifier (ccs) in bits 7..5:
 * 0 download segment, 1 initiate download, 2 initiate upload, 3 upload
 * segment, 4 abort, 5 block upload (bits 1..0: 0 initiate, 1 end response,
 * 2 block acknowledge, 3 start); 6 (block download) is not supported.
 */
#include "dtc/canopen/co_sdo.h"

#include <string.h>

#include "dtc/canopen/co_dev.h"
#include "dtc/canopen/co_od.h"

#define SDO_TX 0x580u
#define CCS_DOWNLOAD_SEGMENT 0u
#define CCS_INITIATE_DOWNLOAD 1u
#define CCS_INITIATE_UPLOAD 2u
#define CCS_UPLOAD_SEGMENT 3u
#define CCS_ABORT 4u
#define CCS_BLOCK_UPLOAD 5u
/* Block upload sub-commands (request byte 0, bits 1..0). */
#define BLK_CS_INITIATE 0u
#define BLK_CS_END 1u
#define BLK_CS_ACK 2u
#define BLK_CS_START 3u
#define BLK_MAX_SEGMENTS 127u

void co_sdo_init(co_sdo_server *s) { memset(s, 0, sizeof *s); }

static void put_u32(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)v;
    b[1] = (uint8_t)(v >> 8);
    b[2] = (uint8_t)(v >> 16);
    b[3] = (uint8_t)(v >> 24);
}

static uint32_t get_u32(const uint8_t *b)
{
    return (uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) | ((uint32_t)b[3] << 24);
}

static void respond(co_dev *c, const uint8_t data[8])
{
    co_sdo_server *s = &c->sdo;
    if (co_dev_send(c, (uint16_t)(SDO_TX + c->node_id), 8u, data) == 0) {
        s->tx_pending = 0u;
        return;
    }
    if (data != s->tx_frame)
        memcpy(s->tx_frame, data, 8u); /* the queue is full: again on the next pass */
    s->tx_pending = 1u;
}

static void send_abort(co_dev *c, uint16_t index, uint8_t sub, uint32_t code)
{
    uint8_t b[8];
    b[0] = 0x80u;
    b[1] = (uint8_t)index;
    b[2] = (uint8_t)(index >> 8);
    b[3] = sub;
    put_u32(&b[4], code);
    respond(c, b);
    c->sdo.state = CO_SDO_IDLE;
}

/* Response to an initiate request: scs in bits 7..5 plus flags, the multiplexer, data. */
static void respond_mux(co_dev *c, uint8_t cmd, uint16_t index, uint8_t sub, const uint8_t data[4])
{
    uint8_t b[8] = {cmd, (uint8_t)index, (uint8_t)(index >> 8), sub, 0u, 0u, 0u, 0u};
    if (data != NULL)
        memcpy(&b[4], data, 4u);
    respond(c, b);
}

/* Start a segmented transfer of entry @p p: toggle 0, nothing moved yet. */
static void begin_transfer(co_dev *c, uint8_t state, const co_param *p, uint32_t size, uint32_t now_ms)
{
    co_sdo_server *s = &c->sdo;
    s->state = state;
    s->index = p->index;
    s->sub = p->sub;
    s->param = (uint16_t)(p - c->app->od.params);
    s->size = size;
    s->pos = 0u;
    s->toggle = 0u;
    s->last_ms = now_ms;
}

/* Check a segment request against the transfer in progress (@p want) and
 * its toggle bit; on a mismatch abort and return false. */
static bool segment_ok(co_dev *c, const uint8_t *req, uint8_t want)
{
    const co_sdo_server *s = &c->sdo;
    if (s->state != want) {
        bool busy = s->state != CO_SDO_IDLE;
        send_abort(c, busy ? s->index : 0u, busy ? s->sub : 0u, CO_ABORT_CMD);
        return false;
    }
    if (((req[0] >> 4) & 1u) != s->toggle) {
        send_abort(c, s->index, s->sub, CO_ABORT_TOGGLE);
        return false;
    }
    return true;
}

static void initiate_download(co_dev *c, const uint8_t *req, uint32_t now_ms)
{
    co_sdo_server *s = &c->sdo;
    uint16_t index = (uint16_t)(req[1] | (req[2] << 8));
    uint8_t sub = req[3];
    uint32_t abort;
    s->state = CO_SDO_IDLE; /* a new initiate replaces any unfinished transfer */
    const co_param *p = co_od_find(&c->app->od, index, sub, &abort);
    if (p == NULL) {
        send_abort(c, index, sub, abort);
        return;
    }
    bool expedited = (req[0] & 0x02u) != 0u;
    bool size_ind = (req[0] & 0x01u) != 0u;
    if (expedited) {
        size_t n = size_ind ? 4u - ((req[0] >> 2) & 3u) : co_dtype_size(p->dtype);
        if (n == 0u)
            n = 4u;
        uint32_t rc = co_od_write(c, p, &req[4], n, CO_WR_SDO);
        if (rc != CO_ABORT_NONE) {
            send_abort(c, index, sub, rc);
            return;
        }
        respond_mux(c, 0x60u, index, sub, NULL);
        return;
    }
    /* Segmented: refuse at once what can never succeed. */
    if ((p->flags & CO_F_WRITE) == 0u || co_dtype_size(p->dtype) == 0u) {
        send_abort(c, index, sub, CO_ABORT_READ_ONLY);
        return;
    }
    uint32_t size = get_u32(&req[4]);
    if (size_ind && size != co_dtype_size(p->dtype)) {
        send_abort(c, index, sub, CO_ABORT_LENGTH);
        return;
    }
    begin_transfer(c, CO_SDO_DOWNLOAD, p, size_ind ? size : 0u, now_ms);
    s->size_known = size_ind ? 1u : 0u;
    respond_mux(c, 0x60u, index, sub, NULL);
}

static void download_segment(co_dev *c, const uint8_t *req, uint32_t now_ms)
{
    co_sdo_server *s = &c->sdo;
    if (!segment_ok(c, req, CO_SDO_DOWNLOAD))
        return;
    uint8_t t = s->toggle;
    uint32_t count = 7u - ((req[0] >> 1) & 7u);
    bool last = (req[0] & 1u) != 0u;
    if (s->pos + count > CO_SDO_BUF || (s->size_known && s->pos + count > s->size)) {
        send_abort(c, s->index, s->sub, CO_ABORT_LENGTH);
        return;
    }
    memcpy(&s->buf[s->pos], &req[1], count);
    s->pos += count;
    s->last_ms = now_ms;
    if (last) {
        if (s->size_known && s->pos != s->size) {
            send_abort(c, s->index, s->sub, CO_ABORT_LENGTH);
            return;
        }
        uint32_t rc = co_od_write(c, &c->app->od.params[s->param], s->buf, s->pos, CO_WR_SDO);
        if (rc != CO_ABORT_NONE) {
            send_abort(c, s->index, s->sub, rc);
            return;
        }
        s->state = CO_SDO_IDLE;
    }
    uint8_t b[8] = {(uint8_t)(0x20u | ((uint32_t)t << 4)), 0u, 0u, 0u, 0u, 0u, 0u, 0u};
    respond(c, b);
    s->toggle ^= 1u;
}

/* The entry @p index:@p sub if it exists and may be read; else the abort is
 * sent and NULL returned. */
static const co_param *find_readable(co_dev *c, uint16_t index, uint8_t sub)
{
    uint32_t abort;
    const co_param *p = co_od_find(&c->app->od, index, sub, &abort);
    if (p == NULL) {
        send_abort(c, index, sub, abort);
        return NULL;
    }
    if ((p->flags & CO_F_READ) == 0u) {
        send_abort(c, index, sub, CO_ABORT_WRITE_ONLY);
        return NULL;
    }
    return p;
}

/* The size of @p p (@p index:@p sub) for an upload, its value read into the
 * transfer buffer (a domain is read piecewise while it is sent). False when
 * the read is refused: the abort has been sent. */
static bool read_for_upload(co_dev *c, const co_param *p, uint16_t index, uint8_t sub, uint32_t *size)
{
    if (p->dtype == CO_DT_DOMAIN) {
        *size = c->app->domain_size(c->app->ctx, p);
        return true;
    }
    size_t len;
    uint32_t rc = co_od_read(c, p, c->sdo.buf, sizeof c->sdo.buf, &len);
    *size = (uint32_t)len;
    if (rc != CO_ABORT_NONE) {
        send_abort(c, index, sub, rc);
        return false;
    }
    return true;
}

static void initiate_upload(co_dev *c, const uint8_t *req, uint32_t now_ms)
{
    co_sdo_server *s = &c->sdo;
    uint16_t index = (uint16_t)(req[1] | (req[2] << 8));
    uint8_t sub = req[3];
    s->state = CO_SDO_IDLE;
    const co_param *p = find_readable(c, index, sub);
    if (p == NULL)
        return;
    uint32_t size;
    if (!read_for_upload(c, p, index, sub, &size))
        return;
    if (p->dtype != CO_DT_DOMAIN && size >= 1u && size <= 4u) {
        uint8_t data[4] = {0u, 0u, 0u, 0u};
        memcpy(data, s->buf, size);
        respond_mux(c, (uint8_t)(0x43u | ((4u - size) << 2)), index, sub, data);
        return;
    }
    /* Segmented upload with the size indicated (also for 0 bytes). */
    begin_transfer(c, CO_SDO_UPLOAD, p, size, now_ms);
    uint8_t data[4];
    put_u32(data, size);
    respond_mux(c, 0x41u, index, sub, data);
}

/* @p n bytes of the entry being uploaded from byte @p offset. */
static void upload_bytes(co_dev *c, uint32_t offset, uint8_t *buf, uint32_t n)
{
    const co_param *p = &c->app->od.params[c->sdo.param];
    if (p->dtype == CO_DT_DOMAIN)
        c->app->domain_read(c->app->ctx, p, offset, buf, n);
    else
        memcpy(buf, &c->sdo.buf[offset], n);
}

static void upload_segment(co_dev *c, const uint8_t *req, uint32_t now_ms)
{
    co_sdo_server *s = &c->sdo;
    if (!segment_ok(c, req, CO_SDO_UPLOAD))
        return;
    uint8_t t = s->toggle;
    uint32_t left = s->size - s->pos;
    uint32_t count = left < 7u ? left : 7u;
    bool last = count == left;
    uint8_t b[8] = {0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u};
    b[0] = (uint8_t)(((uint32_t)t << 4) | ((7u - count) << 1) | (last ? 1u : 0u));
    upload_bytes(c, s->pos, &b[1], count);
    s->pos += count;
    s->toggle ^= 1u;
    s->last_ms = now_ms;
    if (last)
        s->state = CO_SDO_IDLE;
    respond(c, b);
}

/* ------------------------------------------------------------ block upload */

uint16_t co_sdo_crc16(uint16_t crc, const uint8_t *data, uint32_t n)
{
    uint32_t r = crc; /* worked in 32 bits, kept to 16 */
    for (uint32_t i = 0u; i < n; i++) {
        r ^= (uint32_t)data[i] << 8;
        for (uint32_t b = 0u; b < 8u; b++)
            r = (r & 0x8000u) != 0u ? ((r << 1) ^ 0x1021u) & 0xFFFFu : (r << 1) & 0xFFFFu;
    }
    return (uint16_t)r;
}

static void initiate_block_upload(co_dev *c, const uint8_t *req, uint32_t now_ms)
{
    co_sdo_server *s = &c->sdo;
    uint16_t index = (uint16_t)(req[1] | (req[2] << 8));
    uint8_t sub = req[3];
    uint8_t blksize = req[4];
    s->state = CO_SDO_IDLE;
    const co_param *p = find_readable(c, index, sub);
    if (p == NULL)
        return;
    if (blksize == 0u || blksize > BLK_MAX_SEGMENTS) {
        send_abort(c, index, sub, CO_ABORT_BLKSIZE);
        return;
    }
    uint32_t size;
    if (!read_for_upload(c, p, index, sub, &size))
        return;
    /* The protocol switch threshold (byte 5) is not used: always a block transfer. */
    begin_transfer(c, CO_SDO_BLOCK_UPLOAD, p, size, now_ms);
    s->blk_phase = CO_SDO_BLK_INITIATED;
    s->blk_size = blksize;
    s->blk_sent = 0u;
    s->blk_last_seq = 0u;
    s->blk_crc_on = (req[0] & 0x04u) != 0u ? 1u : 0u;
    s->blk_crc = 0u;
    uint8_t data[4];
    put_u32(data, size);
    respond_mux(c, 0xC6u, index, sub, data); /* scs 6, CRC supported, size indicated */
}

/* Send the segments of the present block that the transmit queue takes; the
 * rest follow on later passes (co_sdo_poll). */
static void block_send(co_dev *c, uint32_t now_ms)
{
    co_sdo_server *s = &c->sdo;
    while (s->blk_phase == CO_SDO_BLK_SENDING) {
        uint32_t at = s->pos + 7u * s->blk_sent;
        uint32_t left = s->size > at ? s->size - at : 0u;
        uint32_t count = left < 7u ? left : 7u;
        bool last = count == left;
        uint8_t seq = (uint8_t)(s->blk_sent + 1u);
        uint8_t b[8] = {(uint8_t)(seq | (last ? 0x80u : 0u)), 0u, 0u, 0u, 0u, 0u, 0u, 0u};
        upload_bytes(c, at, &b[1], count);
        if (co_dev_send(c, (uint16_t)(SDO_TX + c->node_id), 8u, b) != 0)
            return; /* queue full: the same segment again on the next pass */
        s->blk_sent = seq;
        s->last_ms = now_ms;
        if (last)
            s->blk_last_seq = seq;
        if (last || seq == s->blk_size)
            s->blk_phase = CO_SDO_BLK_WAIT_ACK;
    }
}

/* The client acknowledged segments 1..ackseq of the block: they are final
 * (into the CRC); the next block starts after them, so unacknowledged ones
 * are sent again. After the last segment: the end, with the CRC. */
static void block_ack(co_dev *c, const uint8_t *req, uint32_t now_ms)
{
    co_sdo_server *s = &c->sdo;
    uint8_t ackseq = req[1];
    uint8_t blksize = req[2];
    if (ackseq > s->blk_sent) {
        send_abort(c, s->index, s->sub, CO_ABORT_SEQNO);
        return;
    }
    if (blksize == 0u || blksize > BLK_MAX_SEGMENTS) {
        send_abort(c, s->index, s->sub, CO_ABORT_BLKSIZE);
        return;
    }
    uint32_t acked = 7u * ackseq;
    if (acked > s->size - s->pos)
        acked = s->size - s->pos;
    if (s->blk_crc_on != 0u) {
        uint8_t chunk[7];
        for (uint32_t done = 0u; done < acked; done += 7u) {
            uint32_t n = acked - done < 7u ? acked - done : 7u;
            upload_bytes(c, s->pos + done, chunk, n);
            s->blk_crc = co_sdo_crc16(s->blk_crc, chunk, n);
        }
    }
    s->last_ms = now_ms;
    bool finished = s->blk_last_seq != 0u && ackseq >= s->blk_last_seq;
    s->pos += acked;
    if (finished) {
        uint32_t last_bytes = s->size - (s->pos - acked) - 7u * ((uint32_t)s->blk_last_seq - 1u);
        uint8_t b[8] = {(uint8_t)(0xC1u | ((7u - last_bytes) << 2)), (uint8_t)s->blk_crc,
                        (uint8_t)(s->blk_crc >> 8), 0u, 0u, 0u, 0u, 0u};
        if (s->blk_crc_on == 0u)
            b[1] = b[2] = 0u;
        s->blk_phase = CO_SDO_BLK_END;
        respond(c, b);
        return;
    }
    s->blk_size = blksize;
    s->blk_sent = 0u;
    s->blk_last_seq = 0u;
    s->blk_phase = CO_SDO_BLK_SENDING;
    block_send(c, now_ms);
}

static void block_upload(co_dev *c, const uint8_t *req, uint32_t now_ms)
{
    co_sdo_server *s = &c->sdo;
    uint32_t cs = req[0] & 3u;
    if (cs == BLK_CS_INITIATE) {
        initiate_block_upload(c, req, now_ms);
        return;
    }
    bool ok = s->state == CO_SDO_BLOCK_UPLOAD &&
              ((cs == BLK_CS_START && s->blk_phase == CO_SDO_BLK_INITIATED) ||
               (cs == BLK_CS_ACK && (s->blk_phase == CO_SDO_BLK_SENDING || s->blk_phase == CO_SDO_BLK_WAIT_ACK)) ||
               (cs == BLK_CS_END && s->blk_phase == CO_SDO_BLK_END));
    if (!ok) {
        bool busy = s->state != CO_SDO_IDLE;
        send_abort(c, busy ? s->index : 0u, busy ? s->sub : 0u, CO_ABORT_CMD);
        return;
    }
    switch (cs) {
    case BLK_CS_START:
        s->blk_phase = CO_SDO_BLK_SENDING;
        s->last_ms = now_ms;
        block_send(c, now_ms);
        break;
    case BLK_CS_ACK:
        block_ack(c, req, now_ms);
        break;
    default: /* BLK_CS_END: the client has it all */
        s->state = CO_SDO_IDLE;
        break;
    }
}

void co_sdo_rx(co_dev *c, const hal_can_frame *f)
{
    uint32_t now_ms = c->pass.now_ms;
    if (f->dlc != 8u || f->rtr)
        return;
    c->sdo.tx_pending = 0u; /* a new request: an answer still waiting is stale */
    switch ((uint32_t)f->data[0] >> 5) {
    case CCS_INITIATE_DOWNLOAD:
        initiate_download(c, f->data, now_ms);
        break;
    case CCS_DOWNLOAD_SEGMENT:
        download_segment(c, f->data, now_ms);
        break;
    case CCS_INITIATE_UPLOAD:
        initiate_upload(c, f->data, now_ms);
        break;
    case CCS_UPLOAD_SEGMENT:
        upload_segment(c, f->data, now_ms);
        break;
    case CCS_ABORT:
        c->sdo.state = CO_SDO_IDLE; /* the client gave up: no response */
        break;
    case CCS_BLOCK_UPLOAD:
        block_upload(c, f->data, now_ms);
        break;
    default: /* block download and reserved specifiers */
        send_abort(c, (uint16_t)(f->data[1] | (f->data[2] << 8)), f->data[3], CO_ABORT_CMD);
        break;
    }
}

void co_sdo_poll(co_dev *c)
{
    uint32_t now_ms = c->pass.now_ms;
    co_sdo_server *s = &c->sdo;
    if (s->tx_pending != 0u)
        respond(c, s->tx_frame);
    if (s->state == CO_SDO_BLOCK_UPLOAD && s->blk_phase == CO_SDO_BLK_SENDING && s->tx_pending == 0u)
        block_send(c, now_ms);
    if (s->state != CO_SDO_IDLE && now_ms - s->last_ms > CO_SDO_TIMEOUT_MS)
        send_abort(c, s->index, s->sub, CO_ABORT_TIMEOUT);
}
