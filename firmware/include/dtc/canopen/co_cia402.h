/**
 * @file co_cia402.h
 * @brief A small CiA 402-style device control state machine: controlword
 *        0x6040 in, statusword 0x6041 out; starts and stops the drive with
 *        drive_set_run().
 *
 * States: switch on disabled -> (shutdown 0x06) ready to switch on ->
 * (switch on 0x07) switched on -> (enable operation 0x0F) operation enabled
 * (drive running). Disable voltage (bit 1 = 0) and quick stop (bits 2..1 =
 * 01) return to switch on disabled and stop; disable operation (0x07) returns
 * to switched on and stops. A latched fault shows as the fault state; a rising
 * edge of bit 7 (fault reset) clears it into switch on disabled. The state
 * follows the drive when something else starts or stops it (e.g. the SIL).
 * Context: BG only.
 */
#ifndef DTC_CANOPEN_CO_CIA402_H
#define DTC_CANOPEN_CO_CIA402_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct drive;

typedef enum {
    CO_CIA402_SWITCH_ON_DISABLED = 0,
    CO_CIA402_READY_TO_SWITCH_ON = 1,
    CO_CIA402_SWITCHED_ON = 2,
    CO_CIA402_OPERATION_ENABLED = 3,
    CO_CIA402_FAULT = 4,
} co_cia402_state;

typedef struct {
    uint8_t state;        /**< co_cia402_state */
    uint16_t controlword; /**< last controlword written */
} co_cia402;

/** Switch on disabled, controlword 0. Context: BG. */
void co_cia402_init(co_cia402 *c);

/** Apply a controlword (from SDO or RPDO). Context: BG. */
void co_cia402_controlword(struct drive *d, uint16_t cw);

/** Follow the drive's run command and fault state (call every pass). Context: BG. */
void co_cia402_sync(struct drive *d);

/** The statusword: state bits, bit 9 remote, bit 10 target reached. Context: BG. */
uint16_t co_cia402_statusword(const struct drive *d);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_CIA402_H */
