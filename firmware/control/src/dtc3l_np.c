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
#include "dtc/dtc3l_np.h"

#include "dtc/npc.h"

/* The zero state looks ahead once |vc1 - vc2| exceeds this fraction of the band. */
#define NP_LOOKAHEAD_FRACTION R(0.5)

/* The zero state with the fewest commutations from each state, never a P<->N
 * step away, OOO on ties (then NNN before PPP), precomputed; tests/unit/test_dtc3l.cpp checks it. */
static const uint8_t zero_after[NPC_N_STATES] = {
    0u, 0u, 13u, 0u, 13u, 13u, 13u, 13u, 13u,    /* NNN..NPP */
    0u, 13u, 13u, 13u, 13u, 13u, 13u, 13u, 26u,  /* ONN..OPP */
    13u, 13u, 13u, 13u, 13u, 26u, 13u, 26u, 26u, /* PNN..PPP */
};

/* The zero state on the way from small state `prev` to the state of its own
 * vector that balances (column 0: the vector's first, P-type state; 1: its
 * N-type one): of OOO, NNN, PPP the ones a P<->N step away from neither,
 * least 2 x commutations(zero, target) + commutations(prev, zero), the first
 * in that order on ties (OOO when none is free), i.e. the loop the
 * look-ahead would run over the three zero states, precomputed;
 * tests/unit/test_dtc3l.cpp checks it against that rule. Rows of states that
 * are not small are never read. */
