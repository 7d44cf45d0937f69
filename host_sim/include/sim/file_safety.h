/**
 * @file file_safety.h
 * @brief What dtc-sim may read and write: the scenario must be a regular file
 *        of bounded size; a run never removes or truncates a file it did not
 *        create itself.
 *
 * Every output is written through a temporary file next to it (OUT.partial,
 * the NVM image through NVM.tmp) and renamed over the output when the run
 * succeeds, so the output itself may be a new name or an existing regular
 * file (replaced as a whole). Before anything is opened for writing,
 * sim_outputs_allowed() checks each output and its temporary against the
 * input and against each other.
 */
#ifndef SIM_FILE_SAFETY_H
#define SIM_FILE_SAFETY_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Largest scenario file read, bytes: scenarios are a few kB. */
#define SIM_SCENARIO_MAX_BYTES (1024L * 1024L)

/** One output of a run. */
typedef struct {
    const char *what;        /**< its option, for messages, e.g. "--csv" */
    const char *path;        /**< as given; NULL: the option was not given (skipped) */
    const char *temp_suffix; /**< the temporary it is written through: path + this, e.g. ".partial" */
} sim_output;

/**
 * Check that the @p n outputs may be written, before any is opened: each
 * output is a new name in an existing, writable folder or an existing regular
 * file (not a directory, device, FIFO or dangling link); no output and no
 * temporary is the input @p input (may be NULL) or the same file as another
 * output or temporary, compared by device and inode when both exist, else by
 * the resolved path (the folder's real path and the name); and no temporary
 * exists already (it would be truncated: a leftover of an interrupted run is
 * for the user to remove).
 * @return true when allowed; else false with ONE line in @p err
 *         ("--csv PATH: problem").
 */
bool sim_outputs_allowed(const char *input, const sim_output *out, size_t n, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif /* SIM_FILE_SAFETY_H */
