/**
 * @file file_safety.h
 * @brief What dtc-sim may read and overwrite: the scenario must be a regular
 *        file of bounded size; an output may only be a new path or an
 *        existing regular file that is not one of the run's inputs.
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

/**
 * Check that @p path may be written as an output named @p what (e.g.
 * "--csv"): it does not exist, or it is a regular file that is neither
 * @p input nor @p other (either may be NULL; compared by device and inode,
 * so another name of the same file is caught too).
 * @return true when allowed; else false with one line in @p err.
 */
bool sim_output_allowed(const char *what, const char *path, const char *input, const char *other, char *err,
                        size_t errlen);

#ifdef __cplusplus
}
#endif

#endif /* SIM_FILE_SAFETY_H */
