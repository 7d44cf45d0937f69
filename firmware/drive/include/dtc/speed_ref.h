/**
 * @file speed_ref.h
 * @brief The one rule for the drive's speed reference, whatever its source.
 *
 * A request becomes the reference in force in two steps:
 *  1. a bus target (SDO 0x2000:1, 0x60FF or 0x6042, the RPDO's target
 *     velocity) is held to the CiA 402 vl limits 0x6046 (drive_co.c): a
 *     non-zero magnitude is raised to at least vl_velocity_min, then limited
 *     to at most vl_velocity_max (the maximum last, so it wins even over an
 *     inconsistent pair); the halt bit holds it at 0;
 *  2. every request, from the bus or from a board's own command (the SIL's
 *     scenario profile), is limited to the declared range of speed_ref_rpm
 *     (0x2000:1, the parameter table's min..max) and to the envelope's top
 *     speed, the control law's speed_max_rad_s (overspeed_rad_s / 1.1); a
 *     request that is not a number leaves the reference as it is.
 * The table keeps the ranges of every speed object inside speed_ref_rpm's
 * (gen_params.py refuses a table where they are not), and a write that would
 * put vl_velocity_min above vl_velocity_max is refused with SDO abort
 * 0x06090036, changing nothing: no object can ask for more than the drive
 * declares. docs/parameters.md states the rule at each object.
 */
#ifndef DTC_SPEED_REF_H
#define DTC_SPEED_REF_H

#include "dtc/ctl.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Step 2 of the rule: @p request_rad_s (mechanical, rad/s) limited to the
 * declared range of speed_ref_rpm and to +-cfg->speed_max_rad_s; a NaN or
 * infinite request gives @p present_rad_s, the reference in force.
 * @return the reference to put in force, rad/s. Context: ANY (no state).
 */
float speed_ref_limit(const ctl_cfg *cfg, float present_rad_s, float request_rad_s);

/** The largest |speed reference| the drive declares, speed_ref_rpm's range, rad/s. Context: ANY. */
float speed_ref_declared_max_rad_s(void);

#ifdef __cplusplus
}
#endif

#endif /* DTC_SPEED_REF_H */
