/**
 * @file plant.c
 * @brief Plant life cycle and integration: one segment per applied vector,
 *        fixed-step RK4 inside each segment, truth snapshots, scheduled changes.
 *
 * Switching instants are segment boundaries, so the integrator never steps
 * across a discontinuity of the applied voltage. Inside a segment the step is
 * the largest h <= h_max_s that divides the segment evenly (and no longer
 * than the DC link's time constant, for stability). The energy
 * accumulators are extra RK4 states, so they are as accurate as the currents.
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "plant_internal.h"

int plant_init(plant_state *s, const plant_config *cfg)
{
    const char *what;
    int rc;
    if (s == NULL)
        return PLANT_EINVAL;
    rc = plant_check_config(cfg, &what);
    if (rc != 0)
        return rc;
    memset(s, 0, sizeof(*s));
    s->cfg = *cfg;
    s->vc1 = 0.5 * cfg->dc.vdc_V;
    s->vc2 = 0.5 * cfg->dc.vdc_V;
    s->omega_m = cfg->initial_omega_m_rad_s;
    if (cfg->initial_flux_frac > 0.0) {
        /* no stator current: psi_s = (Lm / Lr) psi_r */
        double psi_rated = sqrt(2.0 / 3.0) * cfg->sine.v_ll_rms_V / (PLANT_TWO_PI * cfg->sine.f_Hz);
        double lr = cfg->motor.Lm_H + cfg->motor.Llr_H;
        s->psi_r[0] = cfg->initial_flux_frac * psi_rated;
        s->psi_s[0] = s->psi_r[0] * cfg->motor.Lm_H / lr;
    }
    plant_rng_seed(s, cfg->sensor.seed);
    return 0;
}

static void load_x(const plant_state *s, double *x)
{
    x[PX_PSA] = s->psi_s[0];
    x[PX_PSB] = s->psi_s[1];
    x[PX_PRA] = s->psi_r[0];
    x[PX_PRB] = s->psi_r[1];
    x[PX_W] = s->omega_m;
    x[PX_TH] = s->theta_m;
    x[PX_VC1] = s->vc1;
    x[PX_VC2] = s->vc2;
    x[PX_EIN] = s->e_in_J;
    x[PX_ECU] = s->e_cu_J;
    x[PX_EMECH] = s->e_mech_J;
}

static void store_x(plant_state *s, const double *x)
{
    s->psi_s[0] = x[PX_PSA];
    s->psi_s[1] = x[PX_PSB];
    s->psi_r[0] = x[PX_PRA];
    s->psi_r[1] = x[PX_PRB];
    s->omega_m = x[PX_W];
    s->theta_m = remainder(x[PX_TH], PLANT_TWO_PI);
    s->vc1 = x[PX_VC1];
    s->vc2 = x[PX_VC2];
    s->e_in_J = x[PX_EIN];
    s->e_cu_J = x[PX_ECU];
    s->e_mech_J = x[PX_EMECH];
}

static void setup(const plant_state *s, plant_seg *g)
{
    plant_im_coeffs(&s->cfg.motor, s->t_load_Nm, g);
    plant_load_coeffs(&s->cfg.load, g);
    g->coul_dir = 0;
    plant_dc_coeffs(&s->cfg.dc, g);
    g->sine = s->cfg.supply == PLANT_SUPPLY_SINE;
    g->v_pk = sqrt(2.0 / 3.0) * s->cfg.sine.v_ll_rms_V;
    g->w_e = PLANT_TWO_PI * s->cfg.sine.f_Hz;
    g->phase = s->cfg.sine.phase_rad;
    g->n_float = 0;
    g->v_on2 = 2.0 * s->cfg.inverter.v_on_V;
    g->has_drop = g->v_on2 > 0.0;
    g->dvs[0] = g->dvs[1] = 0.0;
}

static void sine_voltage(const plant_seg *g, double t, double v_s[2])
{
    double a = g->w_e * t + g->phase;
    v_s[0] = g->v_pk * cos(a);
    v_s[1] = g->v_pk * sin(a);
}

/* The whole plant's derivative at time t. */
static void rhs(const plant_seg *restrict g, double t, const double *restrict x,
                double *restrict dx)
{
    double i_s[2], i_r[2], v_s[2], i_P = 0.0, i_N = 0.0;
    plant_im_currents(g, x, i_s, i_r);
    if (g->sine)
        sine_voltage(g, t, v_s);
    else if (g->n_float == 0)
        plant_npc_drive_connected(g, x, i_s, v_s, &i_P, &i_N);
    else
        plant_npc_drive(g, x, i_s, i_r, v_s, &i_P, &i_N);
    plant_im_rhs(g, x, i_s, i_r, v_s, dx);
    plant_dc_rhs(g, x, i_P, i_N, dx);
}

