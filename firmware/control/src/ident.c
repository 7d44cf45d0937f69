/**
 * @file ident.c
 * @brief The identification run: configuration, phases, the background's
 *        fits and the verdicts (dtc/ident.h).
 */
#include "dtc/ident.h"

/* ------------------------------------------------------------------ sizing (docs/commissioning.md) */

#define IDENT_MAG_TR R(4.0)         /* MAGNETISE lasts this many plate Tr ... */
#define IDENT_ROTOR_TR R(5.0)       /* ... ROTOR this many: with the plate's Tr within a factor 1.6 of the
                                       true one, the rotor step still covers three true Tr */
#define IDENT_MAG_MIN_S R(0.2)
#define IDENT_ROTOR_MIN_S R(0.25)
#define IDENT_DC_MAX_S R(11.0)      /* each DC stage at most: the standstill part stays under 25 s */
#define IDENT_PROBE_S R(0.01)
#define IDENT_BURSTS 64u
#define IDENT_BURST_GAP 12u         /* regulated periods after each burst, at least */
#define IDENT_SETTLE_BLOCKS 60u
#define IDENT_LOOP_GAIN R(0.5)      /* the regulator's gain per block times the plate's Lsig / (n T) */
#define IDENT_I_HI_MAX R(0.6)       /* i_hi at most this x i_max */
#define IDENT_RS_MIN_PU R(0.005)    /* Rs assumed at least this per unit when the block length is chosen */

static inline bool ident_finite(real_t x) { return x - x == R(0.0); }

static uint32_t ident_ticks_of(real_t t_s, real_t period_s)
{
    real_t n = num_div(t_s, period_s);
    return (uint32_t)n + 1u;
}

static void ident_derive_standstill(ident_cfg *c)
{
    const ident_plate_est *e = &c->est;
    ident_ss_cfg *s = &c->ss;
    real_t T = c->period_s, dt = c->dead_time_s;
    s->period_s = T;
    s->dead_time_s = dt;
    s->w_min_s = num_mac(R(1.5), dt, R(1e-6));
    s->vdc_min_V = c->vdc_min_V;
    s->i_max_A = c->i_max_A > R(0.0) ? c->i_max_A : e->i_peak_A;
    real_t i_hi = num_mul(IDENT_I_HI_MAX, s->i_max_A);
    s->i_hi_A = e->i_mag_A < i_hi ? e->i_mag_A : i_hi;
    s->i_lo_A = num_mul(R(0.5), s->i_hi_A);
    s->hf_di_A = num_mul(R(0.3), s->i_hi_A);
    real_t v_s = num_div(c->vdc_nom_V, R(3.0)); /* a small vector: 2/3 of one capacitor */
    s->hf_duty0 = num_sat(num_div(num_mul(s->hf_di_A, e->sigma_ls_H), num_mul(v_s, T)), num_div(s->w_min_s, T), R(0.9));
    /* the block: the narrowest pulse expected at i_lo (the drops and a low Rs) at
     * least twice w_min, so that errors in the drop, the dead time and the noise
     * on the current skip no pulse (the dead time's error is per pulse: a bin
     * whose pulses are all there has the constant error the fit takes out) */
    real_t v_need = num_mac(R(2.0), c->v_drop_V, num_mul(num_mul(IDENT_RS_MIN_PU, e->z_base_ohm), s->i_lo_A));
    /* ... but a block well inside the stator's transient time constant
     * sigma Ls / (Rs + R_R) (~ 0.15 / (2 s w_e) at the plate's rated slip s),
     * where the current between two pulses is still a straight line */
    real_t t_sig = num_div(R(0.15), num_mul(R(2.0), e->w_slip_rad_s));
    uint32_t n_max = (uint32_t)num_sat(num_div(num_mul(R(0.25), t_sig), T), R(2.0), R(16.0));
    uint32_t n = 2u;
    while (n < n_max && num_mac(num_div(num_mul(v_need, (real_t)n * T), v_s), R(1.0), dt) < R(2.0) * s->w_min_s)
        n++;
    s->n_block = n;
    s->kp_V_A = num_div(num_mul(IDENT_LOOP_GAIN, e->sigma_ls_H), (real_t)n * T);
    s->kp_hold_V_A = num_mul(R(0.25), s->kp_V_A);
    s->ki_V_A = num_mul(R(0.05), s->kp_V_A);
    real_t t1 = num_mul(R(0.03), s->i_hi_A), t2 = num_mul(R(0.01), e->i_peak_A);
    s->turn_A = t1 > t2 ? t1 : t2;
    s->ib_lpf_a = R(1.0) - num_exp(-num_div(T, R(0.01)));
    uint32_t m = (IDENT_BURST_GAP + n - 1u) / n;
    s->cycle = 4u + m * n;
    s->bursts = IDENT_BURSTS;
    s->probe_ticks = ident_ticks_of(IDENT_PROBE_S, T);
    real_t t_mag = num_sat(num_mul(IDENT_MAG_TR, e->tr_s), IDENT_MAG_MIN_S, IDENT_DC_MAX_S);
    real_t t_rot = num_sat(num_mul(IDENT_ROTOR_TR, e->tr_s), IDENT_ROTOR_MIN_S, IDENT_DC_MAX_S);
    uint32_t mag = ident_ticks_of(t_mag, T), sig = s->bursts * s->cycle, rot = ident_ticks_of(t_rot, T);
    /* equal bins, a multiple of the block, each stage a whole number of them */
    uint32_t bin = (mag + sig + rot + (IDENT_BINS - 3u) - 1u) / (IDENT_BINS - 3u);
    bin = (bin + n - 1u) / n * n;
    s->bin_ticks = bin;
    s->g_sigma = (mag + bin - 1u) / bin * bin;
    s->g_rotor = s->g_sigma + (sig + bin - 1u) / bin * bin;
    s->g_end = s->g_rotor + (rot + bin - 1u) / bin * bin;
    s->settle_ticks = IDENT_SETTLE_BLOCKS * n;
}

