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

typedef struct {
    uint32_t reported;   /**< fault bits already announced */
    uint8_t extra_reg;   /**< error-register bits of conditions without a fault bit (parameter set lost) */
} co_emcy;

/** Forget what was announced. Context: BG. */
void co_emcy_init(co_emcy *e);

/** Error register for the fault bits @p faults plus the extra conditions (bit 0 set when any). Context: BG. */
uint8_t co_emcy_error_register(const co_emcy *e, uint32_t faults);

/** Send one emergency message. @return a HAL status. Context: BG. */
int co_emcy_send(uint8_t node_id, uint16_t code, uint8_t error_register, uint32_t faults);

/**
 * Announce fault bits set since the last call (one EMCY each) and the return
 * to no fault (code 0); bits whose message the queue refused are retried on
 * the next call. Context: BG.
 */
void co_emcy_poll(co_emcy *e, uint8_t node_id, uint32_t faults);

/**
 * Send the EMCY of a table event without a fault bit (CO_EMCY_PARAM_SET_LOST,
 * CO_EMCY_RPDO_LENGTH); @p latch keeps its error-register bit set until
 * co_emcy_clear_extra(). Context: BG.
 */
void co_emcy_event(co_emcy *e, uint8_t node_id, uint32_t table_index, uint32_t faults, bool latch);

/** Clear the latched extra conditions (after a successful save or restore). Context: BG. */
void co_emcy_clear_extra(co_emcy *e);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_EMCY_H */
