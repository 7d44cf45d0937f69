/**
 * @file ctl.c
 * @brief The 200 us control step in the order of a tick: protect, run state,
 *        observe, monitor, supervise, speed control, DTC, actuate.
 *
 * Run states: STOPPED (gates off) -> MAGNETISING (zero torque, flux reference
 * ramped up, the DTC builds the flux; premag_s) -> RUNNING (speed control).
 * Any detected fault latches its bit, disables the gates in the same tick and
 * holds FAULTED until ctl_clear_faults() finds its cause gone. The timing of
 * the observation and the actuation: ctl_observe.h.
 *
 * The step's parts are files of their own: the protection (ctl_protect.c),
 * the observation (ctl_observe.h, on dtc/inverter_model.h), the supervision
 * of the operating point (ctl_supervise.c), bring-up levels 1-4
 * (ctl_bringup.c), the outputs (ctl_output.h); the slots of the slow tasks
 * are dtc/ctl_schedule.h's, decided here once per tick.
 */
#include "dtc/ctl.h"

#include <string.h>

#include "ctl_bringup.h"
#include "ctl_observe.h"
#include "ctl_output.h"
#include "ctl_protect.h"
#include "ctl_supervise.h"
#include "dtc/ctl_schedule.h"
#include "dtc/npc.h"
#include "real_bits.h"

void ctl_init(ctl_state *s, const ctl_cfg *cfg)
{
    memset(s, 0, sizeof *s);
    observer_init(&s->obs, &cfg->obs);
    speed_ctl_init(&s->speed, &cfg->speed);
    dtc3l_init(&s->dtc);
    s->run_state = CTL_STOPPED;
    ctl_gates_off(s);
}

uint32_t ctl_clear_faults(ctl_state *s)
{
    s->faults &= s->faults_active;
    if (s->faults == 0u && s->run_state == CTL_FAULTED)
        s->run_state = CTL_STOPPED;
    return s->faults;
}

/* Protect: this tick's faults latched; true when the gates must be off. The
 * slow tasks' slot advances here and nowhere else, once per tick that judges
 * a sample: a stale sample or a value that is not a number leaves it. */
static bool protect(ctl_state *s, const ctl_cfg *cfg, const ctl_in *in)
{
    bool judged;
    uint32_t f = ctl_protect_detect(s, cfg, in, &judged);
    if (judged) {
        s->slow_slot = ctl_schedule_next(s->slow_slot);
        f |= ctl_protect_plausibility(s, cfg, &in->sample);
    }
    return ctl_protect_latch(s, f);
}

static void start(ctl_state *s, const ctl_cfg *cfg)
{
    observer_init(&s->obs, &cfg->obs);
    rs_ident_reset(&s->rsid);
    dtc3l_init(&s->dtc);
    speed_ctl_reset(&s->speed, R(0.0));
    memset(&s->speed_held, 0, sizeof s->speed_held); /* no output of the last run held into this one */
    s->run_state = CTL_MAGNETISING;
    s->t_magnetise_s = R(0.0);
    s->bringup_theta_rad = R(0.0);
    s->t_at_limit_s = R(0.0);
    s->t_stall_win_s = R(0.0);
    s->t_brake_limit_s = R(0.0);
    s->brake_stall = false;
    s->dtc_cmd.psi_ref_Wb = R(0.0);
    s->speed_ref_ramped_rad_s = R(0.0);
    s->te_ref_Nm = R(0.0);
    ctl_guard_reset(&s->guard);
    s->monitor_faults = 0u;
    s->fsw_hz = R(0.0);
    s->fsw_changes = 0u;
    s->dtc_cmd.band_scale = R(1.0);
    s->te_short_Nm = R(0.0);
    s->fw_trim = R(1.0);
    s->psi_target_Wb = cfg->dtc.psi_ref_Wb; /* at standstill: rated (the supervision takes over within a slot cycle) */
    s->te_limit_Nm = cfg->speed.te_max_Nm; /* until the supervision works it out at the flux reached */
    s->short_sum_Nm = R(0.0);
    s->t_dev_s = R(0.0);
    s->t_dev_win_s = R(0.0);
    s->dev_ref_prev_rad_s = R(0.0);
    s->warnings = 0u;
    ctl_gates_off(s); /* the first period after enabling applies OOO */
}

/* The loss-of-control monitor: the window's sums every tick, the check in its
 * slots (the ticks before this one; its verdict joins the tick's faults from
 * the next one on). */
