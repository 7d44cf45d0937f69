/**
 * @file ctl_output.h
 * @brief The control step's outputs shared by its paths: the safe state
 *        (gates off, the zero vector) and the telemetry. Private to
 *        firmware/control (ctl.c and ctl_bringup.c).
 */
#ifndef DTC_CTL_OUTPUT_H
#define DTC_CTL_OUTPUT_H

#include "dtc/ctl.h"
#include "dtc/npc.h"

/* The zero vector (OOO) in both halves for the whole period: a constant,
 * copied as three words. */
static const hal_actuation k_ctl_act_zero = {
    .vector = {{.leg = {HAL_LEG_O, HAL_LEG_O, HAL_LEG_O}}, {.leg = {HAL_LEG_O, HAL_LEG_O, HAL_LEG_O}}},
    .duty0 = R(1.0)};

/* The speed-loop outputs published while no speed loop runs. */
static const speed_out k_ctl_speed_none = {.te_ref_Nm = R(0.0), .eps_hat = R(0.0), .w_norm = R(0.0), .zeta_bar = R(0.0)};

/**
 * Gates off: the board then holds the zero vector, which is where the next
 * start continues from (no P<->N step is possible out of OOO). Context: ISR, BG (ctl_init).
 */
static inline void ctl_gates_off(ctl_state *s)
{
    s->applied.act = k_ctl_act_zero;
    s->applied.state[0] = s->applied.state[1] = s->applied.end_state = (uint8_t)NPC_STATE_OOO;
}

/** The telemetry of this step into @p out, with the speed loop's outputs @p so. Context: ISR. */
static inline void ctl_fill_telemetry(const ctl_state *s, const speed_out *so, ctl_out *out)
{
    ctl_telemetry *t = &out->tel;
    t->speed_ref_rad_s = s->speed_ref_ramped_rad_s;
    t->omega_est_rad_s = s->obs.omega_m_filt_rad_s;
    t->te_ref_Nm = s->te_ref_Nm;
    t->te_est_Nm = s->obs_out.te_Nm;
    t->psi_s_est_Wb = s->obs_out.psi_s_abs_Wb;
    t->psi_ref_Wb = s->dtc_cmd.psi_ref_Wb;
    t->eps_hat = so->eps_hat;
    t->w_norm = so->w_norm;
    t->zeta_bar = so->zeta_bar;
    t->rs_est_ohm = s->obs.rs_ohm;
    t->duty0 = out->act.duty0;
    t->vector_index = s->applied.state[0]; /* out->act is s->applied.act in every path */
    t->state = (uint8_t)s->run_state;
    t->faults = s->faults;
    t->warnings = s->warnings;
}

/** Safe output: gates off, zero vector, zero torque, telemetry. Context: ISR. */
static inline void ctl_output_off(ctl_state *s, ctl_out *out)
{
    ctl_gates_off(s);
    out->act = k_ctl_act_zero; /* = s->applied.act, from the constant */
    out->gate_enable = false;
    s->te_ref_Nm = R(0.0);
    ctl_fill_telemetry(s, &k_ctl_speed_none, out);
}

#endif /* DTC_CTL_OUTPUT_H */
