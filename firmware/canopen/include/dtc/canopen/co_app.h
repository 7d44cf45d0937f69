/**
 * @file co_app.h
 * @brief What an application gives the CANopen device: its object
 *        dictionary and PDO/EMCY tables, and the hooks through which the
 *        device reaches everything that is not CANopen's own.
 *
 * The device (co_dev.h) knows constants, the node id and its communication
 * settings (co_comm_cfg). Every other entry (bind >= CO_BIND_APP) is read and
 * written through read/write, after the device has checked length, access,
 * range and state, so an application only decides what a value means. Frames
 * leave through send; the device never touches a board or an OS itself.
 *
 * All hooks are called in background context (BG) from co_dev functions, never
 * from an interrupt, and must not block. None may be NULL.
 */
#ifndef DTC_CANOPEN_CO_APP_H
#define DTC_CANOPEN_CO_APP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "dtc/canopen/co_emcy.h"
#include "dtc/canopen/co_nmt.h"
#include "dtc/canopen/co_od.h"
#include "dtc/canopen/co_pdo.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** What the device tells the application about its connection to the master. */
typedef enum {
    CO_EVENT_HEARTBEAT_LOST = 1, /**< the consumed heartbeat (0x1016) stopped */
    CO_EVENT_RPDO_TIMEOUT = 2,   /**< RPDO1 stopped arriving (event timer 0x1400:5) */
    CO_EVENT_NMT_STOPPED = 3,    /**< an NMT stop command: SDO and RPDO are ignored from now on */
    CO_EVENT_RESET = 4,          /**< an NMT reset (node or communication) is pending, see reset_ready */
    CO_EVENT_BUS_OFF = 5,        /**< the CAN controller went bus-off (co_pass.bus_off_count moved); once per entry */
} co_event;

typedef struct co_app {
    co_dict od;                  /**< the object dictionary, sorted by (index, sub) */
    const co_pdo_map *tpdo;      /**< telemetry TPDO mappings (sent together each cycle) */
    uint8_t n_tpdo;
    const co_pdo_map *rpdo;      /**< RPDO mappings (number = position) */
    uint8_t n_rpdo;
    const co_emcy_entry *emcy;   /**< EMCY code and error-register bit of each fault bit */
    uint8_t n_emcy;
    uint8_t default_node_id;     /**< 1..127, used when the node-id setting is out of range */
    void *ctx;                   /**< passed to every hook */

    /** Queue one frame; never blocks. @return 0 when queued, < 0 when refused. */
    int (*send)(void *ctx, const hal_can_frame *f);
    /** (Re)open the controller at @p bitrate_bps (at boot-up and communication resets). */
    int (*open)(void *ctx, uint32_t bitrate_bps);
    /** Internal value of an application entry. @return CO_ABORT_NONE or an abort code. */
    uint32_t (*read)(void *ctx, const co_param *p, co_num *internal);
    /** Apply a checked internal value. @return CO_ABORT_NONE, or an abort code and nothing changed. */
    uint32_t (*write)(void *ctx, const co_param *p, const co_num *internal);
    /** Bytes of a domain entry's present content. */
    uint32_t (*domain_size)(void *ctx, const co_param *p);
    /** @p n bytes of a domain entry from byte @p offset; bytes past the content read 0. */
    void (*domain_read)(void *ctx, const co_param *p, uint32_t offset, uint8_t *buf, size_t n);
    /** @return true while entries without CO_F_RUNTIME must not change (the machine runs). */
    bool (*running)(void *ctx);
    /** The master connection changed (CiA 402: apply the abort connection option 0x6007). */
    void (*event)(void *ctx, co_event ev);
    /** @return true when a pending NMT reset may be carried out now (e.g. the machine has stopped). */
    bool (*reset_ready)(void *ctx);
    /** An NMT reset-node command: the application's own reset (before the device boots up again). */
    void (*reset_node)(void *ctx);
    /** The device has just sent its boot-up message (power-on or NMT reset). */
    void (*booted)(void *ctx);
} co_app;

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_APP_H */
