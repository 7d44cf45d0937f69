/**
 * @file dtc3l.c
 * @brief One decision of the three-level DTC: level, comparators, vectors,
 *        band-edge duty split, flux-hold pulse, and the switching states.
 *
 * The torque comparator is a state machine on the predicted torque Te
 * (b = torque_band, b2 = torque_band2):
 *   up (+1)   until Te >= Te* + b, then hold;
 *   down (-1) until Te <= Te* - b, then hold;
 *   hold (0)  until Te leaves [Te* - b, Te* + b] on the side the zero
 *             vector does not return from, then up or down;
 *   |Te* - Te| > b2 forces +-2 (the strong vectors) whatever the state.
 * At positive speed the zero vector lowers the torque, so the drive cycles
 * up -> hold -> up between the band edges; at negative speed down -> hold.
 */
#include "dtc/dtc3l.h"

#include "dtc/dtc3l_np.h"
#include "dtc/dtc3l_table.h"
#include "dtc/npc.h"

/* Below this flux the radial direction is undefined (start of magnetising), Wb. */
#define PSI_TINY_WB R(1e-3)
/* How far (in np_band) an intermediate state may take the neutral point before
 * it is cut short: 2.0 x 1.5 V = 3.0 V. One period of an O-leg current i
 * moves vc1 - vc2 by (T / C) i = 0.09 V per A (C = 2.2 mF per capacitor), up to
 * 3.4 V at the rated peak current; the factor was set on the capability sweep
 * (tools/run-envelope.sh) and the nameplate run: 2.5 and more let the link
 * pass 6.2 V at 1740 rpm generating; with 2.25 the nameplate run's largest
 * deviation was 5.6-6.3 V over 1 % changes of a gain (chaotic: at the voltage
 * limit), with 2.0 5.3-5.7 V, its speed still held. */
#define NP_INTERMEDIATE_ROOM_BANDS R(2.0)
/* A small state the choice among redundant states kept (fewest commutations
 * inside the band) is swapped for the vector's other state when it would
 * take the link beyond 3 x np_band (4.5 V): a rated current moves the link by
 * up to 3.5 V in one period at the LOW level. Not at the band itself: that
 * costs commutations, and 500 rpm with 41 N m then switches at 1.4 kHz. */
#define NP_SMALL_ROOM_BANDS R(3.0)

void dtc3l_init(dtc3l *s)
{
    s->torque_state = 0;
    s->flux_state = 1;
    s->level = (uint8_t)DTC3L_LEVEL_LOW;
}

static int8_t torque_comparator(int8_t state, real_t te, real_t te_ref, real_t b, real_t b2, real_t s_hold)
{
    real_t err = te_ref - te;
    if (num_abs(err) > b2) /* b2 >= 0: one compare for both strong demands */
        return err > R(0.0) ? 2 : -2;
    if (state > 0)
        return te >= te_ref + b ? 0 : 1;
    if (state < 0)
        return te <= te_ref - b ? 0 : -1;
    /* hold is left only when the zero vector itself would not bring the
     * torque back into the band */
    if (te < te_ref - b && s_hold <= R(0.0))
        return 1;
    if (te > te_ref + b && s_hold >= R(0.0))
        return -1;
    return 0;
}

/* dtc3l_select with the sectors already known (dtc3l_sectors: 0..11 and 0..5,
 * so the tables are read without dtc3l_table's reduction mod 12 / 6) */
static uint8_t pick(uint8_t sector, uint8_t sector6, int8_t torque, int8_t flux, uint8_t level)
{
    if (torque == 0)
        return 0u;
    unsigned j = dtc3l_demand_index(torque, flux);
    if (level == (uint8_t)DTC3L_LEVEL_LOW && (torque == 1 || torque == -1))
        return dtc3l_table6_sv[sector6][j];
    return dtc3l_table12_sv[sector][j];
}

/* The band edge that ends comparator state @p cur under slope @p s_cur, the
 * state that follows (@p next = cur when there is none), and the fraction of
 * the period at which the edge is met (> 1: not within the period). */
