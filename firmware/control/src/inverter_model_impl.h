/**
 * @file inverter_model_impl.h
 * @brief The body of inverter_voltage() (dtc/inverter_model.h) as inline
 *        functions, for the control step's observation (ctl_observe.h): the
 *        tick's hot path. Private to firmware/control.
 *
 * The real inverter's legs are worked on the states' packed leg codes
 * (npc_state_legs_packed): the legs that commute are the bytes in which two
 * states' words differ, the rising ones three legs at once (rising_bytes),
 * so that nothing is tested per leg when nothing commutes, and a period of
 * one state compares no duty.
 */
#ifndef DTC_INVERTER_MODEL_IMPL_H
#define DTC_INVERTER_MODEL_IMPL_H

#include "dtc/inverter_model.h"
#include "dtc/npc.h"
#include "real_bits.h"

/* Bit 7 of each byte set where the leg code in @p w_to is at least the one in
 * @p w_from, for the three legs at once. Exact: with codes 0..2 each byte is
 * 0x80 + to - from, 0x7E..0x82, so no byte borrows from the next; where the
 * codes differ, bit 7 is to > from. */
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
        v_V = inverter_dead_time_edge(((up >> sh) & 0x80u) != 0u, late_up, from_V, to_V, dt_per_T, v_V);
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

/* The fraction of a rising edge that is late, from the leg's current:
 * sat(y, 0, 1) for y = 0.5 + i / (2 INVERTER_DROP_BAND_A), on the bits of y
 * (two integer selects). A negative y (sign bit set) gives +0, as the clamp's
 * lower bound; a non-negative one orders like its bits, so the smaller of the
 * bits and 1.0's is the clamp's upper bound. The same value as num_sat for
 * every y but a NaN (1 here; the phase currents are finite: the control step
 * trips SAMPLE_INVALID first; y is never -0). */
static inline real_t late_up_of(real_t i_A)
{
    uint32_t u = f32_bits(R(0.5) + i_A / (R(2.0) * INVERTER_DROP_BAND_A));
    const uint32_t one = 0x3F800000u; /* 1.0f */
    u = (u & 0x80000000u) != 0u ? 0u : u;
    u = u < one ? u : one;
    return f32_of_bits(u);
}

/* The real inverter (dtc/inverter_model.h), leg by leg: each leg takes its mix,
 * drop, first edge and split edge in that order, the legs apart from one
 * another; the path that applies st0 first is apart from the others, and the
 * levels read for the mix (from act's codes: the states' own) are the edges'
 * end levels. With no dead time dt_per_T is 0 and the edges add nothing. */
static inline uint8_t real_inverter_voltage(const inverter_period *p, const real_t level_V[3], const real_t i_A[3],
                                            const inverter_consts *k, real_t v[2])
{
    uint8_t st0 = p->state[0], st1 = p->state[1];
    uint32_t w1 = npc_state_legs_packed[st1];
    uint32_t w_from = npc_state_legs_packed[p->end_state];
    uint8_t end = st1;
    real_t drop4_V = k->drop4_V; /* 0 with the drops off */
    real_t dt = k->dead_time_per_T;
    real_t ua = late_up_of(i_A[0]), ub = late_up_of(i_A[1]), uc = late_up_of(i_A[2]);
    /* the legs' voltages as scalars; the codes read from act where they are
     * needed (fewer registers held) */
    const uint8_t *l0 = p->act.vector[0].leg, *l1 = p->act.vector[1].leg;
    real_t la1 = level_V[l1[0]], lb1 = level_V[l1[1]], lc1 = level_V[l1[2]];
    real_t d0 = p->act.duty0;
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
            end = inverter_period_end_state(st0, st1, d0); /* st0 for a NaN duty */
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

/** inverter_voltage(), inline. Context: ANY. */
static inline uint8_t inverter_voltage_inline(const inverter_period *p, const real_t level_V[3], const real_t i_A[3],
                                              const inverter_consts *k, real_t v_ab[2])
{
    if (k->real)
        return real_inverter_voltage(p, level_V, i_A, k, v_ab);
    /* the ideal inverter: the states' voltages straight in alpha-beta */
    uint8_t st0 = p->state[0], st1 = p->state[1];
    uint8_t end = st1;
    npc_legs_voltage(&p->act.vector[1], level_V, v_ab);
    if (st0 != st1) { /* two states: mixed by the duty (one state's d0 x 0 + v1 would be v1 exactly) */
        real_t v0[2];
        npc_legs_voltage(&p->act.vector[0], level_V, v0);
        real_t d0 = p->act.duty0;
        v_ab[0] = num_mac(d0, v0[0] - v_ab[0], v_ab[0]);
        v_ab[1] = num_mac(d0, v0[1] - v_ab[1], v_ab[1]);
        end = inverter_period_end_state(st0, st1, d0);
    }
    return end;
}

#endif /* DTC_INVERTER_MODEL_IMPL_H */
