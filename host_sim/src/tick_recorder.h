/**
 * @file tick_recorder.h
 * @brief `dtc-sim run --record-samples FILE`: write every control tick's
 *        interrupt inputs and outputs (recording/tick_record.h format) so the
 *        PIL programs can replay the closed-loop trajectory on the Cortex-M4F.
 */
#ifndef SIM_TICK_RECORDER_H
#define SIM_TICK_RECORDER_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "dtc/drive.h"
#include "hal_host/hal_host.h"
#include "recording/tick_record.h"

typedef struct {
    FILE *f;
    char *path;    /**< final name */
    char *partial; /**< PATH.partial while writing */
    tick_rec rec;  /**< the tick being recorded */
    bool failed;   /**< a write failed */
} tick_recorder;

/**
 * Create PATH.partial and write the header and the drive's active
 * configuration. @return 0, or -1 with @p err set.
 */
int tick_recorder_open(tick_recorder *r, const char *path, const char *scenario_name, const struct drive *d,
                       uint32_t period_us, char *err, size_t errlen);

/** Capture the interrupt's inputs of tick @p k (call right before the tick runs). */
void tick_recorder_inputs(tick_recorder *r, uint64_t k, const hal_host_board *b, const struct drive *d);

/** Capture the outputs (right after the tick) and append the record. */
void tick_recorder_outputs(tick_recorder *r, const struct drive *d);

/**
 * Close; on @p keep rename PATH.partial to PATH, else remove it.
 * @return 0, or -1 with @p err set (a write or rename failed; nothing left behind).
 */
int tick_recorder_close(tick_recorder *r, bool keep, char *err, size_t errlen);

#endif /* SIM_TICK_RECORDER_H */