static void ident_derive_rotating(ident_cfg *c)
{
    const ident_plate_est *e = &c->est;
    ident_rot_cfg *r = &c->rot;
    real_t T = c->period_s, w = e->w_m_rad_s;
    r->period_s = T;
    r->pole_pairs = e->pole_pairs;
    r->te_J_Nm = num_mul(c->te_J_frac > R(0.0) ? c->te_J_frac : R(0.3), e->te_Nm);
    r->w_a_rad_s = num_mul(R(0.3), w);
    r->w_b_rad_s = num_mul(R(0.6), w);
    r->w_top_rad_s = num_mul(R(0.7), w);
    r->w_bottom_rad_s = num_mul(R(0.25), w);
    r->w1_rad_s = num_mul(R(0.5), w);
    r->w2_rad_s = num_mul(R(0.8), w);
    r->w_tol_rad_s = num_mul(R(0.02), w);
    r->w_near_rad_s = num_mul(R(0.08), w);
    r->wc_rad_s = R(10.0);
    r->w_lpf_a = R(1.0) - num_exp(-num_div(T, R(0.01)));
    r->start_ticks = ident_ticks_of(R(0.1), T);
    r->settle_ticks = ident_ticks_of(R(0.5), T);
    r->window_ticks = ident_ticks_of(R(1.0), T);
    r->timeout_ticks = ident_ticks_of(R(20.0), T);
}

int ident_cfg_derive(ident_cfg *c)
{
    if (ident_plate_check(&c->plate) != IDENT_PLATE_OK)
        return IDENT_E_PLATE;
    if (!(c->period_s >= R(20e-6) && c->period_s <= R(2e-3) && c->vdc_nom_V > R(0.0) && ident_finite(c->vdc_nom_V) &&
          c->vdc_min_V >= R(0.0) && c->vdc_min_V < c->vdc_nom_V && c->dead_time_s >= R(0.0) &&
          c->dead_time_s <= R(10e-6) && c->v_drop_V >= R(0.0) && c->v_drop_V <= R(50.0) && c->i_max_A >= R(0.0) &&
          ident_finite(c->i_max_A) && c->te_J_frac >= R(0.0) && c->te_J_frac <= R(1.0)))
        return IDENT_E_DRIVE;
    ident_plate_estimate(&c->plate, &c->est);
    ident_derive_standstill(c);
    ident_derive_rotating(c);
    return IDENT_OK;
}

/* ------------------------------------------------------------------ run */

void ident_init(ident *s)
{
    s->phase = IDENT_IDLE;
    s->abort_reason = IDENT_ABORT_NONE;
    s->ticks_standstill = 0u;
    ident_ss_reset(&s->ss);
    ident_rot_reset(&s->rot, R(0.0));
    s->ss_fitted = s->rot_allowed = s->go_rotating = s->rot_fitted = false;
    s->rot_rs_ohm = R(0.0);
}