static inline void monitor_loss_of_control(ctl_state *s, const ctl_cfg *cfg, const real_t v_V[2], const real_t is_A[2])
{
    if (ctl_slot_guard(s->slow_slot)) {
        bool trip = ctl_guard_check(&s->guard, &cfg->guard, cfg->period_s, is_A, s->obs.rs_ohm,
                                    s->obs_out.psi_s_Wb, s->dtc_cmd.psi_ref_Wb, s->run_state == CTL_RUNNING);
        s->monitor_faults = (s->monitor_faults & ~(uint32_t)CTL_FAULT_LOSS_OF_CONTROL) |
                            (trip ? (uint32_t)CTL_FAULT_LOSS_OF_CONTROL : 0u);
        /* the sums in both branches: in this one they were just reset to -0.0,
         * so the reset and the additions fold away (x + -0.0 is x) */
        ctl_guard_accumulate(&s->guard, v_V, is_A);
    } else {
        ctl_guard_accumulate(&s->guard, v_V, is_A);
    }
}

/* Magnetising: zero torque until premag_s, then RUNNING from the estimated speed. */
static void magnetise(ctl_state *s, const ctl_cfg *cfg)
{
    const observer_out *oo = &s->obs_out;
    s->t_magnetise_s += cfg->period_s;
    s->te_ref_Nm = R(0.0);
    if (s->t_magnetise_s >= cfg->dtc.premag_s) {
        s->run_state = CTL_RUNNING;
        s->obs.rs_ohm = rs_ident_result(&s->rsid, &cfg->rsid); /* the model's unless clearly off */
        s->speed_ref_ramped_rad_s = oo->omega_m_rad_s;
        speed_ctl_reset(&s->speed, R(0.0));
        speed_ctl_set_ref(&s->speed, oo->omega_m_rad_s);
    }
}

/* Speed control: ramp the reference, torque command from the speed
 * controller. The speed loop runs every CTL_RBFN_TICKS-th tick, whatever the
 * controller: its command in a slot the monitors leave free, the RBFN's
 * learning of that command and the stall windows each in a later slot of
 * their own, the speed-deviation supervision once per slot cycle; between its steps the torque command and the speed controller's
 * outputs (s->speed_held, written in place) hold. */
static void control_speed(ctl_state *s, const ctl_cfg *cfg, const ctl_in *in)
{
    real_t T = cfg->speed_T_s; /* the speed loop's step */
    bool rbfn = cfg->speed.mode == SPEED_MODE_RBFN;
    uint8_t slot = s->slow_slot;
    if (!ctl_slot_speed_command(slot)) {
        if (ctl_slot_stall(slot)) {
            ctl_stall_step(s, cfg, T);
            return;
        }
        if (rbfn && ctl_slot_rbfn_learn(slot))
            speed_ctl_learn(&s->speed, &cfg->speed, T, &s->speed_held); /* the last command's */
        if (ctl_slot_speed_dev(slot))
            ctl_speed_dev_step(s, cfg, cfg->sup_T_s); /* once per slot cycle */
        return;
    }
    real_t prev = s->speed_ref_ramped_rad_s;
    /* at the target (most steps) the ramp returns it: skipped on equal bits, but not at zero,
     * where prev + (+0) makes a -0 into +0. An input that is the ramped reference itself,
     * within the limit, is that target as it is (finite, not clamped): neither screened nor
     * clamped then. */
    if (!(f32_bits(in->speed_ref_rad_s) == f32_bits(prev) && abs_bits(prev) != 0u &&
          num_abs(prev) <= cfg->speed_max_rad_s)) {
        real_t target = finite_r(in->speed_ref_rad_s) ? in->speed_ref_rad_s : prev;
        target = num_limit(target, cfg->speed_max_rad_s);
        if (f32_bits(target) != f32_bits(prev) || abs_bits(prev) == 0u)
            s->speed_ref_ramped_rad_s = speed_ref_ramp(prev, target, cfg->speed_ramp_step_rad_s);
    }
    speed_in si;
    si.omega_ref_rad_s = s->speed_ref_ramped_rad_s;
    /* (d / T_tick) / CTL_RBFN_TICKS in one product: the division by a power of 2 is exact */
    si.domega_ref_rad_s2 = num_mul(s->speed_ref_ramped_rad_s - prev, cfg->inv_speed_T_per_s);
    si.omega_est_rad_s = s->obs_out.omega_m_rad_s;
    si.te_limit_Nm = s->te_limit_Nm;
    /* both write every output before they read one */
    if (rbfn)
        speed_ctl_command(&s->speed, &cfg->speed, &cfg->motor, T, &si, &s->speed_held);
    else
        speed_ctl_step(&s->speed, &cfg->speed, &cfg->motor, T, &si, &s->speed_held);
    s->te_ref_Nm = s->speed_held.te_ref_Nm;
}

/* Torque and flux control on the state predicted for t_{k+1}; returns the
 * state in force when the chosen period starts. */
