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

void dtc3l_step(dtc3l *s, const dtc3l_cfg *cfg, real_t dt_s, const dtc3l_in *in, dtc3l_out *out)
{
    real_t np_dev = in->np_dev_V;
    real_t vdc = in->vc1_V + in->vc2_V;
    real_t psi = num_sqrt(num_mul(in->psi_s_Wb[0], in->psi_s_Wb[0]) + num_mul(in->psi_s_Wb[1], in->psi_s_Wb[1]));
    uint8_t sector = dtc3l_sector(in->psi_s_Wb[0], in->psi_s_Wb[1]);
    real_t b = cfg->torque_band_Nm;
    real_t bf = cfg->flux_band_Wb;

    /* voltage level from the back-emf, with hysteresis */
    real_t emf_pu = num_div(num_mul(num_abs(in->omega_e_rad_s), in->psi_ref_Wb),
                            num_mul(R(0.333333333), vdc > R(1.0) ? vdc : R(1.0)));
    if (s->level == (uint8_t)DTC3L_LEVEL_LOW && emf_pu > cfg->level_up)
        s->level = (uint8_t)DTC3L_LEVEL_HIGH;
    else if (s->level != (uint8_t)DTC3L_LEVEL_LOW && emf_pu < cfg->level_down)
        s->level = (uint8_t)DTC3L_LEVEL_LOW;

    /* flux: two-level hysteresis */
    if (psi < in->psi_ref_Wb - bf)
        s->flux_state = 1;
    else if (psi > in->psi_ref_Wb + bf)
        s->flux_state = -1;

    int8_t cur = torque_comparator(s->torque_state, in->te_Nm, in->te_ref_Nm, b, cfg->torque_band2_Nm, in->dte0_Nm_s);
    int8_t after = cur; /* comparator state at the end of the period */

    real_t i_abc[3];
    i_abc[0] = in->is_A[0];
    i_abc[1] = num_mac(R(-0.5), in->is_A[0], num_mul(R(0.866025404), in->is_A[1]));
    i_abc[2] = -i_abc[0] - i_abc[1];

    uint8_t sector6 = dtc3l_sector6(in->psi_s_Wb[0], in->psi_s_Wb[1]);
    real_t np_band = cfg->np_band_V;
    real_t dmin = cfg->duty_min;

    /* The states are chosen first (P<->N-free, NP-balancing, fewest
     * commutations); the timing then uses the slope of the state actually
     * applied, which may be an NP intermediate rather than the table's vector. */
    uint8_t sv0 = pick(sector, sector6, cur, s->flux_state, s->level);
    uint8_t st0 = dtc3l_choose_state(sv0, in->prev_state, np_dev, np_band, i_abc);
    uint8_t st1 = st0;
    real_t duty0 = R(1.0);
    bool split = false;

    bool ripple = cfg->ripple_reduction && num_abs(in->omega_m_rad_s) < cfg->ripple_speed_max_rad_s;
    if (ripple) {
        /* Place the band-edge crossing inside the period. An edge reached at
         * the very start hands over to the next comparator state, which is
         * then examined in turn (at most twice: up/down -> hold -> up/down). */
        real_t s_cur = R(0.0), edge = R(0.0), f = R(2.0);
        int8_t next = cur;
        for (int pass = 0; pass < 2; pass++) {
            s_cur = dtc3l_state_slope(in, st0);
            f = exit_edge(cur, s_cur, in, b, dt_s, &edge, &next);
            if (!(f < dmin) || next == cur)
                break;
            cur = next;
            after = cur;
            sv0 = pick(sector, sector6, cur, s->flux_state, s->level);
            st0 = st1 = dtc3l_choose_state(sv0, in->prev_state, np_dev, np_band, i_abc);
        }
        if (f >= dmin && f <= R(1.0) - dmin && next != cur) {
            uint8_t sv_next = pick(sector, sector6, next, s->flux_state, s->level);
            st1 = dtc3l_choose_state(sv_next, st0, np_dev, np_band, i_abc);
            duty0 = f;
            after = next;
            split = true;
            if (next != 0) {
                /* hold -> active: when the active vector would also cross the
                 * opposite edge before the period ends, start it later so that
                 * the period ends on that edge (two-slope duty: Te_end =
                 * Te + s_hold (1 - d) T + s_act d T) and stay in hold */
                real_t s_next = dtc3l_state_slope(in, st1);
                real_t opp = next > 0 ? in->te_ref_Nm + b : in->te_ref_Nm - b;
                real_t g = dtc3l_edge_fraction(edge, s_next, opp, dt_s);
                if (g < R(1.0) - f) {
                    real_t den = num_mul(s_next - s_cur, dt_s);
                    real_t d_act = num_abs(den) > R(1e-6) ? num_div(opp - in->te_Nm - num_mul(s_cur, dt_s), den) : g;
                    d_act = num_sat(d_act, dmin, R(1.0) - dmin);
                    duty0 = R(1.0) - d_act;
                    after = 0;
                }
            }
        }
        /* else: no crossing, or it falls at the next period start */
    }

    /* Flux-drop compensation: a full hold period at the LOW level with the
     * flux below its band gets a pulse of the small vector along the flux,
     * long enough to bring |psi| back to the reference, and short enough to
     * keep the torque in its band over the whole period. */
    if (!split && sv0 == 0u && s->level == (uint8_t)DTC3L_LEVEL_LOW && psi < in->psi_ref_Wb - bf) {
        uint8_t svh = dtc3l_table_flux_hold(sector6);
        uint8_t sth = dtc3l_choose_state(svh, in->prev_state, np_dev, np_band, i_abc);
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
        if (d >= dmin) {
            st0 = sth;
            if (d < R(1.0) - dmin) {
                st1 = dtc3l_choose_state(0u, sth, np_dev, np_band, i_abc);
                duty0 = d;
                split = true;
            } else {
                st1 = sth;
            }
        }
    }

    /* Neutral point at the HIGH level: large vectors draw no NP current and
     * medium ones an uncontrolled one, so an unbalanced link is pulled back
     * during the holds: instead of a zero state, the balancing state of the
     * small vector nearest to the flux (to -flux while the flux is to fall).
     * Its tangential part is at most half of Vdc/3, below the back-emf at
     * this level, so the torque falls much as under a zero state; after a
     * large vector it also costs fewer commutations than OOO. */
    if (s->level != (uint8_t)DTC3L_LEVEL_LOW && num_abs(np_dev) > np_band) {
        uint8_t svn = dtc3l_table_flux_hold((uint8_t)((sector6 + (s->flux_state > 0 ? 0u : 3u)) % 6u));
        bool full = st1 == st0;
        uint8_t sv_b = dtc3l_state_sv(st1);
        if (dtc3l_state_sv(st0) == 0u)
            st0 = dtc3l_choose_state(svn, in->prev_state, np_dev, np_band, i_abc);
        if (full)
            st1 = st0;
        else /* the second state follows the (possibly new) first one */
            st1 = dtc3l_choose_state(sv_b == 0u ? svn : sv_b, st0, np_dev, np_band, i_abc);
    }

    if (st1 == st0)
        duty0 = R(1.0);

    s->torque_state = after;

    dtc3l_legs(st0, &out->act.vector[0]);
    dtc3l_legs(st1, &out->act.vector[1]);
    out->act.duty0 = duty0;
    out->state[0] = st0;
    out->state[1] = st1;
    out->sector = sector;
    out->torque_cmp = cur;
    out->flux_cmp = s->flux_state;
    out->level = s->level;
    out->split = split;
}