static bool ident_active(ident_phase p) { return p != IDENT_IDLE && p != IDENT_DONE && p != IDENT_ABORTED; }

int ident_start(ident *s, const ident_cfg *c, const ident_start_in *in)
{
    if (ident_active(s->phase))
        return IDENT_E_BUSY;
    if (!in->drive_stopped)
        return IDENT_E_NOT_STOPPED;
    if (!(num_abs(in->omega_m_rad_s) <= num_mul(R(0.02), c->est.w_m_rad_s)))
        return IDENT_E_TURNING;
    if (!(in->vdc_V >= c->vdc_min_V))
        return IDENT_E_LINK;
    ident_init(s);
    s->phase = IDENT_PROBE; /* last: the interrupt steps the run from here on */
    return IDENT_OK;
}

static void ident_abort_now(ident *s, ident_abort why, ident_out *out)
{
    s->phase = IDENT_ABORTED;
    s->abort_reason = why;
    out->mode = IDENT_OUT_OFF;
}

static ident_phase ident_ss_phase(ident_ss_stage st)
{
    switch (st) {
    case IDENT_SS_PROBE_OFF:
    case IDENT_SS_PROBE_SHORT:
        return IDENT_PROBE;
    case IDENT_SS_MAGNETISE:
        return IDENT_MAGNETISE;
    case IDENT_SS_SIGMA:
        return IDENT_SIGMA;
    default: /* ROTOR, and END until the step that records the last period reports FINISHED */
        return IDENT_ROTOR;
    }
}

static ident_phase ident_rot_phase(ident_rot_stage st)
{
    static const ident_phase map[] = {IDENT_ROT_START,    IDENT_ROT_ACCEL, IDENT_ROT_DECEL,   IDENT_ROT_NO_LOAD,
                                      IDENT_ROT_FRICTION, IDENT_ROT_STOP,  IDENT_FIT_ROTATING};
    return (unsigned)st < sizeof map / sizeof map[0] ? map[st] : IDENT_FIT_ROTATING;
}

void ident_step(ident *s, const ident_cfg *c, const ident_in *in, ident_out *out)
{
    out->mode = IDENT_OUT_OFF;
    out->te_ref_Nm = out->speed_ref_rad_s = R(0.0);
    out->act.duty0 = R(1.0);
    for (int k = 0; k < 2; k++)
        for (int l = 0; l < 3; l++)
            out->act.vector[k].leg[l] = HAL_LEG_O;
    ident_phase p = s->phase;
    if (!ident_active(p))
        return;
    if (in->fault) {
        ident_abort_now(s, IDENT_ABORT_FAULT, out);
        return;
    }
    if (!in->run) {
        ident_abort_now(s, IDENT_ABORT_STOPPED, out);
        return;
    }
    if (p <= IDENT_ROTOR) {
        ident_ss_status st = ident_ss_step(&s->ss, &c->ss, in, out);
        s->ticks_standstill = s->ss.tick;
        if (st == IDENT_SS_OVERCURRENT)
            ident_abort_now(s, IDENT_ABORT_OVERCURRENT, out);
        else if (st == IDENT_SS_TURNING)
            ident_abort_now(s, IDENT_ABORT_TURNING, out);
        else if (st == IDENT_SS_LINK)
            ident_abort_now(s, IDENT_ABORT_LINK, out);
        else if (st == IDENT_SS_FINISHED)
            s->phase = IDENT_FIT_STANDSTILL;
        else
            s->phase = ident_ss_phase(ident_ss_stage_of(&c->ss, s->ss.tick));
        return;
    }
    if (p == IDENT_FIT_STANDSTILL) {
        if (s->ss_fitted)
            s->phase = s->rot_allowed ? IDENT_WAIT_APPLY : IDENT_DONE;
        return;
    }
    if (p == IDENT_WAIT_APPLY) {
        if (s->go_rotating) {
            ident_rot_reset(&s->rot, s->rot_rs_ohm);
            s->phase = IDENT_ROT_START;
            out->mode = IDENT_OUT_TORQUE; /* the drive's own control starts: it magnetises first */
        }
        return;
    }
    if (p == IDENT_FIT_ROTATING) {
        if (s->rot_fitted)
            s->phase = IDENT_DONE;
        return;
    }
    ident_rot_status st = ident_rot_step(&s->rot, &c->rot, in, out);
    if (st == IDENT_ROT_TIMEOUT)
        ident_abort_now(s, IDENT_ABORT_TIMEOUT, out);
    else if (st == IDENT_ROT_FINISHED)
        s->phase = IDENT_FIT_ROTATING;
    else
        s->phase = ident_rot_phase(s->rot.stage);
}

