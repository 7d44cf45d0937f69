/**
 * @file inverter_model.c
 * @brief The stator voltage of one period of the NPC inverter, ideal or real
 *        (see dtc/inverter_model.h; the body is inverter_model_impl.h's, which
 *        the control step inlines).
 */
#include "dtc/inverter_model.h"

#include "inverter_model_impl.h"

uint8_t inverter_voltage(const inverter_period *p, const real_t level_V[3], const real_t i_A[3],
                         const inverter_consts *k, real_t v_ab[2])
{
    return inverter_voltage_inline(p, level_V, i_A, k, v_ab);
}
