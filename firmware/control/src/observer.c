/**
 * @file observer.c
 * @brief Adaptive full-order flux observer (Kubota) with speed and Rs adaptation.
 *
 * The 4x4 real model is a 2x2 complex one (every 2x2 block is a + j b), so the
 * code works on complex pairs [re, im]. See observer.h for the equations and
 * the discretisation.
 */
#include "dtc/observer.h"

#include <stdbool.h>

/* ---------------------------------------------------------- complex helpers */

/* Im(conj(a) b) = a x b: the planar cross product (one rounding fewer fused). */
static inline real_t ccross(const real_t a[2], const real_t b[2])
{
    return num_mac(a[0], b[1], -num_mul(a[1], b[0]));
}

/* The model matrix at one operating point: a11 real, a12 = a12r + j a12i =
 * c (1/Tr - j omega), a21 = Lm/Tr real, a22 = a22r + j a22i = -1/Tr + j omega. */
typedef struct {
    real_t a11;
    real_t a12r, a12i;
    real_t a21;
    real_t a22r, a22i;
} model_matrix;

/* The terms that depend on Rs alone: the model's a11, the real parts of the
 * Kubota gains (observer_gain) and kt (a11 - 1/Tr), the torque slope's
 * (observer_step). */
typedef struct {
    real_t a11;
    real_t g_is0;
    real_t g_psi0;
    real_t kt_a11_tr;
} rs_terms;

static void rs_terms_at(const observer_model *m, real_t rs_ohm, rs_terms *t)
{
    real_t ar11 = -num_mac(rs_ohm, m->b, m->a_r);
    real_t ar22 = -m->inv_tr;
    /* Kubota: trace and determinant of A + G C are k and k^2 times those of A. */
    t->a11 = ar11;
    t->g_is0 = num_mul(m->gain_k1, ar11 + ar22);
    t->g_psi0 = num_mac(m->gain_k21, num_mac(m->inv_c, ar11, m->lm_tr), -num_mul(m->gain_inv_c_k1, ar11 + ar22));
    t->kt_a11_tr = num_mul(m->kt, ar11 + ar22);
}

/* The model matrix at speed omega_e with the Rs term a11 (rs_terms). */
static void model_matrix_with(const observer_model *m, real_t a11, real_t omega_e, model_matrix *a)
{
    a->a11 = a11;
    a->a12r = m->c_inv_tr;
    a->a12i = -num_mul(m->c, omega_e);
    a->a21 = m->lm_tr;
    a->a22r = -m->inv_tr;
    a->a22i = omega_e;
}

/* out = A x + add, x = [is (2), psi_r (2)]: each row one product and two
 * fused multiply-adds onto the addend. */
static inline void model_apply_add(const model_matrix *a, const real_t x[4], const real_t add[4], real_t out[4])
{
    real_t o0 = num_mac(a->a11, x[0], num_mac(a->a12r, x[2], num_mac(-a->a12i, x[3], add[0])));
    real_t o1 = num_mac(a->a11, x[1], num_mac(a->a12r, x[3], num_mac(a->a12i, x[2], add[1])));
    real_t o2 = num_mac(a->a21, x[0], num_mac(a->a22r, x[2], num_mac(-a->a22i, x[3], add[2])));
    real_t o3 = num_mac(a->a21, x[1], num_mac(a->a22r, x[3], num_mac(a->a22i, x[2], add[3])));
    out[0] = o0;
    out[1] = o1;
    out[2] = o2;
    out[3] = o3;
}

/* out = A x */
static inline void model_apply(const model_matrix *a, const real_t x[4], real_t out[4])
{
    real_t o0 = num_mac(a->a11, x[0], num_mac(a->a12r, x[2], num_mul(-a->a12i, x[3])));
    real_t o1 = num_mac(a->a11, x[1], num_mac(a->a12r, x[3], num_mul(a->a12i, x[2])));
    real_t o2 = num_mac(a->a21, x[0], num_mac(a->a22r, x[2], num_mul(-a->a22i, x[3])));
    real_t o3 = num_mac(a->a21, x[1], num_mac(a->a22r, x[3], num_mul(a->a22i, x[2])));
    out[0] = o0;
    out[1] = o1;
    out[2] = o2;
    out[3] = o3;
}