int ident_continue(ident *s, const ident_result *r)
{
    if (s->phase != IDENT_WAIT_APPLY)
        return IDENT_E_PHASE;
    s->rot_rs_ohm = r->rs_ohm.value;
    s->go_rotating = true; /* last: the interrupt reads it */
    return IDENT_OK;
}

/* ------------------------------------------------------------------ the fits and the verdicts */

static void ident_set(ident_value *v, real_t x, ident_verdict verdict)
{
    v->value = x;
    v->verdict = ident_finite(x) ? verdict : IDENT_VERDICT_FAILED;
}

/* The worse of two verdicts (NONE < OK < DOUBTFUL < FAILED). */
static ident_verdict ident_worse(ident_verdict a, ident_verdict b) { return a > b ? a : b; }

/* OK inside lo..hi, DOUBTFUL outside it, FAILED when not > 0. */
static ident_verdict ident_range(real_t x, real_t lo, real_t hi)
{
    if (!(x > R(0.0)))
        return IDENT_VERDICT_FAILED;
    return x >= lo && x <= hi ? IDENT_VERDICT_OK : IDENT_VERDICT_DOUBTFUL;
}

static void ident_value_clear(ident_value *v)
{
    v->value = R(0.0);
    v->verdict = IDENT_VERDICT_NONE;
}

static void ident_fit_standstill(const ident *s, const ident_cfg *c, ident_result *r)
{
    const ident_plate_est *e = &c->est;
    const ident_ss_cfg *sc = &c->ss;
    real_t zb = e->z_base_ohm, T = sc->period_s;
    ident_value_clear(&r->j_kgm2);
    ident_value_clear(&r->b_Nms);
    ident_value_clear(&r->i0_A);
    r->lm_from_rotation = false;
    r->t_rotating_s = R(0.0);
    r->i_peak_A = s->ss.i_peak_A;
    r->t_standstill_s = num_mul((real_t)s->ticks_standstill, T);

    /* sigma Ls from the bursts */
    real_t lsig = R(0.0), r_hf = R(0.0), misfit = R(1.0);
    int hs = ident_hf_solve(&s->ss.hf, T, &lsig, &r_hf, &misfit);
    ident_verdict v_lsig = hs != 0 ? IDENT_VERDICT_FAILED
                                   : ident_range(lsig, num_div(num_mul(R(0.02), zb), e->w_e_rad_s),
                                                 num_div(num_mul(R(0.6), zb), e->w_e_rad_s));
    if (v_lsig == IDENT_VERDICT_OK && misfit > R(0.1))
        v_lsig = IDENT_VERDICT_DOUBTFUL;
    ident_set(&r->sigma_ls_H, lsig, v_lsig);
    r->r_hf_ohm = r_hf;

    /* Rs, R_R, Tr from the DC record */
    real_t bin_s = num_mul((real_t)sc->bin_ticks, T);
    uint32_t n_bins = sc->g_end / sc->bin_ticks;
    real_t record_s = num_mul((real_t)sc->g_end, T);
    ident_rotor_fit_out f;
    ident_rotor_fit(s->ss.bins, n_bins, bin_s, num_mul(R(0.5), bin_s), num_mul(R(10.0), record_s), &f);
    r->u_off_V = f.u_off_V;
    r->fit_resid_V = f.resid_V;
    bool fit_ok = f.status == 0;
    ident_verdict v_rs = f.status >= 0 ? ident_range(f.rs_ohm, num_mul(R(0.001), zb), num_mul(R(0.2), zb))
                                       : IDENT_VERDICT_FAILED;
    ident_set(&r->rs_ohm, f.rs_ohm, v_rs);
    /* the rotor: the step's transient must stand out of the residual, and the
     * record after the step must cover it (at least 1.5 Tr) */
    real_t t_after_s = num_mul((real_t)(sc->g_end - sc->g_rotor), T);
    ident_verdict v_tr = fit_ok ? ident_range(f.tr_s, num_mul(R(0.2), e->tr_s), num_mul(R(5.0), e->tr_s))
                                : IDENT_VERDICT_FAILED;
    if (v_tr == IDENT_VERDICT_OK && (f.tr_s > num_div(t_after_s, R(1.5)) || !(f.resid_V < num_mul(R(0.1), f.v_span_V))))
        v_tr = IDENT_VERDICT_DOUBTFUL;
    ident_verdict v_rr = fit_ok ? ident_range(f.rr_ref_ohm, num_mul(R(0.001), zb), num_mul(R(0.2), zb))
                                : IDENT_VERDICT_FAILED;
    v_rr = ident_worse(v_rr, v_tr);
    ident_set(&r->tr_s, f.tr_s, v_tr);
    ident_set(&r->rr_ref_ohm, f.rr_ref_ohm, v_rr);
    ident_set(&r->lm_ref_H, f.lm_ref_H, v_rr);
    r->lm_ref_standstill_H = f.lm_ref_H;

    /* the T model (equal leakages) */
    ident_t_params t;
    ident_verdict v_t = ident_worse(v_lsig, v_rr);
    if (ident_t_model(lsig, f.lm_ref_H, f.rr_ref_ohm, &t) != 0)
        v_t = IDENT_VERDICT_FAILED;
    ident_set(&r->lm_H, t.lm_H, v_t);
    ident_set(&r->ls_H, t.ls_H, v_t);
    ident_set(&r->rr_ohm, t.rr_ohm, v_t);
}

