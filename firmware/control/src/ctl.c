/**
 * @file ctl.c
 * @brief The 200 us control step: protect, observe, speed control, DTC, actuate.
 *
 * Timing. The sample of tick k is taken at t_k; the actuation latched at tick
 * k is applied from t_{k+1} to t_{k+2}. So during the period starting now the
 * inverter applies last_act (latched at k-1). The observer advances its state
 * from t_k to t_{k+1} with that voltage, which is at once its update and the
 * one-period-ahead prediction on which the DTC chooses the actuation for
 * t_{k+1}..t_{k+2} (delay compensation).
 *
 * Run states: STOPPED (gates off) -> MAGNETISING (zero torque, flux reference
 * ramped up, the DTC builds the flux; premag_s) -> RUNNING (speed control).
 * Any detected fault latches its bit, disables the gates in the same tick and
 * holds FAULTED until ctl_clear_faults() finds its cause gone.
 */
#include "dtc/ctl.h"

#include <string.h>

/* finite without isfinite(): NaN and +-inf give NaN on subtraction */
static inline bool finite_r(real_t x) { return (x - x) == R(0.0); }

void ctl_cfg_default(ctl_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);

    /* docs/motor-10hp.json */
    motor_model *m = &cfg->motor;
    m->Rs_ohm = R(0.288);
    m->Rr_ohm = R(0.158);
    m->Lm_H = R(0.0416);
    m->Ls_H = R(0.00142) + R(0.0416);
    m->Lr_H = R(0.00142) + R(0.0416);
    m->pole_pairs = R(2.0);
    m->J_kgm2 = R(0.045);
    m->B_Nms = R(0.005);
    cfg->period_s = R(200e-6);
    cfg->vdc_nom_V = R(311.0);
    cfg->c_dc_F = R(2.2e-3);

    speed_cfg_default(&cfg->speed, m);

    dtc3l_cfg *d = &cfg->dtc;
    d->psi_ref_Wb = R(0.45);         /* rated stator flux */
    d->premag_s = R(0.3);            /* > flux ramp (0.13 s) + a few sigma Tr */
    d->flux_band_Wb = R(0.01);
    d->torque_band_Nm = R(3.5);      /* about 850 Hz device switching at 500 rpm */
    d->torque_band2_Nm = R(8.0);
    d->ripple_reduction = true;
    d->ripple_speed_max_rad_s = R(200.0); /* 1900 rpm: the whole speed range */
    d->np_band_V = R(1.5);
    d->level_up = R(0.6);            /* 660 rpm at rated flux and 311 V */
    d->level_down = R(0.5);
    d->duty_min = R(0.05);           /* 10 us at 200 us */

    observer_cfg *o = &cfg->obs;
    o->k_gain = R(1.3);
    o->kp_speed = R(50.0);
    o->ki_speed = R(2000.0);
    o->ki_rs = R(0.0);
    o->speed_lpf_hz = R(50.0);

    cfg->i_trip_A = R(100.0);
    cfg->vdc_max_V = R(400.0);
    cfg->vdc_min_V = R(200.0);
    cfg->np_trip_V = R(30.0);
    cfg->overspeed_rad_s = R(250.0);

    ctl_cfg_derive(cfg);
}

void ctl_cfg_derive(ctl_cfg *cfg)
{
    const motor_model *m = &cfg->motor;
    speed_cfg_derive(&cfg->speed, m);
    observer_cfg_derive(&cfg->obs, m, cfg->period_s);

    /* With |psi_s| ramped at rate r, the rotor flux lags by r sigma Tr and the
     * stator current exceeds psi/Ls by r (1 - sigma) Tr / Ls. */
    real_t sigma = R(1.0) - num_div(num_mul(m->Lm_H, m->Lm_H), num_mul(m->Ls_H, m->Lr_H));
    real_t tr = num_div(m->Lr_H, m->Rr_ohm);
    real_t a_per_wb_s = num_div(num_mul(R(1.0) - sigma, tr), m->Ls_H);
    cfg->psi_ramp_Wb_s = a_per_wb_s > R(0.0) ? num_div(num_mul(R(0.2), cfg->i_trip_A), a_per_wb_s) : R(1.0);
    cfg->np_V_per_A = cfg->c_dc_F > R(0.0) ? num_div(cfg->period_s, cfg->c_dc_F) : R(0.0);
    cfg->inv_period_per_s = cfg->period_s > R(0.0) ? num_div(R(1.0), cfg->period_s) : R(0.0);
}

