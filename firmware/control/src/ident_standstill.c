/**
 * @file ident_standstill.c
 * @brief The standstill part of the identification run: excitation and sums
 *        (dtc/ident_standstill.h).
 *
 * Timing (ctl.h): the sample of tick k is at t_k, the actuation latched at
 * tick k applies from t_{k+1} to t_{k+2}, and the voltage the drive hands in
 * at tick k is that of the period t_k..t_{k+1}. Period g of the record starts
 * at the sample of its tick g (g counts from the start of MAGNETISE); its
 * voltage comes at tick g, its current's trapezoid is complete at tick g + 1.
 */
#include "dtc/ident_standstill.h"

#include "dtc/npc.h"

/* Kinds of period (ident_ss.prev_kind). */
#define IDENT_K_ZERO 0u  /* the zero vector all period */
#define IDENT_K_END 1u   /* the first half of a regulator pulse, at the period's end */
#define IDENT_K_START 2u /* its second half, at the next period's start */
#define IDENT_K_BURST 3u /* burst pulse q = kind - IDENT_K_BURST, 0..3 */

/* States used: the small vectors along +alpha and -alpha, the zero vector. */
#define IDENT_ST_POO 22u
#define IDENT_ST_ONN 9u
#define IDENT_ST_NOO 4u
#define IDENT_ST_OPP 17u
#define IDENT_ST_OOO NPC_STATE_OOO

#define IDENT_HALF_DUTY_MAX R(0.95) /* a half pulse leaves the zero vector for the rest of its period */
#define IDENT_HF_DUTY_MAX R(0.9)

uint32_t ident_ss_ticks(const ident_ss_cfg *c) { return 2u * c->probe_ticks + c->g_end + 1u; }

ident_ss_stage ident_ss_stage_of(const ident_ss_cfg *c, uint32_t tick)
{
    if (tick < c->probe_ticks)
        return IDENT_SS_PROBE_OFF;
    if (tick < 2u * c->probe_ticks)
        return IDENT_SS_PROBE_SHORT;
    uint32_t g = tick - 2u * c->probe_ticks;
    if (g < c->g_sigma)
        return IDENT_SS_MAGNETISE;
    if (g < c->g_rotor)
        return IDENT_SS_SIGMA;
    if (g < c->g_end)
        return IDENT_SS_ROTOR;
    return IDENT_SS_END;
}

void ident_ss_reset(ident_ss *s)
{
    s->tick = 0u;
    s->i_off_A[0] = s->i_off_A[1] = R(0.0);
    s->i_prev_A[0] = s->i_prev_A[1] = R(0.0);
    s->v_prev_V = R(0.0);
    s->prev_kind = IDENT_K_ZERO;
    s->prev_bin = (uint16_t)IDENT_BINS;
    s->integ_V = R(0.0);
    s->i_centre_A = R(0.0);
    s->half_state = IDENT_ST_OOO;
    s->half_duty = R(0.0);
    s->last_state = IDENT_ST_OOO;
    s->burst_n_type = 0u;
    s->hf_duty = R(0.0);
    s->d_cur = s->d_prev = R(0.0);
    s->ib2_A2 = R(0.0);
    s->i_peak_A = R(0.0);
    ident_hf_reset(&s->hf);
    for (uint32_t b = 0u; b < IDENT_BINS; b++) {
        ident_bin *x = &s->bins[b];
        x->v_sum_V = x->i_sum_A = x->ib_sum_A = R(0.0);
        x->n_v = x->n_i = 0u;
        x->use = 0u;
    }
}

/* The regulation stretch period @p g lies in ([*s0, *s1)), or false when g is
 * a burst period (its position 0..3 into *q). */