/* The mean acceleration over a steady-speed window: its halves' mean speeds
 * a half window apart, rad/s^2. */
static real_t ident_rot_accel(const ident_rot_window *w, real_t period_s)
{
    uint32_t n2 = w->n / 2u, n1 = w->n - n2; /* the second half: its last n / 2 ticks (ident_rot_hold) */
    if (n1 == 0u || n2 == 0u)
        return R(0.0);
    real_t m2 = num_div(w->w_late_rad_s, (real_t)n2), m1 = num_div(w->w_rad_s - w->w_late_rad_s, (real_t)n1);
    return num_div(m2 - m1, num_mul(R(0.5) * (real_t)w->n, period_s));
}

/* Ticks over which the switching ripple of the measured torque stays correlated. */
#define IDENT_TE_CORR_TICKS R(10.0)

/* The variance of a window's mean torque from its ripple, N^2 m^2. */
static real_t ident_mean_var(const ident_rot_window *w)
{
    if (w->n < 2u)
        return R(0.0);
    real_t n = (real_t)w->n, m = num_div(w->te_Nm, n);
    real_t var = num_div(w->te2_Nm2, n) - num_mul(m, m);
    return num_div(num_mul(var > R(0.0) ? var : R(0.0), IDENT_TE_CORR_TICKS), n);
}

static void ident_fit_rotating(const ident *s, const ident_cfg *c, ident_result *r)
{
    const ident_plate_est *e = &c->est;
    const ident_rot *x = &s->rot;
    r->t_rotating_s = num_mul((real_t)x->ticks_total, c->period_s);
    /* inertia: the mechanical time constant J w_rated / T_rated within 5 ms .. 100 s */
    bool j_ok = x->up.t_s > R(0.0) && x->down.t_s > R(0.0);
    real_t j = j_ok ? ident_inertia(&x->up, &x->down) : R(0.0);
    real_t tm_per_j = num_div(e->w_m_rad_s, e->te_Nm);
    ident_set(&r->j_kgm2, j,
              j_ok ? ident_range(j, num_div(R(0.005), tm_per_j), num_div(R(100.0), tm_per_j)) : IDENT_VERDICT_FAILED);
    /* friction: the torque at two speeds; at most 10 % of the rated torque at the rated speed */
    const ident_rot_window *a = &x->no_load, *b = &x->friction;
    bool w_ok = a->n > 0u && b->n > 0u;
    if (w_ok) {
        real_t na = R(1.0) / (real_t)a->n, nb = R(1.0) / (real_t)b->n;
        /* the torque that still accelerates the shaft in each window is not friction */
        real_t j_used = r->j_kgm2.verdict == IDENT_VERDICT_OK ? r->j_kgm2.value : R(0.0);
        real_t te_a = num_mul(a->te_Nm, na) - num_mul(j_used, ident_rot_accel(a, c->period_s));
        real_t te_b = num_mul(b->te_Nm, nb) - num_mul(j_used, ident_rot_accel(b, c->period_s));
        real_t bf = ident_friction(te_a, num_mul(a->w_rad_s, na), te_b, num_mul(b->w_rad_s, nb));
        real_t b_max = num_mul(R(0.1), num_div(e->te_Nm, e->w_m_rad_s));
        /* the switching ripple of the torque leaves its window means uncertain by about
         * sd / sqrt(n / IDENT_TE_CORR_TICKS): a difference within three of them is doubtful */
        real_t u2 = num_mac(ident_mean_var(a), R(1.0), ident_mean_var(b));
        bool resolved = num_mul(R(9.0), u2) < num_mul(num_mul(R(0.09), te_b - te_a), te_b - te_a);
        ident_set(&r->b_Nms, bf,
                  bf >= R(0.0) && bf <= b_max && resolved ? IDENT_VERDICT_OK : IDENT_VERDICT_DOUBTFUL);
        /* L_M from the no-load window, checked against the standstill's */
        real_t i0 = R(0.0);
        real_t lm_ref = ident_lm_from_no_load(num_mul(a->p_VsA, na), num_mul(a->q_VsA, na), num_mul(a->i2_A2, na),
                                              num_mul(a->psi2_Wb2, na), r->sigma_ls_H.value, &i0);
        ident_set(&r->i0_A, i0, lm_ref > R(0.0) ? IDENT_VERDICT_OK : IDENT_VERDICT_FAILED);
        real_t ss = r->lm_ref_standstill_H;
        ident_verdict v = ident_range(lm_ref, num_mul(R(0.5), ss), num_mul(R(2.0), ss));
        ident_t_params t;
        if (v == IDENT_VERDICT_OK && ident_t_model(r->sigma_ls_H.value, lm_ref, r->rr_ref_ohm.value, &t) == 0) {
            ident_verdict vt = ident_worse(r->sigma_ls_H.verdict, r->rr_ref_ohm.verdict);
            ident_set(&r->lm_ref_H, lm_ref, v);
            ident_set(&r->lm_H, t.lm_H, vt);
            ident_set(&r->ls_H, t.ls_H, vt);
            ident_set(&r->rr_ohm, t.rr_ohm, vt);
            r->tr_s.value = num_div(lm_ref, r->rr_ref_ohm.value);
            r->lm_from_rotation = true;
        }
    } else {
        ident_set(&r->b_Nms, R(0.0), IDENT_VERDICT_FAILED);
    }
}

