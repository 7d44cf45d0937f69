/**
 * @file co_cia402.h
 * @brief A small CiA 402-style device control state machine: controlword
 *        0x6040 in, statusword 0x6041 out, and the action the application
 *        must take (run, stop, fault reset).
 *
 * States: switch on disabled -> (shutdown 0x06) ready to switch on ->
 * (switch on 0x07) switched on -> (enable operation 0x0F) operation enabled
 * (machine running). Disable voltage (bit 1 = 0) returns to switch on disabled
 * and stops at once; quick stop (bits 2..1 = 01) from operation enabled enters
 * quick stop active (the application ramps down and calls
 * co_cia402_quick_stop_done), from the other states switch on disabled;
 * disable operation (0x07) returns to switched on and stops. A latched fault shows as the fault state; a rising
 * edge of bit 7 (fault reset) clears it into switch on disabled. The state
 * follows the machine when something else starts or stops it (co_cia402_sync).
 * The state machine does nothing itself: it tells the application what to do.
 * Context: BG only.
 */
#ifndef DTC_CANOPEN_CO_CIA402_H
#define DTC_CANOPEN_CO_CIA402_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    CO_CIA402_SWITCH_ON_DISABLED = 0,
    CO_CIA402_READY_TO_SWITCH_ON = 1,
    CO_CIA402_SWITCHED_ON = 2,
    CO_CIA402_OPERATION_ENABLED = 3,
    CO_CIA402_FAULT = 4,
    CO_CIA402_QUICK_STOP_ACTIVE = 5,
} co_cia402_state;

/** What a controlword asks the application to do. */
typedef enum {
    CO_CIA402_KEEP = 0,        /**< nothing changes for the machine */
    CO_CIA402_STOP = 1,        /**< stop (gates off) */
    CO_CIA402_RUN = 2,         /**< start (or keep running) */
    CO_CIA402_FAULT_RESET = 3, /**< stop and clear the faults that are no longer active */
    CO_CIA402_QUICK_STOP = 4,  /**< ramp down (quick stop option 0x605A), then stop */
} co_cia402_action;

typedef struct {
    uint8_t state;        /**< co_cia402_state */
    uint16_t controlword; /**< last controlword written */
} co_cia402;

/** Switch on disabled, controlword 0. Context: BG. */
void co_cia402_init(co_cia402 *c);

/** Apply a controlword (from SDO or RPDO). @return the action for the application. Context: BG. */
co_cia402_action co_cia402_controlword(co_cia402 *c, uint16_t cw);

/** Enter quick stop active from operation enabled (e.g. the abort connection option). @return true if entered. Context: BG. */
bool co_cia402_quick_stop(co_cia402 *c);

/** The quick stop ramp has ended (machine stopped): switch on disabled. Context: BG. */
void co_cia402_quick_stop_done(co_cia402 *c);

/** Disable voltage from the application (e.g. the abort connection option): switch on disabled. Context: BG. */
void co_cia402_disable_voltage(co_cia402 *c);

/**
 * Follow the machine: @p faulted (a fault is latched) and @p running (the
 * run command is on, whoever gave it). Call every pass. Context: BG.
 */
void co_cia402_sync(co_cia402 *c, bool faulted, bool running);

/** The statusword: state bits, bit 9 remote, bit 10 from @p target_reached in operation enabled. Context: BG. */
uint16_t co_cia402_statusword(const co_cia402 *c, bool target_reached);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_CIA402_H */