static real_t exit_edge(int8_t cur, real_t s_cur, const dtc3l_cmd *in, const observer_out *pr, real_t b,
                        real_t dt_s, real_t *edge, int8_t *next)
{
    if (cur > 0) {
        *edge = in->te_ref_Nm + b;
        *next = 0;
    } else if (cur < 0) {
        *edge = in->te_ref_Nm - b;
        *next = 0;
    } else if (s_cur < R(0.0)) {
        *edge = in->te_ref_Nm - b;
        *next = 1;
    } else if (s_cur > R(0.0)) {
        *edge = in->te_ref_Nm + b;
        *next = -1;
    } else {
        *next = 0;
        return R(2.0);
    }
    return dtc3l_edge_fraction(pr->te_pred_Nm, s_cur, *edge, dt_s);
}

/* Rate of change of |psi_s| under the state voltage @p v, Wb/s: psi . (v - Rs is) / |psi|. */
static real_t flux_rate(const dtc3l_cmd *in, const observer_out *pr, const real_t v[2], real_t psi_abs)
{
    real_t e0 = v[0] - num_mul(in->rs_ohm, pr->is_pred_A[0]);
    real_t e1 = v[1] - num_mul(in->rs_ohm, pr->is_pred_A[1]);
    if (psi_abs < PSI_TINY_WB)
        return num_sqrt(num_mul(e0, e0) + num_mul(e1, e1));
    return num_div(num_mul(pr->psi_s_pred_Wb[0], e0) + num_mul(pr->psi_s_pred_Wb[1], e1), psi_abs);
}

/* What one tick knows about the predicted state, computed once. */
typedef struct {
    real_t psi_Wb;            /* |psi_s| predicted */
    uint8_t sector;           /* 0..11 */
    uint8_t sector6;          /* 0..5 */
    real_t i_abc_A[3];        /* predicted phase currents */
    real_t b_Nm, b2_Nm;       /* torque bands of this tick (cfg x in->band_scale) */
    uint8_t prev_state;       /* in->prev_state, or OOO when it is not a state (0..26 from here on) */
    real_t leg_V[3];          /* leg voltage by leg code N, O, P: -vc2, 0, vc1 (the state voltages' selections) */
} tick_geometry;

/* The decision being built: two states, the duty of the first, and the
 * comparator states for the first vector (cur) and at the period end (after). */
typedef struct {
    int8_t cur;
    int8_t after;
    uint8_t sv0;              /* space vector the table gave for cur (or a whole-period flux-hold pulse's) */
    uint8_t st0, st1;
    real_t duty0;
    bool split;
} tick_plan;

/* st0 and st1 of a plan whose zero vector's state is not chosen yet
 * (plan_state, settle_zero): not a state, never looked up */
#define ZERO_PENDING 0xFFu

static void tick_geometry_of(const dtc3l_cfg *cfg, const dtc3l_cmd *in, const observer_out *pr, tick_geometry *g)
{
    g->b_Nm = num_mul(cfg->torque_band_Nm, in->band_scale); /* >= 1: the caller's clamp */
    g->b2_Nm = num_mul(cfg->torque_band2_Nm, in->band_scale);
    const real_t *psi = pr->psi_s_pred_Wb, *is = pr->is_pred_A;
    g->psi_Wb = num_sqrt(num_mul(psi[0], psi[0]) + num_mul(psi[1], psi[1]));
    dtc3l_sectors(psi[0], psi[1], &g->sector, &g->sector6);
    g->i_abc_A[0] = is[0];
    g->i_abc_A[1] = num_mac(R(-0.5), is[0], num_mul(R(0.866025404), is[1]));
    g->i_abc_A[2] = -g->i_abc_A[0] - g->i_abc_A[1];
    g->prev_state = in->prev_state; /* 0..26: the caller's clamp */
    g->leg_V[HAL_LEG_N] = -in->vc2_V;
    g->leg_V[HAL_LEG_O] = R(0.0);
    g->leg_V[HAL_LEG_P] = in->vc1_V;
}

/* npc_state_voltage for the step's own states (0..26), the leg voltages
 * looked up by leg code (the same values as its selections) */
