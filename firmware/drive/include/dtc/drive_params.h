/**
 * @file drive_params.h
 * @brief The drive's persistent parameters as the parameter store sees them:
 *        the persist_params the application binds the store to (drive_params.c).
 *
 * The values are the dictionary entries flagged CO_F_PERSIST, each as its bus
 * bytes under its index and subindex. A save lists them through the
 * dictionary's read path (co_od_read: what a client would upload). A load
 * starts from every default (the control configuration, the communication,
 * CiA 402 and scope settings) and applies each stored record through the
 * dictionary's checked path (co_od_check with CO_WR_LOAD), so a record for an
 * unknown or not persistent entry, or with a value the present firmware
 * refuses, is skipped, never applied; a control configuration ctl_cfg_check
 * refuses is not used at all (its defaults instead), and the configuration is
 * published with one drive_cfg_commit. The context of every hook is the drive.
 * Context: BG.
 */
#ifndef DTC_DRIVE_PARAMS_H
#define DTC_DRIVE_PARAMS_H

#include "dtc/persist.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The drive's side of the store's interface; ctx: the drive (struct drive *). */
extern const persist_params drive_params;

#ifdef __cplusplus
}
#endif

#endif /* DTC_DRIVE_PARAMS_H */
