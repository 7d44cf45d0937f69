/**
 * @file control_keys.h
 * @brief The [control] section of a scenario: firmware tunables by name.
 *
 * One registry (host_sim/src/control_keys.c) maps a scenario key to a field
 * of ctl_cfg (firmware/include/dtc/ctl.h) with its range and unit. To expose
 * another tunable, add one line there (and document it in docs/scenarios.md;
 * a test checks every key is documented).
 */
#ifndef SIM_CONTROL_KEYS_H
#define SIM_CONTROL_KEYS_H

#include <stdbool.h>
#include <stddef.h>

#include "dtc/ctl.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    SIM_CK_REAL = 0, /**< real_t field */
    SIM_CK_U32 = 1,  /**< uint32_t field; the value must be a whole number */
    SIM_CK_BOOL = 2, /**< bool field; the file says 0/1, true/false, on/off, yes/no */
} sim_control_type;

typedef struct {
    const char *name;     /**< scenario key, e.g. "ip_wn_rad_s" */
    size_t offset;        /**< offsetof(ctl_cfg, field) */
    sim_control_type type;
    double min, max;      /**< accepted range, inclusive */
    const char *unit;     /**< "rad/s", "1", ... */
    const char *field;    /**< the ctl_cfg field, for the docs, e.g. "speed.ip.wn_rad_s" */
} sim_control_key;

/** The registry; @p count receives the number of entries. */
const sim_control_key *sim_control_keys(size_t *count);

/** Index of @p name in the registry, or -1. */
int sim_control_key_find(const char *name);

/** Store @p value into the field of @p cfg named by registry entry @p index. */
void sim_control_key_apply(int index, ctl_cfg *cfg, double value);

/** Read the field of @p cfg named by registry entry @p index (for tests and docs). */
double sim_control_key_read(int index, const ctl_cfg *cfg);

#ifdef __cplusplus
}
#endif

#endif /* SIM_CONTROL_KEYS_H */