static void rk4_step(const plant_seg *g, double t, double h, double *x)
{
    double k1[PX_N], k2[PX_N], k3[PX_N], k4[PX_N], xt[PX_N];
    double h2 = 0.5 * h;
    int i;
    rhs(g, t, x, k1);
    for (i = 0; i < PX_N; ++i)
        xt[i] = x[i] + h2 * k1[i];
    rhs(g, t + h2, xt, k2);
    for (i = 0; i < PX_N; ++i)
        xt[i] = x[i] + h2 * k2[i];
    rhs(g, t + h2, xt, k3);
    for (i = 0; i < PX_N; ++i)
        xt[i] = x[i] + h * k3[i];
    rhs(g, t + h, xt, k4);
    for (i = 0; i < PX_N; ++i)
        x[i] += h * (1.0 / 6.0) * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
}

/*
 * Integrate len seconds from t0 with one supply configuration; legs is NULL
 * in sine mode. Gates-off legs re-decide their diode state every step.
 */
static void integrate_segment(plant_seg *g, const uint8_t *legs, double *x,
                              double t0, double len, double h_max)
{
    /* Stability guard: RK4 on the DC link's fastest mode (time constant
     * R C1 C2 / (C1 + C2)) needs h * lambda < 2.78; keep h <= tau so an
     * unusually stiff source cannot blow the integration up. The default
     * link (55 us) is not affected. */
    double tau_dc = 1.0 / (g->inv_r * (g->inv_c1 + g->inv_c2));
    long n;
    if (h_max > tau_dc)
        h_max = tau_dc;
    n = (long)ceil(len / h_max - 1e-9);
    double h;
    int diodes = 0, reconnect = 0;
    long i;
    if (n < 1)
        n = 1;
    h = len / (double)n;
    if (legs != NULL) {
        /* gates off (3) and dead time (4, 5) conduct through diodes */
        diodes = legs[0] >= PLANT_LEG_OFF || legs[1] >= PLANT_LEG_OFF || legs[2] >= PLANT_LEG_OFF;
        /* diode states and on-state drops follow the currents: decide per step */
        reconnect = diodes || g->has_drop;
        plant_npc_connect(g, legs, x);
    }
    for (i = 0; i < n; ++i) {
        if (reconnect && i > 0)
            plant_npc_connect(g, legs, x);
        if (g->load_ext)
            plant_load_decide(g, x);
        rk4_step(g, t0 + (double)i * h, h, x);
        if (g->load_ext)
            plant_load_stop(g, x);
        if (diodes)
            plant_npc_clamp(g, x);
    }
}

/* Leg codes as the integration understands them (anything above 3 is off). */
static void normalise(const uint8_t *in, uint8_t out[3])
{
    int k;
    for (k = 0; k < 3; ++k)
        out[k] = in == NULL || in[k] > PLANT_LEG_OFF ? (uint8_t)PLANT_LEG_OFF : in[k];
}

/* A disconnected phase overrides whatever its leg does. */
static void open_phases(const plant_state *s, uint8_t legs[3])
{
    int k;
    for (k = 0; k < 3; ++k)
        if (s->phase_open[k])
            legs[k] = (uint8_t)PLANT_LEG_OPEN;
}

static void count_switches(plant_state *s, const uint8_t legs[3])
{
    int k;
    if (s->legs_valid) {
        for (k = 0; k < 3; ++k) {
            int a = s->legs_last[k], b = legs[k];
            if (a <= (int)PLANT_LEG_P && b <= (int)PLANT_LEG_P)
                s->switch_count += (unsigned long)(a > b ? a - b : b - a);
        }
    }
    for (k = 0; k < 3; ++k)
        s->legs_last[k] = legs[k];
    s->legs_valid = 1;
}