int ctl_cfg_check(const ctl_cfg *cfg)
{
    const motor_model *m = &cfg->motor;
    if (!(m->Rs_ohm > R(0.0) && m->Rr_ohm > R(0.0) && m->Lm_H > R(0.0) && m->Ls_H > m->Lm_H &&
          m->Lr_H > m->Lm_H && m->pole_pairs >= R(1.0) && m->J_kgm2 > R(0.0) && m->B_Nms >= R(0.0)))
        return CTL_CFG_E_MOTOR;
    if (!(cfg->period_s >= R(20e-6) && cfg->period_s <= R(2e-3) && cfg->vdc_nom_V > R(0.0) && cfg->c_dc_F >= R(0.0)))
        return CTL_CFG_E_PERIOD;
    const dtc3l_cfg *d = &cfg->dtc;
    if (!(d->psi_ref_Wb > R(0.0) && d->premag_s >= R(0.0) && d->flux_band_Wb >= R(0.0) &&
          d->torque_band_Nm >= R(0.0) && d->torque_band2_Nm > d->torque_band_Nm &&
          d->ripple_speed_max_rad_s >= R(0.0) && d->np_band_V >= R(0.0) && d->level_down < d->level_up &&
          d->level_down >= R(0.0) && d->duty_min >= R(0.0) && d->duty_min <= R(0.45)))
        return CTL_CFG_E_DTC;
    const observer_cfg *o = &cfg->obs;
    if (!(o->k_gain >= R(1.0) && o->kp_speed >= R(0.0) && o->ki_speed >= R(0.0) && o->ki_rs >= R(0.0) &&
          o->speed_lpf_hz >= R(0.0)))
        return CTL_CFG_E_OBSERVER;
    if (!(cfg->i_trip_A > R(0.0) && cfg->vdc_max_V > R(0.0) && cfg->vdc_min_V >= R(0.0) &&
          cfg->vdc_min_V < cfg->vdc_max_V && cfg->np_trip_V > R(0.0) && cfg->overspeed_rad_s > R(0.0)))
        return CTL_CFG_E_PROTECTION;
    if (speed_cfg_check(&cfg->speed, m) != SPEED_CFG_OK)
        return CTL_CFG_E_SPEED;
    return CTL_CFG_OK;
}

static void act_zero(hal_actuation *a)
{
    dtc3l_legs(DTC3L_STATE_OOO, &a->vector[0]);
    dtc3l_legs(DTC3L_STATE_OOO, &a->vector[1]);
    a->duty0 = R(1.0);
}

/* Gates off: the board then holds the zero vector, which is where the next
 * start continues from (no P<->N step is possible out of OOO). */
static void gates_off(ctl_state *s)
{
    act_zero(&s->last_act);
    act_zero(&s->prev_act);
    s->last_vector = s->last_act.vector[1];
}

void ctl_init(ctl_state *s, const ctl_cfg *cfg)
{
    memset(s, 0, sizeof *s);
    observer_init(&s->obs, &cfg->obs);
    speed_ctl_init(&s->speed, &cfg->speed);
    dtc3l_init(&s->dtc);
    s->run_state = CTL_STOPPED;
    gates_off(s);
}

uint32_t ctl_clear_faults(ctl_state *s)
{
    s->faults &= s->faults_active;
    if (s->faults == 0u && s->run_state == CTL_FAULTED)
        s->run_state = CTL_STOPPED;
    return s->faults;
}

