/**
 * @file dtc3l_np.c
 * @brief Choice among redundant switching states: neutral-point balance,
 *        fewest commutations, and never a direct P<->N leg step.
 *
 * With C1 = C2 = C the neutral point obeys d(vc1 - vc2)/dt = i_np / C, where
 * i_np is the current the legs at O draw from the neutral point. A small
 * vector's P-type and N-type states put complementary legs at O, so their
 * i_np have opposite signs (POO draws ib + ic = -ia, ONN draws ia): the one
 * with i_np (vc1 - vc2) < 0 pulls the capacitors towards balance.
 * Zero vectors draw no NP current, but the choice among NNN, OOO and PPP
 * decides which small states stay reachable without a P<->N step.
 */
#include "dtc/dtc3l.h"

/* The zero state looks ahead once |vc1 - vc2| exceeds this fraction of the band. */
#define NP_LOOKAHEAD_FRACTION R(0.5)

/* The zero state with the fewest commutations from each state, never a P<->N
 * step away, OOO on ties (then NNN before PPP), precomputed; tests/unit/test_dtc3l.cpp checks it. */
static const uint8_t zero_after[DTC3L_N_STATES] = {
    0u, 0u, 13u, 0u, 13u, 13u, 13u, 13u, 13u,    /* NNN..NPP */
    0u, 13u, 13u, 13u, 13u, 13u, 13u, 13u, 26u,  /* ONN..OPP */
    13u, 13u, 13u, 13u, 13u, 26u, 13u, 26u, 26u, /* PNN..PPP */
};

/* The zero state on the way from small state `prev` to the state of its own
 * vector that balances (column 0: the vector's first, P-type state; 1: its
 * N-type one): of OOO, NNN, PPP the ones a P<->N step away from neither,
 * least 2 x commutations(zero, target) + commutations(prev, zero), the first
 * in that order on ties (OOO when none is free), i.e. the loop the
 * look-ahead ran over the three zero states, precomputed (issue 11);
 * tests/unit/test_dtc3l.cpp checks it against that rule. Rows of states that
 * are not small are never read. */
static const uint8_t zero_toward[DTC3L_N_STATES][2] = {
    {13u, 13u}, /*  0 NNN (not small: unused) */
    {13u, 0u}, /*  1 NNO */
    {13u, 13u}, /*  2 NNP (not small: unused) */
    {13u, 0u}, /*  3 NON */
    {13u, 13u}, /*  4 NOO */
    {13u, 13u}, /*  5 NOP (not small: unused) */
    {13u, 13u}, /*  6 NPN (not small: unused) */
    {13u, 13u}, /*  7 NPO (not small: unused) */
    {13u, 13u}, /*  8 NPP (not small: unused) */
    {13u, 0u}, /*  9 ONN */
    {13u, 13u}, /* 10 ONO */
    {13u, 13u}, /* 11 ONP (not small: unused) */
    {13u, 13u}, /* 12 OON */
    {13u, 13u}, /* 13 OOO (not small: unused) */
    {13u, 13u}, /* 14 OOP */
    {13u, 13u}, /* 15 OPN (not small: unused) */
    {13u, 13u}, /* 16 OPO */
    {26u, 13u}, /* 17 OPP */
    {13u, 13u}, /* 18 PNN (not small: unused) */
    {13u, 13u}, /* 19 PNO (not small: unused) */
    {13u, 13u}, /* 20 PNP (not small: unused) */
    {13u, 13u}, /* 21 PON (not small: unused) */
    {13u, 13u}, /* 22 POO */
    {26u, 13u}, /* 23 POP */
    {13u, 13u}, /* 24 PPN (not small: unused) */
    {26u, 13u}, /* 25 PPO */
    {13u, 13u}, /* 26 PPP (not small: unused) */
};

uint8_t dtc3l_choose_state(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                           const real_t i_abc[3])
{
    /* from here on every vector is 0..18 and every state 0..26: the unchecked look-ups */
    return dtc3l_choose_state_unchecked(sv < DTC3L_N_VECTORS ? sv : 0u,
                                        prev_state < DTC3L_N_STATES ? prev_state : (uint8_t)DTC3L_STATE_OOO,
                                        np_dev_V, np_band_V, i_abc);
}

/* The zero state after @p prev_state (dtc3l_choose_state for the zero vector).
 * @p push0 true: @p push0_VA is np_current(first state of prev_state's
 * vector) x np_dev_V, already worked out by the caller (the NP look-ahead then
 * reuses it: the same product, issue 11). */
static inline uint8_t choose_zero(uint8_t prev_state, real_t np_dev_V, real_t np_band_V, const real_t i_abc[3],
                                  bool push0, real_t push0_VA)
{
    /* From NNN (PPP) the P-type (N-type) small states are a P<->N step away.
     * When the neutral point needs attention, pick the zero state on the way
     * to the balancing state of the small vector just used (the likely next
     * one), so that state stays reachable. */
    if (!(num_abs(np_dev_V) > num_mul(NP_LOOKAHEAD_FRACTION, np_band_V)))
        return zero_after[prev_state];
    uint8_t prev_sv = dtc3l_state_sv_unchecked(prev_state);
    if (dtc3l_sv_class_unchecked(prev_sv) != DTC3L_CLASS_SMALL)
        return num_abs(np_dev_V) > np_band_V ? (uint8_t)DTC3L_STATE_OOO : zero_after[prev_state];
    if (!push0)
        push0_VA = num_mul(dtc3l_np_current_unchecked(dtc3l_sv_state_list[prev_sv][0], i_abc), np_dev_V);
    return zero_toward[prev_state][push0_VA <= R(0.0) ? 0 : 1];
}

