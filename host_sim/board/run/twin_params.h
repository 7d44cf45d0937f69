/* A scenario's [control] keys in the flashed image's parameter store (twin_params.c). */
#ifndef TWIN_PARAMS_H
#define TWIN_PARAMS_H
#include <stddef.h>

#include "board_twin/board.h"
#include "sim/scenario.h"

/* Write the [control] keys of `sc` into the parameter store of the image on `b` (the flash NVM
 * area of its linker script, __nvm_start/__nvm_size) before it is powered on, as `dtctune set
 * KEY VALUE` for each key and then `dtctune save` would leave it: on the host, the firmware's own
 * drive (drive_init loads the store the image holds), its dictionary's checked SDO path
 * (co_od_write, CO_WR_SDO) for each key and the store entry 0x1010:1 for the save, over a copy of
 * the image's NVM bytes that is then programmed into the board's flash. Keys are written in the
 * file's order (--set overrides included). Each key must be a stored (CO_F_PERSIST) dictionary
 * entry bound to the key's ctl_cfg field, the image must accept the value, and the value read back
 * after a reload of the store must be the one asked for; otherwise nothing is written and `err`
 * names the scenario's file:line (or the --set option) and the reason.
 * Returns 0 (also with no [control] keys: nothing is written), 2 for a refused key, 1 for a
 * problem of the image (no NVM area, a store the firmware cannot save). */
int twin_apply_control(board *b, const scenario *sc, char *err, size_t n);

#endif
