/**
 * @file co_sdo.h
 * @brief CANopen SDO server (CiA 301): expedited and segmented upload and
 *        download on 0x600 + id (requests) / 0x580 + id (responses).
 *
 * One transfer at a time; a new initiate request replaces an unfinished one.
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
} co_sdo_state;

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
} co_sdo_server;

/** Forget any transfer. Context: BG. */
void co_sdo_init(co_sdo_server *s);

/** Handle one request frame (COB-ID 0x600 + node id) and send the response. Context: BG. */
void co_sdo_rx(struct co_dev *c, const hal_can_frame *f);

/** Abort (0x05040000) a segmented transfer idle for more than CO_SDO_TIMEOUT_MS. Context: BG. */
void co_sdo_poll(struct co_dev *c);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_SDO_H */
