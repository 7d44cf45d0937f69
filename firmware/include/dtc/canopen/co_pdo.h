/**
 * @file co_pdo.h
 * @brief Telemetry TPDOs at a configurable rate and the command RPDO.
 *
 * The mappings are static and generated from the parameter table
 * (co_tpdo_maps, co_rpdo_maps). Every telemetry cycle sends all TPDOs from
 * one snapshot (the background copy d->bg_snap) and increments the sequence
 * counter they carry. The rate is paced on the control-tick counter of the
 * snapshot with a fractional accumulator, so any rate up to the tick rate
 * averages exactly; a background pass that falls behind drops cycles rather
 * than sending bursts. Context: BG only.
 */
#ifndef DTC_CANOPEN_CO_PDO_H
#define DTC_CANOPEN_CO_PDO_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

struct drive;

typedef struct {
    uint32_t acc;        /**< rate accumulator, Hz x ticks */
    uint32_t last_tick;  /**< snapshot tick of the previous pass */
    uint32_t seq;        /**< telemetry cycles sent (low 16 bits go on the bus) */
    uint32_t dropped;    /**< TPDO frames the transmit queue refused */
    bool primed;         /**< last_tick is valid */
} co_pdo;

/** Restart pacing (keeps the counters). Context: BG. */
void co_pdo_init(co_pdo *p);

/** Send the telemetry TPDOs when due (call every pass in operational state). Context: BG. */
void co_pdo_tx_poll(struct drive *d);

/**
 * Apply RPDO @p num (0-based) from frame @p f: a frame shorter than the
 * mapping is ignored and reported (EMCY 0x8210); each mapped value goes
 * through the checked write path (a refused value is skipped); the
 * controlword is applied last. Context: BG.
 */
void co_pdo_rx(struct drive *d, uint32_t num, const hal_can_frame *f);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_PDO_H */
