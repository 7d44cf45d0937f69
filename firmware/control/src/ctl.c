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
#include "dtc/dead_time.h"

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
    o->regen_angle_rad = R(1.4);      /* regenerating-mode stabilisation (observer.c: its shape) */
    o->regen_speed_rad_s = R(100.0);  /* 477 rpm: fades out below the paper's 500 rpm point */
    o->speed_lpf_hz = R(50.0);

    cfg->i_trip_A = R(100.0);
    cfg->vdc_max_V = R(400.0);
    cfg->vdc_min_V = R(200.0);
    cfg->np_trip_V = R(30.0);
    cfg->overspeed_rad_s = R(310.0);       /* 2960 rpm: the reference limit 310 / 1.1 = 2691 rpm is above 1.5 x base (2610 rpm) */
    cfg->fw_voltage_frac = R(0.9);
    cfg->te_pullout_frac = R(0.9);
    cfg->fsw_max_hz = R(850.0);            /* 0.5..1 kHz at 500 rpm, <= 1.5 kHz everywhere */
    cfg->band_scale_max = R(4.0);
    cfg->rs_ident_tol = R(0.1); /* docs/envelope.md section 6 */
    cfg->regen_flux_min_frac = R(0.7); /* docs/envelope.md section 6; the torque limit at 0.7 x rated flux is 44.6 N m */
    cfg->guard.wc_rad_s = R(6.0);          /* 1 Hz */
    cfg->guard.flux_err_frac = R(0.15);
    cfg->guard.time_s = R(0.01);
    cfg->guard.rs_tol_frac = R(0.3);       /* a winding 30 % warmer than modelled */
    cfg->bringup_level = BRINGUP_SPEED;
    cfg->bringup_hz = R(5.0);
    cfg->stall_time_s = R(1.0);           /* longer than a full-power load recovery in field weakening */
    cfg->bringup_te_Nm = R(0.0);
    cfg->dead_time_comp_s = R(1.0e-6);     /* the board's HRTIM dead time (docs/board.md) */
    cfg->v_drop_V = R(1.0);                /* on-state drop per device, board-dependent (0: none) */
    cfg->guard.v_tol_V = R(6.0);           /* two device drops of ~1 V (2.7 V as a vector) plus dead time, x2 margin */

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
    cfg->dtc.np_V_per_A = cfg->np_V_per_A;
    cfg->inv_period_per_s = cfg->period_s > R(0.0) ? num_div(R(1.0), cfg->period_s) : R(0.0);
    cfg->dead_time_per_T = num_mul(cfg->dead_time_comp_s, cfg->inv_period_per_s); /* the tick's product before: the same bits */
    cfg->real_inverter = cfg->v_drop_V > R(0.0) || cfg->dead_time_comp_s > R(0.0); /* one byte's test per tick */
    cfg->drop4_V = num_mul(R(-4.0), cfg->v_drop_V); /* exact (a power of 2): the tick's product before */
    ctl_guard_cfg_derive(&cfg->guard, cfg->period_s);
    rs_ident_cfg_derive(&cfg->rsid, m, cfg->period_s, cfg->rs_ident_tol);
    /* stator-flux-oriented pull-out torque: Te_max = 1.5 p psi_s^2 (1 - sigma) / (2 sigma Ls) */
    real_t den = num_mul(R(2.0) * sigma, m->Ls_H);
    cfg->te_pullout_Nm_Wb2 = den > R(0.0) ? num_div(num_mul(R(1.5) * m->pole_pairs, R(1.0) - sigma), den) : R(0.0);
    cfg->speed_max_rad_s = num_div(cfg->overspeed_rad_s, R(1.1));
    cfg->fsw_per_change_hz = cfg->period_s > R(0.0) ? num_div(R(1.0), R(6.0) * cfg->period_s) : R(0.0);
    real_t t_sup = num_mul((real_t)CTL_SLOW_SLOTS, cfg->period_s); /* the supervision and regulation step */
    cfg->fsw_lpf_a = num_sat(R(1.0) - num_exp(-num_div(t_sup, R(0.02))), R(0.0), R(1.0));
    cfg->band_rate_T = num_mul(R(5.0), t_sup);
    cfg->sup_lpf_a = num_sat(R(1.0) - num_exp(-num_div(t_sup, R(0.02))), R(0.0), R(1.0));
    cfg->sup_rate_T = num_mul(R(5.0), t_sup);
    cfg->inv_fsw_max_s = cfg->fsw_max_hz > R(0.0) ? num_div(R(1.0), cfg->fsw_max_hz) : R(0.0);
    cfg->fw_v_per_vdc = num_mul(cfg->fw_voltage_frac, NUM_INV_SQRT3);
    cfg->te_limit_Nm_Wb2 = num_mul(cfg->te_pullout_frac, cfg->te_pullout_Nm_Wb2);
    /* rated-flux slip per N m: Rr / (1.5 p psi_r^2), psi_r = psi_ref Lm / Ls (no load) */
    real_t psi_r = num_div(num_mul(cfg->dtc.psi_ref_Wb, m->Lm_H), m->Ls_H);
    real_t slip_den = num_mul(num_mul(R(1.5), m->pole_pairs), num_mul(psi_r, psi_r));
    cfg->slip_rad_s_per_Nm = slip_den > R(0.0) ? num_div(m->Rr_ohm, slip_den) : R(0.0);
    cfg->regen_k2_min = num_mul(cfg->regen_flux_min_frac, cfg->regen_flux_min_frac);
    /* per-tick constants of the flux ramp and the speed loop (the same products
     * the tick worked out before: the same bits) */
    cfg->psi_ramp_step_Wb = num_mul(cfg->psi_ramp_Wb_s, cfg->period_s);
    cfg->speed_T_s = num_mul((real_t)CTL_RBFN_TICKS, cfg->period_s);
    cfg->speed_ramp_step_rad_s = num_mul(cfg->speed.ramp_rad_s2, cfg->speed_T_s);
    cfg->inv_speed_T_per_s = num_mul(R(1.0) / (real_t)CTL_RBFN_TICKS, cfg->inv_period_per_s);
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
          o->speed_lpf_hz >= R(0.0) && o->regen_angle_rad >= R(0.0) && o->regen_angle_rad <= R(1.5) &&
          o->regen_speed_rad_s > R(0.0) && cfg->regen_flux_min_frac >= R(0.5) && cfg->regen_flux_min_frac <= R(1.0)))
        return CTL_CFG_E_OBSERVER;
    if (!(cfg->i_trip_A > R(0.0) && cfg->vdc_max_V > R(0.0) && cfg->vdc_min_V >= R(0.0) &&
          cfg->vdc_min_V < cfg->vdc_max_V && cfg->np_trip_V > R(0.0) && cfg->overspeed_rad_s > R(0.0) &&
          cfg->guard.wc_rad_s > R(0.0) && cfg->guard.flux_err_frac >= R(0.0) && cfg->guard.time_s >= R(0.0) &&
          cfg->guard.rs_tol_frac >= R(0.0) && cfg->guard.v_tol_V >= R(0.0) && cfg->v_drop_V >= R(0.0) &&
          cfg->dead_time_comp_s >= R(0.0) && cfg->dead_time_comp_s <= R(10e-6) &&
          cfg->bringup_level >= BRINGUP_GATE_TEST && cfg->bringup_level <= BRINGUP_SPEED &&
          num_abs(cfg->bringup_hz) <= R(100.0) && cfg->stall_time_s >= R(0.0) && cfg->fw_voltage_frac > R(0.0) && cfg->fw_voltage_frac <= R(1.2) &&
          cfg->te_pullout_frac > R(0.0) && cfg->te_pullout_frac <= R(1.0) && cfg->fsw_max_hz >= R(0.0) &&
          cfg->band_scale_max >= R(1.0) && cfg->rs_ident_tol >= R(0.0) && cfg->rs_ident_tol <= R(1.0)))
        return CTL_CFG_E_PROTECTION;
    if (speed_cfg_check(&cfg->speed, m) != SPEED_CFG_OK)
        return CTL_CFG_E_SPEED;
    return CTL_CFG_OK;
}