static bool ident_stretch(const ident_ss_cfg *c, uint32_t g, uint32_t *s0, uint32_t *s1, uint32_t *q)
{
    if (g < c->g_sigma) {
        *s0 = 0u;
        *s1 = c->g_sigma;
        return true;
    }
    if (g >= c->g_rotor) {
        *s0 = c->g_rotor;
        *s1 = c->g_end;
        return true;
    }
    uint32_t rel = g - c->g_sigma, cyc = rel / c->cycle;
    if (cyc >= c->bursts) { /* the rest of SIGMA after its last burst */
        *s0 = c->g_sigma + c->bursts * c->cycle;
        *s1 = c->g_rotor;
        return true;
    }
    uint32_t pos = rel - cyc * c->cycle;
    if (pos < 4u) {
        *q = pos;
        return false;
    }
    *s0 = c->g_sigma + cyc * c->cycle + 4u;
    *s1 = *s0 + c->cycle - 4u;
    return true;
}

/* The kind of period @p g (IDENT_K_*); *stretch_start true when g starts a stretch. */
static uint8_t ident_kind(const ident_ss_cfg *c, uint32_t g, bool *stretch_start)
{
    uint32_t s0 = 0u, s1 = 0u, q = 0u;
    *stretch_start = false;
    if (g >= c->g_end)
        return IDENT_K_ZERO;
    if (!ident_stretch(c, g, &s0, &s1, &q))
        return (uint8_t)(IDENT_K_BURST + q);
    *stretch_start = g == s0;
    uint32_t r = g - s0;
    if ((r + 1u) % c->n_block == 0u && g + 1u < s1)
        return IDENT_K_END; /* the pulse centred on g + 1, whose second half is in the stretch too */
    if (r % c->n_block == 0u && r > 0u)
        return IDENT_K_START;
    return IDENT_K_ZERO;
}

/* The zero vector all period. */
static void ident_act_zero(hal_actuation *a)
{
    npc_legs(IDENT_ST_OOO, &a->vector[0]);
    npc_legs(IDENT_ST_OOO, &a->vector[1]);
    a->duty0 = R(1.0);
}

/* @p st for the duty @p d at the period's end (@p at_end) or start; the zero vector for the rest. */
static void ident_act_pulse(hal_actuation *a, uint8_t st, real_t d, bool at_end)
{
    if (!(d > R(0.0))) {
        ident_act_zero(a);
        return;
    }
    if (at_end) {
        npc_legs(IDENT_ST_OOO, &a->vector[0]);
        npc_legs(st, &a->vector[1]);
        a->duty0 = R(1.0) - d;
    } else {
        npc_legs(st, &a->vector[0]);
        npc_legs(IDENT_ST_OOO, &a->vector[1]);
        a->duty0 = d;
    }
}

/* Of the two small vectors @p st_a, @p st_b (the same voltage direction), the
 * one whose neutral-point current moves vc1 - vc2 towards zero
 * (d(vc1 - vc2)/dt = i_np / C, npc_np_current). */
static uint8_t ident_np_pick(uint8_t st_a, uint8_t st_b, const ident_in *in)
{
    real_t dev = in->vc1_V - in->vc2_V;
    real_t ia = npc_np_current(st_a, in->i_abc_A);
    return num_mul(ia, dev) <= R(0.0) ? st_a : st_b;
}

/* |alpha voltage| of small vector @p st at the sampled capacitor voltages, V. */
static real_t ident_small_v(uint8_t st, const ident_in *in)
{
    real_t v[2];
    npc_state_voltage(st, in->vc1_V, in->vc2_V, v);
    return num_abs(v[0]);
}

/* The regulator's pulse centred on period g + 1's start: the PI on the current
 * at the last centre (its proportional gain lowered once the stage has
 * settled), the pulse's state and half duty (none when narrower than w_min:
 * the dead time would swallow it). False unless the pulse is there and along
 * the current: the dead time's error is per pulse and of the pulse's sign, so
 * only bins of regular pulses have the constant error the fit takes out. */
