/**
 * @file ident_apply.h
 * @brief Writing the identification run's results to the drive's motor
 *        model, and what depends on it (dtc/ident.h).
 *
 * Apart from ident.h so that the run's state can become part of the
 * control's (ctl.h) without the two headers including each other.
 */
#ifndef DTC_IDENT_APPLY_H
#define DTC_IDENT_APPLY_H

#include <stdint.h>

#include "dtc/ctl.h"
#include "dtc/ident.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Groups of values ident_apply wrote (bits of its return value). */
enum ident_applied {
    IDENT_APPLIED_RS = 1u << 0,        /**< Rs */
    IDENT_APPLIED_MAGNETICS = 1u << 1, /**< Ls, Lr, Lm, Rr (together: they are one model) */
    IDENT_APPLIED_J = 1u << 2,         /**< J */
    IDENT_APPLIED_B = 1u << 3,         /**< B */
};

/**
 * A configuration @p to: @p from with the results @p r of the run @p s
 * whose verdict is IDENT_VERDICT_OK written into its motor model (each group
 * of enum ident_applied only when all its values are OK) and marked set in
 * the ratings mask (an identified value is no longer the plate's estimate: a
 * later commit keeps it; an identified Rs also sets rs_ident_tol to 1: the
 * estimate while magnetising no longer replaces it), then ctl_cfg_rederive() (with a plate: every
 * derived value again from the plate and the identified model; the observer,
 * the speed loop's gains from J, the Rs identification, the flux ramp, the
 * torque limits) and ctl_cfg_check().
 * Only when the run is at IDENT_WAIT_APPLY (the standstill values: the trial
 * configuration the rotating part runs on) or IDENT_DONE. @p from is never
 * written; on a refusal @p to is a copy of it. @p from and @p to must be
 * distinct. @return the groups written (>= 0), IDENT_E_PHASE (not a phase
 * to apply in: an aborted run writes nothing) or IDENT_E_REJECTED (the
 * configuration with them fails its check). Context: BG.
 */
int ident_apply(const ident *s, const ident_result *r, const ctl_cfg *from, ctl_cfg *to);

#ifdef __cplusplus
}
#endif

#endif /* DTC_IDENT_APPLY_H */
