/**
 * @file speed_nominal.c
 * @brief Nominal speed controller: paper eq. 6 with the uncertainty taken as
 *        zero, U = B_n^-1 [dX_d/dt - A_n X + K_x e], which on the nominal
 *        plant gives de/dt = -K_x e (eq. 7). With A_n = -B/J and
 *        B_n = 1/J: U = J (dX_d/dt + K_x e) + B X.
 */
#include "dtc/speed_ctl.h"

void speed_nominal_step(const nominal_cfg *cfg, const motor_model *m, real_t te_max_Nm,
                        const speed_in *in, speed_out *out)
{
    real_t x = in->omega_est_rad_s;
    real_t e = in->omega_ref_rad_s - x;
    real_t acc = num_mac(cfg->k_x, e, in->domega_ref_rad_s2); /* rad/s^2 */
    real_t u = num_mac(m->J_kgm2, acc, num_mul(m->B_Nms, x));
    out->te_ref_Nm = num_limit(u, te_max_Nm);
    out->eps_hat = R(0.0);
    out->w_norm = R(0.0);
    out->zeta_bar = R(0.0);
}