/* dtc3l_choose_state_unchecked; for a small vector outside the NP band whose
 * first state is within reach, also np_current(first state) x np_dev_V
 * (*push0_VA, *push0 true; otherwise *push0 false). */
static inline uint8_t choose_state(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                                   const real_t i_abc[3], bool *push0_known, real_t *push0_VA)
{
    const uint8_t *st = dtc3l_sv_state_list[sv]; /* read in place: no copy (issue 11) */
    dtc3l_class cls = dtc3l_sv_class_unchecked(sv);
    bool small = cls == DTC3L_CLASS_SMALL;
    bool np_out = num_abs(np_dev_V) > np_band_V;
    bool np_forced = small && np_out;
    *push0_known = false;

    /* Zero vector: NNN, OOO or PPP (choose_zero) */
    if (sv == 0u)
        return choose_zero(prev_state, np_dev_V, np_band_V, i_abc, false, R(0.0));
    /* Vectors with a single state (medium, large): nothing to choose. */
    if (cls == DTC3L_CLASS_MEDIUM || cls == DTC3L_CLASS_LARGE)
        return dtc3l_pn_safe_unchecked(prev_state, st[0]); /* st[0] itself unless a leg would step P<->N */
    if (small && !np_forced) {
        /* A small vector inside the band: the state with fewer commutations.
         * Its P-type state is its N-type one a level up in every leg, so from
         * any state their commutation counts differ by an odd number (three
         * legs of +-1 each): never a tie, so the NP preference never decides
         * inside the band and no NP current is needed here. */
        uint8_t c0 = st[0], c1 = st[1];
        bool ok0 = !dtc3l_pn_step_unchecked(prev_state, c0), ok1 = !dtc3l_pn_step_unchecked(prev_state, c1);
        if (ok0 && ok1)
            return dtc3l_leg_changes_unchecked(prev_state, c0) < dtc3l_leg_changes_unchecked(prev_state, c1) ? c0 : c1;
        return ok0 ? c0 : (ok1 ? c1 : dtc3l_pn_safe_unchecked(prev_state, c0));
    }
    if (small) {
        /* A small vector outside the band (np_forced): the balancing state
         * first, then fewer commutations (never a tie); when the balancing
         * state is a P<->N step away, the other state held P<->N-safe if that
         * one balances (below). */
        uint8_t c0 = st[0], c1 = st[1];
        bool ok0 = !dtc3l_pn_step_unchecked(prev_state, c0), ok1 = !dtc3l_pn_step_unchecked(prev_state, c1);
        if (!(ok0 || ok1))
            return dtc3l_pn_safe_unchecked(prev_state, c0);
        real_t push0 = ok0 ? num_mul(dtc3l_np_current_unchecked(c0, i_abc), np_dev_V) : R(0.0);
        real_t push1 = ok1 ? num_mul(dtc3l_np_current_unchecked(c1, i_abc), np_dev_V) : R(0.0);
        *push0_known = ok0;
        *push0_VA = push0;
        bool take1 = !ok0;
        if (ok0 && ok1) {
            bool toward0 = push0 <= R(0.0), toward1 = push1 <= R(0.0);
            if (toward0 != toward1)
                return toward1 ? c1 : c0; /* the one that balances (its push <= 0: no fallback; issue 11) */
            take1 = dtc3l_leg_changes_unchecked(prev_state, c1) < dtc3l_leg_changes_unchecked(prev_state, c0);
        }
        uint8_t chosen = take1 ? c1 : c0;
        if (!((take1 ? push1 : push0) > R(0.0)))
            return chosen;
        uint8_t m = dtc3l_pn_safe_unchecked(prev_state, take1 ? c0 : c1); /* the other state, held P<->N-safe */
        if (dtc3l_sv_class_unchecked(dtc3l_state_sv_unchecked(m)) == DTC3L_CLASS_SMALL &&
            num_mul(dtc3l_np_current_unchecked(m, i_abc), np_dev_V) < R(0.0))
            return m;
        return chosen;
    }
    /* Every vector with more than one state is the zero vector or a small one,
     * both handled above; this keeps the function total. */
    return dtc3l_pn_safe_unchecked(prev_state, st[0]);
}

uint8_t dtc3l_choose_state_unchecked(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                                     const real_t i_abc[3])
{
    bool known;
    real_t push0;
    return choose_state(sv, prev_state, np_dev_V, np_band_V, i_abc, &known, &push0);
}

uint8_t dtc3l_choose_state_push0_unchecked(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                                           const real_t i_abc[3], bool *push0_known, real_t *push0_VA)
{
    return choose_state(sv, prev_state, np_dev_V, np_band_V, i_abc, push0_known, push0_VA);
}

uint8_t dtc3l_choose_zero_unchecked(uint8_t prev_state, real_t np_dev_V, real_t np_band_V, const real_t i_abc[3],
                                    bool push0_known, real_t push0_VA)
{
    return choose_zero(prev_state, np_dev_V, np_band_V, i_abc, push0_known, push0_VA);
}