static bool ident_regulate(ident_ss *s, const ident_ss_cfg *c, const ident_in *in, real_t i_ref, bool settled)
{
    real_t nT = num_mul((real_t)c->n_block, c->period_s);
    real_t e = i_ref - s->i_centre_A;
    real_t kp = settled ? c->kp_hold_V_A : c->kp_V_A;
    real_t v_s = num_mul(R(2.0) / R(3.0), R(0.5) * (in->vc1_V + in->vc2_V));
    real_t u_max = num_div(num_mul(R(2.0) * IDENT_HALF_DUTY_MAX, num_mul(v_s, c->period_s)), nT);
    s->integ_V = num_limit(num_mac(c->ki_V_A, e, s->integ_V), u_max);
    real_t u = num_limit(num_mac(kp, e, s->integ_V), u_max);
    uint8_t st = u >= R(0.0) ? ident_np_pick(IDENT_ST_POO, IDENT_ST_ONN, in)
                             : ident_np_pick(IDENT_ST_NOO, IDENT_ST_OPP, in);
    real_t vs = ident_small_v(st, in);
    /* the dead time: a pulse along the current loses it, one against the current gains it */
    real_t w = num_div(num_mul(num_abs(u), nT), vs > R(1.0) ? vs : R(1.0));
    w = u >= R(0.0) ? w + c->dead_time_s : w - c->dead_time_s;
    if (!(w >= c->w_min_s)) {
        s->half_state = IDENT_ST_OOO;
        s->half_duty = R(0.0);
        return false;
    }
    real_t d = num_div(R(0.5) * w, c->period_s);
    if (d > IDENT_HALF_DUTY_MAX)
        d = IDENT_HALF_DUTY_MAX;
    s->half_state = st;
    s->half_duty = d;
    return u > R(0.0);
}

/* Burst pulse q (0..3: +, -, -, +; a + at the period's end, a - at its start,
 * so the trapezoid's error on the current's integral has one sign in every
 * burst period and drops into the regression's constant). */
static void ident_burst(ident_ss *s, uint32_t q, hal_actuation *a)
{
    bool plus = q == 0u || q == 3u;
    uint8_t st = s->burst_n_type != 0u ? (plus ? IDENT_ST_ONN : IDENT_ST_NOO) : (plus ? IDENT_ST_POO : IDENT_ST_OPP);
    ident_act_pulse(a, st, s->hf_duty, plus);
}

/* Probe: gates off (offsets), then the zero vector (a current through the
 * shorted winding means a turning, magnetised rotor). */
static ident_ss_status ident_probe(ident_ss *s, const ident_ss_cfg *c, const real_t i_ab[2], ident_out *out)
{
    if (s->tick < c->probe_ticks) {
        s->i_off_A[0] += i_ab[0];
        s->i_off_A[1] += i_ab[1];
        if (s->tick + 1u == c->probe_ticks) {
            real_t k = R(1.0) / (real_t)c->probe_ticks;
            s->i_off_A[0] = num_mul(s->i_off_A[0], k);
            s->i_off_A[1] = num_mul(s->i_off_A[1], k);
        }
        out->mode = IDENT_OUT_OFF;
        ident_act_zero(&out->act);
        return IDENT_SS_RUNNING;
    }
    /* the mean square over the zero vector's ticks (one sample's noise is not a rotor) */
    real_t ia = i_ab[0] - s->i_off_A[0], ib = i_ab[1] - s->i_off_A[1];
    s->ib2_A2 += num_mac(ia, ia, num_mul(ib, ib));
    if (s->tick + 1u == 2u * c->probe_ticks) {
        bool turning = num_div(s->ib2_A2, (real_t)c->probe_ticks) > num_mul(c->turn_A, c->turn_A);
        s->ib2_A2 = R(0.0); /* from here on the beta current's low-passed square */
        if (turning)
            return IDENT_SS_TURNING;
    }
    out->mode = IDENT_OUT_ACTUATE;
    ident_act_zero(&out->act);
    s->last_state = IDENT_ST_OOO;
    s->hf_duty = c->hf_duty0;
    return IDENT_SS_RUNNING;
}