static inline void state_voltage(const tick_geometry *g, uint8_t st, real_t v_ab[2])
{
    const hal_vector *l = &npc_state_legs[st];
    real_t va = g->leg_V[l->leg[0]], vb = g->leg_V[l->leg[1]], vc = g->leg_V[l->leg[2]];
    v_ab[0] = num_mul(R(0.333333333), R(2.0) * va - vb - vc);
    v_ab[1] = num_mul(NUM_INV_SQRT3, vb - vc);
}

/* dtc3l_state_slope for the step's own states (0..26). A zero state's
 * voltage is exactly (0, 0) (its three legs select the same voltage x:
 * 2x - x - x = 0), so its slope is dte0 as it is: no voltage worked out for
 * the holds, about every other period. */
static inline real_t voltage_slope(const observer_out *pr, const real_t v[2])
{
    return pr->dte0_Nm_s + num_mul(pr->dte_dv[0], v[0]) + num_mul(pr->dte_dv[1], v[1]);
}

static inline real_t state_slope(const tick_geometry *g, const observer_out *pr, uint8_t st)
{
    if (npc_state_sv_unchecked(st) == 0u)
        return pr->dte0_Nm_s;
    real_t v[2];
    state_voltage(g, st, v);
    return voltage_slope(pr, v);
}

/* Voltage level from the back-emf over Vdc/3, with hysteresis. */
static void decide_voltage_level(dtc3l *s, const dtc3l_cfg *cfg, const dtc3l_cmd *in)
{
    real_t vdc = in->vc1_V + in->vc2_V;
    real_t emf_pu = num_div(num_mul(num_abs(in->omega_e_rad_s), in->psi_ref_Wb),
                            num_mul(R(0.333333333), vdc > R(1.0) ? vdc : R(1.0)));
    if (s->level == (uint8_t)DTC3L_LEVEL_LOW && emf_pu > cfg->level_up)
        s->level = (uint8_t)DTC3L_LEVEL_HIGH;
    else if (s->level != (uint8_t)DTC3L_LEVEL_LOW && emf_pu < cfg->level_down)
        s->level = (uint8_t)DTC3L_LEVEL_LOW;
}

/* Flux demand: two-level hysteresis on |psi_s|. @return true when the flux is
 * below its band (the flux-hold pulse's condition too). */
static bool decide_flux_demand(dtc3l *s, const dtc3l_cfg *cfg, const dtc3l_cmd *in, real_t psi_Wb)
{
    bool low = psi_Wb < in->psi_ref_Wb - cfg->flux_band_Wb;
    if (low)
        s->flux_state = 1;
    else if (psi_Wb > in->psi_ref_Wb + cfg->flux_band_Wb)
        s->flux_state = -1;
    return low;
}

/* Neutral point with the large and medium vectors: a medium vector draws the
 * current of its O-leg phase from the neutral point; when that current would
 * leave the link outside 2 np_band and further off than now (predicted over
 * the period with np_V_per_A = T / C), the large
 * vector at 90 deg from the flux on the same side takes its place (no NP
 * current; the most torque of all; its radial part, +-Vdc/6 over the 30 deg
 * sector, averages out, and the flux comparator still chooses the next
 * medium vectors). The medium vectors are the table's choice only in the odd
 * sectors, where 90 deg is a large-vector direction. */
static uint8_t np_checked_vector(uint8_t sv, const dtc3l_cmd *in, const dtc3l_cfg *cfg, const tick_geometry *g,
                                 int8_t torque)
{
    if (npc_sv_class_unchecked(sv) != NPC_CLASS_MEDIUM || torque == 0)
        return sv;
    /* a strong demand gets the most tangential voltage there is: the large
     * vector at 90 deg (>= 0.97 x 2 Vdc / 3) rather than the medium one at
     * 45..75 deg (0.71..0.97 x Vdc / sqrt 3), which near the voltage limit
     * no longer beats the back-emf */
    bool strong = torque == 2 || torque == -2;
    if (!strong) {
        /* NP prediction over the period: keep the medium vector unless it
         * leaves the link outside twice the band AND further off than now
         * (at the band itself the 90-deg vector is taken so often that the
         * flux, and with it the speed, ripples more near the voltage limit:
         * docs/envelope.md section 5) */
        real_t inp = npc_np_current_unchecked(npc_sv_state_list[sv][0], g->i_abc_A); /* its one state */
        real_t np_next = num_mac(cfg->np_V_per_A, inp, in->np_dev_V);
        if (!(num_abs(np_next) > R(2.0) * cfg->np_band_V && num_abs(np_next) > num_abs(in->np_dev_V)))
            return sv;
    }
    uint8_t dir = (uint8_t)((g->sector + (torque > 0 ? 3u : 9u)) % 12u);
    if ((dir & 1u) != 0u)
        return sv;
    return (uint8_t)(13u + dir / 2u);
}