void plant_advance(plant_state *s, const uint8_t vec0[3], const uint8_t vec1[3],
                   double duty0, double period_s)
{
    plant_seg g;
    double x[PX_N];
    double t0, i_s[2], i_r[2];

    if (s == NULL || !isfinite(period_s) || !(period_s > 0.0))
        return;
    if (!(duty0 > 0.0)) /* also NaN */
        duty0 = 0.0;
    if (duty0 > 1.0)
        duty0 = 1.0;

    setup(s, &g);
    load_x(s, x);
    t0 = s->t_s;

    if (g.sine) {
        double v_s[2];
        int k;
        integrate_segment(&g, NULL, x, t0, period_s, s->cfg.h_max_s);
        sine_voltage(&g, t0 + period_s, v_s);
        for (k = 0; k < 3; ++k)
            s->v_last_V[k] = plant_u[k][0] * v_s[0] + plant_u[k][1] * v_s[1];
        s->i_np_last_A = 0.0;
    } else {
        uint8_t v[2][3];
        double len[2];
        int j;
        const int any_open = s->phase_open[0] || s->phase_open[1] || s->phase_open[2];
        normalise(vec0, v[0]);
        normalise(vec1, v[1]);
        len[0] = duty0 * period_s;
        len[1] = period_s - len[0];
        for (j = 0; j < 2; ++j) {
            double ts = j == 0 ? t0 : t0 + len[0];
            if (len[j] < PLANT_MIN_SEGMENT_S)
                continue;
            if (s->cfg.inverter.dead_time_s > 0.0)
                plant_dead_edge(s, v[j], ts);
            count_switches(s, v[j]);
            if (s->cfg.inverter.dead_time_s > 0.0 || any_open) {
                /* Sub-segments between the ends of the legs' blanking intervals. */
                double t = ts, te = ts + len[j];
                while (te - t >= PLANT_MIN_SEGMENT_S) {
                    uint8_t eff[3];
                    double tn = plant_dead_legs(s, v[j], t, te, eff);
                    open_phases(s, eff);
                    integrate_segment(&g, eff, x, t, tn - t, s->cfg.h_max_s);
                    t = tn;
                }
            } else {
                integrate_segment(&g, v[j], x, ts, len[j], s->cfg.h_max_s);
            }
        }
        /* Voltages and NP current at the end, in the last vector's connection. */
        if (s->legs_valid) {
            uint8_t last[3];
            memcpy(last, s->legs_last, sizeof last);
            open_phases(s, last);
            plant_npc_connect(&g, last, x);
            plant_im_currents(&g, x, i_s, i_r);
            plant_npc_phase(&g, x, i_s, i_r, s->v_last_V, &s->i_np_last_A);
        }
    }
    store_x(s, x);
    s->t_s = t0 + period_s;
}

void plant_get_truth(const plant_state *s, plant_truth *out)
{
    plant_seg g;
    double x[PX_N], i_s[2], i_r[2];
    if (s == NULL || out == NULL)
        return;
    plant_im_coeffs(&s->cfg.motor, s->t_load_Nm, &g);
    load_x(s, x);
    plant_im_currents(&g, x, i_s, i_r);

    out->t_s = s->t_s;
    out->ia_A = plant_u[0][0] * i_s[0] + plant_u[0][1] * i_s[1];
    out->ib_A = plant_u[1][0] * i_s[0] + plant_u[1][1] * i_s[1];
    out->ic_A = plant_u[2][0] * i_s[0] + plant_u[2][1] * i_s[1];
    out->va_V = s->v_last_V[0];
    out->vb_V = s->v_last_V[1];
    out->vc_V = s->v_last_V[2];
    out->is_alpha_A = i_s[0];
    out->is_beta_A = i_s[1];
    out->ir_alpha_A = i_r[0];
    out->ir_beta_A = i_r[1];
    out->psi_s_alpha_Wb = s->psi_s[0];
    out->psi_s_beta_Wb = s->psi_s[1];
    out->psi_r_alpha_Wb = s->psi_r[0];
    out->psi_r_beta_Wb = s->psi_r[1];
    out->te_Nm = plant_im_torque(&g, x, i_s);
    out->omega_m_rad_s = s->omega_m;
    out->theta_m_rad = s->theta_m;
    out->vc1_V = s->vc1;
    out->vc2_V = s->vc2;
    out->i_np_A = s->i_np_last_A;
    out->w_mag_J = plant_im_wmag(x, i_s, i_r);
}

void plant_set_load(plant_state *s, double t_load_Nm)
{
    if (s != NULL && isfinite(t_load_Nm))
        s->t_load_Nm = t_load_Nm;
}

void plant_set_inertia(plant_state *s, double J_kgm2)
{
    if (s != NULL && isfinite(J_kgm2) && J_kgm2 > 0.0)
        s->cfg.motor.J_kgm2 = J_kgm2;
}

void plant_set_friction(plant_state *s, double B_Nms)
{
    if (s != NULL && isfinite(B_Nms) && B_Nms >= 0.0)
        s->cfg.motor.B_Nms = B_Nms;
}

void plant_set_rs(plant_state *s, double Rs_ohm)
{
    if (s != NULL && isfinite(Rs_ohm) && Rs_ohm > 0.0)
        s->cfg.motor.Rs_ohm = Rs_ohm;
}

void plant_set_rr(plant_state *s, double Rr_ohm)
{
    if (s != NULL && isfinite(Rr_ohm) && Rr_ohm > 0.0)
        s->cfg.motor.Rr_ohm = Rr_ohm;
}

void plant_set_lm(plant_state *s, double Lm_H)
{
    if (s != NULL && isfinite(Lm_H) && Lm_H > 0.0)
        s->cfg.motor.Lm_H = Lm_H;
}

void plant_set_phase_open(plant_state *s, int k, int open)
{
    if (s != NULL && k >= 0 && k < 3)
        s->phase_open[k] = (uint8_t)(open != 0);
}

void plant_set_vdc(plant_state *s, double vdc_V)
{
    if (s != NULL && isfinite(vdc_V) && vdc_V > 0.0)
        s->cfg.dc.vdc_V = vdc_V;
}