/* Conditions of this tick (enum ctl_fault bits). */
static uint32_t detect_faults(const ctl_state *s, const ctl_cfg *cfg, const ctl_in *in)
{
    const hal_sample *x = &in->sample;
    uint32_t f = 0u;
    bool active = s->run_state == CTL_MAGNETISING || s->run_state == CTL_RUNNING;

    if (in->fault_input)
        f |= CTL_FAULT_HW;
    if (in->overrun)
        f |= CTL_FAULT_OVERRUN;
    if (!in->sample_fresh)
        return f | CTL_FAULT_STALE_SAMPLE; /* the values are not this tick's: judge nothing on them */
    if (!(finite_r(x->ia_A) && finite_r(x->ib_A) && finite_r(x->ic_A) && finite_r(x->vc1_V) && finite_r(x->vc2_V)))
        return f | CTL_FAULT_SAMPLE_INVALID;

    if (num_abs(x->ia_A) > cfg->i_trip_A || num_abs(x->ib_A) > cfg->i_trip_A || num_abs(x->ic_A) > cfg->i_trip_A)
        f |= CTL_FAULT_OVERCURRENT;
    real_t vdc = x->vc1_V + x->vc2_V;
    if (vdc > cfg->vdc_max_V)
        f |= CTL_FAULT_DC_OVERVOLT;
    if (active && vdc < cfg->vdc_min_V)
        f |= CTL_FAULT_DC_UNDERVOLT;
    if (num_abs(x->vc1_V - x->vc2_V) > cfg->np_trip_V)
        f |= CTL_FAULT_NP_IMBALANCE;
    /* Written as "not within" so that a diverged (NaN) estimate trips too. */
    if (active && !(num_abs(s->obs.omega_m_filt_rad_s) <= cfg->overspeed_rad_s))
        f |= CTL_FAULT_OVERSPEED;
    return f;
}

static void start(ctl_state *s, const ctl_cfg *cfg)
{
    observer_init(&s->obs, &cfg->obs);
    dtc3l_init(&s->dtc);
    speed_ctl_reset(&s->speed, R(0.0));
    s->run_state = CTL_MAGNETISING;
    s->t_magnetise_s = R(0.0);
    s->psi_ref_ramped_Wb = R(0.0);
    s->speed_ref_ramped_rad_s = R(0.0);
    s->te_ref_Nm = R(0.0);
    gates_off(s); /* the first period after enabling applies OOO */
}

static void fill_telemetry(const ctl_state *s, const speed_out *so, ctl_out *out)
{
    ctl_telemetry *t = &out->tel;
    t->speed_ref_rad_s = s->speed_ref_ramped_rad_s;
    t->omega_est_rad_s = s->obs.omega_m_filt_rad_s;
    t->te_ref_Nm = s->te_ref_Nm;
    t->te_est_Nm = s->obs_out.te_Nm;
    t->psi_s_est_Wb = s->obs_out.psi_s_abs_Wb;
    t->psi_ref_Wb = s->psi_ref_ramped_Wb;
    t->eps_hat = so ? so->eps_hat : R(0.0);
    t->w_norm = so ? so->w_norm : R(0.0);
    t->zeta_bar = so ? so->zeta_bar : R(0.0);
    t->rs_est_ohm = s->obs.rs_ohm;
    t->duty0 = out->act.duty0;
    uint8_t st = dtc3l_state_of(&out->act.vector[0]);
    t->vector_index = st < DTC3L_N_STATES ? st : (uint8_t)DTC3L_STATE_OOO;
    t->state = (uint8_t)s->run_state;
    t->faults = s->faults;
}

/* Safe output: gates off, zero vector, telemetry. */
static void output_off(ctl_state *s, ctl_out *out)
{
    gates_off(s);
    out->act = s->last_act;
    out->gate_enable = false;
    s->te_ref_Nm = R(0.0);
    fill_telemetry(s, NULL, out);
}