/* The state realising the table's vector for torque demand @p torque, from @p prev_state. */
static uint8_t state_for_demand(const dtc3l *s, const dtc3l_cfg *cfg, const dtc3l_cmd *in, const tick_geometry *g,
                                int8_t torque, uint8_t prev_state)
{
    uint8_t v = np_checked_vector(pick(g->sector, g->sector6, torque, s->flux_state, s->level), in, cfg, g, torque);
    return dtc3l_choose_state_unchecked(v, prev_state, in->np_dev_V, cfg->np_band_V, g->i_abc_A);
}

/* state_for_demand from the state in force (g->prev_state) for the plan's
 * first state, but the zero vector's state left to settle_zero: in a hold
 * the flux-hold pulse often takes the period's start, and its own zero state
 * follows the pulse (the plan's zero state, with its NP look-ahead, would be
 * worked out and dropped in those ticks). */
static void plan_state(const dtc3l *s, const dtc3l_cfg *cfg, const dtc3l_cmd *in, const tick_geometry *g, tick_plan *p)
{
    uint8_t v = np_checked_vector(pick(g->sector, g->sector6, p->cur, s->flux_state, s->level), in, cfg, g, p->cur);
    p->sv0 = v;
    p->st0 = p->st1 = v == 0u ? (uint8_t)ZERO_PENDING
                              : dtc3l_choose_state_unchecked(v, g->prev_state, in->np_dev_V, cfg->np_band_V, g->i_abc_A);
}

/* The zero vector's state from g->prev_state (dtc3l_choose_state's choice)
 * once the plan keeps it; @p push0 and @p push0_VA as dtc3l_choose_zero_unchecked. */
static inline void settle_zero(const dtc3l_cfg *cfg, const dtc3l_cmd *in, const tick_geometry *g, tick_plan *p,
                               bool push0, real_t push0_VA)
{
    if (p->st0 != ZERO_PENDING)
        return;
    p->st0 = p->st1 = dtc3l_choose_zero_unchecked(g->prev_state, in->np_dev_V, cfg->np_band_V, g->i_abc_A, push0,
                                                  push0_VA);
}

/* The states are chosen first (P<->N-free, NP-balancing, fewest
 * commutations); the timing then uses the slope of the state actually
 * applied, which may be an NP intermediate rather than the table's vector.
 * The whole period goes to the table's vector for the comparator's demand. */
static void plan_table_vector(const dtc3l *s, const dtc3l_cfg *cfg, const dtc3l_cmd *in, const observer_out *pr,
                              const tick_geometry *g, tick_plan *p)
{
    p->cur = torque_comparator(s->torque_state, pr->te_pred_Nm, in->te_ref_Nm, g->b_Nm, g->b2_Nm, pr->dte0_Nm_s);
    p->after = p->cur;
    plan_state(s, cfg, in, g, p);
    p->duty0 = R(1.0);
    p->split = false;
}

/* Ripple reduction: place the band-edge crossing inside the period. An edge
 * reached at the very start hands over to the next comparator state, which is
 * then examined in turn (at most twice: up/down -> hold -> up/down). */
