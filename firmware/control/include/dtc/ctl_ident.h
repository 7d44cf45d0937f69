/**
 * @file ctl_ident.h
 * @brief The identification run as a run state of the control core: the
 *        tick that takes the place of ctl_step while a run lasts (the
 *        standstill part of dtc/ident.h).
 *
 * The caller (the drive's interrupt, drive_isr.c) calls ctl_ident_step()
 * instead of ctl_step() while the background has a run going on; the
 * background starts the run (ident_start), fits and applies the results
 * (ident_background, ident_apply) and ends it. The tick keeps the core's
 * protection in force (every fault the core latches, in the same tick, gates
 * off; ident_step then aborts the run), reconstructs the voltage the
 * inverter applied over the period now ending from the core's own inverter
 * model (dtc/inverter_model.h, the dead time and the device drops of the
 * configuration) and latches the run's actuation in the core's applied
 * period, so the next normal start continues from the state it left.
 *
 * The rotating part's outputs (IDENT_OUT_TORQUE, IDENT_OUT_SPEED) are not
 * carried out by this tick: they turn the gates off, and the run then times
 * out (the drive starts the standstill part only, docs/commissioning.md).
 */
#ifndef DTC_CTL_IDENT_H
#define DTC_CTL_IDENT_H

#include "dtc/ctl.h"
#include "dtc/ident.h"

#ifdef __cplusplus
extern "C" {
#endif

/** What one tick of the identification run works on (ctl_ident_step). */
typedef struct {
    ctl_state *s;             /**< control state: its protection, applied period and telemetry;
                                   run_state stays CTL_STOPPED (or CTL_FAULTED on a fault) */
    const ctl_cfg *cfg;       /**< configuration (the inverter model, the protection levels) */
    ident *id;                /**< the run (ident_step's state) */
    const ident_cfg *ic;      /**< its constants (ident_cfg_derive) */
    const ctl_in *in;         /**< this tick's inputs; in->run false aborts the run */
    ctl_out *out;             /**< actuation for the next period and telemetry */
} ctl_ident_call;

/**
 * One tick of the identification run state, in place of ctl_step().
 * Order: protect (as ctl_step: a fault latches, gates off this tick) ->
 * the voltage of the period now applied -> ident_step (with in->run as the
 * run's command, the core's latched faults as its fault input) -> the run's
 * actuation latched for the next period, or gates off.
 * One argument, so that the interrupt's common path (ctl_step) pays no
 * stack arguments for this rarely taken call.
 * Context: ISR. Bounded work (ident_step's).
 */
void ctl_ident_step(const ctl_ident_call *c);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CTL_IDENT_H */