/* The zero vector (OOO) in both halves for the whole period: a constant
 * (issue 11: copied as three words instead of two table look-ups). */
static const hal_actuation k_act_zero = {
    .vector = {{.leg = {HAL_LEG_O, HAL_LEG_O, HAL_LEG_O}}, {.leg = {HAL_LEG_O, HAL_LEG_O, HAL_LEG_O}}},
    .duty0 = R(1.0)};

static void act_zero(hal_actuation *a) { *a = k_act_zero; }

/* Gates off: the board then holds the zero vector, which is where the next
 * start continues from (no P<->N step is possible out of OOO). */
static void gates_off(ctl_state *s)
{
    act_zero(&s->last_act);
    s->last_state[0] = s->last_state[1] = s->end_state = (uint8_t)NPC_STATE_OOO;
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

/* The bits of @p x: for values >= +0 they order like the values; a negative
 * value's (sign bit set) are above every positive one's, a NaN's above every
 * finite positive one's. */
static inline uint32_t f32_bits(real_t x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* The magnitude bits of @p x: for finite values they order like |x|; a NaN
 * or an infinity is above every finite value's. */
static inline uint32_t abs_bits(real_t x) { return f32_bits(x) & 0x7FFFFFFFu; }

/* The common case in one pass: every sample value finite and no limit of
 * sample_faults() crossed. False sends the tick to sample_faults(), which
 * says which. The phase currents compare as integers (one compare for the
 * largest of the three; a NaN or infinite current fails it); a NaN or an
 * infinity in vc1 or vc2 makes vdc or their difference fail its compare. */
static inline bool sample_within_limits(const ctl_cfg *cfg, const hal_sample *x, real_t vdc, bool uv_judged)
{
    uint32_t ia = abs_bits(x->ia_A), ib = abs_bits(x->ib_A), ic = abs_bits(x->ic_A);
    uint32_t imax = ia > ib ? ia : ib;
    imax = imax > ic ? imax : ic;
    /* vdc in [vdc_min_V, vdc_max_V] as one unsigned compare of the bits
     * (ctl_cfg_check: 0 <= vdc_min_V < vdc_max_V; a negative vdc, a NaN or
     * an infinity fails it, so does -0, which sample_faults() then passes);
     * undervoltage not judged: |vdc| <= vdc_max_V, only an impossible vdc
     * takes the slow path (issue 11: about 3 instructions fewer than two float
     * compares with the lower bound chosen) */
    uint32_t v = uv_judged ? f32_bits(vdc) : abs_bits(vdc);
    uint32_t lo = uv_judged ? f32_bits(cfg->vdc_min_V) : 0u;
    return imax <= abs_bits(cfg->i_trip_A) && v - lo <= f32_bits(cfg->vdc_max_V) - lo &&
           num_abs(x->vc1_V - x->vc2_V) <= cfg->np_trip_V;
}

/* Which limits the sample crosses (the rare case; enum ctl_fault bits). */
static uint32_t sample_faults(const ctl_cfg *cfg, const hal_sample *x, real_t vdc, bool uv_judged)
{
    /* one test for all five: a NaN or an infinity in any of them makes the sum NaN */
    if (!finite_r((x->ia_A - x->ia_A) + (x->ib_A - x->ib_A) + (x->ic_A - x->ic_A) + (x->vc1_V - x->vc1_V) +
                  (x->vc2_V - x->vc2_V)))
        return CTL_FAULT_SAMPLE_INVALID;
    uint32_t f = 0u;
    if (num_abs(x->ia_A) > cfg->i_trip_A || num_abs(x->ib_A) > cfg->i_trip_A || num_abs(x->ic_A) > cfg->i_trip_A)
        f |= CTL_FAULT_OVERCURRENT;
    if (vdc > cfg->vdc_max_V)
        f |= CTL_FAULT_DC_OVERVOLT;
    if (uv_judged && vdc < cfg->vdc_min_V)
        f |= CTL_FAULT_DC_UNDERVOLT;
    if (num_abs(x->vc1_V - x->vc2_V) > cfg->np_trip_V)
        f |= CTL_FAULT_NP_IMBALANCE;
    return f;
}

/* Conditions of this tick (enum ctl_fault bits). */
static uint32_t detect_faults(ctl_state *s, const ctl_cfg *cfg, const ctl_in *in)
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
    /* bring-up levels 1 and 2 need no DC link */
    bool uv_judged = active && cfg->bringup_level > BRINGUP_ADC;
    real_t vdc = x->vc1_V + x->vc2_V;
    if (!sample_within_limits(cfg, x, vdc, uv_judged)) {
        uint32_t sf = sample_faults(cfg, x, vdc, uv_judged);
        if (sf & CTL_FAULT_SAMPLE_INVALID)
            return f | sf; /* judge nothing else on a value that is not a number */
        f |= sf;
    }
    /* Written as "not within" so that a diverged (NaN) estimate trips too. */
    if (active && !(num_abs(s->obs.omega_m_filt_rad_s) <= cfg->overspeed_rad_s))
        f |= CTL_FAULT_OVERSPEED;
    /* the loss-of-control and stall verdicts as their monitors last gave them (in their slots) */
    if (active)
        f |= s->monitor_faults;
    real_t omega_e = num_mul(cfg->motor.pole_pairs, s->obs.omega_m_filt_rad_s);
    /* the slow tasks' slot advances here, once per tick that judges a sample (ctl.h) */
    s->slow_slot = (uint8_t)((s->slow_slot + 1u) & (CTL_SLOW_SLOTS - 1u));
    f |= plaus_check(&s->plaus, x, active, s->run_state == CTL_STOPPED, omega_e, cfg->period_s,
                     (s->slow_slot & (CTL_MONITOR_SLOTS - 1u)) == CTL_SLOT_PLAUS);
    return f;
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
    s->psi_target_Wb = cfg->dtc.psi_ref_Wb; /* at standstill: rated (supervise_flux() takes over within a slot cycle) */
    s->te_limit_Nm = cfg->speed.te_max_Nm; /* until supervise_flux() works it out at the flux reached */
    s->short_sum_Nm = R(0.0);
    gates_off(s); /* the first period after enabling applies OOO */
}

/* The speed-loop outputs published while no speed loop runs. */
static const speed_out k_speed_none = {.te_ref_Nm = R(0.0), .eps_hat = R(0.0), .w_norm = R(0.0), .zeta_bar = R(0.0)};

static void fill_telemetry(const ctl_state *s, const speed_out *so, ctl_out *out)
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
    t->vector_index = s->last_state[0]; /* out->act is last_act in every path */
    t->state = (uint8_t)s->run_state;
    t->faults = s->faults;
}