static void place_band_edge_crossing(const dtc3l *s, const dtc3l_cfg *cfg, real_t dt_s, const dtc3l_cmd *in,
                                     const observer_out *pr,
                                     const tick_geometry *g, tick_plan *p)
{
    real_t b = g->b_Nm;
    real_t dmin = cfg->duty_min;
    real_t s_cur = R(0.0), edge = R(0.0), f = R(2.0);
    int8_t next = p->cur;
    for (int pass = 0;; pass++) {
        /* the zero vector's states all have the slope dte0, chosen or not */
        s_cur = p->sv0 == 0u ? pr->dte0_Nm_s : state_slope(g, pr, p->st0);
        f = exit_edge(p->cur, s_cur, in, pr, b, dt_s, &edge, &next);
        if (next == p->cur)
            return; /* no crossing */
        if (!(f < dmin))
            break;
        p->cur = next;
        p->after = p->cur;
        plan_state(s, cfg, in, g, p);
        if (pass == 1)
            return;
    }
    /* f >= dmin here: exit_edge's fraction is never NaN, so no NaN test */
    if (!(f <= R(1.0) - dmin))
        return; /* it falls at the next period start */
    settle_zero(cfg, in, g, p, false, R(0.0)); /* the state after it follows it */
    p->st1 = state_for_demand(s, cfg, in, g, next, p->st0);
    p->duty0 = f;
    p->after = next;
    p->split = true;
    if (next == 0)
        return;
    /* hold -> active: when the active vector would also cross the opposite
     * edge before the period ends, start it later so that the period ends on
     * that edge (two-slope duty: Te_end = Te + s_hold (1 - d) T + s_act d T)
     * and stay in hold */
    real_t s_next = state_slope(g, pr, p->st1);
    real_t opp = next > 0 ? in->te_ref_Nm + b : in->te_ref_Nm - b;
    real_t gf = dtc3l_edge_fraction(edge, s_next, opp, dt_s);
    if (gf < R(1.0) - f) {
        real_t den = num_mul(s_next - s_cur, dt_s);
        real_t d_act = num_abs(den) > R(1e-6) ? num_div(opp - pr->te_pred_Nm - num_mul(s_cur, dt_s), den) : gf;
        d_act = num_sat(d_act, dmin, R(1.0) - dmin);
        p->duty0 = R(1.0) - d_act;
        p->after = 0;
    }
}

/* num_sat(x, 0, hi) for x >= 0 (or NaN): x above hi gives hi */
static inline real_t upto(real_t x, real_t hi) { return x > hi ? hi : x; }

/* Flux-drop compensation: a full hold period at the LOW level with the flux
 * below its band gets a pulse of the small vector along the flux, long enough
 * to bring |psi| back to the reference, and short enough to keep the torque
 * in its band over the whole period. */
static void add_flux_hold_pulse(const dtc3l *s, const dtc3l_cfg *cfg, real_t dt_s, const dtc3l_cmd *in,
                                const observer_out *pr,
                                const tick_geometry *g, bool flux_low, tick_plan *p)
{
    real_t b = g->b_Nm;
    real_t dmin = cfg->duty_min;
    real_t psi = g->psi_Wb;
    /* flux_low: psi < psi_ref - flux_band, from decide_flux_demand */
    if (!(!p->split && p->sv0 == 0u && s->level == (uint8_t)DTC3L_LEVEL_LOW && flux_low)) {
        settle_zero(cfg, in, g, p, false, R(0.0)); /* no pulse: the plan's zero state, if it has one */
        return;
    }
    uint8_t svh = dtc3l_table_flux_hold(g->sector6);
    bool push0_known;
    real_t push0_VA = R(0.0);
    uint8_t sth = dtc3l_choose_state_push0_unchecked(svh, g->prev_state, in->np_dev_V, cfg->np_band_V, g->i_abc_A,
                                                     &push0_known, &push0_VA);
    real_t v_h[2]; /* the pulse state's voltage, for both its flux rate and its torque slope */
    state_voltage(g, sth, v_h);
    real_t s_h = voltage_slope(pr, v_h);
    real_t hi = in->te_ref_Nm + b, lo = in->te_ref_Nm - b;
    /* a rising pulse peaks at its end. That bound first: below dmin it cuts
     * the pulse whatever the others give (they only shorten it; the flux's d
     * is never NaN: psi below a finite reference, rate > 0), so the flux's
     * duty is not worked out in those periods. Its 2 when the
     * pulse does not rise is no bound: any d >= 2 > 1 - dmin is a whole
     * period (duty_min 0..0.45) */
    real_t d_up = s_h > R(0.0) ? dtc3l_edge_fraction(pr->te_pred_Nm, s_h, hi, dt_s) : R(2.0);
    real_t d = R(0.0); /* when d_up < dmin (so dmin > 0): no pulse */
    if (!(d_up < dmin)) {
        real_t rate = flux_rate(in, pr, v_h, psi);
        d = rate > R(0.0) ? num_div(in->psi_ref_Wb - psi, num_mul(rate, dt_s)) : R(1.0);
        /* d >= 0 here and every bound is positive (psi < psi_ref, rate > 0;
         * lo - end0 and ds of one sign), so only the upper bound can act: a
         * minimum, not num_sat's two compares */
        d = upto(d, d_up);
        /* the period ends at Te + s_z T + (s_h - s_z) d T, inside the band */
        real_t s_z = pr->dte0_Nm_s;
        real_t end0 = pr->te_pred_Nm + num_mul(s_z, dt_s);
        real_t ds = num_mul(s_h - s_z, dt_s);
        if (ds < R(0.0) && end0 > lo)
            d = upto(d, num_div(lo - end0, ds));
        else if (ds > R(0.0) && end0 < hi)
            d = upto(d, num_div(hi - end0, ds));
    }
    if (d < dmin) {
        /* no pulse: the plan's zero state after all, its NP look-ahead
         * reusing the pulse choice's product when the state in force is
         * one of svh's (the same first state) */
        settle_zero(cfg, in, g, p, push0_known && npc_state_sv_unchecked(g->prev_state) == svh, push0_VA);
        return;
    }
    p->st0 = sth;
    if (d < R(1.0) - dmin) {
        /* the zero state's NP look-ahead reuses the pulse choice's product
         * when sth is one of svh's own states */
        p->st1 = dtc3l_choose_zero_unchecked(sth, in->np_dev_V, cfg->np_band_V, g->i_abc_A,
                                             push0_known && npc_state_sv_unchecked(sth) == svh, push0_VA);
        p->duty0 = d;
        p->split = true;
    } else {
        p->st1 = sth;
        if (num_abs(in->np_dev_V) > cfg->np_band_V)
            p->sv0 = svh; /* a whole period of the small vector: cut_intermediate_short checks its state */
    }
}

