/**
 * @file induction_machine.c
 * @brief Fifth-order induction machine in the stationary frame, flux states.
 *
 * States: stator flux psi_s and stator-referred rotor flux psi_r (alpha, beta),
 * mechanical speed omega_m (and the angle, which feeds nothing back).
 *   psi_s = Ls i_s + Lm i_r,  psi_r = Lm i_s + Lr i_r,  Ls = Lls + Lm, Lr = Llr + Lm
 *   dpsi_s/dt = v_s - Rs i_s
 *   dpsi_r/dt = -Rr i_r + j p omega_m psi_r         (squirrel cage, stationary frame)
 *   Te = 1.5 p (psi_s x i_s)                         (amplitude-invariant Clarke)
 *   J domega_m/dt = Te - B omega_m - T_L             (T_L a plain constant, see plant.h)
 * Inverting the inductance matrix: D = Ls Lr - Lm^2,
 *   i_s = (Lr psi_s - Lm psi_r) / D,  i_r = (Ls psi_r - Lm psi_s) / D.
 * Powers in abc terms are 1.5 times the alpha-beta dot products (no zero
 * sequence in an isolated star).
 * The derivative itself (plant_im_currents, plant_im_rhs) is inline in
 * plant_internal.h because the integrator calls it four times per step.
 */
#include "plant_internal.h"

void plant_im_coeffs(const plant_motor_params *m, double t_load_Nm, plant_seg *g)
{
    double Ls = m->Lls_H + m->Lm_H;
    double Lr = m->Llr_H + m->Lm_H;
    double D = Ls * Lr - m->Lm_H * m->Lm_H;
    g->cLr = Lr / D;
    g->cLm = m->Lm_H / D;
    g->cLs = Ls / D;
    g->lm_lr = m->Lm_H / Lr;
    g->d_lr = D / Lr;
    g->Rs = m->Rs_ohm;
    g->Rr = m->Rr_ohm;
    g->p = (double)m->pole_pairs;
    g->inv_J = 1.0 / m->J_kgm2;
    g->B = m->B_Nms;
    g->TL = t_load_Nm;
}

double plant_im_torque(const plant_seg *g, const double *x, const double i_s[2])
{
    return 1.5 * g->p * (x[PX_PSA] * i_s[1] - x[PX_PSB] * i_s[0]);
}

void plant_im_emf(const plant_seg *g, const double *x, const double i_r[2], double e[2])
{
    double pw = g->p * x[PX_W];
    e[0] = g->lm_lr * (-g->Rr * i_r[0] - pw * x[PX_PRB]);
    e[1] = g->lm_lr * (-g->Rr * i_r[1] + pw * x[PX_PRA]);
}

double plant_im_wmag(const double *x, const double i_s[2], const double i_r[2])
{
    return 0.75 * (x[PX_PSA] * i_s[0] + x[PX_PSB] * i_s[1] +
                   x[PX_PRA] * i_r[0] + x[PX_PRB] * i_r[1]);
}