/* Protect: latch this tick's faults; true when the gates must be off. */
static bool protect(ctl_state *s, const ctl_cfg *cfg, const ctl_in *in)
{
    uint32_t f = detect_faults(s, cfg, in);
    s->faults_active = f;
    s->faults |= f;
    if (s->faults != 0u)
        s->run_state = CTL_FAULTED;
    return s->faults != 0u;
}

/* Observe: the voltage applied from t_k to t_{k+1} is last_act with this
 * tick's vc1, vc2; the observer advances to t_{k+1} with it. */
static void observe(ctl_state *s, const ctl_cfg *cfg, const hal_sample *x)
{
    real_t v0[2], v1[2], v[2];
    uint8_t st0 = dtc3l_state_of(&s->last_act.vector[0]);
    uint8_t st1 = dtc3l_state_of(&s->last_act.vector[1]);
    dtc3l_state_voltage(st0, x->vc1_V, x->vc2_V, v0);
    dtc3l_state_voltage(st1, x->vc1_V, x->vc2_V, v1);
    real_t d0 = s->last_act.duty0;
    v[0] = num_mac(d0, v0[0] - v1[0], v1[0]);
    v[1] = num_mac(d0, v0[1] - v1[1], v1[1]);
    real_t is[2];
    is[0] = num_mul(R(0.333333333), R(2.0) * x->ia_A - x->ib_A - x->ic_A);
    is[1] = num_mul(NUM_INV_SQRT3, x->ib_A - x->ic_A);
    observer_step(&s->obs, &cfg->obs, is, v, &s->obs_out);
}

/* Neutral point at t_{k+1}: d(vc1 - vc2)/dt = i_np / C under last_act, V. */
static real_t predict_np_dev(const ctl_state *s, const ctl_cfg *cfg, const hal_sample *x)
{
    uint8_t st0 = dtc3l_state_of(&s->last_act.vector[0]);
    uint8_t st1 = dtc3l_state_of(&s->last_act.vector[1]);
    real_t d0 = s->last_act.duty0;
    real_t i_abc[3] = {x->ia_A, x->ib_A, x->ic_A};
    real_t inp1 = dtc3l_np_current(st1, i_abc);
    real_t inp = num_mac(d0, dtc3l_np_current(st0, i_abc) - inp1, inp1);
    return num_mac(cfg->np_V_per_A, inp, x->vc1_V - x->vc2_V);
}

/* Flux reference: slew-limited so that magnetising does not trip. */
static void ramp_flux_reference(ctl_state *s, const ctl_cfg *cfg)
{
    real_t dpsi = num_mul(cfg->psi_ramp_Wb_s, cfg->period_s);
    s->psi_ref_ramped_Wb = num_sat(cfg->dtc.psi_ref_Wb, s->psi_ref_ramped_Wb - dpsi, s->psi_ref_ramped_Wb + dpsi);
}

/* Magnetising: zero torque until premag_s, then RUNNING from the estimated speed. */
static void magnetise(ctl_state *s, const ctl_cfg *cfg)
{
    const observer_out *oo = &s->obs_out;
    s->t_magnetise_s += cfg->period_s;
    s->te_ref_Nm = R(0.0);
    if (s->t_magnetise_s >= cfg->dtc.premag_s) {
        s->run_state = CTL_RUNNING;
        s->speed_ref_ramped_rad_s = oo->omega_m_rad_s;
        speed_ctl_reset(&s->speed, R(0.0));
        speed_ctl_set_ref(&s->speed, oo->omega_m_rad_s);
    }
}

/* Speed control: ramp the reference, torque command from the speed controller. */
static void control_speed(ctl_state *s, const ctl_cfg *cfg, const ctl_in *in, speed_out *so)
{
    real_t T = cfg->period_s;
    real_t target = finite_r(in->speed_ref_rad_s) ? in->speed_ref_rad_s : s->speed_ref_ramped_rad_s;
    real_t prev = s->speed_ref_ramped_rad_s;
    s->speed_ref_ramped_rad_s = speed_ref_ramp(prev, target, num_mul(cfg->speed.ramp_rad_s2, T));
    speed_in si;
    si.omega_ref_rad_s = s->speed_ref_ramped_rad_s;
    si.domega_ref_rad_s2 = num_mul(s->speed_ref_ramped_rad_s - prev, cfg->inv_period_per_s);
    si.omega_est_rad_s = s->obs_out.omega_m_rad_s;
    speed_ctl_step(&s->speed, &cfg->speed, &cfg->motor, T, &si, so);
    s->te_ref_Nm = so->te_ref_Nm;
}