/* Record period g - 1's current (its trapezoid is complete now) and the
 * bursts' sums; judge the beta current. */
static ident_ss_status ident_record_prev(ident_ss *s, const ident_ss_cfg *c, uint32_t g, const real_t i[2])
{
    if (g == 0u)
        return IDENT_SS_RUNNING;
    real_t ta = num_mul(R(0.5), s->i_prev_A[0] + i[0]);
    real_t tb = num_mul(R(0.5), s->i_prev_A[1] + i[1]);
    real_t x1 = i[0] - s->i_prev_A[0];
    if (s->prev_kind >= IDENT_K_BURST) {
        /* a burst period's current is flat but for its pulse (at the end for a +,
         * at the start for a -): its mean from the step and the duty, not the
         * trapezoid (which is off by a third of the step, and would bias the
         * rotor flux the DC fit works out) */
        uint32_t q = (uint32_t)(s->prev_kind - IDENT_K_BURST);
        real_t h = num_mul(R(0.5), num_mul(x1, s->d_prev));
        ta = q == 0u || q == 3u ? s->i_prev_A[0] + h : i[0] - h;
    }
    uint32_t b = s->prev_bin;
    if (b < IDENT_BINS) {
        ident_bin *x = &s->bins[b];
        x->i_sum_A += ta;
        x->ib_sum_A += tb;
        x->n_i++;
    }
    /* A beta current means the rotor turns: the alpha field it carries through
     * the rotor induces one in the beta winding, which the zero beta voltage
     * shorts (at a high speed it oscillates: its low-passed square, not its mean). */
    s->ib2_A2 = num_mac(c->ib_lpf_a, num_mul(i[1], i[1]) - s->ib2_A2, s->ib2_A2);
    if (s->ib2_A2 > num_mul(c->turn_A, c->turn_A))
        return IDENT_SS_TURNING;
    if (s->prev_kind >= IDENT_K_BURST) {
        ident_hf_add(&s->hf, num_mul(s->v_prev_V, c->period_s), x1, ta - c->i_hi_A);
        if (s->prev_kind == IDENT_K_BURST && x1 > R(0.0)) {
            /* the first pulse's step: the duty of the next pulses aims at hf_di_A */
            real_t k = num_sat(num_div(c->hf_di_A, x1), R(0.7), R(1.4));
            real_t dmin = num_div(c->w_min_s, c->period_s);
            s->hf_duty = num_sat(num_mul(s->hf_duty, k), dmin, IDENT_HF_DUTY_MAX);
        }
    }
    return IDENT_SS_RUNNING;
}

