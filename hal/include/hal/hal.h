/**
 * @file hal.h
 * @brief The hardware abstraction contract: what a board gives the firmware.
 *
 * One binding is linked per build (hal/host for the SIL, hal/stm32g4 for the
 * target, hal/pil for QEMU). Every function states its units, range and the
 * context it may be called from:
 *  - ISR: only from the control-tick interrupt;
 *  - BG:  only from the background loop (never from the interrupt);
 *  - ANY: either; such functions are constant-time and never block.
 * Errors are negative enum hal_status codes.
 */
#ifndef HAL_HAL_H
#define HAL_HAL_H

#include <stddef.h>
#include <stdint.h>

#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------ control tick */

/** Control-tick handler, called by the binding from the tick interrupt. */
typedef void (*hal_tick_handler)(void *ctx);

/**
 * Start the periodic control interrupt. The binding samples the ADCs at the
 * start of every period and then calls @p handler(@p ctx) in interrupt context.
 * @param period_us tick period, us; the product uses 200. Range 50..1000.
 * @return HAL_OK, HAL_EINVAL for a period out of range. Context: BG, once.
 */
int hal_tick_start(hal_tick_handler handler, void *ctx, uint32_t period_us);

/** Stop the control interrupt (the gates are disabled first). Context: BG. */
void hal_tick_stop(void);

/**
 * @return true when the next control tick became due before the current
 * handler finished (a missed deadline: the actuation latched in this tick
 * will be late). Read from the timer's own pending flag, not from a cycle
 * count, so it means the same on every board. Context: ISR, at the end of
 * the handler.
 */
bool hal_tick_missed(void);

/* ----------------------------------------------------- sample and actuation */

/**
 * Read this tick's sample (taken at the start of the period).
 * A sample can be read once: a second read in the same tick returns
 * HAL_EAGAIN, so a stale sample is refused rather than used.
 * @param[out] out the sample, in engineering units (A, V, rad/s).
 * @return HAL_OK or HAL_EAGAIN. Context: ISR.
 */
int hal_sample_read(hal_sample *out);

/**
 * Latch the vectors and duty split for the next period (double-buffered: what
 * is written during tick k is applied from the start of period k+1).
 * @return HAL_OK, HAL_EINVAL for a leg state > HAL_LEG_P or duty outside 0..1
 * (the previous actuation is then kept). Context: ISR.
 */
int hal_actuate(const hal_actuation *act);

/* ------------------------------------------------------- gates and faults */

/** Enable (true) or disable (false) the 12 gate drivers. Disabling is immediate. Context: ANY. */
void hal_gate_enable(bool enable);

/** @return true while the gate drivers are enabled. Context: ANY. */
bool hal_gate_enabled(void);

/**
 * @return true while the hardware fault input (desaturation, over-current
 * comparator) is active; the hardware has then already disabled the gates.
 * Context: ANY.
 */
bool hal_fault_input_active(void);

/* ------------------------------------------------------------ time */

/** Free-running cycle counter, wraps at 2^32. Context: ANY. */
uint32_t hal_cycles(void);

/** @return cycle-counter frequency, Hz (170e6 on the target). Context: ANY. */
uint32_t hal_cycles_hz(void);

/** Milliseconds since start, wraps at 2^32 (about 49 days). Context: ANY. */
uint32_t hal_millis(void);

/* ------------------------------------------------------------- CAN */

/**
 * Open the CAN controller at @p bitrate_bps (125000, 250000, 500000 or 1000000).
 * @return HAL_OK, HAL_EINVAL for another bit rate, HAL_EIO. Context: BG.
 */
int hal_can_open(uint32_t bitrate_bps);

/**
 * Queue a classic frame for transmission; never blocks.
 * @return HAL_OK, HAL_EBUSY when the transmit queue is full, HAL_EINVAL for
 * id > 0x7FF or dlc > 8, HAL_EIO. Context: BG.
 */
int hal_can_send(const hal_can_frame *frame);

/**
 * Take one received frame; never blocks.
 * @return HAL_OK with *frame filled, HAL_EAGAIN when none is waiting. Context: BG.
 */
int hal_can_recv(hal_can_frame *frame);

/**
 * The controller's bus condition. A controller whose transmit error counter
 * passes 255 goes bus-off (ISO 11898-1 fault confinement): it leaves the bus
 * and the binding starts the recovery by itself (on the STM32G4 after 100 ms;
 * the controller then waits for 128 x 11 recessive bits, about 5.6 ms at
 * 250 kbit/s). bus_off stays true until the controller takes part in traffic
 * again; bus_off_count counts every entry, so a bus-off shorter than the
 * caller's polling period is still seen. Constant time, never blocks.
 * @param[out] out the condition (bus_off false and count 0 before hal_can_open).
 * Context: BG.
 */
void hal_can_get_state(hal_can_state *out);

/* -------------------------------------------------------- non-volatile */

/** @return size of the non-volatile area, bytes. Context: ANY. */
uint32_t hal_nvm_size(void);

/**
 * Read @p len bytes at @p offset. @return HAL_OK, HAL_ENOSPC past the end,
 * HAL_EIO. Context: BG.
 */
int hal_nvm_read(uint32_t offset, void *buf, size_t len);

/**
 * Write @p len bytes at @p offset; a power loss may leave any prefix written.
 * @return HAL_OK, HAL_ENOSPC past the end, HAL_EIO. Context: BG.
 */
int hal_nvm_write(uint32_t offset, const void *buf, size_t len);

/* ------------------------------------------------------------ watchdog */

/** Start the independent watchdog with @p timeout_ms (1..4000). Context: BG, once. */
int hal_watchdog_start(uint32_t timeout_ms);

/** Refresh the watchdog. Context: BG (the background loop proves it is alive). */
void hal_watchdog_kick(void);

/* ------------------------------------------------------------ reset cause */

/** Why the processor last started (one value, the most specific cause). */
enum hal_reset_cause {
    HAL_RESET_UNKNOWN = 0,   /**< the binding cannot tell */
    HAL_RESET_POWER_ON = 1,  /**< power-on or brown-out */
    HAL_RESET_PIN = 2,       /**< the reset pin (button, debugger) */
    HAL_RESET_SOFTWARE = 3,  /**< a reset requested by software */
    HAL_RESET_WATCHDOG = 4,  /**< the independent watchdog expired */
    HAL_RESET_WINDOW_WATCHDOG = 5, /**< the window watchdog */
    HAL_RESET_LOW_POWER = 6, /**< an illegal low-power mode entry */
    HAL_RESET_OPTION_LOAD = 7,     /**< the option bytes were reloaded */
};

/**
 * @return the cause of the last reset (enum hal_reset_cause), as read by the
 * binding's start-up code; constant until the next reset. Context: ANY.
 */
uint32_t hal_reset_cause(void);

#ifdef __cplusplus
}
#endif

#endif /* HAL_HAL_H */
