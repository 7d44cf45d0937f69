/**
 * @file ctl_observe.h
 * @brief The observation of the period now applied: the neutral point
 *        predicted for its end, the voltage the inverter applies over it
 *        (dtc/inverter_model.h) and the observer's step with that voltage.
 *        Private to firmware/control (ctl.c and ctl_bringup.c).
 *
 * Timing. The sample of tick k is taken at t_k; the actuation latched at tick
 * k is applied from t_{k+1} to t_{k+2}. So during the period starting now the
 * inverter applies s->applied (latched at k-1). The observer advances its
 * state from t_k to t_{k+1} with that voltage, which is at once its update
 * and the one-period-ahead prediction on which the DTC chooses the actuation
 * for t_{k+1}..t_{k+2} (delay compensation).
 *
 * Inline: the tick's hot path, called from the running step and from the
 * bring-up step.
 */
#ifndef DTC_CTL_OBSERVE_H
#define DTC_CTL_OBSERVE_H

#include "dtc/ctl.h"
#include "dtc/inverter_model.h"
#include "dtc/npc.h"
#include "inverter_model_impl.h"

/**
 * The neutral point at t_{k+1}, vc1 - vc2 in V: d(vc1 - vc2)/dt = i_np / C
 * under the period now applied, from the sample @p x. Context: ISR.
 */
static inline real_t ctl_predict_np_dev(const ctl_state *s, const ctl_cfg *cfg, const hal_sample *x)
{
    uint8_t st0 = s->applied.state[0];
    uint8_t st1 = s->applied.state[1];
    real_t d0 = s->applied.act.duty0;
    real_t i_abc[3] = {x->ia_A, x->ib_A, x->ic_A};
    real_t inp1 = npc_np_current_unchecked(st1, i_abc);
    real_t inp0 = st0 == st1 ? inp1 : npc_np_current_unchecked(st0, i_abc); /* one vector: the same current */
    real_t inp = num_mac(d0, inp0 - inp1, inp1);
    return num_mac(cfg->np_V_per_A, inp, x->vc1_V - x->vc2_V);
}

/**
 * Observe: the voltage applied from t_k to t_{k+1} is the period now applied
 * with the capacitors' mean voltages over it (from the sample @p x and the
 * neutral point @p np_dev_pred_V predicted for t_{k+1}, V); the observer
 * advances to t_{k+1} with it. Writes that voltage @p v (V) and the sampled
 * current @p is (A), alpha-beta, and sets s->applied.end_state to the state
 * the period ends on (the next period's dead-time edges start there).
 * Context: ISR.
 */
static inline void ctl_observe(ctl_state *s, const ctl_cfg *cfg, const hal_sample *x, real_t np_dev_pred_V,
                               real_t v[2], real_t is[2])
{
    /* The capacitors' mean voltages over the period, not their values at its
     * start: the neutral-point current moves vc1 - vc2 by up to 3 V in one
     * period at rated current (the sum stays), and near zero stator frequency
     * the stator voltage is only Rs |is|, about 8 V: the start values left a
     * speed bias of 3-7 rpm at 30 rpm generating (docs/envelope.md section 6).
     * Linear over the period, so the mean is the midpoint: each capacitor
     * moves by half the predicted change, the mean by half of that. */
    real_t q = num_mul(R(0.25), np_dev_pred_V - (x->vc1_V - x->vc2_V));
    /* the levels of the leg codes N, O, P */
    const real_t level_V[3] = {-(x->vc2_V - q), R(0.0), x->vc1_V + q};
    const real_t i[3] = {x->ia_A, x->ib_A, x->ic_A};
    s->applied.end_state = inverter_voltage_inline(&s->applied, level_V, i, &cfg->inv, v);
    is[0] = num_mul(R(0.333333333), R(2.0) * i[0] - i[1] - i[2]);
    is[1] = num_mul(NUM_INV_SQRT3, i[1] - i[2]);
    s->obs.te_cmd_Nm = s->te_ref_Nm; /* the command behind the voltage of this period */
    observer_step_ab(&s->obs, &cfg->obs, is[0], is[1], v[0], v[1], &s->obs_out);
}

#endif /* DTC_CTL_OBSERVE_H */