ident_bg_event ident_background(ident *s, const ident_cfg *c, ident_result *r)
{
    if (s->phase == IDENT_FIT_STANDSTILL && !s->ss_fitted) {
        ident_fit_standstill(s, c, r);
        s->rot_allowed = c->rotating && r->rs_ohm.verdict == IDENT_VERDICT_OK &&
                         r->sigma_ls_H.verdict == IDENT_VERDICT_OK && r->rr_ohm.verdict == IDENT_VERDICT_OK;
        s->ss_fitted = true; /* last: the interrupt reads it */
        return IDENT_BG_STANDSTILL;
    }
    if (s->phase == IDENT_FIT_ROTATING && !s->rot_fitted) {
        ident_fit_rotating(s, c, r);
        s->rot_fitted = true;
        return IDENT_BG_ROTATING;
    }
    return IDENT_BG_NONE;
}

/* ------------------------------------------------------------------ telemetry */

uint32_t ident_progress(const ident *s, const ident_cfg *c)
{
    ident_phase p = s->phase;
    if (p == IDENT_DONE)
        return 100u;
    if (p == IDENT_IDLE || p == IDENT_ABORTED)
        return 0u;
    uint32_t ss_share = c->rotating ? 50u : 95u;
    if (p <= IDENT_ROTOR) {
        uint32_t total = ident_ss_ticks(&c->ss);
        return total > 0u ? (uint32_t)((uint64_t)s->ss.tick * ss_share / total) : 0u;
    }
    if (p == IDENT_FIT_STANDSTILL || p == IDENT_WAIT_APPLY)
        return ss_share;
    /* the rotating stages in equal shares */
    static const uint32_t at[] = {50u, 58u, 66u, 74u, 84u, 94u, 98u};
    uint32_t k = (uint32_t)(p - IDENT_ROT_START);
    return k < sizeof at / sizeof at[0] ? at[k] : 99u;
}

const char *ident_phase_name(ident_phase p)
{
    static const char *const names[] = {"idle",     "probe",    "magnetise", "sigma_ls", "rotor_step", "fit",
                                        "apply",    "start",    "accel",     "decel",    "no_load",    "friction",
                                        "stop",     "compute",  "done",      "aborted"};
    return (unsigned)p < sizeof names / sizeof names[0] ? names[p] : "?";
}

const char *ident_verdict_name(ident_verdict v)
{
    static const char *const names[] = {"-", "ok", "doubtful", "failed"};
    return (unsigned)v < sizeof names / sizeof names[0] ? names[v] : "?";
}