/* The state of small vector @p svn reachable from @p from when it pulls the
 * neutral point back; @p fallback (the state planned before) otherwise: when
 * the balancing state is a P<->N step away, the other one would push the link
 * further off. */
static uint8_t balancing_or(uint8_t fallback, uint8_t svn, uint8_t from, const dtc3l_cfg *cfg, const dtc3l_cmd *in,
                            const tick_geometry *g)
{
    uint8_t c = dtc3l_choose_state_unchecked(svn, from, in->np_dev_V, cfg->np_band_V, g->i_abc_A);
    if (!(num_mul(npc_np_current_unchecked(c, g->i_abc_A), in->np_dev_V) < R(0.0)))
        return fallback;
    return c;
}

/* Neutral point at the HIGH level: large vectors draw no NP current and
 * medium ones an uncontrolled one, so an unbalanced link is pulled back
 * during the holds: instead of a zero state, the balancing state of the
 * small vector nearest to the flux (to -flux while the flux is to fall).
 * Its tangential part is at most half of Vdc/3, below the back-emf at
 * this level, so the torque falls much as under a zero state; after a
 * large vector it also costs fewer commutations than OOO. */
static void balance_np_in_holds(const dtc3l *s, const dtc3l_cfg *cfg, const dtc3l_cmd *in, const tick_geometry *g,
                                tick_plan *p)
{
    if (!(s->level != (uint8_t)DTC3L_LEVEL_LOW && num_abs(in->np_dev_V) > cfg->np_band_V))
        return;
    uint8_t svn = dtc3l_table_flux_hold((uint8_t)((g->sector6 + (s->flux_state > 0 ? 0u : 3u)) % 6u));
    bool full = p->st1 == p->st0;
    uint8_t sv_b = npc_state_sv_unchecked(p->st1);
    if (npc_state_sv_unchecked(p->st0) == 0u)
        p->st0 = balancing_or(p->st0, svn, g->prev_state, cfg, in, g);
    if (full)
        p->st1 = p->st0;
    else if (sv_b == 0u) /* the second state follows the (possibly new) first one */
        p->st1 = balancing_or(dtc3l_choose_state_unchecked(0u, p->st0, in->np_dev_V, cfg->np_band_V, g->i_abc_A), svn, p->st0,
                              cfg, in, g);
    else
        p->st1 = dtc3l_choose_state_unchecked(sv_b, p->st0, in->np_dev_V, cfg->np_band_V, g->i_abc_A);
}