static const uint8_t zero_toward[NPC_N_STATES][2] = {
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

/* The integer part of the choice between a small vector's two states from
 * each state, precomputed from the P<->N, commutation and P<->N-safe tables
 * (one look-up in place of two P<->N tests, two commutation counts and the
 * fallback's P<->N-safe state and class; the rules are choose_state's,
 * below, and tests/unit/test_dtc3l.cpp checks the choices against an
 * independent reference for every state, vector and NP case). Indexed by
 * [prev_state][sv], sv 1..6 (0 and 7 pad the row to eight entries). */
typedef struct {
    uint8_t pick;  /* of the vector's states (first P-type, second N-type) not a P<->N step
                      away, the one with fewer commutations (they never tie); when both are,
                      the first with those legs held at O */
    uint8_t other; /* the vector's state that is not `pick`, with its P<->N legs held at O
                      (0 when neither is in reach) */
    uint8_t reach; /* bit 0: the first state is in reach (no P<->N step), bit 1: the second;
                      bit 2: `other` is a small state */
    uint8_t pad;
} small_choice;

#define SMALL_FIRST_OK 1u
#define SMALL_SECOND_OK 2u
#define SMALL_OTHER_SMALL 4u

static const small_choice small_choice_of[NPC_N_STATES][8] = {
    {/*  0 NNN */ {0u, 0u, 0u, 0u}, {9u, 13u, 2u, 0u}, {12u, 13u, 2u, 0u}, {3u, 13u, 2u, 0u}, {4u, 13u, 2u, 0u}, {1u, 13u, 2u, 0u}, {10u, 13u, 2u, 0u}, {0u, 0u, 0u, 0u}},
    {/*  1 NNO */ {0u, 0u, 0u, 0u}, {9u, 13u, 2u, 0u}, {12u, 13u, 2u, 0u}, {3u, 13u, 2u, 0u}, {4u, 14u, 6u, 0u}, {1u, 14u, 7u, 0u}, {10u, 14u, 6u, 0u}, {0u, 0u, 0u, 0u}},
    {/*  2 NNP */ {0u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {4u, 14u, 6u, 0u}, {1u, 14u, 7u, 0u}, {10u, 14u, 6u, 0u}, {0u, 0u, 0u, 0u}},
    {/*  3 NON */ {0u, 0u, 0u, 0u}, {9u, 13u, 2u, 0u}, {12u, 16u, 6u, 0u}, {3u, 16u, 7u, 0u}, {4u, 16u, 6u, 0u}, {1u, 13u, 2u, 0u}, {10u, 13u, 2u, 0u}, {0u, 0u, 0u, 0u}},
    {/*  4 NOO */ {0u, 0u, 0u, 0u}, {9u, 13u, 2u, 0u}, {12u, 16u, 6u, 0u}, {3u, 16u, 7u, 0u}, {4u, 17u, 7u, 0u}, {1u, 14u, 7u, 0u}, {10u, 14u, 6u, 0u}, {0u, 0u, 0u, 0u}},
    {/*  5 NOP */ {0u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {16u, 0u, 0u, 0u}, {16u, 4u, 5u, 0u}, {4u, 17u, 7u, 0u}, {14u, 1u, 7u, 0u}, {10u, 14u, 6u, 0u}, {0u, 0u, 0u, 0u}},
    {/*  6 NPN */ {0u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {12u, 16u, 6u, 0u}, {3u, 16u, 7u, 0u}, {4u, 16u, 6u, 0u}, {13u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {0u, 0u, 0u, 0u}},
    {/*  7 NPO */ {0u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {12u, 16u, 6u, 0u}, {16u, 3u, 7u, 0u}, {4u, 17u, 7u, 0u}, {14u, 4u, 5u, 0u}, {14u, 0u, 0u, 0u}, {0u, 0u, 0u, 0u}},
    {/*  8 NPP */ {0u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {16u, 0u, 0u, 0u}, {16u, 4u, 5u, 0u}, {17u, 4u, 7u, 0u}, {14u, 4u, 5u, 0u}, {14u, 0u, 0u, 0u}, {0u, 0u, 0u, 0u}},
    {/*  9 ONN */ {0u, 0u, 0u, 0u}, {9u, 22u, 7u, 0u}, {12u, 22u, 6u, 0u}, {3u, 13u, 2u, 0u}, {4u, 13u, 2u, 0u}, {1u, 13u, 2u, 0u}, {10u, 22u, 6u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 10 ONO */ {0u, 0u, 0u, 0u}, {9u, 22u, 7u, 0u}, {12u, 22u, 6u, 0u}, {3u, 13u, 2u, 0u}, {4u, 14u, 6u, 0u}, {1u, 14u, 7u, 0u}, {10u, 23u, 7u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 11 ONP */ {0u, 0u, 0u, 0u}, {22u, 10u, 5u, 0u}, {22u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {4u, 14u, 6u, 0u}, {14u, 1u, 7u, 0u}, {10u, 23u, 7u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 12 OON */ {0u, 0u, 0u, 0u}, {9u, 22u, 7u, 0u}, {12u, 25u, 7u, 0u}, {3u, 16u, 7u, 0u}, {4u, 16u, 6u, 0u}, {1u, 13u, 2u, 0u}, {10u, 22u, 6u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 13 OOO */ {0u, 0u, 0u, 0u}, {22u, 9u, 7u, 0u}, {12u, 25u, 7u, 0u}, {16u, 3u, 7u, 0u}, {4u, 17u, 7u, 0u}, {14u, 1u, 7u, 0u}, {10u, 23u, 7u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 14 OOP */ {0u, 0u, 0u, 0u}, {22u, 10u, 5u, 0u}, {25u, 13u, 1u, 0u}, {16u, 4u, 5u, 0u}, {17u, 4u, 7u, 0u}, {14u, 1u, 7u, 0u}, {23u, 10u, 7u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 15 OPN */ {0u, 0u, 0u, 0u}, {22u, 12u, 5u, 0u}, {12u, 25u, 7u, 0u}, {16u, 3u, 7u, 0u}, {4u, 16u, 6u, 0u}, {13u, 0u, 0u, 0u}, {22u, 0u, 0u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 16 OPO */ {0u, 0u, 0u, 0u}, {22u, 12u, 5u, 0u}, {25u, 12u, 7u, 0u}, {16u, 3u, 7u, 0u}, {17u, 4u, 7u, 0u}, {14u, 4u, 5u, 0u}, {23u, 13u, 1u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 17 OPP */ {0u, 0u, 0u, 0u}, {22u, 13u, 1u, 0u}, {25u, 13u, 1u, 0u}, {16u, 4u, 5u, 0u}, {17u, 4u, 7u, 0u}, {14u, 4u, 5u, 0u}, {23u, 13u, 1u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 18 PNN */ {0u, 0u, 0u, 0u}, {9u, 22u, 7u, 0u}, {12u, 22u, 6u, 0u}, {13u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {10u, 22u, 6u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 19 PNO */ {0u, 0u, 0u, 0u}, {22u, 9u, 7u, 0u}, {12u, 22u, 6u, 0u}, {13u, 0u, 0u, 0u}, {14u, 0u, 0u, 0u}, {14u, 10u, 5u, 0u}, {10u, 23u, 7u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 20 PNP */ {0u, 0u, 0u, 0u}, {22u, 10u, 5u, 0u}, {22u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {14u, 0u, 0u, 0u}, {14u, 10u, 5u, 0u}, {23u, 10u, 7u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 21 PON */ {0u, 0u, 0u, 0u}, {22u, 9u, 7u, 0u}, {12u, 25u, 7u, 0u}, {16u, 12u, 5u, 0u}, {16u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {10u, 22u, 6u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 22 POO */ {0u, 0u, 0u, 0u}, {22u, 9u, 7u, 0u}, {25u, 12u, 7u, 0u}, {16u, 12u, 5u, 0u}, {17u, 13u, 1u, 0u}, {14u, 10u, 5u, 0u}, {23u, 10u, 7u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 23 POP */ {0u, 0u, 0u, 0u}, {22u, 10u, 5u, 0u}, {25u, 13u, 1u, 0u}, {16u, 13u, 1u, 0u}, {17u, 13u, 1u, 0u}, {14u, 10u, 5u, 0u}, {23u, 10u, 7u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 24 PPN */ {0u, 0u, 0u, 0u}, {22u, 12u, 5u, 0u}, {25u, 12u, 7u, 0u}, {16u, 12u, 5u, 0u}, {16u, 0u, 0u, 0u}, {13u, 0u, 0u, 0u}, {22u, 0u, 0u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 25 PPO */ {0u, 0u, 0u, 0u}, {22u, 12u, 5u, 0u}, {25u, 12u, 7u, 0u}, {16u, 12u, 5u, 0u}, {17u, 13u, 1u, 0u}, {14u, 13u, 1u, 0u}, {23u, 13u, 1u, 0u}, {0u, 0u, 0u, 0u}},
    {/* 26 PPP */ {0u, 0u, 0u, 0u}, {22u, 13u, 1u, 0u}, {25u, 13u, 1u, 0u}, {16u, 13u, 1u, 0u}, {17u, 13u, 1u, 0u}, {14u, 13u, 1u, 0u}, {23u, 13u, 1u, 0u}, {0u, 0u, 0u, 0u}},
};

uint8_t dtc3l_choose_state(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                           const real_t i_abc[3])
{
    /* from here on every vector is 0..18 and every state 0..26: the unchecked look-ups */
    return dtc3l_choose_state_unchecked(sv < NPC_N_VECTORS ? sv : 0u,
                                        prev_state < NPC_N_STATES ? prev_state : (uint8_t)NPC_STATE_OOO,
                                        np_dev_V, np_band_V, i_abc);
}

/* The zero state after @p prev_state (dtc3l_choose_state for the zero vector).
 * @p push0 true: @p push0_VA is np_current(first state of prev_state's
 * vector) x np_dev_V, already worked out by the caller (the NP look-ahead then
 * reuses it: the same product). */
static inline uint8_t choose_zero(uint8_t prev_state, real_t np_dev_V, real_t np_band_V, const real_t i_abc[3],
                                  bool push0, real_t push0_VA)
{
    /* From NNN (PPP) the P-type (N-type) small states are a P<->N step away.
     * When the neutral point needs attention, pick the zero state on the way
     * to the balancing state of the small vector just used (the likely next
     * one), so that state stays reachable. */
    if (!(num_abs(np_dev_V) > num_mul(NP_LOOKAHEAD_FRACTION, np_band_V)))
        return zero_after[prev_state];
    uint8_t prev_sv = npc_state_sv_unchecked(prev_state);
    if (npc_sv_class_unchecked(prev_sv) != NPC_CLASS_SMALL)
        return num_abs(np_dev_V) > np_band_V ? (uint8_t)NPC_STATE_OOO : zero_after[prev_state];
    if (!push0)
        push0_VA = num_mul(npc_np_current_unchecked(npc_sv_state_list[prev_sv][0], i_abc), np_dev_V);
    return zero_toward[prev_state][push0_VA <= R(0.0) ? 0 : 1];
}

/* dtc3l_choose_state_unchecked; for a small vector outside the NP band whose
 * first state is within reach, also np_current(first state) x np_dev_V
 * (*push0_VA, *push0 true; otherwise *push0 false). */
static inline uint8_t choose_state(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                                   const real_t i_abc[3], bool *push0_known, real_t *push0_VA)
{
    const uint8_t *st = npc_sv_state_list[sv]; /* read in place: no copy */
    npc_class cls = npc_sv_class_unchecked(sv);
    bool small = cls == NPC_CLASS_SMALL;
    bool np_out = num_abs(np_dev_V) > np_band_V;
    bool np_forced = small && np_out;
    *push0_known = false;

    /* Zero vector: NNN, OOO or PPP (choose_zero) */
    if (sv == 0u)
        return choose_zero(prev_state, np_dev_V, np_band_V, i_abc, false, R(0.0));
    /* Vectors with a single state (medium, large): nothing to choose. */
    if (cls == NPC_CLASS_MEDIUM || cls == NPC_CLASS_LARGE)
        return npc_pn_safe_unchecked(prev_state, st[0]); /* st[0] itself unless a leg would step P<->N */
    if (small) {
        const small_choice *e = &small_choice_of[prev_state][sv];
        /* Inside the band: the state with fewer commutations. Its P-type
         * state is its N-type one a level up in every leg, so from any state
         * their commutation counts differ by an odd number (three legs of
         * +-1 each): never a tie, so the NP preference never decides inside
         * the band and no NP current is needed here. Neither in reach: the
         * P-type state held P<->N-safe, in or out of the band. */
        unsigned reach = e->reach & (SMALL_FIRST_OK | SMALL_SECOND_OK);
        if (!np_forced || reach == 0u)
            return e->pick;
        /* Outside the band (np_forced): the balancing state first, then
         * fewer commutations; when the one taken pushes the link further
         * off, the other state held P<->N-safe if that one is small and
         * balances. */
        uint8_t c0 = st[0], c1 = st[1];
        real_t push; /* of e->pick */
        if (reach == (SMALL_FIRST_OK | SMALL_SECOND_OK)) {
            real_t push0 = num_mul(npc_np_current_unchecked(c0, i_abc), np_dev_V);
            real_t push1 = num_mul(npc_np_current_unchecked(c1, i_abc), np_dev_V);
            *push0_known = true;
            *push0_VA = push0;
            /* exactly one balances (push <= 0): that one, no fallback */
            if (push0 <= R(0.0)) {
                if (!(push1 <= R(0.0)))
                    return c0;
            } else if (push1 <= R(0.0)) {
                return c1;
            }
            push = e->pick == c0 ? push0 : push1;
        } else {
            push = num_mul(npc_np_current_unchecked(e->pick, i_abc), np_dev_V);
            *push0_known = reach == SMALL_FIRST_OK;
            *push0_VA = reach == SMALL_FIRST_OK ? push : R(0.0);
        }
        if (!(push > R(0.0)))
            return e->pick;
        if ((e->reach & SMALL_OTHER_SMALL) != 0u &&
            num_mul(npc_np_current_unchecked(e->other, i_abc), np_dev_V) < R(0.0))
            return e->other;
        return e->pick;
    }
    /* Every vector with more than one state is the zero vector or a small one,
     * both handled above; this keeps the function total. */
    return npc_pn_safe_unchecked(prev_state, st[0]);
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
