/**
 * @file speed_ref.h
 * @brief The one rule for the drive's speed reference, whatever its source.
 *
 * A request becomes the reference in force in three steps:
 *  1. a bus target (SDO 0x2000:1, 0x60FF or 0x6042, the RPDO's target
 *     velocity) is held to the CiA 402 vl limits 0x6046 (drive_co.c): a
 *     non-zero magnitude is raised to at least vl_velocity_min, then limited
 *     to at most vl_velocity_max (the maximum last, so it wins even over an
 *     inconsistent pair); the halt bit holds it at 0;
 *  2. every request, from the bus or from a board's own command (the SIL's
 *     scenario profile), is limited to the declared range of speed_ref_rpm
 *     (0x2000:1, the parameter table's min..max) when it is set
 *     (drive_set_speed_ref); a request that is not a number changes nothing;
 *  3. the reference is limited to the envelope's top speed, the control law's
 *     speed_max_rad_s (overspeed_rad_s / 1.1), where it is used: by the
 *     control law's reference limiter at every speed-loop step, and by a read
 *     of 0x2000:1 or 0x60FF (speed_ref_in_force), so a change of the overspeed
 *     level applies at once to a reference already set.
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
 * Step 2: @p request_rad_s (mechanical, rad/s) limited to the declared range
 * of speed_ref_rpm; a NaN or infinite request gives @p present_rad_s.
 * @return the reference to set, rad/s. Context: ANY (no state).
 */
float speed_ref_declared(float present_rad_s, float request_rad_s);

/**
 * Step 3: the reference @p ref_rad_s as the control law applies it, limited to
 * +-cfg->speed_max_rad_s (the envelope's top speed).
 * @return rad/s. Context: ANY (no state).
 */
float speed_ref_in_force(const ctl_cfg *cfg, float ref_rad_s);

#ifdef __cplusplus
}
#endif

#endif /* DTC_SPEED_REF_H */