/* |vc1 - vc2| after a whole period drawing @p inp_A from the neutral point, V. */
static inline real_t np_left(const dtc3l_cfg *cfg, const dtc3l_cmd *in, real_t inp_A)
{
    return num_abs(num_mac(cfg->np_V_per_A, inp_A, in->np_dev_V));
}

/* The P<->N rule forces an intermediate state when the wanted state is a
 * P<->N step away: between two adjacent large vectors the medium one (PNN ->
 * PON -> PPN), which draws its O-leg's phase current, up to the rated peak,
 * from the neutral point; after a small state of one type the other type of a
 * small vector (then the state that balances is out of reach and the one that
 * does not would be held a whole period). A whole period of such a state
 * moves the link by up to 3.4 V at the rated peak current, unchecked; at the
 * voltage limit these intermediates alone took the neutral point to 9-12 V.
 * Here the period is split instead: the intermediate first, only as long as
 * the NP prediction allows (within NP_INTERMEDIATE_ROOM_BANDS x np_band, at
 * least duty_min), then the wanted state (for a small vector its balancing
 * state). Kept whole when
 * the link has room: at the voltage limit the medium intermediate is also
 * what keeps the flux round (docs/envelope.md section 5). */
static void cut_intermediate_short(const dtc3l_cfg *cfg, const dtc3l_cmd *in, const tick_geometry *g, tick_plan *p)
{
    /* without a shortest segment the intermediate could be given no time at all */
    npc_class cls = npc_sv_class_unchecked(p->sv0);
    /* the holds (about every other period) leave on the integer tests, before the float one */
    if (cls == NPC_CLASS_ZERO || p->split || p->st0 != p->st1 || !(cfg->duty_min > R(0.0)))
        return;
    const uint8_t *st = npc_sv_state_list[p->sv0]; /* read in place */
    uint8_t target = st[0];
    bool small = cls == NPC_CLASS_SMALL;
    if (small) {
        /* the chosen one is kept unless the link is outside its band and the
         * chosen state pushes it further, or it would take the link beyond the
         * room of an intermediate */
        real_t inp_chosen = npc_np_current_unchecked(p->st0, g->i_abc_A);
        real_t n_chosen = np_left(cfg, in, inp_chosen);
        bool wrong_way = num_abs(in->np_dev_V) > cfg->np_band_V && num_mul(inp_chosen, in->np_dev_V) > R(0.0);
        bool far = n_chosen > num_mul(NP_SMALL_ROOM_BANDS, cfg->np_band_V);
        if (!(wrong_way || far))
            return; /* kept whatever the other state does: its NP current not needed */
        /* of the vector's two states, the one that leaves the link nearer to
         * balance; the chosen state's n_chosen when it is one of them (the
         * same expression) */
        real_t n0 = p->st0 == st[0] ? n_chosen : np_left(cfg, in, npc_np_current_unchecked(st[0], g->i_abc_A));
        real_t n1 = p->st0 == st[1] ? n_chosen : np_left(cfg, in, npc_np_current_unchecked(st[1], g->i_abc_A));
        target = n1 < n0 ? st[1] : st[0];
        real_t n_target = n1 < n0 ? n1 : n0;
        bool too_far = far && n_chosen > n_target;
        if (p->st0 == target || !(wrong_way || too_far))
            return;
        if (!npc_pn_step_unchecked(g->prev_state, target)) {
            p->st0 = p->st1 = target; /* one commutation more, within reach */
            return;
        }
    } else if (cls != NPC_CLASS_LARGE && cls != NPC_CLASS_MEDIUM) {
        return;
    }
    if (p->st0 == target)
        return;
    uint8_t mid = small ? npc_pn_safe_unchecked(g->prev_state, target) : p->st0;
    if (npc_pn_step_unchecked(mid, target) || npc_pn_step_unchecked(g->prev_state, mid))
        return;
    real_t d = R(1.0);
    if (small && npc_state_sv_unchecked(mid) == 0u) {
        /* a zero state draws no NP current (exactly 0 from finite phase
         * currents: OOO's sum to 0 by construction): not outward, as below,
         * without its NP current */
        d = cfg->duty_min;
    } else {
        real_t dv = num_mul(cfg->np_V_per_A, npc_np_current_unchecked(mid, g->i_abc_A)); /* V per whole period */
        bool outward = num_mul(dv, in->np_dev_V) > R(0.0);
        if (small && !outward) {
            d = cfg->duty_min; /* the intermediate does not push the link out: as short as the timer allows */
        } else if (outward || num_abs(in->np_dev_V) > cfg->np_band_V) {
            real_t room = num_mul(NP_INTERMEDIATE_ROOM_BANDS, cfg->np_band_V) - num_abs(in->np_dev_V);
            d = num_abs(dv) > R(1e-6) ? num_div(room, num_abs(dv)) : R(1.0);
            d = num_sat(d, cfg->duty_min, R(1.0));
        }
    }
    if (d > R(1.0) - cfg->duty_min)
        return;
    p->st0 = mid;
    p->st1 = target;
    p->duty0 = d;
    p->split = true;
}