/* e' = e exp(-j phi), phi = sgn(omega) angle shape(|omega| / speed) below
 * speed (observer.h), only while the drive brakes against the rotation: the
 * estimated torque AND the torque command oppose the estimated speed. The
 * command makes the test robust while the observer converges (a flying start
 * motors: the estimate's torque sign is noise then, the command's is not).
 * shape: REGEN_SHAPE_AT_ZERO at standstill, rising (REGEN_RISE) to 1 at 0.2,
 * 1 up to REGEN_PLATEAU_HI, then down to 0 at speed. Chosen on the capability
 * sweep (docs/envelope.md section 6): the plateau holds rated regenerating
 * torque at 1.5-4 Hz of stator frequency (100-200 rpm; a linear fade
 * from 1 rad gave 0.6-0.8 rad there and the shaft ran away); the smaller
 * angle near standstill (0.56 rad at 0, 0.82 rad at 30 rpm) keeps the 30 rpm
 * points from the bias a large rotation gives where the stator frequency is
 * near zero (0.7 rad at 0 held two of them 0.4-0.5 rpm outside 5 rpm 2.5 s
 * after the load; held longer they drift anyway, docs/envelope.md). cos
 * and sin by their Taylor series to the 4th and 5th power: |phi| <= 1.5 rad
 * keeps the error below 0.1 % of the rotation, and only + and x keep the host
 * and target results bit-identical. */
#define REGEN_MIN_NM R(2.0)        /* below this the sign of a torque is noise */
#define REGEN_SHAPE_AT_ZERO R(0.4) /* shape at standstill */
#define REGEN_RISE R(3.0)          /* shape per unit of |omega|/speed below the plateau: 1 at 0.2 */
#define REGEN_PLATEAU_HI R(0.45)   /* end of the plateau, fraction of speed */
#define REGEN_FALL R(1.81818182)   /* 1 / (1 - REGEN_PLATEAU_HI): 0 at speed */
/* With the flux lowered so that the stator frequency opposes the rotation
 * (observer.regen_low_flux): there the full angle pulls the estimate off. */
#define REGEN_LOW_FLUX_SCALE R(0.25)
/* cos and sin of the rotation by the series above */
static inline void rotation_of(real_t phi, real_t *c, real_t *sn)
{
    real_t p2 = num_mul(phi, phi);
    *c = R(1.0) - num_mul(p2, R(0.5) - num_mul(p2, R(0.0416666667)));
    *sn = num_mul(phi, R(1.0) - num_mul(p2, R(0.166666667) - num_mul(p2, R(0.00833333333))));
}
static void rotate_for_regeneration(const observer_cfg *cfg, real_t omega_e, real_t te_Nm, real_t te_cmd_Nm,
                                    bool low_flux, const real_t e[2], real_t er[2])
{
    real_t w = num_abs(omega_e);
    bool regenerating = omega_e >= R(0.0) ? (te_Nm < -REGEN_MIN_NM && te_cmd_Nm < -REGEN_MIN_NM)
                                          : (te_Nm > REGEN_MIN_NM && te_cmd_Nm > REGEN_MIN_NM);
    if (!(cfg->regen_angle_rad > R(0.0)) || w >= cfg->regen_speed_rad_s || !regenerating) {
        er[0] = e[0];
        er[1] = e[1];
        return;
    }
    real_t x = num_mul(w, cfg->m.inv_regen_speed);
    real_t shape;
    bool plateau = false;
    if (x > REGEN_PLATEAU_HI)
        shape = num_mul(R(1.0) - x, REGEN_FALL);
    else {
        shape = num_mac(REGEN_RISE, x, REGEN_SHAPE_AT_ZERO);
        plateau = shape >= R(1.0); /* shape 1 */
    }
    real_t c, sn;
    if (plateau) {
        /* on the plateau the angle is the configuration's: its cos and sin were
         * derived once (observer_cfg_derive, the same operations, so the same bits;
         * sin(-phi) = -sin(phi) exactly in the series) */
        c = cfg->m.regen_cos[low_flux];
        sn = cfg->m.regen_sin[low_flux];
        if (omega_e < R(0.0))
            sn = -sn;
    } else {
        real_t phi = num_mul(cfg->regen_angle_rad, shape);
        if (low_flux)
            phi = num_mul(phi, REGEN_LOW_FLUX_SCALE);
        if (omega_e < R(0.0))
            phi = -phi;
        rotation_of(phi, &c, &sn);
    }
    er[0] = num_mac(c, e[0], num_mul(sn, e[1]));
    er[1] = num_mac(c, e[1], -num_mul(sn, e[0]));
}

/* The ZOH series' factors 1/4, 1/3, 1/2 (advance_with); the steps T x these
 * are derived once (observer_model.h_T). */
