/**
 * @file control_keys.h
 * @brief The [control] key registry, portable part: a scenario key's name and
 *        the ctl_cfg field it sets, in the order of control_keys.def.
 *
 * Linked by both ends of a recording: dtc-sim (through its scenario view,
 * sim/control_keys.h, which adds the value ranges and units) and the target's
 * dtc-pil.elf, which sets a recording's configuration words (tick_record.h)
 * on the fields named here. Written to the firmware's rules (C11, no 64-bit
 * floating point, no mutable state); background context only.
 */
#ifndef RECORDING_CONTROL_KEYS_H
#define RECORDING_CONTROL_KEYS_H

#include <stddef.h>

#include "dtc/ctl.h"

#ifdef __cplusplus
extern "C" {
#endif

/** How a key's field is stored in ctl_cfg. */
typedef enum {
    CONTROL_KEY_REAL = 0, /**< real_t (float) */
    CONTROL_KEY_U32 = 1,  /**< uint32_t */
    CONTROL_KEY_BOOL = 2, /**< bool */
} control_key_type;

/** One registry entry. */
typedef struct {
    const char *name;      /**< scenario key, e.g. "ip_wn_rad_s" */
    size_t offset;         /**< offsetof(ctl_cfg, field), bytes */
    control_key_type type; /**< the field's type */
} control_key;

/**
 * The registry, in control_keys.def order (the order of a recording's
 * configuration words). @p count receives the number of entries.
 */
const control_key *control_keys(size_t *count);

/** Index of the key spelled @p name (NUL-terminated), or -1 when there is none. */
int control_key_find(const char *name);

#ifdef __cplusplus
}
#endif

#endif /* RECORDING_CONTROL_KEYS_H */
