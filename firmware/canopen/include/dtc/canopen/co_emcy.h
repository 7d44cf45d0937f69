/**
 * @file co_emcy.h
 * @brief CANopen emergency producer (0x80 + node id) and error register (0x1001).
 *
 * Codes and error-register classes come from the parameter table
 * ([[emcy]] entries -> co_emcy_table). One EMCY per newly latched fault bit,
 * code 0x0000 when every fault is gone. Frame: code (2 bytes little-endian),
 * error register, fault bits (4 bytes little-endian), 0. Context: BG only.
 */
#ifndef DTC_CANOPEN_CO_EMCY_H
#define DTC_CANOPEN_CO_EMCY_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct co_dev;

/** Error code and error-register bit of one fault bit of the application (or of an event). */
typedef struct {
    uint32_t fault_bit;       /**< bit of the application's fault word, 0 for events without one */
    uint16_t code;            /**< CiA 301 emergency error code */
    uint8_t reg_bit;          /**< error register bit (0 generic, 1 current, 2 voltage, 5 profile, 7 manufacturer) */
} co_emcy_entry;

/** The device's own event: an RPDO shorter than its mapping (CiA 301 0x8210, generic). */
#define CO_EMCY_CODE_RPDO_LENGTH 0x8210u
/** The device's own event: back on the bus after a bus-off (CiA 301 0x8140, communication). */
#define CO_EMCY_CODE_BUS_OFF_RECOVERED 0x8140u

#define CO_EMCY_QUEUE 4u /**< events waiting for the inhibit time (0x1015) at most */
#define CO_ERR_HISTORY 8u /**< errors kept in the history 0x1003 */

/**
 * The pre-defined error field 0x1003 (CiA 301): one entry per EMCY sent with
 * a non-zero code, newest first; an entry is the code (bits 15..0) and the
 * error register the message carried (bits 23..16). Kept over NMT resets.
 */
typedef struct {
    uint32_t entry[CO_ERR_HISTORY]; /**< entry[0] newest */
    uint8_t count;                  /**< entries recorded, 0..CO_ERR_HISTORY */
} co_err_history;

typedef struct {
    uint32_t reported;   /**< fault bits already announced */
    uint8_t extra_reg;   /**< error-register bits of latched events without a fault bit */
    bool sent_once;      /**< last_ms is valid */
    uint32_t last_ms;    /**< pass clock of the last EMCY sent (inhibit time) */
    uint8_t n_queued;    /**< events waiting */
    co_emcy_entry queued[CO_EMCY_QUEUE]; /**< distinct events waiting for the inhibit time, oldest first */
} co_emcy;

/** Forget what was announced. Context: BG. */
void co_emcy_init(co_emcy *e);

/**
 * Error register 0x1001 for the pass's fault word (the application's table
 * maps bits to register bits) plus the latched events; bit 0 set when any.
 * Context: BG.
 */
uint8_t co_emcy_error_register(const struct co_dev *c);

/**
 * Send one emergency message (code, error register, fault word), unless the
 * inhibit time 0x1015 since the last one has not passed. @return 0 when sent,
 * < 0 when refused (inhibited or the queue full). Context: BG.
 */
int co_emcy_send(struct co_dev *c, uint16_t code, uint8_t error_register, uint32_t faults);

/**
 * Announce fault bits set since the last call (one EMCY each, bits the table
 * does not name with the generic code 0x1000) and the return to no fault
 * (code 0); bits whose message the queue refused are retried on the next call.
 * Context: BG.
 */
void co_emcy_poll(struct co_dev *c);

/**
 * Send the EMCY of an event without a fault bit (@p entry: its code and
 * register bit); @p latch keeps the register bit set until
 * co_emcy_clear_extra(). Within the inhibit time the event waits (sent by a
 * later co_emcy_poll); an event whose code already waits is not queued twice,
 * so a flood of one error gives one message. Context: BG.
 */
void co_emcy_event(struct co_dev *c, const co_emcy_entry *entry, bool latch);

/** Clear the latched events (e.g. after a successful save or restore). Context: BG. */
void co_emcy_clear_extra(co_emcy *e);

/** Record an error: the oldest falls out when the history is full. Context: BG. */
void co_err_history_push(co_err_history *h, uint16_t code, uint8_t error_register);

/**
 * Sub @p sub of 0x1003: 0 the count, 1..count the entries newest first,
 * 0 above the count. @return CO_ABORT_NONE, CO_ABORT_NO_SUB above
 * CO_ERR_HISTORY. Context: BG.
 */
uint32_t co_err_history_read(const co_err_history *h, uint8_t sub, uint32_t *value);

/** Clear the history (0x1003:0 written with 0). Context: BG. */
void co_err_history_clear(co_err_history *h);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_EMCY_H */
