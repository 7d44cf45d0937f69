/**
 * @file hal_types.h
 * @brief Plain data types shared by the HAL contract and the control code.
 *
 * These types are the whole vocabulary a board and the firmware exchange. They
 * contain no vendor types and their layout does not depend on build flags, so
 * the host SIL, the PIL build and the target run the same structs.
 */
#ifndef HAL_HAL_TYPES_H
#define HAL_HAL_TYPES_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Return codes of HAL functions: 0 on success, a negative code otherwise. */
enum hal_status {
    HAL_OK = 0,
    HAL_EIO = -5,     /**< hardware or backend failure */
    HAL_EAGAIN = -11, /**< nothing available now (no frame, stale sample) */
    HAL_EBUSY = -16,  /**< queue full; try again later */
    HAL_EINVAL = -22, /**< argument out of range */
    HAL_ENOSPC = -28, /**< address outside the device */
};

/** Three-level leg state of one NPC phase leg (output relative to the DC-link midpoint). */
typedef enum {
    HAL_LEG_N = 0, /**< leg tied to the negative rail: -vc2 */
    HAL_LEG_O = 1, /**< leg clamped to the neutral point: 0 V */
    HAL_LEG_P = 2, /**< leg tied to the positive rail: +vc1 */
} hal_leg_state;

/** One switching state of the inverter: a leg state per phase a, b, c. */
typedef struct {
    uint8_t leg[3]; /**< hal_leg_state for phases a, b, c */
} hal_vector;

/**
 * Everything the board samples at the start of a control tick.
 * Currents are phase currents flowing into the motor; their sum is ideally 0.
 */
typedef struct {
    float ia_A, ib_A, ic_A; /**< phase currents, A, range +-current full scale */
    float vc1_V;            /**< upper DC-link capacitor voltage (P to neutral point), V, >= 0 */
    float vc2_V;            /**< lower DC-link capacitor voltage (neutral point to N), V, >= 0 */
    float speed_meas_rad_s; /**< measured mechanical speed, rad/s: diagnostics only, never control */
    bool speed_meas_valid;  /**< false when the board has no speed sensor */
    uint32_t seq;           /**< tick sequence number; a repeated value marks a stale sample */
} hal_sample;

/**
 * What the firmware applies during the next control period: vector[0] for
 * duty0 of the period, then vector[1] for the rest. duty0 = 1 applies only
 * vector[0]. The board must never step a leg directly between P and N; the
 * firmware guarantees it between consecutive vectors, including across periods.
 */
typedef struct {
    hal_vector vector[2]; /**< vectors in the order applied */
    float duty0;          /**< fraction of the period for vector[0], 0..1 */
} hal_actuation;

/** A classic CAN frame (11-bit identifiers only; CANopen uses no extended ids). */
typedef struct {
    uint16_t id;     /**< 11-bit identifier, 0..0x7FF */
    uint8_t dlc;     /**< data length, 0..8 */
    bool rtr;        /**< remote transmission request */
    uint8_t data[8]; /**< payload; bytes past dlc are undefined */
} hal_can_frame;

/** The CAN controller's condition on the bus (hal_can_get_state). */
typedef struct {
    bool bus_off;            /**< off the bus now (bus-off, or its recovery still under way): nothing is sent or received */
    uint32_t bus_off_count;  /**< bus-off events since power-on (each entry into bus-off counts once), wraps at 2^32 */
} hal_can_state;

#ifdef __cplusplus
}
#endif

#endif /* HAL_HAL_TYPES_H */