static uint8_t control_torque_flux(ctl_state *s, const ctl_cfg *cfg, const hal_sample *x, real_t np_dev_pred_V)
{
    uint8_t st1 = s->applied.state[1];
    /* the prediction is read where the observer left it (s->obs_out); the command is kept
     * in the state, so its band scale, written by the regulation once per slot cycle, and
     * its flux reference, the ramp's (which stands still at its target), are not copied
     * every tick */
    dtc3l_cmd *cmd = &s->dtc_cmd;
    cmd->te_ref_Nm = s->te_ref_Nm;
    cmd->rs_ohm = s->obs.rs_ohm;
    cmd->omega_e_rad_s = s->obs.omega_e_rad_s;
    cmd->vc1_V = x->vc1_V;
    cmd->vc2_V = x->vc2_V;
    cmd->np_dev_V = np_dev_pred_V;
    /* the applied states are always state numbers: only ctl_gates_off() (OOO), actuate()
     * and ctl_bringup_step() (P<->N guard outputs, 0..26) write them, so no clamp (the
     * observation relies on the same, and so does end_state, which ctl_gates_off(),
     * ctl_observe() and ctl_bringup_step() write from those states only) */
    cmd->prev_state = st1;
    cmd->decide_level = ctl_slot_level(s->slow_slot);
    dtc3l_step_predicted(&s->dtc, &cfg->dtc, cfg->period_s, cmd, &s->obs_out, &s->dtc_out);
    return st1;
}

/* Actuate: the last guard against a P<->N step (the DTC never asks for
 * one), then latch for the next period. */
static void actuate(ctl_state *s, const ctl_cfg *cfg, uint8_t prev_state, ctl_out *out)
{
    hal_actuation act;
    /* prev_state is a state number, the DTC's states come from its tables: all 0..26 */
    uint8_t a0 = npc_pn_safe_unchecked(prev_state, s->dtc_out.state[0]);
    uint8_t a1 = npc_pn_safe_unchecked(a0, s->dtc_out.state[1]);
    /* in 0..1 by construction (dtc3l.h; duty_min is 0..0.45 by ctl_cfg_check),
     * and a clamp would not catch a NaN either: no compare */
    act.duty0 = s->dtc_out.act.duty0;
    npc_legs_pair_unchecked(a0, a1, &act);
    ctl_regulate_switching_frequency(s, cfg, prev_state, a0, a1);

    s->applied.act = act;
    s->applied.state[0] = a0;
    s->applied.state[1] = a1;
    out->act = act;
    out->gate_enable = true;
}

/* restrict (the definition only; the header's prototype is compatible): the
 * caller's state, configuration, inputs and outputs are distinct objects, so a
 * store through one need not reload the others. */
void ctl_step(ctl_state *restrict s, const ctl_cfg *restrict cfg, const ctl_in *restrict in, ctl_out *restrict out)
{
    if (protect(s, cfg, in)) {
        ctl_output_off(s, out); /* gates off in this very tick */
        return;
    }
    if (!in->run) {
        s->run_state = CTL_STOPPED;
        ctl_output_off(s, out);
        return;
    }
    if (s->run_state == CTL_STOPPED)
        start(s, cfg);
    if (cfg->bringup_level < BRINGUP_TORQUE) {
        ctl_bringup_step(s, cfg, in, out);
        return;
    }

    real_t v_V[2], is_A[2];
    real_t np_dev_pred_V = ctl_predict_np_dev(s, cfg, &in->sample);
    ctl_observe(s, cfg, &in->sample, np_dev_pred_V, v_V, is_A);
    monitor_loss_of_control(s, cfg, v_V, is_A);
    if (ctl_slot_supervise(s->slow_slot))
        ctl_supervise_operating_point(s, cfg, &in->sample);
    ctl_ramp_flux_reference(s, cfg);

    const speed_out *so = &k_ctl_speed_none; /* the telemetry's speed-loop outputs (a constant: no test per tick) */
    if (s->run_state == CTL_MAGNETISING) {
        /* copies for this call, made in the magnetising ticks only, so that the
         * voltage need not be kept in memory every tick */
        const real_t v_m[2] = {v_V[0], v_V[1]}, is_m[2] = {is_A[0], is_A[1]};
        rs_ident_step(&s->rsid, &cfg->rsid, v_m, is_m, s->obs.omega_e_rad_s);
        magnetise(s, cfg);
    }
    if (s->run_state == CTL_RUNNING && cfg->bringup_level == BRINGUP_TORQUE)
        s->te_ref_Nm = num_limit(cfg->bringup_te_Nm, cfg->speed.te_max_Nm); /* level 5: no speed loop */
    else if (s->run_state == CTL_RUNNING) {
        control_speed(s, cfg, in);
        so = &s->speed_held;
    }

    uint8_t prev_state = control_torque_flux(s, cfg, &in->sample, np_dev_pred_V);
    actuate(s, cfg, prev_state, out);
    ctl_fill_telemetry(s, so, out);
}
