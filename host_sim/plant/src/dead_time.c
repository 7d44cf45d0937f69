/**
 * @file dead_time.c
 * @brief Dead time of the NPC legs: when each leg is blanked and between
 *        which two levels.
 *
 * The firmware (and the HAL) hand the plant P/O/N per leg and the duty split,
 * as the board's timers see them. The gate drivers then delay every turn-on
 * by the dead time: at a commutation edge of a leg from level a to an
 * adjacent level b (N<->O or O<->P), the outgoing device turns off at the
 * edge and the incoming one dead_time_s later. In between, the inner device
 * both states share stays on and the current picks the level through the
 * diodes (npc_inverter.c, codes PLANT_LEG_DEAD_NO / _OP): into the motor
 * (i > 0) the lower of a and b, out of the motor the upper one. So the edge
 * is delayed by the dead time when the current flows the "wrong" way for it
 * and is on time otherwise: per commutation pair the leg loses
 * sgn(i) (Vdc/2) dead_time_s of volt-seconds, the classic uncompensated
 * dead-time error.
 *
 * Edges are at the start of each applied vector (from the previously applied
 * one, also across periods), and a blanking interval that runs past the end
 * of a period continues into the next one (plant_state.dead_until_s). A
 * second edge of the same leg inside the blanking restarts it between the
 * new pair (a commutation shorter than the dead time never turns its
 * device on). A direct P<->N step (which the firmware never commands) blanks
 * all four devices: gates off for the dead time. Changes to or from gates off
 * are not delayed.
 */
#include "plant_internal.h"

void plant_dead_edge(plant_state *s, const uint8_t legs[3], double t_s)
{
    int k;
    if (!s->legs_valid)
        return;
    for (k = 0; k < 3; ++k) {
        unsigned a = s->legs_last[k], b = legs[k];
        if (a <= PLANT_LEG_P && b <= PLANT_LEG_P && a != b) {
            s->dead_until_s[k] = t_s + s->cfg.inverter.dead_time_s;
            s->dead_code[k] = (uint8_t)(a + b == 1u ? PLANT_LEG_DEAD_NO
                                                   : (a + b == 3u ? PLANT_LEG_DEAD_OP : PLANT_LEG_OFF));
        } else if (b > PLANT_LEG_P) {
            s->dead_until_s[k] = t_s; /* gates off ends any blanking */
        }
    }
}

double plant_dead_legs(const plant_state *s, const uint8_t cmd[3], double t_s, double t_end_s, uint8_t eff[3])
{
    double next = t_end_s;
    int k;
    for (k = 0; k < 3; ++k) {
        eff[k] = cmd[k];
        if (cmd[k] <= PLANT_LEG_P && s->dead_until_s[k] - t_s >= PLANT_MIN_SEGMENT_S) {
            eff[k] = s->dead_code[k];
            if (s->dead_until_s[k] < next)
                next = s->dead_until_s[k];
        }
    }
    /* No sliver of a segment after the blanking: it ends with the segment. */
    if (t_end_s - next < PLANT_MIN_SEGMENT_S)
        next = t_end_s;
    return next;
}
