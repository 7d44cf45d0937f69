/**
 * @file control_keys.h
 * @brief The [control] section of a scenario: firmware tunables by name.
 *
 * The scenario view of the registry: every key of recording/control_keys.def
 * (the one list, shared with the recorded-tick file) with the range a
 * scenario value must lie in, its unit and its ctl_cfg field's name. Indices
 * are those of the portable registry (recording/control_keys.h). To expose
 * another tunable, add one line to control_keys.def and document it in
 * docs/scenarios.md (a test checks every key is documented).
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
