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

#include <stddef.h>

/* Below this flux the radial direction is undefined (start of magnetising), Wb. */
#define PSI_TINY_WB R(1e-3)

void dtc3l_init(dtc3l *s)
{
    s->torque_state = 0;
    s->flux_state = 1;
    s->level = (uint8_t)DTC3L_LEVEL_LOW;
}

static int8_t torque_comparator(int8_t state, real_t te, real_t te_ref, real_t b, real_t b2, real_t s_hold)
{
    real_t err = te_ref - te;
    if (err > b2)
        return 2;
    if (err < -b2)
        return -2;
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

/* dtc3l_select with the sectors already known */
static uint8_t pick(uint8_t sector, uint8_t sector6, int8_t torque, int8_t flux, uint8_t level)
{
    if (level == (uint8_t)DTC3L_LEVEL_LOW && (torque == 1 || torque == -1))
        return dtc3l_table6(sector6, torque, flux);
    return dtc3l_table(sector, torque, flux, level);
}

/* The band edge that ends comparator state @p cur under slope @p s_cur, the
 * state that follows (@p next = cur when there is none), and the fraction of
 * the period at which the edge is met (> 1: not within the period). */
static real_t exit_edge(int8_t cur, real_t s_cur, const dtc3l_in *in, real_t b, real_t dt_s, real_t *edge,
                        int8_t *next)
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
    return dtc3l_edge_fraction(in->te_Nm, s_cur, *edge, dt_s);
}

/* Rate of change of |psi_s| under state @p st, Wb/s: psi . (v - Rs is) / |psi|. */
static real_t flux_rate(const dtc3l_in *in, uint8_t st, real_t psi_abs)
{
    real_t v[2];
    dtc3l_state_voltage(st, in->vc1_V, in->vc2_V, v);
    real_t e0 = v[0] - num_mul(in->rs_ohm, in->is_A[0]);
    real_t e1 = v[1] - num_mul(in->rs_ohm, in->is_A[1]);
    if (psi_abs < PSI_TINY_WB)
        return num_sqrt(num_mul(e0, e0) + num_mul(e1, e1));
    return num_div(num_mul(in->psi_s_Wb[0], e0) + num_mul(in->psi_s_Wb[1], e1), psi_abs);
}

/* What one tick knows about the predicted state, computed once. */
typedef struct {
    real_t psi_Wb;            /* |psi_s| predicted */
    uint8_t sector;           /* 0..11 */
    uint8_t sector6;          /* 0..5 */
    real_t i_abc_A[3];        /* predicted phase currents */
} tick_geometry;

/* The decision being built: two states, the duty of the first, and the
 * comparator states for the first vector (cur) and at the period end (after). */
typedef struct {
    int8_t cur;
    int8_t after;
    uint8_t sv0;              /* space vector the table gave for cur */
    uint8_t st0, st1;
    real_t duty0;
    bool split;
} tick_plan;

static void tick_geometry_of(const dtc3l_in *in, tick_geometry *g)
{
    g->psi_Wb = num_sqrt(num_mul(in->psi_s_Wb[0], in->psi_s_Wb[0]) + num_mul(in->psi_s_Wb[1], in->psi_s_Wb[1]));
    g->sector = dtc3l_sector(in->psi_s_Wb[0], in->psi_s_Wb[1]);
    g->i_abc_A[0] = in->is_A[0];
    g->i_abc_A[1] = num_mac(R(-0.5), in->is_A[0], num_mul(R(0.866025404), in->is_A[1]));
    g->i_abc_A[2] = -g->i_abc_A[0] - g->i_abc_A[1];
    g->sector6 = dtc3l_sector6(in->psi_s_Wb[0], in->psi_s_Wb[1]);
}

/* Voltage level from the back-emf over Vdc/3, with hysteresis. */
static void decide_voltage_level(dtc3l *s, const dtc3l_cfg *cfg, const dtc3l_in *in)
{
    real_t vdc = in->vc1_V + in->vc2_V;
    real_t emf_pu = num_div(num_mul(num_abs(in->omega_e_rad_s), in->psi_ref_Wb),
                            num_mul(R(0.333333333), vdc > R(1.0) ? vdc : R(1.0)));
    if (s->level == (uint8_t)DTC3L_LEVEL_LOW && emf_pu > cfg->level_up)
        s->level = (uint8_t)DTC3L_LEVEL_HIGH;
    else if (s->level != (uint8_t)DTC3L_LEVEL_LOW && emf_pu < cfg->level_down)
        s->level = (uint8_t)DTC3L_LEVEL_LOW;
}

