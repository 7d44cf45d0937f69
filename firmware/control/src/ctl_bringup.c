/**
 * @file ctl_bringup.c
 * @brief The control step at bring-up levels 1-4 (see ctl_bringup.h): the
 *        level's actuation (bringup.c) behind the P<->N guard, the observer
 *        at the V/f levels.
 */
#include "ctl_bringup.h"

#include "ctl_observe.h"
#include "ctl_output.h"
#include "dtc/bringup.h"
#include "dtc/inverter_model.h"
#include "dtc/npc.h"

void ctl_bringup_step(ctl_state *s, const ctl_cfg *cfg, const ctl_in *in, ctl_out *out)
{
    uint32_t level = cfg->bringup_level;
    s->run_state = CTL_RUNNING;
    s->t_magnetise_s += cfg->period_s; /* time since the start */
    s->te_ref_Nm = R(0.0);
    if (level == BRINGUP_ADC) {
        ctl_output_off(s, out);
        s->run_state = CTL_RUNNING;
        return;
    }
    hal_actuation act;
    if (level == BRINGUP_GATE_TEST) {
        act.vector[0] = act.vector[1] = bringup_gate_pattern(s->t_magnetise_s);
        act.duty0 = R(1.0);
    } else {
        real_t v_V[2], is_A[2];
        ctl_observe(s, cfg, &in->sample, ctl_predict_np_dev(s, cfg, &in->sample), v_V, is_A);
        real_t w_e = num_mul(R(2.0) * NUM_PI, cfg->bringup_hz);
        s->bringup_theta_rad += num_mul(w_e, cfg->period_s);
        if (s->bringup_theta_rad > NUM_PI)
            s->bringup_theta_rad -= R(2.0) * NUM_PI;
        else if (s->bringup_theta_rad < -NUM_PI)
            s->bringup_theta_rad += R(2.0) * NUM_PI;
        /* V/f: the back-emf of the rated flux at this frequency, plus Rs x 5 A against the drop */
        real_t v_mag = num_mul(num_abs(w_e), cfg->dtc.psi_ref_Wb) + num_mul(cfg->motor.Rs_ohm, R(5.0));
        act = bringup_vf(s->bringup_theta_rad, v_mag, in->sample.vc1_V, in->sample.vc2_V);
    }
    /* the level's vectors are not the control step's own states: checked on the way in */
    uint8_t prev = s->applied.state[1];
    uint8_t a0 = npc_pn_safe(prev, npc_state_of(&act.vector[0]));
    uint8_t a1 = npc_pn_safe(a0, npc_state_of(&act.vector[1]));
    npc_legs(a0, &act.vector[0]);
    npc_legs(a1, &act.vector[1]);
    /* the state the period now ending ends on (ctl_observe works it out too, but not at every level) */
    s->applied.end_state = inverter_period_end_state(s->applied.state[0], s->applied.state[1], s->applied.act.duty0);
    s->applied.act = act;
    s->applied.state[0] = a0;
    s->applied.state[1] = a1;
    out->act = act;
    out->gate_enable = true;
    ctl_fill_telemetry(s, &k_ctl_speed_none, out);
}
