/**
 * @file load_model.c
 * @brief Shaft loads besides the constant torque: Coulomb (dry) friction,
 *        extra viscous friction and a fan/pump load T = k w |w|.
 *
 * All three follow the sign of the speed (they only brake), unlike the
 * constant load of plant_state.t_load_Nm, which is active. The sign function
 * of the Coulomb term is discontinuous at w = 0; rather than smoothing it
 * (a stiff slope RK4 cannot take at 40 us), its direction is fixed for each
 * step (plant_load_decide), a zero crossing is clamped to 0 (plant_load_stop),
 * and at w = 0 the friction balances the other torques up to its level, so
 * every RK4 stage of a stuck rotor sees dw/dt = 0 exactly.
 */
#include <stddef.h>

#include "plant_internal.h"

void plant_load_coeffs(const plant_load_params *l, plant_seg *g)
{
    g->Tc = l->coulomb_Nm;
    g->Bv = l->viscous_Nms;
    g->kf = l->fan_Nms2;
    /* Only a configured model takes the extra terms: the default runs keep
     * exactly the arithmetic they always had. */
    g->load_ext = g->Tc != 0.0 || g->Bv != 0.0 || g->kf != 0.0;
}

void plant_load_decide(plant_seg *g, const double *x)
{
    double w = x[PX_W];
    if (w > 0.0) {
        g->coul_dir = 1;
    } else if (w < 0.0) {
        g->coul_dir = -1;
    } else {
        double i_s[2], i_r[2], t_drive;
        plant_im_currents(g, x, i_s, i_r);
        t_drive = plant_im_torque(g, x, i_s) - g->TL;
        g->coul_dir = t_drive > g->Tc ? 1 : (t_drive < -g->Tc ? -1 : 0);
    }
}

void plant_load_stop(const plant_seg *g, double *x)
{
    if (g->Tc > 0.0 && g->coul_dir != 0 && (double)g->coul_dir * x[PX_W] <= 0.0)
        x[PX_W] = 0.0;
}

double plant_load_torque(const plant_state *s, double omega_m_rad_s)
{
    const plant_load_params *l;
    double w = omega_m_rad_s, sg;
    if (s == NULL)
        return 0.0;
    l = &s->cfg.load;
    sg = w > 0.0 ? 1.0 : (w < 0.0 ? -1.0 : 0.0);
    return s->t_load_Nm + l->coulomb_Nm * sg + l->viscous_Nms * w + l->fan_Nms2 * w * fabs(w);
}
