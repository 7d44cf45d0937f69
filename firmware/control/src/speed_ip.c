/**
 * @file speed_ip.c
 * @brief IP speed controller (paper eq. 1-3): integral of the error,
 *        proportional on the measured speed, so the closed loop has no zero.
 *
 * Discretisation: forward-Euler integrator, integ_k+1 = integ_k + ki e_k T.
 * At 200 us and wn of some tens of rad/s (wn T < 0.01) the discrete poles
 * are within 1 % of the continuous design.
 *
 * Anti-windup: conditional integration. While the command is limited and
 * the error would drive it further into the limit, the integrator is frozen;
 * as the speed rises the -kp X term then pulls the command out of the limit
 * by itself, so a saturated start ends with a small, bounded overshoot
 * instead of the long overshoot of a wound-up integrator.
 */
#include "dtc/speed_ctl.h"

void speed_ip_bumpless(ip_state *s, const ip_cfg *cfg, real_t te_now_Nm, real_t omega_rad_s)
{
    /* Te* = integ - kp X  =>  integ = Te* + kp X. */
    s->integ_Nm = num_mac(cfg->kp, omega_rad_s, te_now_Nm);
}

void speed_ip_step(ip_state *s, const ip_cfg *cfg, const motor_model *m, real_t te_max_Nm,
                   real_t dt_s, const speed_in *in, speed_out *out)
{
    (void)m; /* the gains already hold J and B (eq. 3) */
    real_t x = in->omega_est_rad_s;
    real_t e = in->omega_ref_rad_s - x;
    real_t p = -num_mul(cfg->kp, x); /* everything but the integral */

    real_t integ_new = num_mac(num_mul(cfg->ki, dt_s), e, s->integ_Nm);
    real_t te_u = integ_new + p;
    /* Freeze the integrator only in the direction that winds it up. */
    if ((te_u > te_max_Nm && e > R(0.0)) || (te_u < -te_max_Nm && e < R(0.0)))
        integ_new = s->integ_Nm;
    /* Hard bound: the integral never needs to exceed what puts the output
     * at the limit from the other side, whatever the history. */
    real_t bound = te_max_Nm + num_abs(p);
    s->integ_Nm = num_limit(integ_new, bound);

    out->te_ref_Nm = num_limit(s->integ_Nm + p, te_max_Nm);
    out->eps_hat = R(0.0);
    out->w_norm = R(0.0);
    out->zeta_bar = R(0.0);
}