/* Flux demand: two-level hysteresis on |psi_s|. */
static void decide_flux_demand(dtc3l *s, const dtc3l_cfg *cfg, const dtc3l_in *in, real_t psi_Wb)
{
    if (psi_Wb < in->psi_ref_Wb - cfg->flux_band_Wb)
        s->flux_state = 1;
    else if (psi_Wb > in->psi_ref_Wb + cfg->flux_band_Wb)
        s->flux_state = -1;
}

/* The state realising the table's vector for torque demand @p torque. */
static uint8_t state_for_demand(const dtc3l *s, const dtc3l_cfg *cfg, const dtc3l_in *in, const tick_geometry *g,
                                int8_t torque, uint8_t prev_state, uint8_t *sv)
{
    uint8_t v = pick(g->sector, g->sector6, torque, s->flux_state, s->level);
    if (sv)
        *sv = v;
    return dtc3l_choose_state(v, prev_state, in->np_dev_V, cfg->np_band_V, g->i_abc_A);
}

/* The states are chosen first (P<->N-free, NP-balancing, fewest
 * commutations); the timing then uses the slope of the state actually
 * applied, which may be an NP intermediate rather than the table's vector.
 * The whole period goes to the table's vector for the comparator's demand. */
static void plan_table_vector(const dtc3l *s, const dtc3l_cfg *cfg, const dtc3l_in *in, const tick_geometry *g,
                              tick_plan *p)
{
    p->cur = torque_comparator(s->torque_state, in->te_Nm, in->te_ref_Nm, cfg->torque_band_Nm,
                               cfg->torque_band2_Nm, in->dte0_Nm_s);
    p->after = p->cur;
    p->st0 = state_for_demand(s, cfg, in, g, p->cur, in->prev_state, &p->sv0);
    p->st1 = p->st0;
    p->duty0 = R(1.0);
    p->split = false;
}

/* Ripple reduction: place the band-edge crossing inside the period. An edge
 * reached at the very start hands over to the next comparator state, which is
 * then examined in turn (at most twice: up/down -> hold -> up/down). */
static void place_band_edge_crossing(const dtc3l *s, const dtc3l_cfg *cfg, real_t dt_s, const dtc3l_in *in,
                                     const tick_geometry *g, tick_plan *p)
{
    real_t b = cfg->torque_band_Nm;
    real_t dmin = cfg->duty_min;
    real_t s_cur = R(0.0), edge = R(0.0), f = R(2.0);
    int8_t next = p->cur;
    for (int pass = 0; pass < 2; pass++) {
        s_cur = dtc3l_state_slope(in, p->st0);
        f = exit_edge(p->cur, s_cur, in, b, dt_s, &edge, &next);
        if (!(f < dmin) || next == p->cur)
            break;
        p->cur = next;
        p->after = p->cur;
        p->st0 = p->st1 = state_for_demand(s, cfg, in, g, p->cur, in->prev_state, &p->sv0);
    }
    if (!(f >= dmin && f <= R(1.0) - dmin && next != p->cur))
        return; /* no crossing, or it falls at the next period start */
    p->st1 = state_for_demand(s, cfg, in, g, next, p->st0, NULL);
    p->duty0 = f;
    p->after = next;
    p->split = true;
    if (next == 0)
        return;
    /* hold -> active: when the active vector would also cross the opposite
     * edge before the period ends, start it later so that the period ends on
     * that edge (two-slope duty: Te_end = Te + s_hold (1 - d) T + s_act d T)
     * and stay in hold */
    real_t s_next = dtc3l_state_slope(in, p->st1);
    real_t opp = next > 0 ? in->te_ref_Nm + b : in->te_ref_Nm - b;
    real_t gf = dtc3l_edge_fraction(edge, s_next, opp, dt_s);
    if (gf < R(1.0) - f) {
        real_t den = num_mul(s_next - s_cur, dt_s);
        real_t d_act = num_abs(den) > R(1e-6) ? num_div(opp - in->te_Nm - num_mul(s_cur, dt_s), den) : gf;
        d_act = num_sat(d_act, dmin, R(1.0) - dmin);
        p->duty0 = R(1.0) - d_act;
        p->after = 0;
    }
}

/* Flux-drop compensation: a full hold period at the LOW level with the flux
 * below its band gets a pulse of the small vector along the flux, long enough
 * to bring |psi| back to the reference, and short enough to keep the torque
 * in its band over the whole period. */
