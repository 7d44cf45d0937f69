/**
 * @file ctl_ident.c
 * @brief The identification run state's tick (dtc/ctl_ident.h): the core's
 *        protection, the applied voltage from the core's inverter model, the
 *        run's step, its actuation latched in the core's applied period.
 */
#include "dtc/ctl_ident.h"

#include "ctl_observe.h"
#include "ctl_output.h"
#include "ctl_protect.h"
#include "dtc/ctl_schedule.h"
#include "dtc/npc.h"

void ctl_ident_step(const ctl_ident_call *c)
{
    ctl_state *s = c->s;
    const ctl_cfg *cfg = c->cfg;
    const ctl_in *in = c->in;
    ctl_out *out = c->out;
    /* the protection exactly as ctl_step runs it: the slot advances on a judged sample */
    bool judged;
    uint32_t f = ctl_protect_detect(s, cfg, in, &judged);
    if (judged) {
        s->slow_slot = ctl_schedule_next(s->slow_slot);
        f |= ctl_protect_plausibility(s, cfg, &in->sample);
    }
    bool trip = ctl_protect_latch(s, f);
    if (!trip && s->run_state != CTL_FAULTED)
        s->run_state = CTL_STOPPED; /* the run is a state of its own; the core's control stays stopped */

    const hal_sample *x = &in->sample;
    ident_in ii;
    ii.i_abc_A[0] = x->ia_A;
    ii.i_abc_A[1] = x->ib_A;
    ii.i_abc_A[2] = x->ic_A;
    ii.vc1_V = x->vc1_V;
    ii.vc2_V = x->vc2_V;
    /* the voltage of the period now applied (latched at the last tick), as the observer builds it */
    real_t np_dev_pred_V = ctl_predict_np_dev(s, cfg, x);
    real_t q = num_mul(R(0.25), np_dev_pred_V - (x->vc1_V - x->vc2_V));
    const real_t level_V[3] = {-(x->vc2_V - q), R(0.0), x->vc1_V + q};
    s->applied.end_state = inverter_voltage(&s->applied, level_V, ii.i_abc_A, &cfg->inv, ii.v_ab_V);
    ii.omega_m_rad_s = R(0.0); /* the standstill part judges a turning rotor itself */
    ii.psi_s_Wb[0] = ii.psi_s_Wb[1] = R(0.0);
    ii.run = in->run;
    ii.fault = trip || s->faults != 0u;
    ii.control_running = false;

    ident_out io;
    ident_step(c->id, c->ic, &ii, &io);
    if (trip || io.mode != IDENT_OUT_ACTUATE) {
        ctl_output_off(s, out);
        return;
    }
    /* the run's vectors are the zero vector and states adjacent to it: no P<->N step */
    s->applied.act = io.act;
    s->applied.state[0] = npc_state_of(&io.act.vector[0]);
    s->applied.state[1] = npc_state_of(&io.act.vector[1]);
    s->te_ref_Nm = R(0.0);
    out->act = io.act;
    out->gate_enable = true;
    ctl_fill_telemetry(s, &k_ctl_speed_none, out);
}
