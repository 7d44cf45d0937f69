/**
 * @file persist.c
 * @brief Two-slot parameter storage with sequence numbers and CRC-32
 *        (layout and rules in dtc/persist.h). It reaches the values only
 *        through its persist_params.
 */
#include "dtc/persist.h"

#include <string.h>

#include "hal/hal.h"

#define RECORD_HEADER PERSIST_RECORD_HEADER
#define CHUNK 64u

uint32_t persist_crc32(uint32_t crc, const void *data, size_t len)
{
    const uint8_t *p = (const uint8_t *)data;
    uint32_t c = ~crc;
    for (size_t i = 0u; i < len; i++) {
        c ^= p[i];
        for (uint32_t k = 0u; k < 8u; k++)
            c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}

static void put16(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)v;
    b[1] = (uint8_t)(v >> 8);
}

static void put32(uint8_t *b, uint32_t v)
{
    put16(b, v);
    put16(b + 2, v >> 16);
}

static uint32_t get16(const uint8_t *b) { return (uint32_t)b[0] | ((uint32_t)b[1] << 8); }
static uint32_t get32(const uint8_t *b) { return get16(b) | (get16(b + 2) << 16); }

typedef struct {
    bool valid;      /**< header and CRC check out */
    bool erased;     /**< the header is all 0xFF (never written) */
    bool old_format; /**< the magic, but another format: a set an older firmware stored */
    bool io_error;   /**< the NVM could not be read */
    uint16_t count;  /**< records */
    uint32_t seq;
    uint32_t len;    /**< payload bytes */
} slot_info;

static uint32_t slot_size(void) { return hal_nvm_size() / 2u; }

static slot_info scan(uint32_t slot)
{
    slot_info si;
    memset(&si, 0, sizeof si);
    uint32_t base = slot * slot_size();
    uint8_t h[PERSIST_HEADER_SIZE];
    if (slot_size() < PERSIST_HEADER_SIZE || hal_nvm_read(base, h, sizeof h) != HAL_OK) {
        si.io_error = true;
        return si;
    }
    si.erased = true;
    for (uint32_t i = 0u; i < sizeof h; i++)
        si.erased = si.erased && h[i] == 0xFFu;
    if (get32(h) != PERSIST_MAGIC)
        return si;
    if (get16(h + 4) != PERSIST_FORMAT) {
        si.old_format = true;
        return si;
    }
    si.count = (uint16_t)get16(h + 6);
    si.seq = get32(h + 8);
    si.len = get32(h + 12);
    if (si.len > slot_size() - PERSIST_HEADER_SIZE)
        return si;
    uint32_t crc = persist_crc32(0u, h, 16u);
    uint8_t chunk[CHUNK];
    for (uint32_t at = 0u; at < si.len; at += CHUNK) {
        uint32_t n = si.len - at < CHUNK ? si.len - at : CHUNK;
        if (hal_nvm_read(base + PERSIST_HEADER_SIZE + at, chunk, n) != HAL_OK) {
            si.io_error = true;
            return si;
        }
        crc = persist_crc32(crc, chunk, n);
    }
    si.valid = crc == get32(h + 16);
    return si;
}

/* Newer by serial-number arithmetic (survives the wrap of the counter). */
static bool newer(uint32_t a, uint32_t b) { return (int32_t)(a - b) > 0; }

/* Index of the slot with the newest valid set, or -1. */
static int newest(const slot_info si[2])
{
    if (si[0].valid && si[1].valid)
        return newer(si[1].seq, si[0].seq) ? 1 : 0;
    if (si[0].valid)
        return 0;
    if (si[1].valid)
        return 1;
    return -1;
}

