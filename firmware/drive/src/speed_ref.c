/**
 * @file speed_ref.c
 * @brief The speed reference's limits (see dtc/speed_ref.h).
 */
#include "dtc/speed_ref.h"

#include "dtc/param_table.h"

float speed_ref_declared(float present_rad_s, float request_rad_s)
{
    if (!(request_rad_s - request_rad_s == 0.0f))
        return present_rad_s; /* NaN or infinite: nothing to limit, nothing changes */
    /* The table's range, so the limit and the range a master reads from the
     * EDS are one number (bus rpm over the entry's rpm per rad/s). */
    const co_param *p = &co_params[CO_P_SPEED_REF_RPM];
    float lo = p->min.f / p->k, hi = p->max.f / p->k;
    float x = request_rad_s;
    if (x > hi)
        x = hi;
    if (x < lo)
        x = lo;
    return x;
}

float speed_ref_in_force(const ctl_cfg *cfg, float ref_rad_s)
{
    float top = cfg->speed_max_rad_s;
    if (ref_rad_s > top)
        return top;
    if (ref_rad_s < -top)
        return -top;
    return ref_rad_s;
}