static const real_t k_zoh_inv_n[3] = {R(0.25), R(0.333333333), R(0.5)};

/* ------------------------------------------------------------------- API */

void observer_cfg_derive(observer_cfg *cfg, const motor_model *mm, real_t period_s)
{
    observer_model *m = &cfg->m;
    real_t ls = mm->Ls_H, lr = mm->Lr_H, lm = mm->Lm_H;
    real_t sigma = R(1.0) - num_div(num_mul(lm, lm), num_mul(ls, lr));
    real_t tr = num_div(lr, mm->Rr_ohm);

    m->sigma_ls = num_mul(sigma, ls);
    m->b = num_div(R(1.0), m->sigma_ls);
    m->a_r = num_div(R(1.0) - sigma, num_mul(sigma, tr));
    m->c = num_div(lm, num_mul(m->sigma_ls, lr));
    m->inv_c = num_div(R(1.0), m->c);
    m->inv_tr = num_div(R(1.0), tr);
    m->lm_tr = num_div(lm, tr);
    m->lm_lr = num_div(lm, lr);
    m->pole_pairs = mm->pole_pairs;
    m->inv_pole_pairs = num_div(R(1.0), mm->pole_pairs);
    m->kt = num_mul(num_mul(R(1.5), mm->pole_pairs), m->lm_lr);
    m->rs_nom_ohm = mm->Rs_ohm;
    /* Rs of a hot winding is at most about 1.5 x cold; allow 0.5..2 x. */
    m->rs_min_ohm = num_mul(R(0.5), mm->Rs_ohm);
    m->rs_max_ohm = num_mul(R(2.0), mm->Rs_ohm);
    m->period_s = period_s;
    m->inv_regen_speed = cfg->regen_speed_rad_s > R(0.0) ? num_div(R(1.0), cfg->regen_speed_rad_s) : R(0.0);
    if (cfg->speed_lpf_hz > R(0.0))
        m->lpf_alpha = R(1.0) - num_exp(-num_mul(num_mul(R(2.0) * NUM_PI, cfg->speed_lpf_hz), period_s));
    else
        m->lpf_alpha = R(1.0);
    /* The discretisation is accurate to omega T = 0.3 (240 Hz at 200 us);
     * the estimate is clamped there so a diverging adaptation stays bounded. */
    m->omega_max_rad_s = num_div(R(0.3), period_s);
    m->ki_speed_T = num_mul(cfg->ki_speed, period_s);
    m->ki_rs_T = num_mul(cfg->ki_rs, period_s);
    m->gain_k1 = cfg->k_gain - R(1.0);
    m->gain_k21 = num_mul(cfg->k_gain, cfg->k_gain) - R(1.0);
    m->gain_inv_c_k1 = num_mul(m->inv_c, m->gain_k1);
    m->kt_b = num_mul(m->kt, m->b);
    m->c_inv_tr = num_mul(m->c, m->inv_tr);
    for (int n = 0; n < 3; n++)
        m->h_T[n] = num_mul(period_s, k_zoh_inv_n[n]);
    rs_terms t;
    rs_terms_at(m, m->rs_nom_ohm, &t); /* the same operations as the step's, so the same bits */
    m->nom_a11 = t.a11;
    m->nom_g_is0 = t.g_is0;
    m->nom_g_psi0 = t.g_psi0;
    m->nom_kt_a11_tr = t.kt_a11_tr;
    m->one_minus_lpf_alpha = R(1.0) - m->lpf_alpha;
    /* the plateau's rotation: phi = angle x 1 (x REGEN_LOW_FLUX_SCALE), as rotate_for_regeneration */
    real_t phi = num_mul(cfg->regen_angle_rad, R(1.0));
    rotation_of(phi, &m->regen_cos[0], &m->regen_sin[0]);
    rotation_of(num_mul(phi, REGEN_LOW_FLUX_SCALE), &m->regen_cos[1], &m->regen_sin[1]);
    m->lpf_alpha_pp = num_mul(m->lpf_alpha, m->inv_pole_pairs);
}

void observer_init(observer *s, const observer_cfg *cfg)
{
    s->is_A[0] = s->is_A[1] = R(0.0);
    s->psi_r_Wb[0] = s->psi_r_Wb[1] = R(0.0);
    s->omega_e_rad_s = R(0.0);
    s->omega_int_rad_s = R(0.0);
    s->omega_m_filt_rad_s = R(0.0);
    s->rs_ohm = cfg->m.rs_nom_ohm;
    s->te_cmd_Nm = R(0.0);
    s->regen_low_flux = false;
}