ident_ss_status ident_ss_step(ident_ss *s, const ident_ss_cfg *c, const ident_in *in, ident_out *out)
{
    out->mode = IDENT_OUT_OFF;
    out->te_ref_Nm = out->speed_ref_rad_s = R(0.0);
    ident_act_zero(&out->act);
    const real_t *iabc = in->i_abc_A;
    for (int k = 0; k < 3; k++)
        if (num_abs(iabc[k]) > s->i_peak_A)
            s->i_peak_A = num_abs(iabc[k]);
    if (!(s->i_peak_A <= c->i_max_A))
        return IDENT_SS_OVERCURRENT; /* (a NaN current counts as one) */
    if (!(in->vc1_V + in->vc2_V >= c->vdc_min_V))
        return IDENT_SS_LINK;
    real_t i_ab[2] = {num_mul(R(0.333333333), R(2.0) * iabc[0] - iabc[1] - iabc[2]),
                      num_mul(NUM_INV_SQRT3, iabc[1] - iabc[2])};
    uint32_t tick = s->tick;
    if (tick < 2u * c->probe_ticks) {
        ident_ss_status st = ident_probe(s, c, i_ab, out);
        s->tick = tick + 1u;
        return st;
    }
    uint32_t g = tick - 2u * c->probe_ticks;
    real_t i[2] = {i_ab[0] - s->i_off_A[0], i_ab[1] - s->i_off_A[1]};
    ident_ss_status st = ident_record_prev(s, c, g, i);
    if (st != IDENT_SS_RUNNING)
        return st;
    if (g >= c->g_end) {
        s->tick = tick + 1u;
        return IDENT_SS_FINISHED; /* gates off: the current falls through the diodes */
    }

    /* this period's voltage into its bin; a bin counts when it starts settled in MAGNETISE or ROTOR */
    bool stretch_start = false;
    uint8_t kind = ident_kind(c, g, &stretch_start);
    uint32_t b = g / c->bin_ticks;
    ident_bin *x = &s->bins[b];
    if (g % c->bin_ticks == 0u) {
        bool dc = g < c->g_sigma || g >= c->g_rotor;
        uint32_t from = g < c->g_sigma ? 0u : c->g_rotor;
        x->use = (uint8_t)(dc && g >= from + c->settle_ticks);
    }
    x->v_sum_V += in->v_ab_V[0];
    x->n_v++;
    if (kind >= IDENT_K_BURST)
        x->use = 0u;
    if (stretch_start || kind == IDENT_K_START)
        s->i_centre_A = i[0];

    /* the actuation for period g + 1 */
    bool next_start = false;
    uint8_t next = ident_kind(c, g + 1u, &next_start);
    real_t i_ref = g + 1u >= c->g_rotor ? c->i_lo_A : c->i_hi_A;
    hal_actuation act;
    real_t d_next = R(0.0);
    if (next == IDENT_K_END) {
        /* settled in a DC stage: the lower gain, so the current's noise moves the pulses less */
        uint32_t from = g + 1u < c->g_sigma ? 0u : (g + 1u >= c->g_rotor ? c->g_rotor : c->g_sigma);
        if (!ident_regulate(s, c, in, i_ref, g + 1u >= from + c->settle_ticks)) {
            /* the pulse around t_{g+2} is not regular: its two periods' bins do not count */
            s->bins[(g + 1u) / c->bin_ticks].use = 0u;
            if ((g + 2u) / c->bin_ticks < IDENT_BINS)
                s->bins[(g + 2u) / c->bin_ticks].use = 0u;
        }
        ident_act_pulse(&act, s->half_state, s->half_duty, true);
    } else if (next == IDENT_K_START) {
        ident_act_pulse(&act, s->half_state, s->half_duty, false);
    } else if (next >= IDENT_K_BURST) {
        uint32_t q = (uint32_t)(next - IDENT_K_BURST);
        if (q == 0u)
            s->burst_n_type ^= 1u; /* P- and N-type bursts in turn: the neutral point stays */
        ident_burst(s, q, &act);
        d_next = s->hf_duty;
    } else {
        ident_act_zero(&act);
    }
    /* the last guard against a P<->N step (the patterns above never make one) */
    uint8_t a0 = npc_pn_safe(s->last_state, npc_state_of(&act.vector[0]));
    uint8_t a1 = npc_pn_safe(a0, npc_state_of(&act.vector[1]));
    npc_legs(a0, &act.vector[0]);
    npc_legs(a1, &act.vector[1]);
    s->last_state = act.duty0 < R(1.0) ? a1 : a0;

    s->i_prev_A[0] = i[0];
    s->i_prev_A[1] = i[1];
    s->v_prev_V = in->v_ab_V[0];
    s->prev_kind = kind;
    s->prev_bin = (uint16_t)b;
    s->d_prev = s->d_cur;
    s->d_cur = d_next;
    s->tick = tick + 1u;
    out->mode = IDENT_OUT_ACTUATE;
    out->act = act;
    return IDENT_SS_RUNNING;
}
