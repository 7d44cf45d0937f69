/**
 * @file npc_states.c
 * @brief The tables of dtc/npc.h: per state its leg codes, neutral-point
 *        legs, space vector, and per pair of states the P<->N steps, the
 *        commutations and the P<->N-safe state.
 *
 * The per-state and per-pair tables are written out by the preprocessor from
 * the leg rules (state = a*9 + b*3 + c; NPC_LEG_PN, NPC_LEG_SAFE; a leg at O
 * draws its phase current from the neutral point; a commutation is one level
 * step of one leg), so that they are constants in flash and cannot disagree
 * with the rules. Only the space vectors need the geometry of the voltages
 * and are written by hand.
 */
#include "dtc/npc.h"

#include <stddef.h>

/* npc_legs_pair_unchecked writes both vectors' six leg bytes as one word and one half-word */
_Static_assert(sizeof(hal_vector) == 3u && offsetof(hal_actuation, vector) == 0u, "hal_actuation: six leg bytes first");
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "npc_legs_pair_unchecked packs the leg codes little-endian"
#endif

_Static_assert(NPC_N == (unsigned)HAL_LEG_N && NPC_O == (unsigned)HAL_LEG_O && NPC_P == (unsigned)HAL_LEG_P,
               "the leg codes are hal_leg_state's");

/* Space vector of each state (see dtc/npc.h for the numbering). From the leg
 * voltages +vc1 / 0 / -vc2 and the amplitude-invariant Clarke transform; e.g.
 * PON (21): (E, 0, -E) -> E (1 + j/sqrt3) = medium at 30 deg. */
const uint8_t npc_state_sv_of[NPC_N_STATES] = {
    0u,  /*  0 NNN */ 5u,  /*  1 NNO */ 17u, /*  2 NNP */
    3u,  /*  3 NON */ 4u,  /*  4 NOO */ 10u, /*  5 NOP */
    15u, /*  6 NPN */ 9u,  /*  7 NPO */ 16u, /*  8 NPP */
    1u,  /*  9 ONN */ 6u,  /* 10 ONO */ 11u, /* 11 ONP */
    2u,  /* 12 OON */ 0u,  /* 13 OOO */ 5u,  /* 14 OOP */
    8u,  /* 15 OPN */ 3u,  /* 16 OPO */ 4u,  /* 17 OPP */
    13u, /* 18 PNN */ 12u, /* 19 PNO */ 18u, /* 20 PNP */
    7u,  /* 21 PON */ 1u,  /* 22 POO */ 6u,  /* 23 POP */
    14u, /* 24 PPN */ 2u,  /* 25 PPO */ 0u,  /* 26 PPP */
};

/* States of each space vector, preferred first; 0xFF pads. Small vectors list
 * the P-type state (more legs at P than at N) first. */
const uint8_t npc_sv_state_list[NPC_N_VECTORS][3] = {
    {13u, 0u, 26u},                                                  /* zero: OOO, NNN, PPP */
    {22u, 9u, 0xFFu}, {25u, 12u, 0xFFu}, {16u, 3u, 0xFFu},           /* small 0, 60, 120 */
    {17u, 4u, 0xFFu}, {14u, 1u, 0xFFu}, {23u, 10u, 0xFFu},           /* small 180, 240, 300 */
    {21u, 0xFFu, 0xFFu}, {15u, 0xFFu, 0xFFu}, {7u, 0xFFu, 0xFFu},    /* medium 30, 90, 150 */
    {5u, 0xFFu, 0xFFu}, {11u, 0xFFu, 0xFFu}, {19u, 0xFFu, 0xFFu},    /* medium 210, 270, 330 */
    {18u, 0xFFu, 0xFFu}, {24u, 0xFFu, 0xFFu}, {6u, 0xFFu, 0xFFu},    /* large 0, 60, 120 */
    {8u, 0xFFu, 0xFFu}, {2u, 0xFFu, 0xFFu}, {20u, 0xFFu, 0xFFu},     /* large 180, 240, 300 */
};

/* Class of each space vector: zero, six small, six medium, six large. */
const uint8_t npc_sv_class_of[NPC_N_VECTORS] = {
    (uint8_t)NPC_CLASS_ZERO,
    (uint8_t)NPC_CLASS_SMALL,  (uint8_t)NPC_CLASS_SMALL,  (uint8_t)NPC_CLASS_SMALL,
    (uint8_t)NPC_CLASS_SMALL,  (uint8_t)NPC_CLASS_SMALL,  (uint8_t)NPC_CLASS_SMALL,
    (uint8_t)NPC_CLASS_MEDIUM, (uint8_t)NPC_CLASS_MEDIUM, (uint8_t)NPC_CLASS_MEDIUM,
    (uint8_t)NPC_CLASS_MEDIUM, (uint8_t)NPC_CLASS_MEDIUM, (uint8_t)NPC_CLASS_MEDIUM,
    (uint8_t)NPC_CLASS_LARGE,  (uint8_t)NPC_CLASS_LARGE,  (uint8_t)NPC_CLASS_LARGE,
    (uint8_t)NPC_CLASS_LARGE,  (uint8_t)NPC_CLASS_LARGE,  (uint8_t)NPC_CLASS_LARGE,
};