void observer_gain(const observer_cfg *cfg, real_t omega_e, real_t rs_ohm, real_t g_is[2], real_t g_psi[2])
{
    const observer_model *m = &cfg->m;
    rs_terms t;
    rs_terms_at(m, rs_ohm, &t);
    g_is[0] = t.g_is0;
    g_is[1] = num_mul(m->gain_k1, omega_e);
    g_psi[0] = t.g_psi0;
    g_psi[1] = -num_mul(m->gain_inv_c_k1, omega_e);
}

/* One stage of the ZOH series: w_out = y + h A w_in (w_out may be w_in). Written out
 * three times (not a loop): the loop's register shuffles cost more than its body saves. */
static inline void zoh_stage(const model_matrix *a, real_t h, const real_t y[4], const real_t w_in[4],
                             real_t w_out[4])
{
    real_t aw[4];
    model_apply(a, w_in, aw);
    for (int i = 0; i < 4; i++)
        w_out[i] = num_mac(h, aw[i], y[i]);
}

/* observer_model_advance with the model matrix already built and the input
 * u = [u_is, u_psi]; @p h holds T x k_zoh_inv_n (observer_model.h_T) */
static void advance_with(const model_matrix *pa, real_t T, const real_t h[3], const real_t x[4], const real_t u[4],
                         real_t x_next[4])
{
    const model_matrix a = *pa;

    /* y = A x + u, the derivative at the period start */
    real_t y[4], w[4];
    model_apply_add(&a, x, u, y);

    /* x+ = x + T (y + T/2 A (y + T/3 A (y + T/4 A y))): the ZOH step of the
     * matrix exponential to fourth order, evaluated with four A products. */
    zoh_stage(&a, h[0], y, y, w);
    zoh_stage(&a, h[1], y, w, w);
    zoh_stage(&a, h[2], y, w, w);
    for (int i = 0; i < 4; i++)
        x_next[i] = num_mac(T, w[i], x[i]);
}

void observer_model_advance(const observer_model *m, real_t rs_ohm, real_t omega_e, const real_t x[4],
                            const real_t u_is[2], const real_t u_psi[2], real_t x_next[4])
{
    rs_terms t;
    rs_terms_at(m, rs_ohm, &t);
    model_matrix a;
    model_matrix_with(m, t.a11, omega_e, &a);
    const real_t u[4] = {u_is[0], u_is[1], u_psi[0], u_psi[1]};
    advance_with(&a, m->period_s, m->h_T, x, u, x_next);
}

