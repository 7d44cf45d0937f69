/**
 * @file drive_params.c
 * @brief The drive's persistent parameters for the parameter store: which
 *        values, their bus bytes, defaults, and a stored set applied through
 *        the dictionary's checked path (rules in dtc/drive_params.h).
 */
#include "dtc/drive_params.h"

#include <stddef.h>

#include "dtc/canopen/co_od.h"
#include "dtc/drive.h"
#include "dtc/drive_co.h"
#include "dtc/param_table.h"
#include "hal/hal.h"

/* The next persistent entry from *cursor (an index into the table), as read by a client. */
static int next_value(void *ctx, uint32_t *cursor, persist_record *rec)
{
    drive *d = ctx;
    for (uint32_t i = *cursor; i < CO_PARAM_COUNT; i++) {
        const co_param *p = &co_params[i];
        if ((p->flags & CO_F_PERSIST) == 0u)
            continue;
        *cursor = i + 1u;
        size_t n = co_dtype_size(p->dtype);
        if (n > sizeof rec->value || co_od_read(&d->co, p, rec->value, n, &n) != CO_ABORT_NONE)
            return HAL_EIO;
        rec->index = p->index;
        rec->sub = p->sub;
        rec->len = (uint8_t)n;
        return 1;
    }
    *cursor = CO_PARAM_COUNT;
    return 0;
}

/* Every parameter to its default; the configuration in the copy being edited until finish. */
static void set_defaults(void *ctx)
{
    drive *d = ctx;
    ctl_cfg *e = drive_cfg_edit(d);
    ctl_cfg_default(e);
    d->params_edit = e;
    drive_co_defaults(d);
}

static bool take_value(void *ctx, const persist_record *rec)
{
    drive *d = ctx;
    const co_param *p = co_od_find(&drive_od, rec->index, rec->sub, NULL);
    co_num v;
    if (p == NULL || (p->flags & CO_F_PERSIST) == 0u ||
        co_od_check(p, rec->value, rec->len, CO_WR_LOAD, &v) != CO_ABORT_NONE)
        return false;
    drive_co_apply(d, p, &v, d->params_edit);
    return true;
}

static uint32_t put_in_use(void *ctx)
{
    drive *d = ctx;
    uint32_t dropped = 0u;
    /* A stored configuration the control core refuses is not used at all:
     * judged as derived from its stored ratings and set mask. */
    if (!ctl_cfg_rederive(d->params_edit) || ctl_cfg_check(d->params_edit) != CTL_CFG_OK) {
        ctl_cfg_default(d->params_edit);
        dropped = 1u;
    }
    d->params_edit = NULL;
    drive_cfg_commit(d);
    return dropped;
}

const persist_params drive_params = {next_value, set_defaults, take_value, put_in_use};