/* ---------------------------------------------------- from the leg rules */

/* leg codes of state s, and the state of leg codes a, b, c */
#define LEG_A(s) ((s) / 9u)
#define LEG_B(s) ((s) / 3u % 3u)
#define LEG_C(s) ((s) % 3u)
#define STATE_OF(a, b, c) (9u * (a) + 3u * (b) + (c))

/* F(x, s) for every state s, joined by OP (two copies: a row macro that
 * itself runs over the states is not expanded again inside the first) */
#define EACH_STATE(F, x, OP)                                                                                 \
    F(x, 0u) OP F(x, 1u) OP F(x, 2u) OP F(x, 3u) OP F(x, 4u) OP F(x, 5u) OP F(x, 6u) OP F(x, 7u) OP F(x, 8u) \
    OP F(x, 9u) OP F(x, 10u) OP F(x, 11u) OP F(x, 12u) OP F(x, 13u) OP F(x, 14u) OP F(x, 15u) OP F(x, 16u)   \
    OP F(x, 17u) OP F(x, 18u) OP F(x, 19u) OP F(x, 20u) OP F(x, 21u) OP F(x, 22u) OP F(x, 23u) OP F(x, 24u)  \
    OP F(x, 25u) OP F(x, 26u)
#define EACH_ROW(F)                                                                                          \
    F(0u), F(1u), F(2u), F(3u), F(4u), F(5u), F(6u), F(7u), F(8u), F(9u), F(10u), F(11u), F(12u), F(13u),    \
    F(14u), F(15u), F(16u), F(17u), F(18u), F(19u), F(20u), F(21u), F(22u), F(23u), F(24u), F(25u), F(26u)
#define COMMA ,

#define LEGS(s) {{(uint8_t)LEG_A(s), (uint8_t)LEG_B(s), (uint8_t)LEG_C(s)}}
const hal_vector npc_state_legs[NPC_N_STATES] = {EACH_ROW(LEGS)};

/* a state's three leg bytes in one load (npc_legs_pair_unchecked) */
#define PACKED(s) (LEG_A(s) | LEG_B(s) << 8 | LEG_C(s) << 16)
const uint32_t npc_state_legs_packed[NPC_N_STATES] = {EACH_ROW(PACKED)};

#define AT_O(leg) ((leg) == NPC_O ? R(1.0) : R(0.0))
#define NP_LEGS(s) {AT_O(LEG_A(s)), AT_O(LEG_B(s)), AT_O(LEG_C(s))}
const real_t npc_np_legs[NPC_N_STATES][3] = {EACH_ROW(NP_LEGS)};

/* from -> to steps some leg P<->N */
#define PN_STATES(f, t) \
    (NPC_LEG_PN(LEG_A(f), LEG_A(t)) || NPC_LEG_PN(LEG_B(f), LEG_B(t)) || NPC_LEG_PN(LEG_C(f), LEG_C(t)))
#define PN_BIT(f, t) (PN_STATES(f, t) ? 1u << (t) : 0u)
#define PN_MASK(f) (EACH_STATE(PN_BIT, f, |))
const uint32_t npc_pn_step_mask[NPC_N_STATES] = {EACH_ROW(PN_MASK)};

/* commutations: the level steps of the three legs */
#define STEPS(a, b) ((a) > (b) ? (a) - (b) : (b) - (a))
#define CHANGES(f, t) (uint8_t)(STEPS(LEG_A(f), LEG_A(t)) + STEPS(LEG_B(f), LEG_B(t)) + STEPS(LEG_C(f), LEG_C(t)))
#define CHANGES_ROW(f) {EACH_STATE(CHANGES, f, COMMA)}
const uint8_t npc_changes[NPC_N_STATES][NPC_N_STATES] = {EACH_ROW(CHANGES_ROW)};

/* to with each leg that would step P<->N from `from` held at O */
#define SAFE(f, t) \
    (uint8_t)STATE_OF(NPC_LEG_SAFE(LEG_A(f), LEG_A(t)), NPC_LEG_SAFE(LEG_B(f), LEG_B(t)), NPC_LEG_SAFE(LEG_C(f), LEG_C(t)))
#define SAFE_ROW(f) {EACH_STATE(SAFE, f, COMMA)}
const uint8_t npc_pn_safe_to[NPC_N_STATES][NPC_N_STATES] = {EACH_ROW(SAFE_ROW)};

/* the rules' helpers stay in this file (the target compiles the layer as one unit) */
#undef LEG_A
#undef LEG_B
#undef LEG_C
#undef STATE_OF
#undef EACH_STATE
#undef EACH_ROW
#undef COMMA
#undef LEGS
#undef PACKED
#undef AT_O
#undef NP_LEGS
#undef PN_STATES
#undef PN_BIT
#undef PN_MASK
#undef STEPS
#undef CHANGES
#undef CHANGES_ROW
#undef SAFE
#undef SAFE_ROW
