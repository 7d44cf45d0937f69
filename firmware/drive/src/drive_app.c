/**
 * @file drive_app.c
 * @brief The drive application: composes the interrupt side (drive_isr.c),
 *        the CANopen binding (drive_co.c) and the parameter store (persist.c,
 *        bound to the drive's values by drive_params.c) into the object a
 *        board owns, and runs its background loop.
 *
 * Who calls whom (no file calls back up):
 *   drive_app -> drive_isr, drive_co, drive_ident, persist, drive_params
 *   drive_ident -> drive_isr
 *   drive_co -> drive_isr, persist      drive_params -> drive_co, drive_isr
 *   persist -> its persist_params only (function pointers), the HAL's NVM
 */
#include "dtc/drive.h"

#include <string.h>

#include "dtc/drive_co.h"
#include "dtc/drive_ident.h"
#include "dtc/drive_params.h"
#include "hal/hal.h"

void drive_init(drive *d)
{
    memset(d, 0, sizeof *d);
    drive_isr_init(d);
    d->reset_cause = (uint8_t)hal_reset_cause();
    drive_co_init(d);
    persist_init(&d->persist, &drive_params, d);
    (void)persist_load(&d->persist); /* defaults, then the stored set; status in d->persist */
    ctl_init(&d->ctl, drive_cfg(d)); /* the control state from the configuration in use */
}

void drive_background(drive *d)
{
    drive_co_process(d);
    drive_ident_background(d);
    hal_watchdog_kick();
}
