/**
 * @file fdcan.h
 * @brief FDCAN1 as a classic CAN node: bit timing from PCLK1, the fixed
 *        message RAM layout with this node's acceptance filters, the Tx FIFO,
 *        Rx FIFO 0, and the bus-off recovery, all polled from the background.
 *        FDCAN1_IT0 (least urgent, never ahead of the control tick) only wakes
 *        the sleeping background when a frame came in or the Tx FIFO emptied.
 *        Private to hal/stm32g4.
 */
#ifndef HAL_STM32G4_FDCAN_H
#define HAL_STM32G4_FDCAN_H

#include <stdint.h>

#include "hal/hal_types.h"

/**
 * Open FDCAN1 at @p bitrate_bps (125, 250, 500 or 1000 kbit/s) with the
 * sample point nearest 87.5 %; accept NMT, SYNC, RPDO1..4, SDO requests and
 * heartbeats (standard ids), reject the rest. Needs the clock tree up
 * (clock_init()) and the pins in their FDCAN function. Context: BG.
 * @return HAL_OK, HAL_EINVAL for another bit rate, HAL_EIO when no bit
 * timing fits the clock or the controller did not enter initialisation.
 */
int fdcan_open(uint32_t bitrate_bps);

/**
 * Queue @p frame (standard id, classic CAN) in the Tx FIFO; never waits.
 * Context: BG.
 * @return HAL_OK, HAL_EINVAL for a NULL frame, id > 0x7FF or dlc > 8,
 * HAL_EIO while closed or bus-off, HAL_EBUSY when the FIFO is full.
 */
int fdcan_send(const hal_can_frame *frame);

/**
 * Take the oldest frame of Rx FIFO 0 into @p frame (extended and FD frames
 * are dropped). A FIFO overrun since the last call is counted. Context: BG.
 * @return HAL_OK, HAL_EINVAL for a NULL frame, HAL_EAGAIN when none waits or
 * the controller is closed.
 */
int fdcan_recv(hal_can_frame *frame);

/**
 * The controller's state into @p out (bus-off now, bus-off events since
 * open); runs the bus-off recovery like every other call: 100 ms after a
 * bus-off the controller rejoins by itself (BOARD_FAULT_CAN_BUSOFF recorded).
 * Context: BG.
 */
void fdcan_get_state(hal_can_state *out);

/**
 * @return how many times FDCAN1's interrupt woke the background since reset
 * (a frame received or the Tx FIFO emptied; wraps). Context: ANY.
 */
uint32_t fdcan_wakeups(void);

#endif /* HAL_STM32G4_FDCAN_H */
