/**
 * @file dtc3l_vectors.c
 * @brief The 27 switching states and 19 space vectors of the three-level NPC
 *        inverter: leg codes, voltages from the measured capacitor voltages,
 *        neutral-point current, and the P<->N step rule.
 */
#include "dtc/dtc3l.h"

/* Space vector of each state (see dtc3l.h for the numbering). Derived from
 * the leg voltages +vc1 / 0 / -vc2 and the amplitude-invariant Clarke
 * transform; e.g. PON (21): (E, 0, -E) -> E (1 + j/sqrt3) = medium at 30 deg. */
static const uint8_t state_sv[DTC3L_N_STATES] = {
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
static const uint8_t sv_states[DTC3L_N_VECTORS][3] = {
    {13u, 0u, 26u},                                                  /* zero: OOO, NNN, PPP */
    {22u, 9u, 0xFFu}, {25u, 12u, 0xFFu}, {16u, 3u, 0xFFu},           /* small 0, 60, 120 */
    {17u, 4u, 0xFFu}, {14u, 1u, 0xFFu}, {23u, 10u, 0xFFu},           /* small 180, 240, 300 */
    {21u, 0xFFu, 0xFFu}, {15u, 0xFFu, 0xFFu}, {7u, 0xFFu, 0xFFu},    /* medium 30, 90, 150 */
    {5u, 0xFFu, 0xFFu}, {11u, 0xFFu, 0xFFu}, {19u, 0xFFu, 0xFFu},    /* medium 210, 270, 330 */
    {18u, 0xFFu, 0xFFu}, {24u, 0xFFu, 0xFFu}, {6u, 0xFFu, 0xFFu},    /* large 0, 60, 120 */
    {8u, 0xFFu, 0xFFu}, {2u, 0xFFu, 0xFFu}, {20u, 0xFFu, 0xFFu},     /* large 180, 240, 300 */
};

static inline uint8_t leg_of(uint8_t state, unsigned k)
{
    static const uint8_t div[3] = {9u, 3u, 1u};
    return (uint8_t)((state / div[k]) % 3u);
}

void dtc3l_legs(uint8_t state, hal_vector *v)
{
    if (state >= DTC3L_N_STATES)
        state = DTC3L_STATE_OOO;
    for (unsigned k = 0; k < 3u; k++)
        v->leg[k] = leg_of(state, k);
}

uint8_t dtc3l_state_of(const hal_vector *v)
{
    if (v->leg[0] > HAL_LEG_P || v->leg[1] > HAL_LEG_P || v->leg[2] > HAL_LEG_P)
        return 0xFFu;
    return (uint8_t)(v->leg[0] * 9u + v->leg[1] * 3u + v->leg[2]);
}

uint8_t dtc3l_state_sv(uint8_t state) { return state < DTC3L_N_STATES ? state_sv[state] : 0u; }

dtc3l_class dtc3l_sv_class(uint8_t sv)
{
    if (sv == 0u || sv >= DTC3L_N_VECTORS)
        return DTC3L_CLASS_ZERO;
    if (sv <= 6u)
        return DTC3L_CLASS_SMALL;
    return sv <= 12u ? DTC3L_CLASS_MEDIUM : DTC3L_CLASS_LARGE;
}

uint8_t dtc3l_sv_states(uint8_t sv, uint8_t states[3])
{
    if (sv >= DTC3L_N_VECTORS)
        sv = 0u;
    uint8_t n = 0u;
    for (unsigned i = 0; i < 3u; i++) {
        states[i] = sv_states[sv][i];
        if (states[i] != 0xFFu)
            n++;
    }
    return n;
}

void dtc3l_state_voltage(uint8_t state, real_t vc1_V, real_t vc2_V, real_t v_ab[2])
{
    real_t vleg[3];
    for (unsigned k = 0; k < 3u; k++) {
        uint8_t l = state < DTC3L_N_STATES ? leg_of(state, k) : (uint8_t)HAL_LEG_O;
        vleg[k] = l == HAL_LEG_P ? vc1_V : (l == HAL_LEG_N ? -vc2_V : R(0.0));
    }
    /* Clarke of the leg voltages: the common mode drops out, as in an isolated star. */
    v_ab[0] = num_mul(R(0.333333333), R(2.0) * vleg[0] - vleg[1] - vleg[2]);
    v_ab[1] = num_mul(NUM_INV_SQRT3, vleg[1] - vleg[2]);
}

real_t dtc3l_np_current(uint8_t state, const real_t i_abc[3])
{
    real_t i = R(0.0);
    if (state >= DTC3L_N_STATES)
        return i;
    for (unsigned k = 0; k < 3u; k++)
        if (leg_of(state, k) == HAL_LEG_O)
            i += i_abc[k];
    return i;
}

bool dtc3l_pn_step(uint8_t from, uint8_t to)
{
    if (from >= DTC3L_N_STATES || to >= DTC3L_N_STATES)
        return false;
    for (unsigned k = 0; k < 3u; k++) {
        int d = (int)leg_of(from, k) - (int)leg_of(to, k);
        if (d == 2 || d == -2)
            return true;
    }
    return false;
}

uint8_t dtc3l_leg_changes(uint8_t from, uint8_t to)
{
    uint8_t n = 0u;
    if (from >= DTC3L_N_STATES || to >= DTC3L_N_STATES)
        return 0u;
    for (unsigned k = 0; k < 3u; k++) {
        int d = (int)leg_of(from, k) - (int)leg_of(to, k);
        n = (uint8_t)(n + (uint8_t)(d < 0 ? -d : d));
    }
    return n;
}

uint8_t dtc3l_pn_safe(uint8_t from, uint8_t to)
{
    if (from >= DTC3L_N_STATES || to >= DTC3L_N_STATES)
        return DTC3L_STATE_OOO;
    static const uint8_t w[3] = {9u, 3u, 1u};
    uint8_t out = 0u;
    for (unsigned k = 0; k < 3u; k++) {
        uint8_t a = leg_of(from, k), b = leg_of(to, k);
        int d = (int)a - (int)b;
        uint8_t l = (d == 2 || d == -2) ? (uint8_t)HAL_LEG_O : b;
        out = (uint8_t)(out + l * w[k]);
    }
    return out;
}