/* Torque and flux control on the state predicted for t_{k+1}; returns the
 * state in force when the chosen period starts. */
static uint8_t control_torque_flux(ctl_state *s, const ctl_cfg *cfg, const hal_sample *x, real_t np_dev_pred_V)
{
    const observer_out *oo = &s->obs_out;
    uint8_t st1 = dtc3l_state_of(&s->last_act.vector[1]);
    dtc3l_in di;
    di.te_ref_Nm = s->te_ref_Nm;
    di.psi_ref_Wb = s->psi_ref_ramped_Wb;
    di.te_Nm = oo->te_pred_Nm;
    di.psi_s_Wb[0] = oo->psi_s_pred_Wb[0];
    di.psi_s_Wb[1] = oo->psi_s_pred_Wb[1];
    di.is_A[0] = oo->is_pred_A[0];
    di.is_A[1] = oo->is_pred_A[1];
    di.dte0_Nm_s = oo->dte0_Nm_s;
    di.dte_dv[0] = oo->dte_dv[0];
    di.dte_dv[1] = oo->dte_dv[1];
    di.rs_ohm = s->obs.rs_ohm;
    di.omega_e_rad_s = s->obs.omega_e_rad_s;
    di.omega_m_rad_s = oo->omega_m_rad_s;
    di.vc1_V = x->vc1_V;
    di.vc2_V = x->vc2_V;
    di.np_dev_V = np_dev_pred_V;
    di.prev_state = st1 < DTC3L_N_STATES ? st1 : (uint8_t)DTC3L_STATE_OOO;
    dtc3l_step(&s->dtc, &cfg->dtc, cfg->period_s, &di, &s->dtc_out);
    return di.prev_state;
}

/* Actuate: the last guard against a P<->N step (the DTC never asks for one),
 * then latch for the next period. */
static void actuate(ctl_state *s, uint8_t prev_state, ctl_out *out)
{
    hal_actuation act = s->dtc_out.act;
    uint8_t a0 = dtc3l_pn_safe(prev_state, dtc3l_state_of(&act.vector[0]));
    uint8_t a1 = dtc3l_pn_safe(a0, dtc3l_state_of(&act.vector[1]));
    dtc3l_legs(a0, &act.vector[0]);
    dtc3l_legs(a1, &act.vector[1]);
    act.duty0 = num_sat(act.duty0, R(0.0), R(1.0));

    s->prev_act = s->last_act;
    s->last_act = act;
    s->last_vector = act.vector[1];
    out->act = act;
    out->gate_enable = true;
}

void ctl_step(ctl_state *s, const ctl_cfg *cfg, const ctl_in *in, ctl_out *out)
{
    if (protect(s, cfg, in)) {
        output_off(s, out); /* gates off in this very tick */
        return;
    }
    if (!in->run) {
        s->run_state = CTL_STOPPED;
        output_off(s, out);
        return;
    }
    if (s->run_state == CTL_STOPPED)
        start(s, cfg);

    observe(s, cfg, &in->sample);
    real_t np_dev_pred_V = predict_np_dev(s, cfg, &in->sample);
    ramp_flux_reference(s, cfg);

    speed_out so;
    memset(&so, 0, sizeof so);
    if (s->run_state == CTL_MAGNETISING)
        magnetise(s, cfg);
    if (s->run_state == CTL_RUNNING)
        control_speed(s, cfg, in, &so);

    uint8_t prev_state = control_torque_flux(s, cfg, &in->sample, np_dev_pred_V);
    actuate(s, prev_state, out);
    fill_telemetry(s, &so, out);
}
