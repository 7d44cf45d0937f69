/**
 * @file dtc3l_ripple.c
 * @brief Torque slopes and band-edge timing for the low-speed ripple reduction.
 *
 * Over one period the torque under a fixed vector is close to a straight line
 * whose slope is dTe/dt = dte0 + dte_dv . v (linear in the stator voltage,
 * from the observer model at the predicted state). The time at which that line
 * meets a band edge gives the duty of the vector.
 */
#include "dtc/dtc3l.h"

real_t dtc3l_edge_fraction(real_t te_Nm, real_t slope_Nm_s, real_t edge_Nm, real_t period_s)
{
    real_t gap = edge_Nm - te_Nm;
    real_t reach = num_mul(slope_Nm_s, period_s);
    /* at the edge now */
    if (gap == R(0.0))
        return R(0.0);
    /* standing still, moving away (or already beyond it), or not getting there
     * within the period; the comparator deals with a torque beyond an edge */
    if (num_mul(gap, reach) <= R(0.0) || num_abs(gap) >= num_abs(reach))
        return R(2.0);
    return num_div(gap, reach);
}

real_t dtc3l_state_slope(const dtc3l_in *in, uint8_t state)
{
    real_t v[2];
    dtc3l_state_voltage(state, in->vc1_V, in->vc2_V, v);
    return in->dte0_Nm_s + num_mul(in->dte_dv[0], v[0]) + num_mul(in->dte_dv[1], v[1]);
}
