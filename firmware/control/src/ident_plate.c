/**
 * @file ident_plate.c
 * @brief First estimates from the rating plate (dtc/ident_plate.h).
 */
#include "dtc/ident_plate.h"

#include <stdbool.h>

/* Leakage reactance assumed for the estimates, per unit of the base
 * impedance (the Krause table's motors: 0.10..0.21). */
#define IDENT_PLATE_X_SIGMA_PU R(0.15)
/* The magnetising current is taken as at least this share of the rated
 * current (a plate whose power factor leaves less is implausible). */
#define IDENT_PLATE_I0_MIN_PU R(0.1)
#define IDENT_PLATE_P_MAX 12

static inline bool ident_plate_finite_pos(real_t x) { return x > R(0.0) && x - x == R(0.0); }

/* The pole pairs: the largest p whose synchronous speed 60 f / p is above the rated speed. */
static int ident_plate_pairs(const ident_plate *p)
{
    int best = 0;
    for (int k = 1; k <= IDENT_PLATE_P_MAX; k++)
        if (num_div(R(60.0) * p->f_Hz, (real_t)k) > p->speed_rpm)
            best = k;
    return best;
}

int ident_plate_check(const ident_plate *p)
{
    if (!(ident_plate_finite_pos(p->p_W) && ident_plate_finite_pos(p->v_ll_V) && ident_plate_finite_pos(p->i_A) &&
          ident_plate_finite_pos(p->f_Hz) && ident_plate_finite_pos(p->speed_rpm) && p->cos_phi >= R(0.3) &&
          p->cos_phi <= R(0.99)))
        return IDENT_PLATE_E_VALUE;
    if (ident_plate_pairs(p) == 0)
        return IDENT_PLATE_E_SPEED;
    return IDENT_PLATE_OK;
}

void ident_plate_estimate(const ident_plate *p, ident_plate_est *e)
{
    const real_t two_pi = R(2.0) * NUM_PI;
    real_t pp = (real_t)ident_plate_pairs(p);
    e->pole_pairs = pp;
    e->w_e_rad_s = num_mul(two_pi, p->f_Hz);
    e->w_m_rad_s = num_mul(p->speed_rpm, num_div(two_pi, R(60.0)));
    e->w_slip_rad_s = e->w_e_rad_s - num_mul(pp, e->w_m_rad_s);
    e->te_Nm = num_div(p->p_W, e->w_m_rad_s);
    real_t sqrt2 = num_sqrt(R(2.0));
    e->i_peak_A = num_mul(sqrt2, p->i_A);
    real_t v_ph = num_mul(p->v_ll_V, NUM_INV_SQRT3);
    e->v_peak_V = num_mul(sqrt2, v_ph);
    e->psi_s_Wb = num_div(e->v_peak_V, e->w_e_rad_s);
    e->z_base_ohm = num_div(v_ph, p->i_A);
    e->sigma_ls_H = num_div(num_mul(IDENT_PLATE_X_SIGMA_PU, e->z_base_ohm), e->w_e_rad_s);
    real_t sin_phi = num_sqrt(R(1.0) - num_mul(p->cos_phi, p->cos_phi));
    real_t i0_pu = sin_phi - IDENT_PLATE_X_SIGMA_PU;
    if (i0_pu < IDENT_PLATE_I0_MIN_PU)
        i0_pu = IDENT_PLATE_I0_MIN_PU;
    e->i_mag_A = num_mul(i0_pu, e->i_peak_A);
    /* the rated slip of the current model: w_slip = iq / (id Tr), iq ~ cos phi, id ~ i0 (per unit) */
    e->tr_s = num_div(num_div(p->cos_phi, i0_pu), e->w_slip_rad_s);
}
