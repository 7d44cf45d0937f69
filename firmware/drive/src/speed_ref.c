/**
 * @file speed_ref.c
 * @brief The speed reference's limits (see dtc/speed_ref.h).
 */
#include "dtc/speed_ref.h"

#include "dtc/param_table.h"

/* The declared range is the table's, so the limit and the range a master
 * reads from the EDS are one number (bus rpm over the entry's rpm per rad/s). */
static float declared_min_rad_s(void)
{
    const co_param *p = &co_params[CO_P_SPEED_REF_RPM];
    return p->min.f / p->k;
}

float speed_ref_declared_max_rad_s(void)
{
    const co_param *p = &co_params[CO_P_SPEED_REF_RPM];
    return p->max.f / p->k;
}

float speed_ref_limit(const ctl_cfg *cfg, float present_rad_s, float request_rad_s)
{
    if (!(request_rad_s - request_rad_s == 0.0f))
        return present_rad_s; /* NaN or infinite: nothing to limit, nothing changes */
    float top = cfg->speed_max_rad_s;
    float hi = speed_ref_declared_max_rad_s();
    float lo = declared_min_rad_s();
    if (hi > top)
        hi = top;
    if (lo < -top)
        lo = -top;
    float x = request_rad_s;
    if (x > hi)
        x = hi;
    if (x < lo)
        x = lo;
    return x;
}
