/**
 * @file co_dev.h
 * @brief The drive's CANopen device: communication settings, the protocol
 *        objects, the background pass, and the handlers of the object
 *        dictionary entries bound to functions (CO_BIND_FN).
 *
 * co_dev_process() is the whole of CANopen in one background pass: start-up
 * (open CAN, boot-up), a consistent telemetry snapshot for this pass, up to
 * CO_RX_BUDGET received frames dispatched by COB-ID (NMT, SDO, RPDO), NMT
 * resets, SDO timeout, heartbeat, EMCY, the CiA 402 state, telemetry TPDOs.
 * It never blocks and never touches state the interrupt owns.
 * Context: BG only.
 */
#ifndef DTC_CANOPEN_CO_DEV_H
#define DTC_CANOPEN_CO_DEV_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "dtc/canopen/co_cia402.h"
#include "dtc/canopen/co_emcy.h"
#include "dtc/canopen/co_nmt.h"
#include "dtc/canopen/co_od.h"
#include "dtc/canopen/co_pdo.h"
#include "dtc/canopen/co_sdo.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

struct drive;

#define CO_RX_BUDGET 16u /**< received frames handled per background pass at most */

/** Communication settings (parameters 0x1017, 0x2500; persisted). */
typedef struct {
    uint8_t node_id;        /**< node id 1..127 used from the next boot or NMT reset */
    uint8_t nmt_autostart;  /**< 1: operational right after boot-up */
    uint16_t bitrate_kbps;  /**< 125, 250, 500, 1000, from the next boot or NMT reset */
    uint16_t heartbeat_ms;  /**< producer heartbeat period, ms (0: off) */
    uint16_t telemetry_hz;  /**< telemetry TPDO rate, Hz (0: off) */
} co_comm_cfg;

typedef struct {
    co_comm_cfg comm;       /**< settings (parameters) */
    uint8_t node_id;        /**< node id in use */
    bool started;           /**< CAN opened and boot-up sent */
    co_nmt nmt;
    co_sdo_server sdo;
    co_emcy emcy;
    co_pdo pdo;
    co_cia402 cia402;
    uint32_t rx_frames;     /**< frames received since boot */
} co_dev;

/** Communication settings to their table defaults, not started. Context: BG. */
void co_dev_init(co_dev *c);

/** Set the communication and scope settings to the table defaults. Context: BG. */
void co_dev_defaults(struct drive *d);

/** One background pass of the CANopen device (see the file comment). Context: BG. */
void co_dev_process(struct drive *d);

/** Send a frame; counts refusals. @return a HAL status. Context: BG. */
int co_dev_send(uint16_t id, uint8_t dlc, const uint8_t *data);

/* ---------------------------------------------- handlers of fn.* entries */

/**
 * Read the internal value of a CO_BIND_FN entry, in the entry's internal unit
 * (the speed reference in rad/s; words and counters unscaled).
 * @return CO_ABORT_NONE or an abort code. Context: BG.
 */
uint32_t co_fn_read(struct drive *d, const co_param *p, co_num *internal);

/**
 * Apply a checked internal value (internal unit, as co_fn_read) to a
 * CO_BIND_FN entry. @return CO_ABORT_NONE (applied) or an abort code
 * (nothing changed). Context: BG.
 */
uint32_t co_fn_write(struct drive *d, const co_param *p, const co_num *internal);

/** Size in bytes of a domain entry's present content (0 while the scope has no capture). Context: BG. */
uint32_t co_fn_domain_size(struct drive *d, const co_param *p);

/**
 * Copy @p n bytes of a domain entry from byte @p offset into @p buf; bytes
 * past the present content read as 0. Context: BG.
 */
void co_fn_domain_read(struct drive *d, const co_param *p, uint32_t offset, uint8_t *buf, size_t n);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_DEV_H */
