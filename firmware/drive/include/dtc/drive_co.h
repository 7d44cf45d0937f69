/**
 * @file drive_co.h
 * @brief The binding of the drive to its CANopen device: the drive's object
 *        dictionary (generated, dtc/param_table.h), the hooks of co_app, the
 *        handlers of the function-bound entries (speed reference, store,
 *        restore, CiA 402 words, scope, status) and the background pass.
 *
 * This is the one place where the drive's commands meet CANopen: the CANopen
 * layer (firmware/canopen) knows nothing of the drive, the interrupt side
 * knows nothing of CANopen, and the persistent values (drive_params.c) go
 * through this dictionary. The store's commands (0x1010 save, 0x1011
 * restore, an NMT reset node's reload) call the store object the
 * application bound (drive_app.c). Context: BG only.
 */
#ifndef DTC_DRIVE_CO_H
#define DTC_DRIVE_CO_H

#include "dtc/canopen/co_dev.h"
#include "dtc/ctl.h"
#include "dtc/drive.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Where the drive's dictionary entries live (co_param.bind, after the CANopen layer's own). */
enum drive_bind {
    DRIVE_BIND_CFG = CO_BIND_APP,  /**< ctl_cfg member at offset (written via drive_cfg_edit/commit) */
    DRIVE_BIND_SCOPE,              /**< scope_cfg member at offset (d->scope.cfg) */
    DRIVE_BIND_APP,                /**< drive_app_cfg member at offset (d->app: CiA 402 settings) */
    DRIVE_BIND_SNAP,               /**< drive_snapshot member at offset (the background copy d->bg_snap) */
    DRIVE_BIND_DRIVE,              /**< drive member at offset (read only) */
    DRIVE_BIND_FN,                 /**< a handler in drive_co.c; offset is a co_fn_id */
};

/** The drive's object dictionary (co_params of dtc/param_table.h). */
extern const co_dict drive_od;

/** Fill in d->co_app and initialise d->co bound to it. Context: BG, from drive_init (drive_app.c). */
void drive_co_init(drive *d);

/**
 * One CANopen pass: take the telemetry snapshot, start the device, hand it
 * up to CO_RX_BUDGET received frames, follow the CiA 402 state, then its
 * periodic duties (SDO timeout, heartbeat, EMCY, telemetry). Never blocks.
 * Context: BG.
 */
void drive_co_process(drive *d);

/** Communication and scope settings to the table's defaults. Context: BG. */
void drive_co_defaults(drive *d);

/**
 * Apply an already checked raw value to @p p; configuration entries go into
 * @p edit (a copy from drive_cfg_edit) which the caller commits. Used for
 * batches (a stored set, the defaults: drive_params.c). Context: BG.
 */
void drive_co_apply(drive *d, const co_param *p, const co_num *raw, ctl_cfg *edit);

/** @return true while the drive is commanded to run or is magnetising/running. Context: BG. */
bool drive_co_running(const drive *d);

#ifdef __cplusplus
}
#endif

#endif /* DTC_DRIVE_CO_H */
