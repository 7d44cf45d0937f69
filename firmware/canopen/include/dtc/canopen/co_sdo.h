/**
 * @file co_sdo.h
 * @brief CANopen SDO server (CiA 301): expedited and segmented upload and
 *        download, and block upload, on 0x600 + id (requests) / 0x580 + id
 *        (responses).
 *
 * Block upload (the scope capture's fast path): blocks of up to 127 segments
 * of 7 bytes, each block acknowledged by the client; segments it did not
 * acknowledge are sent again; CRC-16 (CCITT, polynomial 0x1021, initial 0)
 * over the data when the client asks for it. Segments that the transmit queue
 * refuses are sent on the following passes. Block download is not supported
 * (0x05040001).
 *
 * One transfer at a time; a new initiate request replaces an unfinished one.
 * An answer that the transmit queue refuses (e.g. full of telemetry TPDOs)
 * is not lost: it is sent again at the start of the next pass's duties, until
 * the client's next request makes it stale.
 * Values pass through the object dictionary's checked path (co_od.h), so a
 * refused request changes nothing. Segmented downloads are collected whole
 * and written only after the last segment. Domains (the scope capture) are
 * streamed segment by segment. Frames whose length is not 8 and remote frames
 * are ignored (no abort can be addressed reliably). Context: BG only.
 */
#ifndef DTC_CANOPEN_CO_SDO_H
#define DTC_CANOPEN_CO_SDO_H

#include <stdint.h>

#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

struct co_dev;

#define CO_SDO_BUF 64u            /**< bytes of one non-domain value (largest string) */
#define CO_SDO_TIMEOUT_MS 1000u   /**< idle time that aborts a segmented transfer */

typedef enum {
    CO_SDO_IDLE = 0,
    CO_SDO_DOWNLOAD = 1,
    CO_SDO_UPLOAD = 2,
    CO_SDO_BLOCK_UPLOAD = 3, /**< see co_sdo_block_phase */
} co_sdo_state;

/** Where a block upload stands. */
typedef enum {
    CO_SDO_BLK_INITIATED = 0, /**< initiate answered, waiting for the client's start */
    CO_SDO_BLK_SENDING = 1,   /**< sending the segments of a block */
    CO_SDO_BLK_WAIT_ACK = 2,  /**< the block is out, waiting for its acknowledge */
    CO_SDO_BLK_END = 3,       /**< end sent (size, CRC), waiting for the client's end response */
} co_sdo_block_phase;

typedef struct {
    uint8_t state;          /**< co_sdo_state */
    uint8_t toggle;         /**< toggle bit expected in the next segment */
    uint8_t sub;            /**< subindex of the transfer */
    uint8_t size_known;     /**< download: the client indicated the size */
    uint16_t index;         /**< index of the transfer */
    uint16_t param;         /**< position in the dictionary of the entry being transferred */
    uint32_t size;          /**< total bytes (upload) or indicated size (download) */
    uint32_t pos;           /**< bytes transferred so far */
    uint32_t last_ms;       /**< pass clock (now_ms) of the last request */
    uint8_t buf[CO_SDO_BUF];/**< value being uploaded, or download collected so far */
    /* block upload */
    uint8_t blk_phase;      /**< co_sdo_block_phase */
    uint8_t blk_size;       /**< segments per block the client accepts, 1..127 */
    uint8_t blk_sent;       /**< segments of this block sent (the last seqno) */
    uint8_t blk_last_seq;   /**< seqno of the segment that carried the last data, 0: not yet sent */
    uint8_t blk_crc_on;     /**< the client asked for the CRC */
    uint16_t blk_crc;       /**< CRC of the bytes acknowledged so far */
    /* an answer the transmit queue refused (full of TPDOs): sent again on the next pass */
    uint8_t tx_pending;     /**< tx_frame waits to be sent */
    uint8_t tx_frame[8];    /**< the refused answer */
} co_sdo_server;

/** Forget any transfer. Context: BG. */
void co_sdo_init(co_sdo_server *s);

/** Handle one request frame (COB-ID 0x600 + node id) and send the response. Context: BG. */
void co_sdo_rx(struct co_dev *c, const hal_can_frame *f);

/**
 * Send an answer the transmit queue refused; continue a block upload whose
 * segments it refused; abort (0x05040000) a transfer idle for more than
 * CO_SDO_TIMEOUT_MS. Context: BG.
 */
void co_sdo_poll(struct co_dev *c);

/** CRC-16 of CiA 301 block transfers (CCITT: polynomial 0x1021, no reflection) over @p n bytes, continuing @p crc (0 to start). Context: ANY. */
uint16_t co_sdo_crc16(uint16_t crc, const uint8_t *data, uint32_t n);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_SDO_H */
