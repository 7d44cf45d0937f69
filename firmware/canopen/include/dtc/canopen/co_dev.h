/**
 * @file co_dev.h
 * @brief A CANopen slave device (CiA 301 with the CiA 402 state machine):
 *        communication settings, the protocol objects, and one background
 *        pass in three calls.
 *
 * The application owns the device and drives it once per background pass:
 * co_dev_begin_pass() (start-up: open CAN, boot-up; the pass's clock, tick and
 * fault word), co_dev_rx() for each received frame (dispatch by COB-ID: NMT,
 * SDO, RPDO; NMT resets carried out), co_dev_end_pass() (SDO timeout,
 * heartbeat, EMCY, telemetry TPDOs). Everything the device needs of the
 * application comes through the co_app interface it was given. Nothing here
 * blocks. Context: BG only.
 */
#ifndef DTC_CANOPEN_CO_DEV_H
#define DTC_CANOPEN_CO_DEV_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "dtc/canopen/co_app.h"
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

#define CO_RX_BUDGET 16u /**< received frames an application should hand over per pass at most */

/** Communication settings (parameters 0x1017, 0x2500; persisted). */
typedef struct {
    uint8_t node_id;        /**< node id 1..127 used from the next boot or NMT reset */
    uint8_t nmt_autostart;  /**< 1: operational right after boot-up */
    uint16_t bitrate_kbps;  /**< 125, 250, 500, 1000, from the next boot or NMT reset */
    uint16_t heartbeat_ms;  /**< producer heartbeat period, ms (0: off) */
    uint16_t telemetry_hz;  /**< telemetry TPDO rate, Hz (0: off) */
    uint32_t hb_consumer;   /**< 0x1016:1 heartbeat consumer: bits 23..16 node id, 15..0 time ms (0: off) */
    uint16_t rpdo_timeout_ms; /**< 0x1400:5 RPDO1 event timer: once started, RPDO1 is expected this often (0: off) */
    uint16_t emcy_inhibit_100us; /**< 0x1015 least time between two EMCY messages, 100 us */
    uint8_t error_behaviour; /**< 0x1029:1 on a communication error: 0 pre-operational, 1 no change, 2 stopped */
} co_comm_cfg;

/** What the application tells the device at the start of a pass. */
typedef struct {
    uint32_t now_ms;  /**< millisecond clock, wraps at 2^32 */
    uint32_t tick;    /**< the application's control-tick counter (telemetry pacing) */
    uint32_t tick_hz; /**< control ticks per second, >= 1 */
    uint32_t faults;  /**< the application's fault word (EMCY, error register 0x1001) */
    bool bus_off;     /**< the CAN controller is off the bus now (hal_can_state.bus_off) */
    uint32_t bus_off_count; /**< its bus-off entries so far (hal_can_state.bus_off_count), wraps */
} co_pass;

typedef struct co_dev {
    const co_app *app;      /**< the application's interface (not owned) */
    co_comm_cfg comm;       /**< settings (parameters) */
    uint8_t node_id;        /**< node id in use */
    bool started;           /**< CAN opened and boot-up sent */
    co_pass pass;           /**< this pass's clock, tick and faults */
    co_nmt nmt;
    co_sdo_server sdo;
    co_emcy emcy;
    co_err_history err_history; /**< 0x1003, kept over NMT resets (cleared by co_dev_init) */
    co_pdo pdo;
    co_cia402 cia402;
    uint32_t rx_frames;     /**< frames received since boot */
    bool reset_announced;   /**< the pending NMT reset was told to the application */
    bool bus_primed;        /**< bus_off_count holds the controller's count */
    bool bus_off_pending;   /**< a bus-off was reported: EMCY 0x8140 once back on the bus */
    uint32_t bus_off_count; /**< the controller's bus-off count last seen */
} co_dev;

/**
 * Bind the device to @p app (kept by pointer), communication settings to the
 * dictionary's defaults, not started. Context: BG.
 */
void co_dev_init(co_dev *c, const co_app *app);

/** Set the communication settings (CO_BIND_COMM entries) to their defaults. Context: BG. */
void co_dev_comm_defaults(co_dev *c);

/**
 * Start a pass: remember @p pass; the first time (and after resets) open CAN
 * and boot up. A bus-off entry seen in @p pass (its count moved) is a
 * communication error: the NMT state per 0x1029 and the application's event
 * CO_EVENT_BUS_OFF, once per entry; back on the bus, EMCY 0x8140 (recovered
 * from bus-off). Context: BG.
 */
void co_dev_begin_pass(co_dev *c, const co_pass *pass);

/** Handle one received frame; an NMT reset it carries is carried out at once. Context: BG. */
void co_dev_rx(co_dev *c, const hal_can_frame *f);

/** Finish a pass: SDO timeout, heartbeat, EMCY for new faults, telemetry TPDOs when due. Context: BG. */
void co_dev_end_pass(co_dev *c);

/**
 * A communication error (heartbeat lost, RPDO timeout): EMCY @p emcy_code
 * (error register bit 4), the NMT state per 0x1029, then the application's
 * event hook. Context: BG.
 */
void co_dev_comm_error(co_dev *c, co_event ev, uint16_t emcy_code);

/** Send a frame through the application. @return 0 when queued, < 0 when refused. Context: BG. */
int co_dev_send(co_dev *c, uint16_t id, uint8_t dlc, const uint8_t *data);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_DEV_H */
