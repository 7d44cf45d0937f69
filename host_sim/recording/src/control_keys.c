/**
 * @file control_keys.c
 * @brief The portable registry (control_keys.h), expanded from control_keys.def
 *        without the scenario value ranges, so the target links no 64-bit
 *        floating point.
 */
#include "recording/control_keys.h"

#include <string.h>

#define CK_REAL(name, field, min, max, unit) {name, offsetof(ctl_cfg, field), CONTROL_KEY_REAL},
#define CK_U32(name, field, min, max, unit) {name, offsetof(ctl_cfg, field), CONTROL_KEY_U32},
#define CK_BOOL(name, field) {name, offsetof(ctl_cfg, field), CONTROL_KEY_BOOL},

static const control_key keys[] = {
#include "recording/control_keys.def"
};

const control_key *control_keys(size_t *count)
{
    *count = sizeof keys / sizeof keys[0];
    return keys;
}

int control_key_find(const char *name)
{
    for (size_t i = 0u; i < sizeof keys / sizeof keys[0]; i++)
        if (strcmp(keys[i].name, name) == 0)
            return (int)i;
    return -1;
}