/* restrict as ctl_step: state, configuration, inputs and outputs are distinct objects. */
void observer_step_ab(observer *restrict s, const observer_cfg *restrict cfg, real_t is_a_A, real_t is_b_A,
                      real_t v_a_V, real_t v_b_V, observer_out *restrict out)
{
    const real_t is_meas[2] = {is_a_A, is_b_A};
    const real_t v[2] = {v_a_V, v_b_V};
    const observer_model *m = &cfg->m;
    real_t T = m->period_s;
    const real_t p0 = s->psi_r_Wb[0], p1 = s->psi_r_Wb[1];

    /* current error at t_k */
    real_t e[2] = {is_meas[0] - s->is_A[0], is_meas[1] - s->is_A[1]};
    real_t te = num_mul(m->kt, ccross(s->psi_r_Wb, is_meas));

    /* speed adaptation: PI on e x psi_r_hat (a Lyapunov-derived law) */
    real_t er[2];
    rotate_for_regeneration(cfg, s->omega_e_rad_s, te, s->te_cmd_Nm, s->regen_low_flux, e, er);
    real_t eps = num_mac(er[0], p1, -num_mul(er[1], p0));
    s->omega_int_rad_s = num_limit(num_mac(m->ki_speed_T, eps, s->omega_int_rad_s), m->omega_max_rad_s);
    real_t omega_e = num_limit(num_mac(cfg->kp_speed, eps, s->omega_int_rad_s), m->omega_max_rad_s);
    s->omega_e_rad_s = omega_e;

    /* Rs adaptation: a winding hotter than modelled makes |is| smaller than |is_hat| */
    if (cfg->ki_rs > R(0.0)) {
        real_t ei = num_mac(e[0], s->is_A[0], num_mul(e[1], s->is_A[1]));
        s->rs_ohm = num_sat(num_mac(-m->ki_rs_T, ei, s->rs_ohm), m->rs_min_ohm, m->rs_max_ohm);
    }

    /* estimates at t_k: the measured current is fresher than is_hat */
    real_t ps0 = num_mac(m->sigma_ls, is_meas[0], num_mul(m->lm_lr, p0));
    real_t ps1 = num_mac(m->sigma_ls, is_meas[1], num_mul(m->lm_lr, p1));
    out->psi_s_Wb[0] = ps0;
    out->psi_s_Wb[1] = ps1;
    out->psi_s_abs_Wb = num_sqrt_nonneg(num_mac(ps0, ps0, num_mul(ps1, ps1))); /* a sum of squares */
    out->te_Nm = te;

    /* advance to t_{k+1}: u_is = b v - g_is e, u_psi = -g_psi e */
    /* the Rs terms: derived once for the nominal Rs (the usual case: no Rs
     * adaptation, identification kept the model's), else worked out here */
    rs_terms rt;
    if (s->rs_ohm == m->rs_nom_ohm) {
        rt.a11 = m->nom_a11;
        rt.g_is0 = m->nom_g_is0;
        rt.g_psi0 = m->nom_g_psi0;
        rt.kt_a11_tr = m->nom_kt_a11_tr;
    } else {
        rs_terms_at(m, s->rs_ohm, &rt);
    }
    /* g = g0 + j g1: -g e = (-g0 e0 + g1 e1) + j (-g0 e1 - g1 e0) */
    real_t g_is1 = num_mul(m->gain_k1, omega_e);
    real_t g_psi1 = -num_mul(m->gain_inv_c_k1, omega_e);
    real_t u[4];
    u[0] = num_mac(-rt.g_is0, e[0], num_mac(g_is1, e[1], num_mul(m->b, v[0])));
    u[1] = num_mac(-rt.g_is0, e[1], num_mac(-g_is1, e[0], num_mul(m->b, v[1])));
    u[2] = num_mac(-rt.g_psi0, e[0], num_mul(g_psi1, e[1]));
    u[3] = num_mac(-rt.g_psi0, e[1], -num_mul(g_psi1, e[0]));

    real_t x[4] = {s->is_A[0], s->is_A[1], p0, p1};
    real_t xn[4];
    model_matrix a;
    model_matrix_with(m, rt.a11, omega_e, &a);
    advance_with(&a, T, m->h_T, x, u, xn);
    s->is_A[0] = xn[0];
    s->is_A[1] = xn[1];
    s->psi_r_Wb[0] = xn[2];
    s->psi_r_Wb[1] = xn[3];

    /* prediction for t_{k+1} */
    out->is_pred_A[0] = xn[0];
    out->is_pred_A[1] = xn[1];
    out->psi_s_pred_Wb[0] = num_mac(m->sigma_ls, xn[0], num_mul(m->lm_lr, xn[2]));
    out->psi_s_pred_Wb[1] = num_mac(m->sigma_ls, xn[1], num_mul(m->lm_lr, xn[3]));
    real_t cr = ccross(&xn[2], &xn[0]); /* psi_r x is */
    out->te_pred_Nm = num_mul(m->kt, cr);

    /* torque slopes at t_{k+1}: dTe/dt = kt (dpsi_r/dt x is + psi_r x dis/dt),
     * linear in v: dte0 + dte_dv . v. With the model (observer.h) the zero-voltage
     * part is, in closed form (z = conj(psi_r) is: cr = Im z, psi_r x (a12 psi_r)
     * = a12i |psi_r|^2, (a22 psi_r) x is = a22r Im z - a22i Re z):
     *   dte0 = kt ((a11 - 1/Tr) cr - omega (Re z + c |psi_r|^2))
     *        = kt (a11 - 1/Tr) cr - kt omega (psi_r . (is + c psi_r)) */
    real_t q0 = num_mac(m->c, xn[2], xn[0]);
    real_t q1 = num_mac(m->c, xn[3], xn[1]);
    real_t pq = num_mac(xn[2], q0, num_mul(xn[3], q1));
    out->dte0_Nm_s = num_mac(rt.kt_a11_tr, cr, -num_mul(num_mul(m->kt, omega_e), pq));
    real_t ktb = m->kt_b;
    out->dte_dv[0] = -num_mul(ktb, xn[3]);
    out->dte_dv[1] = num_mul(ktb, xn[2]);

    /* filtered mechanical speed for the speed loop: (1 - alpha) s + (alpha / p) omega_e */
    s->omega_m_filt_rad_s = num_mac(m->lpf_alpha_pp, omega_e, num_mul(m->one_minus_lpf_alpha, s->omega_m_filt_rad_s));
    out->omega_m_rad_s = s->omega_m_filt_rad_s;
}