static void emit(dtc3l *s, const tick_plan *p, dtc3l_out *out)
{
    s->torque_state = p->after;
    out->act.duty0 = p->st1 == p->st0 ? R(1.0) : p->duty0;
    out->state[0] = p->st0;
    out->state[1] = p->st1;
    out->level = s->level;
}

void dtc3l_step_predicted(dtc3l *s, const dtc3l_cfg *cfg, real_t dt_s, const dtc3l_cmd *in,
                          const observer_out *pr, dtc3l_out *out)
{
    tick_geometry g;
    tick_plan p;
    tick_geometry_of(cfg, in, pr, &g);
    if (in->decide_level)
        decide_voltage_level(s, cfg, in);
    bool flux_low = decide_flux_demand(s, cfg, in, g.psi_Wb);
    plan_table_vector(s, cfg, in, pr, &g, &p);
    if (cfg->ripple_reduction && num_abs(pr->omega_m_rad_s) < cfg->ripple_speed_max_rad_s)
        place_band_edge_crossing(s, cfg, dt_s, in, pr, &g, &p);
    add_flux_hold_pulse(s, cfg, dt_s, in, pr, &g, flux_low, &p);
    balance_np_in_holds(s, cfg, in, &g, &p);
    cut_intermediate_short(cfg, in, &g, &p);
    emit(s, &p, out);
}

/* The flat form: its prediction fields where dtc3l_step_predicted reads them
 * (observer_out's other fields are not read). */
void dtc3l_step(dtc3l *s, const dtc3l_cfg *cfg, real_t dt_s, const dtc3l_in *in, dtc3l_out *out)
{
    observer_out pr;
    pr.te_pred_Nm = in->te_Nm;
    pr.psi_s_pred_Wb[0] = in->psi_s_Wb[0];
    pr.psi_s_pred_Wb[1] = in->psi_s_Wb[1];
    pr.is_pred_A[0] = in->is_A[0];
    pr.is_pred_A[1] = in->is_A[1];
    pr.dte0_Nm_s = in->dte0_Nm_s;
    pr.dte_dv[0] = in->dte_dv[0];
    pr.dte_dv[1] = in->dte_dv[1];
    pr.omega_m_rad_s = in->omega_m_rad_s;
    dtc3l_cmd c;
    c.te_ref_Nm = in->te_ref_Nm;
    c.psi_ref_Wb = in->psi_ref_Wb;
    c.rs_ohm = in->rs_ohm;
    c.omega_e_rad_s = in->omega_e_rad_s;
    c.vc1_V = in->vc1_V;
    c.vc2_V = in->vc2_V;
    c.np_dev_V = in->np_dev_V;
    c.prev_state = in->prev_state < NPC_N_STATES ? in->prev_state : (uint8_t)NPC_STATE_OOO;
    c.band_scale = in->band_scale > R(1.0) ? in->band_scale : R(1.0);
    c.decide_level = true;
    dtc3l_step_predicted(s, cfg, dt_s, &c, &pr, out);
    npc_legs_pair_unchecked(out->state[0], out->state[1], &out->act); /* both 0..26 */
}