static void add_flux_hold_pulse(const dtc3l *s, const dtc3l_cfg *cfg, real_t dt_s, const dtc3l_in *in,
                                const tick_geometry *g, tick_plan *p)
{
    real_t b = cfg->torque_band_Nm;
    real_t dmin = cfg->duty_min;
    real_t psi = g->psi_Wb;
    if (!(!p->split && p->sv0 == 0u && s->level == (uint8_t)DTC3L_LEVEL_LOW && psi < in->psi_ref_Wb - cfg->flux_band_Wb))
        return;
    uint8_t svh = dtc3l_table_flux_hold(g->sector6);
    uint8_t sth = dtc3l_choose_state(svh, in->prev_state, in->np_dev_V, cfg->np_band_V, g->i_abc_A);
    real_t rate = flux_rate(in, sth, psi);
    real_t d = rate > R(0.0) ? num_div(in->psi_ref_Wb - psi, num_mul(rate, dt_s)) : R(1.0);
    real_t s_h = dtc3l_state_slope(in, sth);
    real_t s_z = in->dte0_Nm_s;
    real_t hi = in->te_ref_Nm + b, lo = in->te_ref_Nm - b;
    /* a rising pulse peaks at its end */
    if (s_h > R(0.0))
        d = num_sat(d, R(0.0), dtc3l_edge_fraction(in->te_Nm, s_h, hi, dt_s));
    /* the period ends at Te + s_z T + (s_h - s_z) d T, inside the band */
    real_t end0 = in->te_Nm + num_mul(s_z, dt_s);
    real_t ds = num_mul(s_h - s_z, dt_s);
    if (ds < R(0.0) && end0 > lo)
        d = num_sat(d, R(0.0), num_div(lo - end0, ds));
    else if (ds > R(0.0) && end0 < hi)
        d = num_sat(d, R(0.0), num_div(hi - end0, ds));
    if (d < dmin)
        return;
    p->st0 = sth;
    if (d < R(1.0) - dmin) {
        p->st1 = dtc3l_choose_state(0u, sth, in->np_dev_V, cfg->np_band_V, g->i_abc_A);
        p->duty0 = d;
        p->split = true;
    } else {
        p->st1 = sth;
    }
}

/* Neutral point at the HIGH level: large vectors draw no NP current and
 * medium ones an uncontrolled one, so an unbalanced link is pulled back
 * during the holds: instead of a zero state, the balancing state of the
 * small vector nearest to the flux (to -flux while the flux is to fall).
 * Its tangential part is at most half of Vdc/3, below the back-emf at
 * this level, so the torque falls much as under a zero state; after a
 * large vector it also costs fewer commutations than OOO. */
static void balance_np_in_holds(const dtc3l *s, const dtc3l_cfg *cfg, const dtc3l_in *in, const tick_geometry *g,
                                tick_plan *p)
{
    if (!(s->level != (uint8_t)DTC3L_LEVEL_LOW && num_abs(in->np_dev_V) > cfg->np_band_V))
        return;
    uint8_t svn = dtc3l_table_flux_hold((uint8_t)((g->sector6 + (s->flux_state > 0 ? 0u : 3u)) % 6u));
    bool full = p->st1 == p->st0;
    uint8_t sv_b = dtc3l_state_sv(p->st1);
    if (dtc3l_state_sv(p->st0) == 0u)
        p->st0 = dtc3l_choose_state(svn, in->prev_state, in->np_dev_V, cfg->np_band_V, g->i_abc_A);
    if (full)
        p->st1 = p->st0;
    else /* the second state follows the (possibly new) first one */
        p->st1 = dtc3l_choose_state(sv_b == 0u ? svn : sv_b, p->st0, in->np_dev_V, cfg->np_band_V, g->i_abc_A);
}

static void emit(dtc3l *s, const tick_geometry *g, const tick_plan *p, dtc3l_out *out)
{
    s->torque_state = p->after;
    dtc3l_legs(p->st0, &out->act.vector[0]);
    dtc3l_legs(p->st1, &out->act.vector[1]);
    out->act.duty0 = p->st1 == p->st0 ? R(1.0) : p->duty0;
    out->state[0] = p->st0;
    out->state[1] = p->st1;
    out->sector = g->sector;
    out->torque_cmp = p->cur;
    out->flux_cmp = s->flux_state;
    out->level = s->level;
    out->split = p->split;
}

void dtc3l_step(dtc3l *s, const dtc3l_cfg *cfg, real_t dt_s, const dtc3l_in *in, dtc3l_out *out)
{
    tick_geometry g;
    tick_plan p;
    tick_geometry_of(in, &g);
    decide_voltage_level(s, cfg, in);
    decide_flux_demand(s, cfg, in, g.psi_Wb);
    plan_table_vector(s, cfg, in, &g, &p);
    if (cfg->ripple_reduction && num_abs(in->omega_m_rad_s) < cfg->ripple_speed_max_rad_s)
        place_band_edge_crossing(s, cfg, dt_s, in, &g, &p);
    add_flux_hold_pulse(s, cfg, dt_s, in, &g, &p);
    balance_np_in_holds(s, cfg, in, &g, &p);
    emit(s, &g, &p, out);
}