/* Safe output: gates off, zero vector, telemetry. */
static void output_off(ctl_state *s, ctl_out *out)
{
    gates_off(s);
    act_zero(&out->act); /* = s->last_act, from the constant */
    out->gate_enable = false;
    s->te_ref_Nm = R(0.0);
    fill_telemetry(s, &k_speed_none, out);
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

/* Neutral point at t_{k+1}: d(vc1 - vc2)/dt = i_np / C under last_act, V. */
static real_t predict_np_dev(const ctl_state *s, const ctl_cfg *cfg, const hal_sample *x)
{
    uint8_t st0 = s->last_state[0];
    uint8_t st1 = s->last_state[1];
    real_t d0 = s->last_act.duty0;
    real_t i_abc[3] = {x->ia_A, x->ib_A, x->ic_A};
    real_t inp1 = npc_np_current_unchecked(st1, i_abc);
    real_t inp0 = st0 == st1 ? inp1 : npc_np_current_unchecked(st0, i_abc); /* one vector: the same current */
    real_t inp = num_mac(d0, inp0 - inp1, inp1);
    return num_mac(cfg->np_V_per_A, inp, x->vc1_V - x->vc2_V);
}

/* The state a period applying st0 for duty0 of it, then st1, ends on: st1
 * unless duty0 is 1 (st0 alone; a NaN duty counts as 1, as everywhere the
 * duty is tested against 1). */
static inline uint8_t period_end_state(uint8_t st0, uint8_t st1, real_t duty0)
{
    return duty0 < R(1.0) ? st1 : st0;
}

/* The leg voltage is lower than the state says by the on-state drop of the two
 * conducting devices, against the phase current: v_drop_V per device, with a
 * sign softened over +-DROP_BAND_A so a current at zero does not toggle it. */
#define DROP_BAND_A R(0.5)
/* Bit 7 of each byte set where the leg code in @p w_to is at least the one in
 * @p w_from, for the three legs at once. Exact: with codes 0..2 each byte is
 * 0x80 + to - from, 0x7E..0x82, so no byte borrows from the next; where the
 * codes differ, bit 7 is dead_time_edge_moving's to > from. */
static inline uint32_t rising_bytes(uint32_t w_from, uint32_t w_to)
{
    return (w_to | 0x80808080u) - w_from;
}

/* The dead time's edge of one leg (byte @p sh / 8 of the packed words), when it
 * commutes (its byte of @p moved set), between the levels @p from_V -> @p to_V,
 * rising when its byte of @p up (rising_bytes) has bit 7. */
static inline real_t leg_edge_on_levels(real_t v_V, unsigned sh, uint32_t moved, uint32_t up, real_t late_up,
                                        real_t from_V, real_t to_V, real_t dt_per_T)
{
    if ((moved >> sh) & 0xFFu)
        v_V = dead_time_edge_levels(((up >> sh) & 0x80u) != 0u, late_up, from_V, to_V, dt_per_T, v_V);
    return v_V;
}

/* The period's first edges, from the state the last one ended on (packed codes
 * @p w_from) to the first one it applies (@p w_first, whose levels @p la, @p lb,
 * @p lc were read for the mix: only the edges' starting levels are read here). */
static inline void first_edges(real_t *va, real_t *vb, real_t *vc, uint32_t w_from, uint32_t w_first, real_t la,
                               real_t lb, real_t lc, real_t ua, real_t ub, real_t uc, const real_t level_V[3],
                               real_t dt_per_T)
{
    uint32_t moved = w_from ^ w_first;
    if (moved != 0u) {
        uint32_t up = rising_bytes(w_from, w_first);
        *va = leg_edge_on_levels(*va, 0u, moved, up, ua, level_V[w_from & 0xFFu], la, dt_per_T);
        *vb = leg_edge_on_levels(*vb, 8u, moved, up, ub, level_V[(w_from >> 8) & 0xFFu], lb, dt_per_T);
        *vc = leg_edge_on_levels(*vc, 16u, moved, up, uc, level_V[(w_from >> 16) & 0xFFu], lc, dt_per_T);
    }
}

/* The fraction of a rising edge that is late, from the leg's current (dead_time.h):
 * sat(y, 0, 1) for y = 0.5 + i / (2 DROP_BAND_A), on the bits of y (issue 11: two
 * integer selects instead of two float compares per leg). A negative y (sign bit
 * set) gives +0, as the clamp's lower bound; a non-negative one orders like its
 * bits, so the smaller of the bits and 1.0's is the clamp's upper bound. The same
 * value as num_sat for every y but a NaN (1 here; the phase currents are finite
 * here: detect_faults() trips SAMPLE_INVALID first; y is never -0). */
static inline real_t late_up_of(real_t i_A)
{
    uint32_t u = f32_bits(R(0.5) + i_A / (R(2.0) * DROP_BAND_A));
    const uint32_t one = 0x3F800000u; /* 1.0f */
    u = (u & 0x80000000u) != 0u ? 0u : u;
    u = u < one ? u : one;
    real_t y;
    memcpy(&y, &u, sizeof y);
    return y;
}

/* The three legs' voltages of a real inverter, V: the commanded ones (the
 * duty's mix of the period's two vectors), less the device drops, plus the
 * dead time's error (dead_time.h; with no dead time dt_per_T is 0 and the
 * edges add nothing). The drop: 2 v_drop_V x sat(i / DROP_BAND_A, -1, 1)
 * = 4 v_drop_V x late_up - 2 v_drop_V, with late_up = sat(0.5 + i / (2
 * DROP_BAND_A), 0, 1) the dead time's softened sign; the constant 2 v_drop_V,
 * common to the three legs, drops out of the stator voltage. The dead time's
 * edges: from the state the last period ended on (s->end_state) to the first
 * one this period applies, then between its two states when it applies both
 * (0 < duty0 < 1); the legs that commute are the bytes in which the states'
 * packed leg codes differ (issue 11: no duty compare with one state, no
 * per-leg code test when nothing commutes). Each leg takes its mix, drop, first
 * edge and split edge in that order, the legs apart from one another; the
 * path that applies st0 first is apart from the others, and the levels read
 * for the mix (last_act's codes: the states' own, ctl_step writes them
 * together) are the edges' end levels (issue 11; the results are the same bits
 * as leg by leg in one pass). Writes the stator voltage @p v
 * (alpha-beta: one Clarke transform of the three legs), V; returns the state
 * this period ends on (st1 unless duty0 is 1). Inline: without the hint GCC
 * kept it out of ctl_step (issue 11). */
static inline uint8_t apply_real_inverter(const ctl_state *s, const ctl_cfg *cfg, const real_t level_V[3],
                                          const hal_sample *x, real_t v[2])
{
    uint8_t st0 = s->last_state[0], st1 = s->last_state[1];
    uint32_t w1 = npc_state_legs_packed[st1];
    uint32_t w_from = npc_state_legs_packed[s->end_state];
    uint8_t end = st1;
    real_t drop4_V = cfg->drop4_V; /* 0 with the drops off */
    real_t dt = cfg->dead_time_per_T;
    real_t ua = late_up_of(x->ia_A), ub = late_up_of(x->ib_A), uc = late_up_of(x->ic_A);
    /* the legs' voltages as scalars (an array stayed in memory: issue 11); the codes
     * read from last_act where they are needed (fewer registers held) */
    const uint8_t *l0 = s->last_act.vector[0].leg, *l1 = s->last_act.vector[1].leg;
    real_t la1 = level_V[l1[0]], lb1 = level_V[l1[1]], lc1 = level_V[l1[2]];
    real_t d0 = s->last_act.duty0;
    real_t va = la1, vb = lb1, vc = lc1;
    real_t la0 = R(0.0), lb0 = R(0.0), lc0 = R(0.0); /* st0's levels: read, and used, only when st0 != st1 */
    if (st0 != st1) {
        la0 = level_V[l0[0]];
        lb0 = level_V[l0[1]];
        lc0 = level_V[l0[2]];
        va = num_mac(d0, la0 - la1, la1);
        vb = num_mac(d0, lb0 - lb1, lb1);
        vc = num_mac(d0, lc0 - lc1, lc1);
    }
    va = num_mac(drop4_V, ua, va);
    vb = num_mac(drop4_V, ub, vb);
    vc = num_mac(drop4_V, uc, vc);
    if (st0 == st1 || !(d0 > R(0.0))) { /* the period starts on st1 */
        first_edges(&va, &vb, &vc, w_from, w1, la1, lb1, lc1, ua, ub, uc, level_V, dt);
        if (st0 != st1)
            end = period_end_state(st0, st1, d0); /* st0 for a NaN duty */
    } else { /* st0 first */
        uint32_t w0 = npc_state_legs_packed[st0];
        first_edges(&va, &vb, &vc, w_from, w0, la0, lb0, lc0, ua, ub, uc, level_V, dt);
        if (d0 < R(1.0)) { /* then st0 -> st1, on the levels read for the mix */
            uint32_t moved = w0 ^ w1, up = rising_bytes(w0, w1);
            va = leg_edge_on_levels(va, 0u, moved, up, ua, la0, la1, dt);
            vb = leg_edge_on_levels(vb, 8u, moved, up, ub, lb0, lb1, dt);
            vc = leg_edge_on_levels(vc, 16u, moved, up, uc, lc0, lc1, dt);
        } else {
            end = st0;
        }
    }
    v[0] = num_mul(R(0.333333333), R(2.0) * va - vb - vc);
    v[1] = num_mul(NUM_INV_SQRT3, vb - vc);
    return end;
}

/* Observe: the voltage applied from t_k to t_{k+1} is last_act with the
 * capacitors' mean voltages over the period (from this tick's vc1, vc2 and
 * the predicted neutral point at t_{k+1}); the observer advances to t_{k+1}
 * with it. Returns that voltage and the sampled current (alpha-beta), and
 * sets s->end_state, the state that period ends in (the next period's dead-time
 * edges start from it). Leg by leg (the commanded level, the device drops, the
 * dead time), then one Clarke transform. Inline: without the hint GCC stopped
 * inlining it into ctl_step (+20 per tick, issue 11). */
static inline void observe(ctl_state *s, const ctl_cfg *cfg, const hal_sample *x, real_t np_dev_pred_V, real_t v[2],
                    real_t is[2])
{
    uint8_t st0 = s->last_state[0];
    uint8_t st1 = s->last_state[1];
    /* The capacitors' mean voltages over the period, not their values at its
     * start: the neutral-point current moves vc1 - vc2 by up to 3 V in one
     * period at rated current (the sum stays), and near zero stator frequency
     * the stator voltage is only Rs |is|, about 8 V: the start values left a
     * speed bias of 3-7 rpm at 30 rpm generating (docs/envelope.md section 6).
     * Linear over the period, so the mean is the midpoint: each capacitor
     * moves by half the predicted change, the mean by half of that. */
    real_t q = num_mul(R(0.25), np_dev_pred_V - (x->vc1_V - x->vc2_V));
    /* the levels of the leg codes N, O, P (last_act holds the states' codes) */
    const real_t level_V[3] = {-(x->vc2_V - q), R(0.0), x->vc1_V + q};
    const real_t i[3] = {x->ia_A, x->ib_A, x->ic_A};
    uint8_t end = st1; /* the state this period ends on */
    if (!cfg->real_inverter) {
        /* an ideal inverter: the states' voltages straight in alpha-beta */
        npc_legs_voltage(&s->last_act.vector[1], level_V, v);
        if (st0 != st1) { /* two states: mixed by the duty (one state's d0 x 0 + v1 would be v1 exactly) */
            real_t v0[2];
            npc_legs_voltage(&s->last_act.vector[0], level_V, v0);
            real_t d0 = s->last_act.duty0;
            v[0] = num_mac(d0, v0[0] - v[0], v[0]);
            v[1] = num_mac(d0, v0[1] - v[1], v[1]);
            end = period_end_state(st0, st1, d0);
        }
    } else {
        /* leg by leg (the commanded level, the device drops, the dead time), then one Clarke transform */
        end = apply_real_inverter(s, cfg, level_V, x, v);
    }
    s->end_state = end; /* the next period's dead-time edges start there */
    is[0] = num_mul(R(0.333333333), R(2.0) * i[0] - i[1] - i[2]);
    is[1] = num_mul(NUM_INV_SQRT3, i[1] - i[2]);
    s->obs.te_cmd_Nm = s->te_ref_Nm; /* the command behind the voltage of this period */
    observer_step_ab(&s->obs, &cfg->obs, is[0], is[1], v[0], v[1], &s->obs_out);
}

/* Lowered flux for regeneration near zero stator frequency. A load driving
 * the motor at low speed puts the stator frequency (rotor speed minus the
 * slip) near zero, where the speed estimate drifts (the machine is not
 * observable there; docs/envelope.md section 6). The slip grows as 1/flux^2
 * at a given torque, so a lower flux takes the stator frequency through zero
 * to the side opposing the rotation, LOWFLUX_MARGIN_RAD_S beyond it, where
 * the observer holds the speed. Decided on the rated-flux slip of the torque
 * command and the estimated speed (neither moves with the flux, so the
 * decision does not feed back on itself), with hysteresis; only where a flux
 * of at least regen_flux_min_frac x rated reaches the margin (the torque
 * limit at that flux stays above the rated torque). Returns the flux factor
 * (1 = rated) and sets the observer's regen_low_flux. */
#define LOWFLUX_MARGIN_RAD_S R(2.5)    /* stator frequency aimed at: 0.4 Hz against the rotation */
#define LOWFLUX_ENTER_RAD_S R(6.3)     /* rated-flux stator frequency below which it starts, 1.0 Hz */
#define LOWFLUX_EXIT_RAD_S R(8.8)      /* ... and above which it ends, 1.4 Hz */
#define LOWFLUX_EXIT_K2 R(0.92)        /* hysteresis of the reach test, x regen_k2_min */
#define LOWFLUX_MIN_NM R(2.0)          /* below this the sign of the command is noise */
static real_t regen_flux_factor(ctl_state *s, const ctl_cfg *cfg)
{
    real_t w = s->obs.omega_e_rad_s;
    real_t te = s->te_ref_Nm;
    bool regen = s->run_state == CTL_RUNNING && (w >= R(0.0) ? te < -LOWFLUX_MIN_NM : te > LOWFLUX_MIN_NM);
    if (!regen || !(cfg->regen_flux_min_frac < R(1.0))) { /* the usual case, and cheap */
        s->obs.regen_low_flux = false;
        return R(1.0);
    }
    real_t a = num_abs(w);
    real_t slip = num_mul(num_abs(te), cfg->slip_rad_s_per_Nm);
    real_t k2 = num_div(slip, a + LOWFLUX_MARGIN_RAD_S);
    bool on = s->obs.regen_low_flux ? (a - slip < LOWFLUX_EXIT_RAD_S && k2 >= num_mul(LOWFLUX_EXIT_K2, cfg->regen_k2_min))
                                    : (a - slip < LOWFLUX_ENTER_RAD_S && k2 >= cfg->regen_k2_min);
    s->obs.regen_low_flux = on;
    if (!on || k2 >= R(1.0))
        return R(1.0);
    return num_sqrt(k2 > cfg->regen_k2_min ? k2 : cfg->regen_k2_min);
}

/* Flux target: rated, or what the measured DC link allows at the present
 * speed (field weakening), whichever is lower; then the torque limit at the
 * flux reference. One supervision step (CTL_SLOT_SUPERVISE, every
 * CTL_SLOW_SLOTS ticks): the operating point moves slowly against that. */
static void supervise_flux(ctl_state *s, const ctl_cfg *cfg, const hal_sample *x)
{
    /* Voltage margin: a DTC that keeps falling short of the torque command
     * by more than the band has no voltage left to raise the torque; the
     * weakening flux is then trimmed down (and recovers when it is not).
     * The shortfall is the mean of the ticks since the last step. */
    real_t short_Nm = num_mul(s->short_sum_Nm, R(1.0) / (real_t)CTL_SLOW_SLOTS);
    s->short_sum_Nm = R(0.0);
    s->te_short_Nm = num_mac(cfg->sup_lpf_a, short_Nm - s->te_short_Nm, s->te_short_Nm);
    real_t over = num_div(s->te_short_Nm - cfg->dtc.torque_band2_Nm, cfg->speed.te_max_Nm);
    s->fw_trim = num_sat(s->fw_trim - num_mul(cfg->sup_rate_T, over), R(0.85), R(1.0));

    real_t target = num_mul(cfg->dtc.psi_ref_Wb, regen_flux_factor(s, cfg));
    real_t v_max = num_mul(num_mul(cfg->fw_v_per_vdc, s->fw_trim), x->vc1_V + x->vc2_V);
    real_t w = num_abs(s->obs.omega_e_rad_s);
    if (num_mul(target, w) > v_max)
        target = num_div(v_max, w);
    s->psi_target_Wb = target;
    real_t psi = s->dtc_cmd.psi_ref_Wb;
    real_t te_po = num_mul(cfg->te_limit_Nm_Wb2, num_mul(psi, psi));
    s->te_limit_Nm = te_po < cfg->speed.te_max_Nm ? te_po : cfg->speed.te_max_Nm;
}

/* Every tick: the shortfall summed for supervise_flux(), and the flux
 * reference slew-limited towards its target so that magnetising does not trip. */
static void ramp_flux_reference(ctl_state *s, const ctl_cfg *cfg)
{
    s->short_sum_Nm += num_abs(s->te_ref_Nm) - num_abs(s->obs_out.te_Nm);
    /* at the target (most ticks) the clamp would return the target's very bits: skipped,
     * judged on the bits (a NaN stays NaN, -0 stays -0; issue 11) */
    if (f32_bits(s->psi_target_Wb) == f32_bits(s->dtc_cmd.psi_ref_Wb))
        return;
    real_t dpsi = cfg->psi_ramp_step_Wb;
    s->dtc_cmd.psi_ref_Wb = num_sat(s->psi_target_Wb, s->dtc_cmd.psi_ref_Wb - dpsi, s->dtc_cmd.psi_ref_Wb + dpsi);
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

/* Speed control: ramp the reference, torque command from the speed controller. */
/* Speed error beyond which a torque command at the limit counts towards a stall: 3 rad/s = 29 rpm. */
#define STALL_SPEED_ERR_RAD_S R(3.0)
#define STALL_WINDOW_S R(0.1)

/* Braking at the torque limit, off speed, at low speed, and the (estimated)
 * speed does not fall at all over BRAKE_STALL_TIME_S: the load drives the
 * machine harder than the drive can brake, or the estimate no longer follows
 * a shaft the load is running away with (a rated generating load at 100 rpm:
 * the estimate stays near 130 rpm while the shaft passes 1000 rpm within
 * 0.3 s). Only below BRAKE_STALL_SPEED_RAD_S (477 rpm), where the
 * loss-of-control monitor is blind at low stator frequency; above it the
 * stall timer and that monitor judge. A deceleration at the limit lowers the
 * filtered estimate in every window, however large the inertia (at 1 rad/s^2
 * by 0.1 rad/s), so it does not trip this. */
#define BRAKE_STALL_TIME_S R(0.1)
#define BRAKE_STALL_SPEED_RAD_S R(50.0)
static void brake_stall_step(ctl_state *s, const ctl_cfg *cfg, bool at_limit, bool off_speed, real_t T)
{
    real_t w = num_abs(s->obs.omega_m_filt_rad_s);
    bool braking = num_mul(s->te_ref_Nm, s->obs.omega_m_filt_rad_s) < R(0.0);
    if (!(at_limit && cfg->stall_time_s > R(0.0) && braking && w < BRAKE_STALL_SPEED_RAD_S)) {
        s->t_brake_limit_s = R(0.0);
        return;
    }
    if (!off_speed)
        return; /* on speed at the limit: full braking power, the window waits */
    if (s->t_brake_limit_s == R(0.0))
        s->w_brake_start_rad_s = w;
    s->t_brake_limit_s += T;
    if (s->t_brake_limit_s < BRAKE_STALL_TIME_S)
        return;
    if (!(w < s->w_brake_start_rad_s))
        s->brake_stall = true;
    s->t_brake_limit_s = R(0.0); /* next window */
}

/* A command pinned at the limit while the speed stays away from its reference, and does
 * not come nearer, means the loop cannot hold the speed it is asked for (overload,
 * pull-out, or an estimate that no longer moves with the shaft). Counted in windows of
 * STALL_WINDOW_S: a window whose error shrank (an acceleration or deceleration at the
 * limit, however slow) does not count, nor does time at the limit on speed (full
 * power); leaving the limit restarts the count. Off speed is judged on the filtered
 * estimate (a noisy estimate hovering at the threshold restarted the old timer for
 * ever: 100 rpm with the rated load generating ran away with no trip). One step per
 * speed-loop step T, in its own slot (CTL_SLOT_STALL, not the command's: issue 11), on
 * the command held since and the filtered estimate of this tick. */
static void stall_step(ctl_state *s, const ctl_cfg *cfg, real_t T)
{
    bool at_limit = num_abs(s->te_ref_Nm) >= num_mul(R(0.98), s->te_limit_Nm);
    real_t err = num_abs(s->speed_ref_ramped_rad_s - s->obs.omega_m_filt_rad_s);
    bool off_speed = err > STALL_SPEED_ERR_RAD_S;
    if (!at_limit) {
        s->t_at_limit_s = R(0.0);
        s->t_stall_win_s = R(0.0);
    } else if (off_speed) {
        if (s->t_stall_win_s == R(0.0))
            s->err_win_start_rad_s = err;
        s->t_stall_win_s += T;
        if (s->t_stall_win_s >= STALL_WINDOW_S) {
            if (!(err < s->err_win_start_rad_s))
                s->t_at_limit_s += s->t_stall_win_s;
            s->t_stall_win_s = R(0.0);
        }
    }
    brake_stall_step(s, cfg, at_limit, off_speed, T);
    /* the verdict, judged here where its inputs change rather than every tick (issue 11): the rare
     * conditions first, the configuration's switch-off last */
    bool stall = (s->brake_stall || s->t_at_limit_s >= cfg->stall_time_s) && cfg->stall_time_s > R(0.0);
    s->monitor_faults = (s->monitor_faults & ~(uint32_t)CTL_FAULT_STALL) | (stall ? (uint32_t)CTL_FAULT_STALL : 0u);
}

/* The speed loop runs every CTL_RBFN_TICKS-th tick, whatever the controller:
 * its command in a slot the monitors leave free, the RBFN's learning of that
 * command and the stall windows each in a later slot of their own (ctl.h);
 * between its steps the torque command and the speed controller's outputs
 * (s->speed_held, written in place: no copy per tick, issue 11) hold. */
static void control_speed(ctl_state *s, const ctl_cfg *cfg, const ctl_in *in)
{
    real_t T = cfg->speed_T_s; /* the speed loop's step */
    bool rbfn = cfg->speed.mode == SPEED_MODE_RBFN;
    unsigned k = s->slow_slot & (CTL_RBFN_TICKS - 1u);
    if (k != CTL_SLOT_RBFN) {
        if (k == CTL_SLOT_STALL)
            stall_step(s, cfg, T);
        else if (rbfn && k == CTL_SLOT_RBFN_LEARN)
            speed_ctl_learn(&s->speed, &cfg->speed, T, &s->speed_held); /* the last command's */
        return;
    }
    real_t prev = s->speed_ref_ramped_rad_s;
    /* at the target (most steps) the ramp returns it: skipped on equal bits, but not at zero,
     * where prev + (+0) makes a -0 into +0 (issue 11: on the command tick, the worst one).
     * An input that is the ramped reference itself, within the limit, is that target as
     * it is (finite, not clamped): neither screened nor clamped then. */
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
    uint8_t st1 = s->last_state[1];
    /* the prediction is read where the observer left it (s->obs_out); the command is kept
     * in the state, so its band scale, written by the regulation once per slot cycle, and
     * its flux reference, the ramp's (which stands still at its target), are not copied
     * every tick (issue 11) */
    dtc3l_cmd *cmd = &s->dtc_cmd;
    cmd->te_ref_Nm = s->te_ref_Nm;
    cmd->rs_ohm = s->obs.rs_ohm;
    cmd->omega_e_rad_s = s->obs.omega_e_rad_s;
    cmd->vc1_V = x->vc1_V;
    cmd->vc2_V = x->vc2_V;
    cmd->np_dev_V = np_dev_pred_V;
    /* last_state is always a state number: only gates_off() (OOO), actuate() and bringup_step()
     * (P<->N guard outputs, 0..26) write it, so no clamp (issue 11; observe() and
     * predict_np_dev() rely on the same, and so does end_state, which gates_off(), observe()
     * and bringup_step() write from last_state values only) */
    cmd->prev_state = st1;
    cmd->decide_level = s->slow_slot == CTL_SLOT_LEVEL;
    dtc3l_step_predicted(&s->dtc, &cfg->dtc, cfg->period_s, cmd, &s->obs_out, &s->dtc_out);
    return st1;
}

/* Switching frequency: the leg changes of the actuations latched, summed
 * every tick and low-passed once per slot cycle (CTL_SLOT_FSW) as a device
 * switching frequency from their mean; above fsw_max_hz the torque
 * bands widen (integral action on the band scale, clamped to
 * 1..band_scale_max), below it they return to the configured ones. The
 * bands thereby follow speed and load: the torque slopes, and with them the
 * switching rate for a given band, grow with the back-emf and the current.
 * The 20 ms filter and the 5 1/s band rate need no per-tick step (issue 11). */
static void regulate_switching_frequency(ctl_state *s, const ctl_cfg *cfg, uint8_t prev_state, uint8_t a0,
                                         uint8_t a1)
{
    uint32_t n = s->fsw_changes + npc_leg_changes_unchecked(prev_state, a0); /* all three 0..26 */
    if (a1 != a0)
        n += npc_leg_changes_unchecked(a0, a1);
    if (s->slow_slot != CTL_SLOT_FSW) {
        s->fsw_changes = (uint8_t)n; /* at most 4 x 12 */
        return;
    }
    s->fsw_changes = 0u;
    real_t f = num_mul(num_mul((real_t)n, cfg->fsw_per_change_hz), R(1.0) / (real_t)CTL_SLOW_SLOTS);
    s->fsw_hz = num_mac(cfg->fsw_lpf_a, f - s->fsw_hz, s->fsw_hz);
    if (!(cfg->fsw_max_hz > R(0.0))) {
        s->dtc_cmd.band_scale = R(1.0);
        return;
    }
    real_t rel = num_mul(s->fsw_hz, cfg->inv_fsw_max_s) - R(1.0);
    real_t k = num_mul(cfg->band_rate_T, s->dtc_cmd.band_scale);
    s->dtc_cmd.band_scale = num_sat(num_mac(k, rel, s->dtc_cmd.band_scale), R(1.0), cfg->band_scale_max);
}

/* Actuate: the last guard against a P<->N step (the DTC never asks for
 * one), then latch for the next period. */
static void actuate(ctl_state *s, const ctl_cfg *cfg, uint8_t prev_state, ctl_out *out)
{
    hal_actuation act;
    /* prev_state was clamped, the DTC's states come from its tables: all 0..26 */
    uint8_t a0 = npc_pn_safe_unchecked(prev_state, s->dtc_out.state[0]);
    uint8_t a1 = npc_pn_safe_unchecked(a0, s->dtc_out.state[1]);
    /* in 0..1 by construction (dtc3l.h; duty_min is 0..0.45 by ctl_cfg_check),
     * and a clamp would not catch a NaN either: no compare (issue 11) */
    act.duty0 = s->dtc_out.act.duty0;
    npc_legs_pair_unchecked(a0, a1, &act);
    regulate_switching_frequency(s, cfg, prev_state, a0, a1);

    s->last_act = act;
    s->last_state[0] = a0;
    s->last_state[1] = a1;
    out->act = act;
    out->gate_enable = true;
}

/*
 * Bring-up levels 1-4 (dtc/bringup.h): no magnetising, no speed or torque
 * control, no loss-of-control monitor; the actuation is a gate-test pattern,
 * nothing (level 2: gates off), or open-loop V/f with the observer running.
 */
static void bringup_step(ctl_state *s, const ctl_cfg *cfg, const ctl_in *in, ctl_out *out)
{
    uint32_t level = cfg->bringup_level;
    s->run_state = CTL_RUNNING;
    s->t_magnetise_s += cfg->period_s; /* time since the start */
    s->te_ref_Nm = R(0.0);
    if (level == BRINGUP_ADC) {
        output_off(s, out);
        s->run_state = CTL_RUNNING;
        return;
    }
    hal_actuation act;
    if (level == BRINGUP_GATE_TEST) {
        act.vector[0] = act.vector[1] = bringup_gate_pattern(s->t_magnetise_s);
        act.duty0 = R(1.0);
    } else {
        real_t v_V[2], is_A[2];
        observe(s, cfg, &in->sample, predict_np_dev(s, cfg, &in->sample), v_V, is_A);
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
    uint8_t prev = s->last_state[1];
    uint8_t a0 = npc_pn_safe(prev, npc_state_of(&act.vector[0]));
    uint8_t a1 = npc_pn_safe(a0, npc_state_of(&act.vector[1]));
    npc_legs(a0, &act.vector[0]);
    npc_legs(a1, &act.vector[1]);
    /* the state the period now ending ends on (observe() works it out too, but not at every level) */
    s->end_state = period_end_state(s->last_state[0], s->last_state[1], s->last_act.duty0);
    s->last_act = act;
    s->last_state[0] = a0;
    s->last_state[1] = a1;
    out->act = act;
    out->gate_enable = true;
    fill_telemetry(s, &k_speed_none, out);
}

/* restrict (the definition only; the header's prototype is compatible): the
 * caller's state, configuration, inputs and outputs are distinct objects, so a
 * store through one need not reload the others (issue 11: about 6 instructions
 * per tick, no float operation moved). */
void ctl_step(ctl_state *restrict s, const ctl_cfg *restrict cfg, const ctl_in *restrict in, ctl_out *restrict out)
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
    if (cfg->bringup_level < BRINGUP_TORQUE) {
        bringup_step(s, cfg, in, out);
        return;
    }

    real_t v_V[2], is_A[2];
    real_t np_dev_pred_V = predict_np_dev(s, cfg, &in->sample);
    observe(s, cfg, &in->sample, np_dev_pred_V, v_V, is_A);
    if ((s->slow_slot & (CTL_MONITOR_SLOTS - 1u)) == CTL_SLOT_GUARD) { /* its window closes: the check of the ticks before this one */
        bool trip = ctl_guard_check(&s->guard, &cfg->guard, cfg->period_s, is_A, s->obs.rs_ohm,
                                    s->obs_out.psi_s_Wb, s->dtc_cmd.psi_ref_Wb, s->run_state == CTL_RUNNING);
        s->monitor_faults = (s->monitor_faults & ~(uint32_t)CTL_FAULT_LOSS_OF_CONTROL) |
                            (trip ? (uint32_t)CTL_FAULT_LOSS_OF_CONTROL : 0u);
        /* in this branch, so that the compiler sees the sums just reset to -0.0: it
         * drops both the reset and the additions (x + -0.0 is x; cycle count) */
        ctl_guard_accumulate(&s->guard, v_V, is_A);
    } else {
        ctl_guard_accumulate(&s->guard, v_V, is_A);
    }
    if (s->slow_slot == CTL_SLOT_SUPERVISE) {
        supervise_flux(s, cfg, &in->sample);
    }
    ramp_flux_reference(s, cfg);

    const speed_out *so = &k_speed_none; /* the telemetry's speed-loop outputs (a constant: no test per tick) */
    if (s->run_state == CTL_MAGNETISING) {
        /* copies made here (the magnetising ticks only): with v_V itself GCC kept the voltage
         * in memory for this call every tick (issue 11) */
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
    fill_telemetry(s, so, out);
}
