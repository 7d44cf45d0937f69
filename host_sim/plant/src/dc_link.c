/**
 * @file dc_link.c
 * @brief Split DC link: a source V_dc with series resistance R charging two
 *        capacitors in series, loaded by the inverter's rail currents.
 *
 * Nodes: P (top of C1), O (between C1 and C2, the neutral point), N (bottom
 * of C2). vc1 = v_P - v_O, vc2 = v_O - v_N. The source pushes
 * i_src = (V_dc - vc1 - vc2) / R into P and takes it back from N. The
 * inverter draws i_P out of P, i_np out of O and i_N out of N (currents into
 * the motor, so i_P + i_np + i_N = 0 for an isolated star).
 *   KCL at P: i_src = i_C1 + i_P, with i_C1 = C1 dvc1/dt flowing P -> O
 *             => C1 dvc1/dt = i_src - i_P
 *   KCL at N: i_C2 (flowing O -> N, = C2 dvc2/dt) = i_src + i_N
 *             => C2 dvc2/dt = i_src + i_N
 *   KCL at O: i_C1 = i_C2 + i_np, consistent with the two above.
 * With C1 = C2 = C: d(vc1 - vc2)/dt = -(i_P + i_N)/C = i_np / C, so a current
 * drawn from the neutral point into the motor raises vc1 relative to vc2.
 */
#include "plant_internal.h"

void plant_dc_coeffs(const plant_dc_params *d, plant_seg *g)
{
    g->vdc = d->vdc_V;
    g->inv_r = 1.0 / d->r_src_ohm;
    g->inv_c1 = 1.0 / d->c1_F;
    g->inv_c2 = 1.0 / d->c2_F;
}

/* The derivative (the two equations derived above) is plant_dc_rhs, inline in
 * plant_internal.h because the integrator calls it four times per step. */
