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
 *   J domega_m/dt = Te - B omega_m - T_L - T_models  (T_L a plain constant, see plant.h;
 *                                                     T_models: load_model.c)
 * Inverting the inductance matrix: D = Ls Lr - Lm^2,
 *   i_s = (Lr psi_s - Lm psi_r) / D,  i_r = (Ls psi_r - Lm psi_s) / D.
 * Powers in abc terms are 1.5 times the alpha-beta dot products (no zero
 * sequence in an isolated star).
 * The derivative itself (plant_im_currents, plant_im_rhs) is inline in
 * plant_internal.h because the integrator calls it four times per step.
 *
 * Main-flux saturation (optional): the magnetising branch follows
 *   i_m = (psi_m / Lm0) (1 + (|psi_m| / psi_k)^n),   psi_m = Lm(psi_m) i_m,
 * so Lm(psi_m) = Lm0 / (1 + (|psi_m|/psi_k)^n): Lm0 at low flux, Lm0/2 at the
 * knee psi_k. Smooth (n >= 2), odd, strictly monotone; a generic "linear +
 * power" magnetising curve (no saturation data for the 10 hp motor), and
 * only the main flux saturates. With flux states the currents follow from
 *   psi_s = Lls i_s + psi_m,  psi_r = Llr i_r + psi_m,  i_m = i_s + i_r:
 * psi_m is parallel to a = psi_s/Lls + psi_r/Llr and its magnitude m solves
 *   F(m) = m (1/Lm0 + 1/Lls + 1/Llr) + (m/Lm0) (m/psi_k)^n - |a| = 0,
 * increasing and convex, so Newton from the linear solution (an upper bound)
 * converges monotonically. Te = 1.5 p (psi_s x i_s) holds unchanged. The
 * emf of a floating phase and the current clamp of the diode model use the
 * unsaturated inductances (approximate with saturation), and w_mag is the
 * linear formula (exact only without saturation).
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
    g->sat = m->Lm_sat_psi_Wb > 0.0;
    if (g->sat) {
        g->inv_Lls = 1.0 / m->Lls_H;
        g->inv_Llr = 1.0 / m->Llr_H;
        g->inv_Lm0 = 1.0 / m->Lm_H;
        g->inv_psik = 1.0 / m->Lm_sat_psi_Wb;
        g->sat_n = m->Lm_sat_exponent;
    }
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

void plant_im_currents_sat(const plant_seg *g, const double *x, double i_s[2], double i_r[2])
{
    double a0 = x[PX_PSA] * g->inv_Lls + x[PX_PRA] * g->inv_Llr;
    double a1 = x[PX_PSB] * g->inv_Lls + x[PX_PRB] * g->inv_Llr;
    double a = sqrt(a0 * a0 + a1 * a1);
    double c = g->inv_Lm0 + g->inv_Lls + g->inv_Llr;
    double m = a / c; /* the linear solution: F(m) >= 0 there */
    double pm0, pm1;
    int it;
    for (it = 0; it < 50 && m > 0.0; ++it) {
        double r = pow(m * g->inv_psik, g->sat_n);
        double f = m * c + m * g->inv_Lm0 * r - a;
        double df = c + g->inv_Lm0 * r * (1.0 + g->sat_n);
        double step = f / df;
        m -= step;
        if (!(fabs(step) > 1e-15 * m))
            break;
    }
    pm0 = a > 0.0 ? m * a0 / a : 0.0;
    pm1 = a > 0.0 ? m * a1 / a : 0.0;
    i_s[0] = (x[PX_PSA] - pm0) * g->inv_Lls;
    i_s[1] = (x[PX_PSB] - pm1) * g->inv_Lls;
    i_r[0] = (x[PX_PRA] - pm0) * g->inv_Llr;
    i_r[1] = (x[PX_PRB] - pm1) * g->inv_Llr;
}
