/**
 * @file co_nmt.h
 * @brief CANopen NMT slave (CiA 301): states, commands on COB-ID 0x000,
 *        boot-up message and heartbeat producer (0x700 + node id).
 *
 * State changes take effect as soon as the command is processed; resets are
 * only requested here (reset_req) and carried out by the device (co_dev.c)
 * because they reach beyond communication. Context: BG only.
 */
#ifndef DTC_CANOPEN_CO_NMT_H
#define DTC_CANOPEN_CO_NMT_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

struct co_dev;

/** NMT states, numbered as in the heartbeat byte. */
typedef enum {
    CO_NMT_INITIALISING = 0x00,   /**< also the boot-up message */
    CO_NMT_STOPPED = 0x04,
    CO_NMT_OPERATIONAL = 0x05,
    CO_NMT_PRE_OPERATIONAL = 0x7F,
} co_nmt_state;

/** NMT command specifiers (byte 0 of a frame on COB-ID 0x000). */
enum {
    CO_NMT_CMD_START = 0x01,
    CO_NMT_CMD_STOP = 0x02,
    CO_NMT_CMD_PRE_OPERATIONAL = 0x80,
    CO_NMT_CMD_RESET_NODE = 0x81,
    CO_NMT_CMD_RESET_COMM = 0x82,
};

/** Reset requested by an NMT command, carried out by co_dev. */
typedef enum {
    CO_NMT_RESET_NONE = 0,
    CO_NMT_RESET_COMM = 1, /**< re-read node id and bit rate, boot up again */
    CO_NMT_RESET_NODE = 2, /**< also the application's own reset (co_app.reset_node: e.g. stop, reload what it stores) */
} co_nmt_reset;

/** Heartbeat consumer states (0x1016). */
typedef enum {
    CO_HBC_WAITING = 0, /**< configured, no heartbeat seen yet: not monitored (CiA 301) */
    CO_HBC_ACTIVE = 1,  /**< heartbeats arriving */
    CO_HBC_LOST = 2,    /**< none within the time: reported once, until one arrives again */
} co_hbc_state;

typedef struct {
    uint8_t state;         /**< co_nmt_state */
    uint8_t hbc_state;     /**< co_hbc_state */
    uint32_t hbc_last_ms;  /**< pass clock of the last consumed heartbeat */
    uint8_t reset_req;     /**< co_nmt_reset pending */
    uint32_t hb_last_ms;   /**< pass clock (now_ms) of the last heartbeat */
} co_nmt;

/** Enter @p state (pre-operational or operational) after boot-up at @p now_ms. Context: BG. */
void co_nmt_init(co_nmt *n, uint8_t state, uint32_t now_ms);

/**
 * Handle a frame on COB-ID 0x000. Only 2-byte data frames whose node byte is
 * 0 (all) or @p node_id count; others, and unknown commands, are ignored.
 * Context: BG.
 */
void co_nmt_rx(co_nmt *n, uint8_t node_id, const hal_can_frame *f);

/** Send the boot-up message (0x700 + id, one byte 0x00). @return a HAL status. Context: BG. */
int co_nmt_send_bootup(struct co_dev *c);

/**
 * Heartbeat producer: send the state every @p period_ms (0: off) of
 * the pass clock; after a long pause it resumes without a burst. Context: BG.
 */
void co_nmt_heartbeat(struct co_dev *c, uint16_t period_ms, uint32_t now_ms);

/**
 * Heartbeat consumer: a frame @p f on 0x700 + the configured node refreshes
 * it. @return true when @p f was that heartbeat. Context: BG.
 */
bool co_nmt_consume(struct co_dev *c, const hal_can_frame *f);

/**
 * Heartbeat consumer check at @p now_ms: once heartbeats have been seen, none
 * for the configured time is a communication error (reported once). Context: BG.
 */
void co_nmt_consumer_check(struct co_dev *c, uint32_t now_ms);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_NMT_H */
