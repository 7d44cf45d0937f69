/**
 * @file control_keys.c
 * @brief The scenario view of the [control] key registry (sim/control_keys.h):
 *        the keys of recording/control_keys.def with their value ranges,
 *        units and field names, and a scenario value stored into or read
 *        from its field.
 *
 * Host code: the ranges and values are 64-bit because the parser reads
 * decimal text as double and checks it before narrowing to the field's type.
 */
#include "sim/control_keys.h"

#include <stdint.h>
#include <string.h>

#define CK_REAL(name, field, lo, hi, unit) {name, offsetof(ctl_cfg, field), SIM_CK_REAL, lo, hi, unit, #field},
#define CK_U32(name, field, lo, hi, unit) {name, offsetof(ctl_cfg, field), SIM_CK_U32, lo, hi, unit, #field},
#define CK_BOOL(name, field) {name, offsetof(ctl_cfg, field), SIM_CK_BOOL, 0.0, 1.0, "bool", #field},

static const sim_control_key keys[] = {
#include "recording/control_keys.def"
};

const sim_control_key *sim_control_keys(size_t *count)
{
    *count = sizeof keys / sizeof keys[0];
    return keys;
}

int sim_control_key_find(const char *name)
{
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (strcmp(keys[i].name, name) == 0)
            return (int)i;
    return -1;
}

void sim_control_key_apply(int index, ctl_cfg *cfg, double value)
{
    const sim_control_key *k = &keys[index];
    unsigned char *p = (unsigned char *)cfg + k->offset;
    switch (k->type) {
    case SIM_CK_REAL: {
        real_t v = (real_t)value;
        memcpy(p, &v, sizeof v);
        break;
    }
    case SIM_CK_U32: {
        uint32_t v = (uint32_t)value;
        memcpy(p, &v, sizeof v);
        break;
    }
    case SIM_CK_BOOL: {
        bool v = value != 0.0;
        memcpy(p, &v, sizeof v);
        break;
    }
    }
}

double sim_control_key_read(int index, const ctl_cfg *cfg)
{
    const sim_control_key *k = &keys[index];
    const unsigned char *p = (const unsigned char *)cfg + k->offset;
    switch (k->type) {
    case SIM_CK_REAL: {
        real_t v;
        memcpy(&v, p, sizeof v);
        return (double)v;
    }
    case SIM_CK_U32: {
        uint32_t v;
        memcpy(&v, p, sizeof v);
        return (double)v;
    }
    case SIM_CK_BOOL: {
        bool v;
        memcpy(&v, p, sizeof v);
        return v ? 1.0 : 0.0;
    }
    }
    return 0.0;
}
