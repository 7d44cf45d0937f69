/**
 * @file drive_ident.h
 * @brief The drive's identification run (dtc/ident.h) as a run state: the
 *        background starts it, runs its fits and writes its results to the
 *        motor model; the interrupt steps it in place of the control
 *        (drive_isr.c -> ctl_ident_step, dtc/ctl_ident.h).
 *
 * Who owns what (drive.h's ident_* members):
 *   - ident_on, ident_run: written by the background only (single words);
 *     the interrupt steps the run while ident_on, with ident_run as its
 *     command: drive_ident_stop() drops it and the next tick aborts to gates
 *     off (a CiA 402 disable, a quick stop, a lost master);
 *   - ident, ident_cfg, ident_res: dtc/ident.h's sharing rules (the
 *     interrupt writes the phase and the sums, the background the rest);
 *   - ident_error, ident_outcome, ident_applied: background.
 *
 * The run is refused unless the drive is stopped (no run command, the core
 * stopped with no fault latched, no quick stop), the rotor at rest (the last
 * speed estimate within 2 % of the rated speed; the run's probe then checks
 * the currents with the zero vector) and the link ready (above vdc_min_V).
 * At its end the results whose verdict is ok are written to the active
 * configuration (ident_apply: Rs, then Ls, Lr, Lm, Rr together; what depends
 * on them derived again), published with drive_cfg_commit. An aborted run
 * writes nothing: the configuration in use and the stored set stay as they
 * were. Nothing here stores: the results reach the NVM with a `save`.
 * Only the standstill part runs in the drive (a rotating start is refused
 * with DRIVE_IDENT_E_ROTATING).
 */
#ifndef DTC_DRIVE_IDENT_H
#define DTC_DRIVE_IDENT_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/ident.h"
#include "dtc/ratings_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct drive drive;

/** The drive's refusals beyond enum ident_error (negative). */
enum drive_ident_error {
    DRIVE_IDENT_E_ROTATING = -20, /**< the rotating part was asked for: not carried out by the drive */
    DRIVE_IDENT_E_CIA402 = -21,   /**< over CAN: the CiA 402 state is not "Switched on" */
};

/** How the last run ended (drive.ident_outcome). */
typedef enum {
    DRIVE_IDENT_NONE = 0,     /**< no run since the start */
    DRIVE_IDENT_RUNNING = 1,  /**< a run is going on */
    DRIVE_IDENT_DONE = 2,     /**< ended: the ok results written (drive.ident_applied) */
    DRIVE_IDENT_ABORTED = 3,  /**< stopped early (ident.abort_reason): nothing written */
    DRIVE_IDENT_REJECTED = 4, /**< ended, but the configuration with the results failed its check: nothing written */
    DRIVE_IDENT_REFUSED = 5,  /**< the last start was refused (drive.ident_error) */
} drive_ident_outcome;

/**
 * The identification's plate from the configuration's ratings (ctl_cfg.plate:
 * power, voltage, current, frequency, speed; cos phi the plate's, else the
 * ratings' estimate, held to 0.3..0.99). Context: ANY.
 */
void drive_ident_plate_of(const ratings *r, ident_plate *p);

/**
 * Start a run on the plate @p plate (NULL: the configuration's ratings, drive_ident_plate_of), the
 * standstill part only (@p rotating must be false). Refused (nothing
 * changes but drive.ident_error / ident_outcome) while a run is going on,
 * unless the drive is stopped, while the rotor turns, with the link below
 * vdc_min_V, or when the plate or the drive's values fail ident_cfg_derive.
 * @return 0 or the refusal (enum ident_error, enum drive_ident_error).
 * Context: BG.
 */
int drive_ident_start(drive *d, const ident_plate *plate, bool rotating);

/** Abort a run going on (the interrupt turns the gates off in its next tick). Context: BG. */
void drive_ident_stop(drive *d);

/** True while a run is going on. Context: BG. */
bool drive_ident_running(const drive *d);

/** Progress of the run now or the last one, 0..100 %. Context: BG. */
uint32_t drive_ident_progress(const drive *d);

/**
 * The background's share, every pass (drive_background): the fits when a
 * part has ended, the results written at the end, the run state left.
 * Context: BG.
 */
void drive_ident_background(drive *d);

#ifdef __cplusplus
}
#endif

#endif /* DTC_DRIVE_IDENT_H */