/* Hand the records of a valid slot to the owner; @return the number skipped. */
static uint32_t apply_slot(const persist_state *st, uint32_t slot, const slot_info *si)
{
    uint32_t base = slot * slot_size() + PERSIST_HEADER_SIZE;
    uint32_t at = 0u, skipped = 0u;
    for (uint32_t r = 0u; r < si->count; r++) {
        uint8_t rec[RECORD_HEADER];
        if (at + RECORD_HEADER > si->len || hal_nvm_read(base + at, rec, RECORD_HEADER) != HAL_OK)
            return skipped + (si->count - r);
        uint32_t n = rec[3];
        if (at + RECORD_HEADER + n > si->len)
            return skipped + (si->count - r);
        if (n > PERSIST_VALUE_MAX) { /* a value no owner of this firmware has: step over it */
            at += RECORD_HEADER + n;
            skipped++;
            continue;
        }
        persist_record v;
        v.index = (uint16_t)get16(rec);
        v.sub = rec[2];
        v.len = (uint8_t)n;
        if (hal_nvm_read(base + at + RECORD_HEADER, v.value, n) != HAL_OK)
            return skipped + (si->count - r);
        at += RECORD_HEADER + n;
        if (!st->params->take(st->ctx, &v))
            skipped++;
    }
    return skipped;
}

void persist_init(persist_state *st, const persist_params *params, void *ctx)
{
    memset(st, 0, sizeof *st);
    st->params = params;
    st->ctx = ctx;
    st->status = PERSIST_EMPTY;
}

uint8_t persist_load(persist_state *st)
{
    st->params->defaults(st->ctx);

    slot_info si[2] = {scan(0u), scan(1u)};
    int best = newest(si);
    uint32_t skipped = best >= 0 ? apply_slot(st, (uint32_t)best, &si[best]) : 0u;
    skipped += st->params->finish(st->ctx); /* the set as a whole, then in use */
    uint8_t status;
    if (best < 0) {
        if (si[0].io_error || si[1].io_error)
            status = PERSIST_NO_NVM;
        else if (si[0].erased && si[1].erased)
            status = PERSIST_EMPTY;
        else if ((si[0].old_format || si[0].erased) && (si[1].old_format || si[1].erased))
            status = PERSIST_OLD_FORMAT;
        else
            status = PERSIST_CORRUPT;
    } else {
        const slot_info *other = &si[best ^ 1];
        if (skipped > 0u)
            status = PERSIST_PARTIAL;
        else if (!other->valid && !other->erased)
            status = PERSIST_RECOVERED;
        else
            status = PERSIST_LOADED;
    }
    st->status = status;
    return status;
}

int persist_save(persist_state *st, persist_save_kind kind, uint8_t *work, size_t work_size)
{
    if (work_size < PERSIST_HEADER_SIZE)
        return HAL_ENOSPC;
    uint8_t *h = work, *payload = work + PERSIST_HEADER_SIZE;
    size_t room = work_size - PERSIST_HEADER_SIZE;
    uint32_t len = 0u, cursor = 0u;
    uint16_t count = 0u;
    persist_record rec;
    int more = 0;
    while (kind == PERSIST_SAVE_VALUES && (more = st->params->next(st->ctx, &cursor, &rec)) > 0) {
        if (rec.len > PERSIST_VALUE_MAX)
            return HAL_EIO;
        if (len + RECORD_HEADER + rec.len > room)
            return HAL_ENOSPC;
        put16(payload + len, rec.index);
        payload[len + 2u] = rec.sub;
        payload[len + 3u] = rec.len;
        memcpy(payload + len + RECORD_HEADER, rec.value, rec.len);
        len += RECORD_HEADER + rec.len;
        count++;
    }
    if (more < 0)
        return more;
    if (slot_size() < PERSIST_HEADER_SIZE + len)
        return HAL_ENOSPC;
    /* the slot not holding the newest set */
    slot_info si[2] = {scan(0u), scan(1u)};
    int best = newest(si);
    uint32_t target = best == 0 ? 1u : 0u;
    uint32_t seq = best < 0 ? 1u : si[best].seq + 1u;

    put32(h, PERSIST_MAGIC);
    put16(h + 4, PERSIST_FORMAT);
    put16(h + 6, count);
    put32(h + 8, seq);
    put32(h + 12, len);
    put32(h + 16, persist_crc32(persist_crc32(0u, h, 16u), payload, len));

    /* One write of header and payload, so each page of the slot is erased
     * once. Until every byte is written the slot does not validate (the
     * header's CRC covers the payload: a cut after the header leaves an
     * erased or torn payload that fails it), and the other slot still holds
     * the previous set. */
    int rc = hal_nvm_write(target * slot_size(), work, PERSIST_HEADER_SIZE + len);
    if (rc != HAL_OK)
        return rc;
    st->status = PERSIST_LOADED;
    st->saves++;
    return HAL_OK;
}
