/**
 * @file co_pdo.h
 * @brief Telemetry TPDOs at a configurable rate and the command RPDO.
 *
 * The mappings are static, given by the application (co_app tpdo, rpdo).
 * Every telemetry cycle sends all TPDOs, read in one pass (the application
 * reads a consistent snapshot), and increments the sequence counter they
 * carry. The rate is paced on the application's control-tick counter of the
 * pass with a fractional accumulator, so any rate up to the tick rate
 * averages exactly; a background pass that falls behind drops cycles rather
 * than sending bursts. An RPDO writes its entries in frame order, the CiA 402
 * controlword (0x6040) last, so enabling starts with the new reference.
 * Context: BG only.
 */
#ifndef DTC_CANOPEN_CO_PDO_H
#define DTC_CANOPEN_CO_PDO_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

struct co_dev;

/** A static PDO mapping. */
typedef struct {
    uint16_t cob_base;        /**< COB-ID without the node id */
    uint8_t n;                /**< mapped entries */
    uint8_t bytes;            /**< frame length */
    uint16_t param[8];        /**< position in the dictionary of each mapped entry, in frame order */
} co_pdo_map;

typedef struct {
    uint32_t acc;        /**< rate accumulator, Hz x ticks */
    uint32_t last_tick;  /**< snapshot tick of the previous pass */
    uint32_t seq;        /**< telemetry cycles sent (low 16 bits go on the bus) */
    uint32_t dropped;    /**< TPDO frames the transmit queue refused */
    bool primed;         /**< last_tick is valid */
    bool rpdo_seen;      /**< an RPDO1 arrived since boot-up: its event timer is monitored */
    bool rpdo_timed_out; /**< the timeout was reported (until the next RPDO1) */
    uint32_t rpdo_last_ms; /**< pass clock of the last RPDO1 */
} co_pdo;

/** Restart pacing (keeps the counters). Context: BG. */
void co_pdo_init(co_pdo *p);

/** Send the telemetry TPDOs when due (call every pass in operational state). Context: BG. */
void co_pdo_tx_poll(struct co_dev *c);

/**
 * Apply RPDO @p num (0-based) from frame @p f: a frame shorter than the
 * mapping is ignored and reported (EMCY 0x8210); each mapped value goes
 * through the checked write path (a refused value is skipped); the
 * controlword is applied last. Context: BG.
 */
void co_pdo_rx(struct co_dev *c, uint32_t num, const hal_can_frame *f);

/**
 * RPDO1 event timer (0x1400:5): once an RPDO1 has arrived, none for longer
 * than the timer is a communication error (reported once). Context: BG.
 */
void co_pdo_rx_check(struct co_dev *c, uint32_t now_ms);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_PDO_H */
