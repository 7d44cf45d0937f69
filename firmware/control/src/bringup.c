/**
 * @file bringup.c
 * @brief Bring-up levels 1 and 3: gate-test patterns and open-loop V/f (dtc/bringup.h).
 */
#include "dtc/bringup.h"

#include "dtc/npc.h"

hal_vector bringup_gate_pattern(real_t t_s)
{
    /* 12 steps: for each leg OOO, P, OOO, N (a P<->N step never occurs). */
    uint32_t step = (uint32_t)(t_s / BRINGUP_PATTERN_S) % 12u;
    hal_vector v = {{HAL_LEG_O, HAL_LEG_O, HAL_LEG_O}};
    uint32_t leg = step / 4u, phase = step % 4u;
    if (phase == 1u)
        v.leg[leg] = HAL_LEG_P;
    else if (phase == 3u)
        v.leg[leg] = HAL_LEG_N;
    return v;
}

hal_actuation bringup_vf(real_t theta_rad, real_t v_mag_V, real_t vc1_V, real_t vc2_V)
{
    real_t u[2] = {num_cos(theta_rad), num_sin(theta_rad)};
    uint8_t best = 13u; /* OOO */
    real_t best_p = R(0.0);
    for (uint8_t st = 0u; st < NPC_N_STATES; st++) {
        real_t v[2];
        npc_state_voltage(st, vc1_V, vc2_V, v);
        real_t p = num_mul(v[0], u[0]) + num_mul(v[1], u[1]);
        if (p > best_p) {
            best_p = p;
            best = st;
        }
    }
    hal_actuation act;
    npc_legs(best, &act.vector[0]);
    npc_legs(13u, &act.vector[1]);
    act.duty0 = best_p > R(0.0) ? num_sat(v_mag_V / best_p, R(0.0), R(1.0)) : R(0.0);
    return act;
}
