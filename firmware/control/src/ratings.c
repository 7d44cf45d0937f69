/**
 * @file ratings.c
 * @brief The plate's checks, its per-unit bases, the plate-only motor
 *        estimate and the derived defaults (ratings.h).
 *
 * Every PU_ constant below is one of the 10 hp drive's tuned values over its
 * base (the plate of docs/motor-10hp.json: 7457 W, 220 V, 24.4 A, 60 Hz,
 * 1744 rpm, cos phi 0.886, on 311 V: I_b 34.51 A, w_b 376.99 rad/s,
 * psi_b 0.4765 Wb, T_r 40.83 N m, w_mr 182.63 rad/s, with J = 0.045 kg m^2
 * t_m 0.2013 s), so that plate gives those values again and another motor
 * the same per-unit behaviour. docs/commissioning.md has the table.
 */
#include "dtc/ratings.h"

#include <string.h>

/* A PU_ constant as a literal of the working type, and as text for the rule. */
#define PU_R(k) R(k)
#define PU_STR_(k) #k
#define PU_STR(k) PU_STR_(k)
#define PU_SQRT2 R(1.41421356237310)

/* ------------------------------------------------------ reference drive */

void ratings_reference(ratings *r, motor_model *m)
{
    /* the plate of docs/motor-10hp.json and the board's inverter label
     * (30 A rated, 100 A peak: its over-current trip) on its 311 V link */
    r->P_W = R(7457.0);
    r->V_ll_V = R(220.0);
    r->I_A = R(24.4);
    r->f_Hz = R(60.0);
    r->n_rpm = R(1744.0);
    r->cos_phi = R(0.886);
    r->vdc_nom_V = R(311.0);
    r->inv_I_rated_A = R(30.0);
    r->inv_I_peak_A = R(100.0);
    /* the motor's own model (docs/motor-10hp.json) */
    m->Rs_ohm = R(0.288);
    m->Rr_ohm = R(0.158);
    m->Lm_H = R(0.0416);
    m->Ls_H = R(0.00142) + R(0.0416);
    m->Lr_H = R(0.00142) + R(0.0416);
    m->pole_pairs = R(2.0);
    m->J_kgm2 = R(0.045);
    m->B_Nms = R(0.005);
}

/* ------------------------------------------------------------------ plate */

/* Ranges of the fields (the issue's: 0.5 kW .. 5 MW, 200 V .. 6.6 kV). The
 * speed's range only bounds the number; the pole-count and slip rules judge
 * it against the frequency. A cos phi of 0 is "not on the plate"; given, it
 * is at least 0.3 (no motor's rated point is below). */
static const struct {
    const char *name;
    real_t min, max;
} k_field[RATINGS_FIELD_COUNT] = {
    [RATINGS_FIELD_NONE] = {"", R(0.0), R(0.0)},
    [RATINGS_FIELD_P_W] = {"P_W", R(500.0), R(5.0e6)},
    [RATINGS_FIELD_V_LL_V] = {"V_ll_V", R(200.0), R(6600.0)},
    [RATINGS_FIELD_I_A] = {"I_A", R(0.5), R(1.0e4)},
    [RATINGS_FIELD_F_HZ] = {"f_Hz", R(5.0), R(400.0)},
    [RATINGS_FIELD_N_RPM] = {"n_rpm", R(1.0), R(24000.0)},
    [RATINGS_FIELD_COS_PHI] = {"cos_phi", R(0.3), R(1.0)},
    [RATINGS_FIELD_VDC_NOM_V] = {"vdc_nom_V", R(200.0), R(12000.0)},
    [RATINGS_FIELD_INV_I_RATED_A] = {"inv_I_rated_A", R(0.5), R(1.0e4)},
    [RATINGS_FIELD_INV_I_PEAK_A] = {"inv_I_peak_A", R(0.7), R(3.0e4)},
};

static real_t plate_value(const ratings *r, ratings_field f)
{
    switch (f) {
    case RATINGS_FIELD_P_W: return r->P_W;
    case RATINGS_FIELD_V_LL_V: return r->V_ll_V;
    case RATINGS_FIELD_I_A: return r->I_A;
    case RATINGS_FIELD_F_HZ: return r->f_Hz;
    case RATINGS_FIELD_N_RPM: return r->n_rpm;
    case RATINGS_FIELD_COS_PHI: return r->cos_phi;
    case RATINGS_FIELD_VDC_NOM_V: return r->vdc_nom_V;
    case RATINGS_FIELD_INV_I_RATED_A: return r->inv_I_rated_A;
    case RATINGS_FIELD_INV_I_PEAK_A: return r->inv_I_peak_A;
    case RATINGS_FIELD_NONE:
    case RATINGS_FIELD_COUNT:
    default: return R(0.0);
    }
}

/* finite without isfinite(): NaN and +-inf give NaN on subtraction */
static bool plate_finite(real_t x) { return (x - x) == R(0.0); }

static ratings_error plate_error(ratings_field f, ratings_reason why)
{
    ratings_error e = {f, why};
    return e;
}

/* p = floor(60 f / n), for 60 f / n >= 1 (n below synchronous of p = 1). */
static real_t pole_pairs_of(const ratings *r)
{
    real_t x = num_div(R(60.0) * r->f_Hz, r->n_rpm);
    return (real_t)(int32_t)x;
}

ratings_error ratings_check(const ratings *r)
{
    for (int i = RATINGS_FIELD_NONE + 1; i < RATINGS_FIELD_COUNT; i++) {
        ratings_field f = (ratings_field)i;
        real_t x = plate_value(r, f);
        if (!plate_finite(x))
            return plate_error(f, RATINGS_E_NOT_FINITE);
        if (f == RATINGS_FIELD_COS_PHI) {
            if (x < R(0.0))
                return plate_error(f, RATINGS_E_NOT_POSITIVE);
            if (x == R(0.0))
                continue; /* not on the plate */
        } else if (!(x > R(0.0))) {
            return plate_error(f, RATINGS_E_NOT_POSITIVE);
        }
        if (x < k_field[f].min)
            return plate_error(f, RATINGS_E_BELOW_RANGE);
        if (x > k_field[f].max)
            return plate_error(f, RATINGS_E_ABOVE_RANGE);
    }
    /* The rated speed is below synchronous: below that of one pole pair, and
     * by a rated slip of at least RATINGS_SLIP_MIN below that of its own pole
     * count (no induction motor runs nearer; the slip is then at most
     * 1 / (p + 1) <= 0.5 by the floor). */
    if (!(r->n_rpm < R(60.0) * r->f_Hz))
        return plate_error(RATINGS_FIELD_N_RPM, RATINGS_E_SPEED_SYNCHRONOUS);
    real_t p = pole_pairs_of(r);
    if (p > (real_t)RATINGS_POLE_PAIRS_MAX)
        return plate_error(RATINGS_FIELD_N_RPM, RATINGS_E_POLES);
    real_t slip = R(1.0) - num_div(num_mul(p, r->n_rpm), R(60.0) * r->f_Hz);
    if (!(slip >= RATINGS_SLIP_MIN))
        return plate_error(RATINGS_FIELD_N_RPM, RATINGS_E_SPEED_SYNCHRONOUS);
    /* The line voltage's peak a three-level inverter gives is 1.10 Vdc
     * (six-step: the fundamental of the line voltage is sqrt 6 / pi Vdc rms). */
    if (num_mul(PU_SQRT2, r->V_ll_V) > num_mul(RATINGS_SIX_STEP_LL, r->vdc_nom_V))
        return plate_error(RATINGS_FIELD_VDC_NOM_V, RATINGS_E_LINK_TOO_LOW);
    /* The shaft power is below the electrical input (efficiency < 1), and not
     * so far below it that efficiency x power factor is no motor's. */
    real_t s_va = num_mul(num_mul(NUM_SQRT3, r->V_ll_V), r->I_A);
    real_t p_in = r->cos_phi > R(0.0) ? num_mul(s_va, r->cos_phi) : s_va;
    if (r->P_W > p_in)
        return plate_error(RATINGS_FIELD_P_W, RATINGS_E_POWER_ABOVE_INPUT);
    if (r->P_W < num_mul(RATINGS_ETA_PF_MIN, s_va))
        return plate_error(RATINGS_FIELD_P_W, RATINGS_E_POWER_TOO_LOW);
    /* The label: a peak current at least the rated current's peak. */
    if (r->inv_I_peak_A < num_mul(PU_SQRT2, r->inv_I_rated_A))
        return plate_error(RATINGS_FIELD_INV_I_PEAK_A, RATINGS_E_PEAK_BELOW_RATED);
    /* The motor against the inverter. Continuous: a motor up to 1.5 x the
     * inverter's rated current may run (below its rated torque; the inverter's
     * thermal limit is its own), a larger one is a plate or a label mistyped.
     * Peak: the trip (at most the inverter's peak) stays 1.5 x above the
     * motor's rated peak current, so the rated torque is reached with margin. */
    if (r->I_A > num_mul(RATINGS_MOTOR_OVER_INVERTER_MAX, r->inv_I_rated_A))
        return plate_error(RATINGS_FIELD_I_A, RATINGS_E_MOTOR_ABOVE_INVERTER);
    if (r->inv_I_peak_A < num_mul(RATINGS_PEAK_MARGIN, num_mul(PU_SQRT2, r->I_A)))
        return plate_error(RATINGS_FIELD_INV_I_PEAK_A, RATINGS_E_PEAK_BELOW_MOTOR);
    return plate_error(RATINGS_FIELD_NONE, RATINGS_OK);
}

uint32_t ratings_abort_code(ratings_reason reason)
{
    /* CiA 301 SDO abort codes (dtc/canopen/co_od.h CO_ABORT_*; the control
     * layer does not include the CANopen layer) */
    switch (reason) {
    case RATINGS_OK: return 0u;
    case RATINGS_E_NOT_FINITE: return 0x06090030u;      /* invalid value */
    case RATINGS_E_NOT_POSITIVE:
    case RATINGS_E_BELOW_RANGE:
    case RATINGS_E_POLES: return 0x06090032u;           /* value too low */
    case RATINGS_E_ABOVE_RANGE:
    case RATINGS_E_SPEED_SYNCHRONOUS: return 0x06090031u; /* value too high */
    case RATINGS_E_LINK_TOO_LOW:
    case RATINGS_E_POWER_ABOVE_INPUT:
    case RATINGS_E_POWER_TOO_LOW:
    case RATINGS_E_PEAK_BELOW_RATED:
    case RATINGS_E_PEAK_BELOW_MOTOR:
    case RATINGS_E_MOTOR_ABOVE_INVERTER:
    case RATINGS_E_PERIOD:
    default: return 0x06090036u;                        /* a relation between values broken */
    }
}

const char *ratings_field_name(ratings_field field)
{
    return field > RATINGS_FIELD_NONE && field < RATINGS_FIELD_COUNT ? k_field[field].name : "";
}

real_t ratings_field_min(ratings_field field)
{
    if (field == RATINGS_FIELD_COS_PHI)
        return R(0.0); /* 0: not on the plate */
    return field > RATINGS_FIELD_NONE && field < RATINGS_FIELD_COUNT ? k_field[field].min : R(0.0);
}

real_t ratings_field_max(ratings_field field)
{
    return field > RATINGS_FIELD_NONE && field < RATINGS_FIELD_COUNT ? k_field[field].max : R(0.0);
}

const char *ratings_reason_text(ratings_reason reason)
{
    switch (reason) {
    case RATINGS_OK: return "";
    case RATINGS_E_NOT_FINITE: return "is not a finite number";
    case RATINGS_E_NOT_POSITIVE: return "must be > 0";
    case RATINGS_E_BELOW_RANGE: return "is below its range";
    case RATINGS_E_ABOVE_RANGE: return "is above its range";
    case RATINGS_E_SPEED_SYNCHRONOUS: return "is not below synchronous speed by a slip of at least 0.1 %";
    case RATINGS_E_POLES: return "gives more than 32 pole pairs at the rated frequency";
    case RATINGS_E_LINK_TOO_LOW: return "cannot give the rated line voltage (sqrt 2 V_ll above 1.10 vdc)";
    case RATINGS_E_POWER_ABOVE_INPUT: return "is above the electrical input sqrt 3 V_ll I cos phi";
    case RATINGS_E_POWER_TOO_LOW: return "is below 0.25 sqrt 3 V_ll I (no motor's efficiency x power factor)";
    case RATINGS_E_PEAK_BELOW_RATED: return "is below sqrt 2 x the inverter's rated current";
    case RATINGS_E_PEAK_BELOW_MOTOR: return "is below 1.5 x the motor's rated peak current sqrt 2 I_A";
    case RATINGS_E_MOTOR_ABOVE_INVERTER: return "is above 1.5 x the inverter's rated current";
    case RATINGS_E_PERIOD: return "is above what the control period follows at the overspeed trip";
    default: return "is refused";
    }
}

/* ------------------------------------------------------------------ bases */

/* Efficiency of a standard 4-pole motor at its rated power, a fit of the
 * IEC 60034-30-1 IE3 class (82.5 % at 0.75 kW, 90.4 % at 7.5 kW, 95.0 % at
 * 75 kW, 96.0 % at 375 kW): 1 - 0.175 (P / 750 W)^-1/4, within 0.5 % of the
 * class over 0.75..375 kW. Used only when the plate has no cos phi. */
#define PU_ETA_LOSS R(0.175)
static real_t efficiency_estimate(real_t P_W)
{
    real_t q = num_sqrt(num_sqrt(num_div(P_W, R(750.0)))); /* (P / 750 W)^1/4 */
    return num_sat(R(1.0) - num_div(PU_ETA_LOSS, q), R(0.7), R(0.985));
}

void ratings_base_of(const ratings *r, ratings_base *b)
{
    b->pole_pairs = pole_pairs_of(r);
    b->slip = R(1.0) - num_div(num_mul(b->pole_pairs, r->n_rpm), R(60.0) * r->f_Hz);
    b->S_b = num_mul(num_mul(NUM_SQRT3, r->V_ll_V), r->I_A);
    if (r->cos_phi > R(0.0)) {
        b->cos_phi = r->cos_phi;
    } else {
        /* P = eta cos phi S: the power factor the efficiency of a standard motor leaves */
        b->cos_phi = num_sat(num_div(num_div(r->P_W, b->S_b), efficiency_estimate(r->P_W)), R(0.5), R(0.95));
    }
    b->V_b = num_mul(R(0.816496581), r->V_ll_V); /* sqrt(2/3) */
    b->I_b = num_mul(PU_SQRT2, r->I_A);
    b->w_b = num_mul(R(2.0) * NUM_PI, r->f_Hz);
    b->psi_b = num_div(b->V_b, b->w_b);
    b->Z_b = num_div(b->V_b, b->I_b);
    b->L_b = num_div(b->Z_b, b->w_b);
    b->T_b = num_mul(num_mul(R(1.5), b->pole_pairs), num_mul(b->psi_b, b->I_b));
    b->w_mb = num_div(b->w_b, b->pole_pairs);
    b->w_mr = num_mul(R(2.0) * NUM_PI / R(60.0), r->n_rpm);
    b->T_r = num_div(r->P_W, b->w_mr);
    b->vdc_b = r->vdc_nom_V;
}

/* --------------------------------------------------------- motor estimate */

/* Stator resistance in per unit of Z_b: 0.03 at 10 kW falling as
 * P^-1/8, fitted to the reference machines (the 10 hp motor and the four of
 * Krause, Wasynczuk, Sudhoff, "Analysis of Electric Machinery and Drive
 * Systems", 0.010..0.055 pu over 2.2 kW..1.7 MW): within a factor 2 of each,
 * the range in which the identification while magnetising corrects it
 * (dtc/rs_ident.h: 0.5..2 x the model's). */
#define PU_RS 0.03
/* Each leakage in per unit of L_b (the reference machines: 0.053..0.103 pu,
 * textbook values 0.05..0.1 pu), split equally between stator and rotor.
 * The observer is what bounds it: with the plate-only model it holds all
 * five reference machines for 0.065..0.075 pu; 1.5 x the 3 hp machine's
 * leakage (0.08 pu) or 0.7 x the 2250 hp one's (0.06 pu) loses its speed
 * estimate at load (tests/unit/test_ratings.cpp, RatingsClosedLoop). */
#define PU_LEAKAGE 0.07
/* Inertia constant H = J w_mb^2 / (2 P) of a drive train, motor and load:
 * 0.5 s (Krause's four machines: 0.53..0.79 s; the 10 hp motor's rotor
 * alone 0.107 s). An inertia the speed loop overestimates leaves it slower
 * and better damped than designed (wn sqrt(J / J_est), zeta
 * sqrt(J_est / J): the gains scale with wn ~ 1 / t_m), an underestimated one
 * faster and less damped, so the estimate errs high rather than low. */
#define PU_H_S 0.5
/* Friction and windage: 1 % of the rated power at rated speed. */
#define PU_FRICTION 0.01
/* The magnetising current's share of the rated current, bounds of the
 * estimate (magnetising reactances of 1.4..6.7 pu): a plate whose power
 * factor leaves no reactive power for the magnetising is not trusted for it. */
#define PU_IM_MIN R(0.15)
#define PU_IM_MAX R(0.7)

void ratings_motor_estimate(const ratings *r, const ratings_base *b, motor_model *m)
{
    real_t i_rms = r->I_A;
    real_t v_ph = num_mul(NUM_INV_SQRT3, r->V_ll_V);
    real_t cphi = b->cos_phi;
    real_t sphi = num_sqrt(R(1.0) - num_mul(cphi, cphi));
    /* Rotor: at the rated slip the rotor branch is nearly resistive, so the
     * rotor current is the active current I cos phi and the air-gap power
     * P / (1 - s) = 3 Rr I_r^2 / s. */
    real_t i_r = num_mul(i_rms, cphi);
    real_t p_ag = num_div(r->P_W, R(1.0) - b->slip);
    m->Rr_ohm = num_div(num_mul(b->slip, p_ag), num_mul(R(3.0), num_mul(i_r, i_r)));
    /* Stator: per unit of Z_b, PU_RS (P / 10 kW)^-1/8. */
    real_t q = num_sqrt(num_sqrt(num_sqrt(num_div(r->P_W, R(1.0e4))))); /* (P / 10 kW)^1/8 */
    m->Rs_ohm = num_div(num_mul(PU_R(PU_RS), b->Z_b), q);
    real_t l_leak = num_mul(PU_R(PU_LEAKAGE), b->L_b);
    real_t x_leak = num_mul(l_leak, b->w_b);
    /* Magnetising: the reactive power 3 V I sin phi less that of the two
     * leakages (stator at I, rotor at I_r) is the magnetising branch's,
     * 3 E I_m, at the air-gap voltage E = |V - (Rs + j X_l) I e^-j phi|. */
    real_t q_var = num_mul(num_mul(R(3.0), v_ph), num_mul(i_rms, sphi));
    real_t q_leak = num_mul(num_mul(R(3.0), x_leak), num_mul(i_rms, i_rms) + num_mul(i_r, i_r));
    real_t d_re = num_mul(m->Rs_ohm, i_r) + num_mul(x_leak, num_mul(i_rms, sphi));
    real_t d_im = num_mul(x_leak, i_r) - num_mul(m->Rs_ohm, num_mul(i_rms, sphi));
    real_t e_re = v_ph - d_re;
    real_t e_v = num_sqrt(num_mul(e_re, e_re) + num_mul(d_im, d_im));
    real_t i_m = num_div(q_var - q_leak, R(3.0) * e_v);
    i_m = num_sat(i_m, num_mul(PU_IM_MIN, i_rms), num_mul(PU_IM_MAX, i_rms));
    m->Lm_H = num_div(num_div(e_v, i_m), b->w_b);
    m->Ls_H = m->Lm_H + l_leak;
    m->Lr_H = m->Lm_H + l_leak;
    m->pole_pairs = b->pole_pairs;
    /* Inertia: J = 2 H P / w_mb^2. */
    m->J_kgm2 = num_div(num_mul(R(2.0) * PU_R(PU_H_S), r->P_W), num_mul(b->w_mb, b->w_mb));
    m->B_Nms = num_div(num_mul(PU_R(PU_FRICTION), r->P_W), num_mul(b->w_mr, b->w_mr));
}

/* -------------------------------------------------------- derived values */

/* The DC link's stored energy per VA of the motor, C vdc^2 / (4 S_b) (two
 * capacitors C in series): 5.72 ms with the 10 hp board's 2.2 mF. The
 * capacitance is the inverter's own: this is a placeholder of its size until
 * it is set from the inverter's data. */
#define PU_C_DC_TAU_S 5.72e-3
/* Trips: 100 A = 2.9 I_b (at most the inverter's peak); 400 V = 1.286 vdc;
 * 200 V = 0.643 vdc; the neutral point 30 V = 0.0965 vdc; overspeed
 * 310 rad/s = 1.697 w_mr (its speed-reference limit, / 1.1, is 1.54 w_mr:
 * field weakening to 1.5 x rated speed). */
#define PU_I_TRIP 2.9
#define PU_VDC_MAX 1.286
#define PU_VDC_MIN 0.643
#define PU_NP_TRIP 0.0965
#define PU_OVERSPEED 1.697
/* The neutral point's band 1.5 V = 0.00482 vdc. */
#define PU_NP_BAND 0.00482
/* DTC bands: flux 0.01 Wb = 0.021 psi_b; torque 3.5 N m = 0.0857 T_r (about
 * 850 Hz device switching at 500 rpm) and 8 N m = 0.196 T_r; ripple
 * reduction up to 200 rad/s = 1.095 w_mr (the whole speed range). */
#define PU_FLUX_BAND 0.021
#define PU_TORQUE_BAND 0.0857
#define PU_TORQUE_BAND2 0.196
#define PU_RIPPLE_SPEED 1.095
/* Observer: the speed adaptation's error Im(e* psi_r) scales as I_b psi_b
 * and its output as w_b, so its gains do in w_b / (I_b psi_b): kp 50 =
 * 2.18 pu, ki 2000 1/s = 87.2 pu / s; the regenerating-mode rotation fades
 * out at 100 rad/s = 0.265 w_b (electrical). */
#define PU_OBS_KP 2.18
#define PU_OBS_KI 87.2
#define PU_OBS_REGEN_SPEED 0.265
/* Loss-of-control monitor: its corner 6 rad/s = 0.0159 w_b and its time
 * 10 ms = 3.77 / w_b follow the stator frequency (the same verdict per
 * electrical radian); the voltage error it tolerates 6 V = 0.0193 vdc (the
 * compensated dead time's and the drops' residue scale with the link). */
#define PU_GUARD_WC 0.0159
#define PU_GUARD_TIME 3.77
#define PU_GUARD_V_TOL 0.0193
/* Bring-up V/f at 5 Hz = 0.0833 f. */
#define PU_BRINGUP_HZ 0.0833
/* Speed loop. A rated load step leaves a speed dip of (dT / T_r) / (t_m wn)
 * in per unit of w_mr, so wn t_m is the per-unit constant: wn = 10 rad/s
 * with t_m 0.2013 s is 2.01 / t_m. The nominal controller's K_x = 40 1/s =
 * 4 wn, the RBFN's K = 2 zeta wn (the IP's proportional action), its
 * learning rates gamma_w = 4000 = 40 wn^2 and gamma_zeta = 1000 = 10 wn^2,
 * its bound's leak 0.5 1/s = 0.05 wn. The ramp 100 rad/s^2 = 0.11 T_r / J
 * (11 % of the rated torque accelerates), the bound's ceiling 200 rad/s^2 =
 * 0.22 T_r / J (22 % of it as robust torque); the boundary layer and the
 * dead zone 1 rad/s = 0.00548 w_mr; the stall time 1 s = 5 t_m. */
#define PU_WN_TM 2.01
#define PU_K_X_WN 4.0
#define PU_GAMMA_W_WN2 40.0
#define PU_GAMMA_ZETA_WN2 10.0
#define PU_ZETA_LEAK_WN 0.05
#define PU_RAMP 0.11
#define PU_ZETA_MAX 0.22
#define PU_RBFN_BOUNDARY 0.00548
#define PU_RBFN_DEAD_ZONE 0.00548
#define PU_STALL_TIME_TM 5.0
/* Below this mechanical time constant the speed loop's gains stop growing:
 * the torque loop (a few ms) and the speed loop's 0.8 ms step bound it, not
 * the inertia (at most 4 x the 10 hp drive's gains). */
#define PU_T_M_MIN_S R(0.05)
/* Torque limit: 80 N m = 1.96 T_r, and at most the torque of the current
 * i_trip / 1.5 (the 10 hp drive's 80 N m draws 65 A of its 100 A trip) and
 * te_pullout_frac x the pull-out at the flux reference. */
#define PU_TE_MAX 1.96
#define PU_TE_CURRENT_MARGIN R(1.5)
/* Magnetising: the flux ramp, then ten sigma Tr for the rotor flux (which
 * follows the stator flux with that time constant) to settle: 0.31 s for
 * the 10 hp motor. */
#define PU_PREMAG_SIGMA_TR R(10.0)
/* Constants of the control law that are macros today (ctl.c, observer.c,
 * rs_ident.c, dtc3l.c, plausibility.h), in the same bases: the drop's
 * sign band 0.5 A = 0.0145 I_b; the lowered regenerating flux's margin
 * 2.5 rad/s = 0.00663 w_b, entry 6.3 = 0.0167 w_b, exit 8.8 = 0.0233 w_b
 * (stator frequencies) and its smallest command 2 N m = 0.049 T_r; the
 * stall's speed error 3 rad/s = 0.0164 w_mr, window 0.1 s = 0.5 t_m; the
 * braking stall below 50 rad/s = 0.265 w_mb (where the loss-of-control
 * monitor is blind: a stator frequency) within 0.1 s = 0.5 t_m; the V/f
 * boost's 5 A = 0.145 I_b; the observer's regenerating torque 2 N m =
 * 0.049 T_r; the Rs identification's standstill 2 rad/s = 0.0053 w_b, its
 * judging from 0.15 s = the flux ramp + sigma Tr, its least charge
 * 0.2 A s = 0.0058 s x I_b; the DTC's "no flux yet" 1 mWb = 0.0021 psi_b;
 * the current sum's tolerance 5 A = 0.145 I_b, "current flows" 3 A =
 * 0.087 I_b, an open phase 0.5 A = 0.0145 I_b, judged above 2 Hz = 0.0333 f. */
#define PU_DROP_BAND 0.0145
#define PU_LOWFLUX_MARGIN 0.00663
#define PU_LOWFLUX_ENTER 0.0167
#define PU_LOWFLUX_EXIT 0.0233
#define PU_LOWFLUX_MIN_TE 0.049
#define PU_STALL_SPEED_ERR 0.0164
#define PU_STALL_WINDOW_TM 0.5
#define PU_BRAKE_STALL_SPEED 0.265
#define PU_BRAKE_STALL_TIME_TM 0.5
#define PU_BRINGUP_BOOST 0.145
#define PU_OBS_REGEN_MIN_TE 0.049
#define PU_RSID_MAX_SPEED 0.0053
#define PU_RSID_MIN_CHARGE_S 0.0058
#define PU_DTC_PSI_TINY 0.0021
#define PU_PLAUS_SUM_ABS 0.145
#define PU_PLAUS_CURRENT 0.087
#define PU_PLAUS_OPEN 0.0145
#define PU_PLAUS_PHASE_MIN 0.0333

#define PU_FIELD(f) offsetof(ctl_cfg, f)
#define PU_ENTRY(ident, field_name, offset, unit_text, rule_text, est) \
    [ident] = {ident, field_name, unit_text, rule_text, offset, est}
#define PU_CFG(ident, f, unit_text, rule_text) PU_ENTRY(ident, #f, PU_FIELD(f), unit_text, rule_text, false)
#define PU_MOTOR(ident, f, unit_text, rule_text) PU_ENTRY(ident, #f, PU_FIELD(f), unit_text, rule_text, true)
#define PU_MACRO(ident, where, unit_text, rule_text) PU_ENTRY(ident, where, RATINGS_NO_FIELD, unit_text, rule_text, false)

const ratings_derivable ratings_derivables[RATINGS_ID_COUNT] = {
    PU_MOTOR(RATINGS_ID_MOTOR_RS, motor.Rs_ohm, "ohm", PU_STR(PU_RS) " Z_b (P / 10 kW)^-1/8"),
    PU_MOTOR(RATINGS_ID_MOTOR_RR, motor.Rr_ohm, "ohm", "s P / ((1 - s) 3 (I cos phi)^2)"),
    PU_MOTOR(RATINGS_ID_MOTOR_LM, motor.Lm_H, "H", "E / (w_b I_m), 3 E I_m = 3 V I sin phi - 3 X_l (I^2 + (I cos phi)^2)"),
    PU_MOTOR(RATINGS_ID_MOTOR_LS, motor.Ls_H, "H", "Lm + " PU_STR(PU_LEAKAGE) " L_b"),
    PU_MOTOR(RATINGS_ID_MOTOR_LR, motor.Lr_H, "H", "Lm + " PU_STR(PU_LEAKAGE) " L_b"),
    PU_MOTOR(RATINGS_ID_MOTOR_J, motor.J_kgm2, "kg m^2", "2 H P / w_mb^2, H = " PU_STR(PU_H_S) " s"),
    PU_MOTOR(RATINGS_ID_MOTOR_B, motor.B_Nms, "N m s/rad", PU_STR(PU_FRICTION) " P / w_mr^2"),
    PU_CFG(RATINGS_ID_C_DC, c_dc_F, "F", "4 x " PU_STR(PU_C_DC_TAU_S) " s x S_b / vdc^2"),
    PU_CFG(RATINGS_ID_PSI_REF, dtc.psi_ref_Wb, "Wb", "|V_b - Rs I_b e^-j phi| / w_b"),
    PU_CFG(RATINGS_ID_I_TRIP, i_trip_A, "A", "min(" PU_STR(PU_I_TRIP) " I_b, inv_I_peak)"),
    PU_CFG(RATINGS_ID_VDC_MAX, vdc_max_V, "V", PU_STR(PU_VDC_MAX) " vdc"),
    PU_CFG(RATINGS_ID_VDC_MIN, vdc_min_V, "V", PU_STR(PU_VDC_MIN) " vdc"),
    PU_CFG(RATINGS_ID_NP_TRIP, np_trip_V, "V", PU_STR(PU_NP_TRIP) " vdc"),
    PU_CFG(RATINGS_ID_NP_BAND, dtc.np_band_V, "V", PU_STR(PU_NP_BAND) " vdc"),
    PU_CFG(RATINGS_ID_OVERSPEED, overspeed_rad_s, "rad/s", PU_STR(PU_OVERSPEED) " w_mr"),
    PU_CFG(RATINGS_ID_FLUX_BAND, dtc.flux_band_Wb, "Wb", PU_STR(PU_FLUX_BAND) " psi_b"),
    PU_CFG(RATINGS_ID_TORQUE_BAND, dtc.torque_band_Nm, "N m", PU_STR(PU_TORQUE_BAND) " T_r"),
    PU_CFG(RATINGS_ID_TORQUE_BAND2, dtc.torque_band2_Nm, "N m", PU_STR(PU_TORQUE_BAND2) " T_r"),
    PU_CFG(RATINGS_ID_RIPPLE_SPEED_MAX, dtc.ripple_speed_max_rad_s, "rad/s", PU_STR(PU_RIPPLE_SPEED) " w_mr"),
    PU_CFG(RATINGS_ID_OBS_KP_SPEED, obs.kp_speed, "(rad/s)/(A Wb)", PU_STR(PU_OBS_KP) " w_b / (I_b psi_b)"),
    PU_CFG(RATINGS_ID_OBS_KI_SPEED, obs.ki_speed, "(rad/s^2)/(A Wb)", PU_STR(PU_OBS_KI) " 1/s x w_b / (I_b psi_b)"),
    PU_CFG(RATINGS_ID_OBS_REGEN_SPEED, obs.regen_speed_rad_s, "rad/s", PU_STR(PU_OBS_REGEN_SPEED) " w_b"),
    PU_CFG(RATINGS_ID_GUARD_WC, guard.wc_rad_s, "rad/s", PU_STR(PU_GUARD_WC) " w_b"),
    PU_CFG(RATINGS_ID_GUARD_TIME, guard.time_s, "s", PU_STR(PU_GUARD_TIME) " / w_b"),
    PU_CFG(RATINGS_ID_GUARD_V_TOL, guard.v_tol_V, "V", PU_STR(PU_GUARD_V_TOL) " vdc"),
    PU_CFG(RATINGS_ID_BRINGUP_HZ, bringup_hz, "Hz", PU_STR(PU_BRINGUP_HZ) " f"),
    PU_CFG(RATINGS_ID_IP_WN, speed.ip.wn_rad_s, "rad/s", PU_STR(PU_WN_TM) " / t_m, t_m = max(J w_mr / T_r, 0.05 s)"),
    PU_CFG(RATINGS_ID_REF_WN, speed.ref_wn_rad_s, "rad/s", "wn (speed.ip.wn_rad_s)"),
    PU_CFG(RATINGS_ID_NOMINAL_K_X, speed.nominal.k_x, "1/s", PU_STR(PU_K_X_WN) " wn"),
    PU_CFG(RATINGS_ID_RBFN_K, speed.rbfn.k, "1/s", "2 zeta wn"),
    PU_CFG(RATINGS_ID_RBFN_GAMMA_W, speed.rbfn.gamma_w, "1/s^2", PU_STR(PU_GAMMA_W_WN2) " wn^2"),
    PU_CFG(RATINGS_ID_RBFN_GAMMA_ZETA, speed.rbfn.gamma_zeta, "1/s^2", PU_STR(PU_GAMMA_ZETA_WN2) " wn^2"),
    PU_CFG(RATINGS_ID_RBFN_ZETA_LEAK, speed.rbfn.zeta_leak, "1/s", PU_STR(PU_ZETA_LEAK_WN) " wn"),
    PU_CFG(RATINGS_ID_SPEED_RAMP, speed.ramp_rad_s2, "rad/s^2", PU_STR(PU_RAMP) " T_r / J"),
    PU_CFG(RATINGS_ID_RBFN_BOUNDARY, speed.rbfn.boundary_rad_s, "rad/s", PU_STR(PU_RBFN_BOUNDARY) " w_mr"),
    PU_CFG(RATINGS_ID_RBFN_DEAD_ZONE, speed.rbfn.zeta_dead_zone_rad_s, "rad/s", PU_STR(PU_RBFN_DEAD_ZONE) " w_mr"),
    PU_CFG(RATINGS_ID_RBFN_ZETA_MAX, speed.rbfn.zeta_max, "rad/s^2", PU_STR(PU_ZETA_MAX) " T_r / J"),
    PU_CFG(RATINGS_ID_STALL_TIME, stall_time_s, "s", PU_STR(PU_STALL_TIME_TM) " t_m"),
    PU_CFG(RATINGS_ID_SPEED_DEV_BAND, speed_dev_band_rad_s, "rad/s", "w_mb - w_mr (the rated slip speed)"),
    PU_CFG(RATINGS_ID_SPEED_DEV_TIME, speed_dev_time_s, "s", PU_STR(PU_STALL_TIME_TM) " t_m"),
    PU_CFG(RATINGS_ID_TE_MAX, speed.te_max_Nm, "N m",
        "min(" PU_STR(PU_TE_MAX) " T_r, torque at i_trip / 1.5, te_pullout_frac x pull-out at psi_ref)"),
    PU_CFG(RATINGS_ID_RBFN_M_W, speed.rbfn.m_w, "rad/s^2", "1.25 sqrt(n) te_max / J (speed_rbfn_size)"),
    PU_CFG(RATINGS_ID_RBFN_CENTRES, speed.rbfn.centre, "rad/s", "evenly over +-(te_max / J) / sqrt(gamma_w) (speed_rbfn_size)"),
    PU_CFG(RATINGS_ID_RBFN_WIDTHS, speed.rbfn.width, "rad/s", "0.75 x the centres' spacing (speed_rbfn_size)"),
    PU_CFG(RATINGS_ID_PREMAG, dtc.premag_s, "s", "psi_ref / psi_ramp_Wb_s + 10 sigma Tr"),
    PU_MACRO(RATINGS_ID_DROP_BAND, "ctl.c DROP_BAND_A", "A", PU_STR(PU_DROP_BAND) " I_b"),
    PU_MACRO(RATINGS_ID_LOWFLUX_MARGIN, "ctl.c LOWFLUX_MARGIN_RAD_S", "rad/s", PU_STR(PU_LOWFLUX_MARGIN) " w_b"),
    PU_MACRO(RATINGS_ID_LOWFLUX_ENTER, "ctl.c LOWFLUX_ENTER_RAD_S", "rad/s", PU_STR(PU_LOWFLUX_ENTER) " w_b"),
    PU_MACRO(RATINGS_ID_LOWFLUX_EXIT, "ctl.c LOWFLUX_EXIT_RAD_S", "rad/s", PU_STR(PU_LOWFLUX_EXIT) " w_b"),
    PU_MACRO(RATINGS_ID_LOWFLUX_MIN_TE, "ctl.c LOWFLUX_MIN_NM", "N m", PU_STR(PU_LOWFLUX_MIN_TE) " T_r"),
    PU_MACRO(RATINGS_ID_STALL_SPEED_ERR, "ctl.c STALL_SPEED_ERR_RAD_S", "rad/s", PU_STR(PU_STALL_SPEED_ERR) " w_mr"),
    PU_MACRO(RATINGS_ID_STALL_WINDOW, "ctl.c STALL_WINDOW_S", "s", PU_STR(PU_STALL_WINDOW_TM) " t_m"),
    PU_MACRO(RATINGS_ID_BRAKE_STALL_SPEED, "ctl.c BRAKE_STALL_SPEED_RAD_S", "rad/s", PU_STR(PU_BRAKE_STALL_SPEED) " w_mb"),
    PU_MACRO(RATINGS_ID_BRAKE_STALL_TIME, "ctl.c BRAKE_STALL_TIME_S", "s", PU_STR(PU_BRAKE_STALL_TIME_TM) " t_m"),
    PU_MACRO(RATINGS_ID_BRINGUP_BOOST, "ctl.c bringup_step: the V/f boost Rs x 5 A", "A", PU_STR(PU_BRINGUP_BOOST) " I_b"),
    PU_MACRO(RATINGS_ID_OBS_REGEN_MIN_TE, "observer.c REGEN_MIN_NM", "N m", PU_STR(PU_OBS_REGEN_MIN_TE) " T_r"),
    PU_MACRO(RATINGS_ID_RSID_MAX_SPEED, "rs_ident.c RS_IDENT_MAX_SPEED_RAD_S", "rad/s", PU_STR(PU_RSID_MAX_SPEED) " w_b"),
    PU_MACRO(RATINGS_ID_RSID_SPEED_FROM, "rs_ident.c RS_IDENT_SPEED_FROM_S", "s", "psi_ref / psi_ramp_Wb_s + sigma Tr"),
    PU_MACRO(RATINGS_ID_RSID_MIN_CHARGE, "rs_ident.c RS_IDENT_MIN_CHARGE_AS", "A s", PU_STR(PU_RSID_MIN_CHARGE_S) " s x I_b"),
    PU_MACRO(RATINGS_ID_DTC_PSI_TINY, "dtc3l.c PSI_TINY_WB", "Wb", PU_STR(PU_DTC_PSI_TINY) " psi_b"),
    PU_MACRO(RATINGS_ID_PLAUS_SUM_ABS, "plausibility.h PLAUS_SUM_ABS_A", "A", PU_STR(PU_PLAUS_SUM_ABS) " I_b"),
    PU_MACRO(RATINGS_ID_PLAUS_CURRENT, "plausibility.h PLAUS_CURRENT_A", "A", PU_STR(PU_PLAUS_CURRENT) " I_b"),
    PU_MACRO(RATINGS_ID_PLAUS_OPEN, "plausibility.h PLAUS_OPEN_A", "A", PU_STR(PU_PLAUS_OPEN) " I_b"),
    PU_MACRO(RATINGS_ID_PLAUS_PHASE_MIN, "plausibility.h PLAUS_PHASE_MIN_HZ", "Hz", PU_STR(PU_PLAUS_PHASE_MIN) " f"),
};

ratings_id ratings_id_at(size_t offset)
{
    for (int i = 0; i < (int)RATINGS_ID_COUNT; i++) {
        size_t off = ratings_derivables[i].cfg_offset;
        size_t len = sizeof(real_t);
        if (i == (int)RATINGS_ID_RBFN_CENTRES || i == (int)RATINGS_ID_RBFN_WIDTHS)
            len = (size_t)RBFN_NODES_MAX * sizeof(real_t);
        if (off != RATINGS_NO_FIELD && offset >= off && offset < off + len)
            return (ratings_id)i;
    }
    return RATINGS_ID_COUNT;
}

ratings_error ratings_prepare(ratings_derivation *d, const ratings *r)
{
    ratings_error e = ratings_check(r);
    if (e.reason != RATINGS_OK)
        return e;
    d->plate = *r;
    ratings_base_of(r, &d->base);
    ratings_motor_estimate(r, &d->base, &d->estimate);
    ratings_reference(&d->ref_plate, &d->ref_model);
    ratings_base_of(&d->ref_plate, &d->ref_base);
    return e;
}

/* The reference drive's tuned values (ctl_cfg_default's until the ratings;
 * why each: the PU_ comments above). Each derived value is one of them times
 * the ratio of the plate's base to the reference plate's: the per-unit
 * constant PU_ computed from the same float operations, so the reference
 * plate gives these values exactly (a ratio of equal numbers is 1). */
#define REF_C_DC_F R(2.2e-3)
#define REF_PSI_REF_WB R(0.45)         /* rated stator flux */
#define REF_I_TRIP_A R(100.0)
#define REF_VDC_MAX_V R(400.0)
#define REF_VDC_MIN_V R(200.0)
#define REF_NP_TRIP_V R(30.0)
#define REF_NP_BAND_V R(1.5)
#define REF_OVERSPEED_RAD_S R(310.0)   /* 2960 rpm: its reference limit 310 / 1.1 = 2691 rpm is above 1.5 x base */
#define REF_FLUX_BAND_WB R(0.01)
#define REF_TORQUE_BAND_NM R(3.5)      /* about 850 Hz device switching at 500 rpm */
#define REF_TORQUE_BAND2_NM R(8.0)
#define REF_RIPPLE_SPEED_RAD_S R(200.0) /* 1900 rpm: the whole speed range */
#define REF_OBS_KP R(50.0)
#define REF_OBS_KI R(2000.0)
#define REF_OBS_REGEN_SPEED_RAD_S R(100.0) /* 477 rpm: fades out below the paper's 500 rpm point */
#define REF_GUARD_WC_RAD_S R(6.0)      /* 1 Hz */
#define REF_GUARD_TIME_S R(0.01)
#define REF_GUARD_V_TOL_V R(6.0)       /* two device drops of ~1 V (2.7 V as a vector) plus dead time, x2 margin */
#define REF_BRINGUP_HZ R(5.0)
#define REF_WN_RAD_S R(10.0)
#define REF_K_X R(40.0)
#define REF_GAMMA_W R(4000.0)
#define REF_GAMMA_ZETA R(1000.0)
#define REF_ZETA_LEAK R(0.5)
#define REF_RAMP_RAD_S2 R(100.0)
#define REF_RBFN_BOUNDARY_RAD_S R(1.0)
#define REF_RBFN_DEAD_ZONE_RAD_S R(1.0)
#define REF_ZETA_MAX R(200.0)
#define REF_STALL_TIME_S R(1.0)        /* longer than a full-power load recovery in field weakening */
/* Speed deviation: the band the rated slip speed (1800 - 1744 rpm = 5.86 rad/s: a controller with
 * integral action holds the speed well inside it; the nominal controller's lasting error under a
 * load T is T / (J K_x), 11 rad/s at 20 N m), the time the stall's (5 t_m). */
#define REF_SPEED_DEV_BAND_RAD_S R(5.86)
#define REF_SPEED_DEV_TIME_S R(1.0)
#define REF_TE_MAX_NM R(80.0)          /* 2 x rated torque, below the 88 N m pull-out */
#define REF_PREMAG_S R(0.3)            /* the flux ramp (0.13 s) + a few sigma Tr */
#define REF_DROP_BAND_A R(0.5)
#define REF_LOWFLUX_MARGIN_RAD_S R(2.5)
#define REF_LOWFLUX_ENTER_RAD_S R(6.3)
#define REF_LOWFLUX_EXIT_RAD_S R(8.8)
#define REF_LOWFLUX_MIN_NM R(2.0)
#define REF_STALL_SPEED_ERR_RAD_S R(3.0)
#define REF_STALL_WINDOW_S R(0.1)
#define REF_BRAKE_STALL_SPEED_RAD_S R(50.0)
#define REF_BRAKE_STALL_TIME_S R(0.1)
#define REF_BRINGUP_BOOST_A R(5.0)
#define REF_OBS_REGEN_MIN_NM R(2.0)
#define REF_RSID_MAX_SPEED_RAD_S R(2.0)
#define REF_RSID_SPEED_FROM_S R(0.15)
#define REF_RSID_MIN_CHARGE_AS R(0.2)
#define REF_DTC_PSI_TINY_WB R(0.001)
#define REF_PLAUS_SUM_ABS_A R(5.0)
#define REF_PLAUS_CURRENT_A R(3.0)
#define REF_PLAUS_OPEN_A R(0.5)
#define REF_PLAUS_PHASE_MIN_HZ R(2.0)

/* ref x base / ref_base */
static real_t scaled(real_t ref, real_t base, real_t ref_base) { return num_mul(ref, num_div(base, ref_base)); }

/* sigma and Tr of the model in use */
static real_t sigma_of(const motor_model *m)
{
    return R(1.0) - num_div(num_mul(m->Lm_H, m->Lm_H), num_mul(m->Ls_H, m->Lr_H));
}

/* The mechanical time constant the speed loop is scaled by: J w_mr / T_r, s (ratings.h IP_WN). */
static real_t t_mech_s(const ratings_base *b, real_t J_kgm2)
{
    real_t t = num_div(num_mul(J_kgm2, b->w_mr), b->T_r);
    return t > PU_T_M_MIN_S ? t : PU_T_M_MIN_S;
}

/* The torque of the current @p i_A (peak) at the flux reference, the rotor
 * flux psi_ref Lm / Ls (the no-load value, as ctl_cfg_derive's slip). */
static real_t torque_at_current(const ctl_cfg *cfg, real_t i_A)
{
    const motor_model *m = &cfg->motor;
    real_t psi_r = num_div(num_mul(cfg->dtc.psi_ref_Wb, m->Lm_H), m->Ls_H);
    real_t i_d = num_div(cfg->dtc.psi_ref_Wb, m->Ls_H);
    real_t i_q = num_sqrt(num_mul(i_A, i_A) - num_mul(i_d, i_d));
    real_t kt = num_mul(num_mul(R(1.5), m->pole_pairs), num_div(m->Lm_H, m->Lr_H));
    return num_mul(num_mul(kt, psi_r), i_q);
}

/* The flux ramp's time psi_ref / rate, the rate ctl_cfg_derive's: the
 * magnetising current's transient at most a fifth of i_trip, s. */
static real_t flux_ramp_s(const motor_model *m, real_t psi_ref_Wb, real_t i_trip_A)
{
    real_t tr = num_div(m->Lr_H, m->Rr_ohm);
    real_t a_per_wb_s = num_div(num_mul(R(1.0) - sigma_of(m), tr), m->Ls_H);
    real_t rate = num_div(num_mul(R(0.2), i_trip_A), a_per_wb_s);
    return rate > R(0.0) ? num_div(psi_ref_Wb, rate) : R(0.0);
}

/* The flux ramp plus k sigma Tr: the magnetising time (k = 10) and the Rs
 * identification's start (k = 1), s. */
static real_t magnetising_s(const motor_model *m, real_t psi_ref_Wb, real_t i_trip_A, real_t k)
{
    real_t tr = num_div(m->Lr_H, m->Rr_ohm);
    return flux_ramp_s(m, psi_ref_Wb, i_trip_A) + num_mul(num_mul(k, sigma_of(m)), tr);
}

/* The stator flux at the rated point: |V_b - Rs I_b e^-j phi| / w_b, Wb. */
static real_t rated_flux_Wb(const ratings_base *b, real_t Rs_ohm)
{
    real_t ri = num_mul(Rs_ohm, b->I_b);
    real_t re = b->V_b - num_mul(ri, b->cos_phi);
    real_t im = num_mul(ri, num_sqrt(R(1.0) - num_mul(b->cos_phi, b->cos_phi)));
    return num_div(num_sqrt(num_mul(re, re) + num_mul(im, im)), b->w_b);
}

/* The RBFN sized by speed_rbfn_size for the torque limit and J in @p cfg. */
static void rbfn_sized(const ctl_cfg *cfg, rbfn_cfg *r)
{
    *r = cfg->speed.rbfn;
    speed_rbfn_size(r, cfg->speed.te_max_Nm, cfg->motor.J_kgm2);
}

real_t ratings_value(const ratings_derivation *d, const ctl_cfg *cfg, ratings_id id)
{
    const ratings *r = &d->plate;
    const ratings_base *b = &d->base;
    const ratings_base *rb0 = &d->ref_base;
    const motor_model *m0 = &d->ref_model;
    const motor_model *est = &d->estimate;
    const motor_model *m = &cfg->motor;
    real_t wn = cfg->speed.ip.wn_rad_s;
    real_t wn_ratio = num_div(wn, REF_WN_RAD_S);
    real_t tm_ratio = num_div(t_mech_s(b, m->J_kgm2), t_mech_s(rb0, m0->J_kgm2));
    real_t accel_ratio = num_div(num_div(b->T_r, m->J_kgm2), num_div(rb0->T_r, m0->J_kgm2));
    real_t obs_ratio = num_div(num_div(b->w_b, num_mul(b->I_b, b->psi_b)),
                               num_div(rb0->w_b, num_mul(rb0->I_b, rb0->psi_b)));
    rbfn_cfg rb;
    switch (id) {
    case RATINGS_ID_MOTOR_RS: return est->Rs_ohm;
    case RATINGS_ID_MOTOR_RR: return est->Rr_ohm;
    case RATINGS_ID_MOTOR_LM: return est->Lm_H;
    case RATINGS_ID_MOTOR_LS: return m->Lm_H + (est->Ls_H - est->Lm_H); /* the estimate's leakage on the Lm in use */
    case RATINGS_ID_MOTOR_LR: return m->Lm_H + (est->Lr_H - est->Lm_H);
    case RATINGS_ID_MOTOR_J: return est->J_kgm2;
    case RATINGS_ID_MOTOR_B: return est->B_Nms;
    case RATINGS_ID_C_DC:
        return scaled(REF_C_DC_F, num_div(b->S_b, num_mul(b->vdc_b, b->vdc_b)),
                      num_div(rb0->S_b, num_mul(rb0->vdc_b, rb0->vdc_b)));
    case RATINGS_ID_PSI_REF:
        /* the rated point's stator flux, less the reference's 0.7 % below its own */
        return scaled(REF_PSI_REF_WB, rated_flux_Wb(b, m->Rs_ohm), rated_flux_Wb(rb0, m0->Rs_ohm));
    case RATINGS_ID_I_TRIP: {
        real_t i = scaled(REF_I_TRIP_A, b->I_b, rb0->I_b);
        return i < r->inv_I_peak_A ? i : r->inv_I_peak_A;
    }
    case RATINGS_ID_VDC_MAX: return scaled(REF_VDC_MAX_V, b->vdc_b, rb0->vdc_b);
    case RATINGS_ID_VDC_MIN: return scaled(REF_VDC_MIN_V, b->vdc_b, rb0->vdc_b);
    case RATINGS_ID_NP_TRIP: return scaled(REF_NP_TRIP_V, b->vdc_b, rb0->vdc_b);
    case RATINGS_ID_NP_BAND: return scaled(REF_NP_BAND_V, b->vdc_b, rb0->vdc_b);
    case RATINGS_ID_OVERSPEED: return scaled(REF_OVERSPEED_RAD_S, b->w_mr, rb0->w_mr);
    case RATINGS_ID_FLUX_BAND: return scaled(REF_FLUX_BAND_WB, b->psi_b, rb0->psi_b);
    case RATINGS_ID_TORQUE_BAND: return scaled(REF_TORQUE_BAND_NM, b->T_r, rb0->T_r);
    case RATINGS_ID_TORQUE_BAND2: return scaled(REF_TORQUE_BAND2_NM, b->T_r, rb0->T_r);
    case RATINGS_ID_RIPPLE_SPEED_MAX: return scaled(REF_RIPPLE_SPEED_RAD_S, b->w_mr, rb0->w_mr);
    case RATINGS_ID_OBS_KP_SPEED: return num_mul(REF_OBS_KP, obs_ratio);
    case RATINGS_ID_OBS_KI_SPEED: return num_mul(REF_OBS_KI, obs_ratio);
    case RATINGS_ID_OBS_REGEN_SPEED: return scaled(REF_OBS_REGEN_SPEED_RAD_S, b->w_b, rb0->w_b);
    case RATINGS_ID_GUARD_WC: return scaled(REF_GUARD_WC_RAD_S, b->w_b, rb0->w_b);
    case RATINGS_ID_GUARD_TIME: return scaled(REF_GUARD_TIME_S, rb0->w_b, b->w_b);
    case RATINGS_ID_GUARD_V_TOL: return scaled(REF_GUARD_V_TOL_V, b->vdc_b, rb0->vdc_b);
    case RATINGS_ID_BRINGUP_HZ: return scaled(REF_BRINGUP_HZ, r->f_Hz, d->ref_plate.f_Hz);
    case RATINGS_ID_IP_WN: return num_div(REF_WN_RAD_S, tm_ratio);
    case RATINGS_ID_REF_WN: return wn;
    case RATINGS_ID_NOMINAL_K_X: return num_mul(REF_K_X, wn_ratio);
    case RATINGS_ID_RBFN_K: return num_mul(R(2.0) * cfg->speed.ip.zeta, wn);
    case RATINGS_ID_RBFN_GAMMA_W: return num_mul(REF_GAMMA_W, num_mul(wn_ratio, wn_ratio));
    case RATINGS_ID_RBFN_GAMMA_ZETA: return num_mul(REF_GAMMA_ZETA, num_mul(wn_ratio, wn_ratio));
    case RATINGS_ID_RBFN_ZETA_LEAK: return num_mul(REF_ZETA_LEAK, wn_ratio);
    case RATINGS_ID_SPEED_RAMP: return num_mul(REF_RAMP_RAD_S2, accel_ratio);
    case RATINGS_ID_RBFN_BOUNDARY: return scaled(REF_RBFN_BOUNDARY_RAD_S, b->w_mr, rb0->w_mr);
    case RATINGS_ID_RBFN_DEAD_ZONE: return scaled(REF_RBFN_DEAD_ZONE_RAD_S, b->w_mr, rb0->w_mr);
    case RATINGS_ID_RBFN_ZETA_MAX: return num_mul(REF_ZETA_MAX, accel_ratio);
    case RATINGS_ID_STALL_TIME: return num_mul(REF_STALL_TIME_S, tm_ratio);
    case RATINGS_ID_SPEED_DEV_BAND: return scaled(REF_SPEED_DEV_BAND_RAD_S, b->w_mb - b->w_mr, rb0->w_mb - rb0->w_mr);
    case RATINGS_ID_SPEED_DEV_TIME: return num_mul(REF_SPEED_DEV_TIME_S, tm_ratio);
    case RATINGS_ID_TE_MAX: {
        real_t te = scaled(REF_TE_MAX_NM, b->T_r, rb0->T_r);
        real_t te_i = torque_at_current(cfg, num_div(cfg->i_trip_A, PU_TE_CURRENT_MARGIN));
        real_t te_po = num_mul(cfg->te_limit_Nm_Wb2, num_mul(cfg->dtc.psi_ref_Wb, cfg->dtc.psi_ref_Wb));
        te = te_i < te ? te_i : te;
        return te_po < te ? te_po : te;
    }
    case RATINGS_ID_RBFN_M_W: rbfn_sized(cfg, &rb); return rb.m_w;
    case RATINGS_ID_RBFN_CENTRES: rbfn_sized(cfg, &rb); return rb.centre[rb.n_nodes >= 1u && rb.n_nodes <= RBFN_NODES_MAX ? rb.n_nodes - 1u : 0u];
    case RATINGS_ID_RBFN_WIDTHS: rbfn_sized(cfg, &rb); return rb.width[0];
    case RATINGS_ID_PREMAG:
        return scaled(REF_PREMAG_S, magnetising_s(m, cfg->dtc.psi_ref_Wb, cfg->i_trip_A, PU_PREMAG_SIGMA_TR),
                      magnetising_s(m0, REF_PSI_REF_WB, REF_I_TRIP_A, PU_PREMAG_SIGMA_TR));
    case RATINGS_ID_DROP_BAND: return scaled(REF_DROP_BAND_A, b->I_b, rb0->I_b);
    case RATINGS_ID_LOWFLUX_MARGIN: return scaled(REF_LOWFLUX_MARGIN_RAD_S, b->w_b, rb0->w_b);
    case RATINGS_ID_LOWFLUX_ENTER: return scaled(REF_LOWFLUX_ENTER_RAD_S, b->w_b, rb0->w_b);
    case RATINGS_ID_LOWFLUX_EXIT: return scaled(REF_LOWFLUX_EXIT_RAD_S, b->w_b, rb0->w_b);
    case RATINGS_ID_LOWFLUX_MIN_TE: return scaled(REF_LOWFLUX_MIN_NM, b->T_r, rb0->T_r);
    case RATINGS_ID_STALL_SPEED_ERR: return scaled(REF_STALL_SPEED_ERR_RAD_S, b->w_mr, rb0->w_mr);
    case RATINGS_ID_STALL_WINDOW: return num_mul(REF_STALL_WINDOW_S, tm_ratio);
    case RATINGS_ID_BRAKE_STALL_SPEED: return scaled(REF_BRAKE_STALL_SPEED_RAD_S, b->w_mb, rb0->w_mb);
    case RATINGS_ID_BRAKE_STALL_TIME: return num_mul(REF_BRAKE_STALL_TIME_S, tm_ratio);
    case RATINGS_ID_BRINGUP_BOOST: return scaled(REF_BRINGUP_BOOST_A, b->I_b, rb0->I_b);
    case RATINGS_ID_OBS_REGEN_MIN_TE: return scaled(REF_OBS_REGEN_MIN_NM, b->T_r, rb0->T_r);
    case RATINGS_ID_RSID_MAX_SPEED: return scaled(REF_RSID_MAX_SPEED_RAD_S, b->w_b, rb0->w_b);
    case RATINGS_ID_RSID_SPEED_FROM:
        return scaled(REF_RSID_SPEED_FROM_S, magnetising_s(m, cfg->dtc.psi_ref_Wb, cfg->i_trip_A, R(1.0)),
                      magnetising_s(m0, REF_PSI_REF_WB, REF_I_TRIP_A, R(1.0)));
    case RATINGS_ID_RSID_MIN_CHARGE: return scaled(REF_RSID_MIN_CHARGE_AS, b->I_b, rb0->I_b);
    case RATINGS_ID_DTC_PSI_TINY: return scaled(REF_DTC_PSI_TINY_WB, b->psi_b, rb0->psi_b);
    case RATINGS_ID_PLAUS_SUM_ABS: return scaled(REF_PLAUS_SUM_ABS_A, b->I_b, rb0->I_b);
    case RATINGS_ID_PLAUS_CURRENT: return scaled(REF_PLAUS_CURRENT_A, b->I_b, rb0->I_b);
    case RATINGS_ID_PLAUS_OPEN: return scaled(REF_PLAUS_OPEN_A, b->I_b, rb0->I_b);
    case RATINGS_ID_PLAUS_PHASE_MIN: return scaled(REF_PLAUS_PHASE_MIN_HZ, r->f_Hz, d->ref_plate.f_Hz);
    case RATINGS_ID_COUNT:
    default: return R(0.0);
    }
}

/* Write ids [from, to) that have a scalar field and are not set. */
static void derive_range(ctl_cfg *cfg, const ratings_derivation *d, const ratings_mask *set, ratings_id from,
                         ratings_id to)
{
    for (int i = (int)from; i < (int)to; i++) {
        ratings_id id = (ratings_id)i;
        size_t off = ratings_derivables[id].cfg_offset;
        if (off == RATINGS_NO_FIELD || ratings_mask_has(set, id))
            continue;
        real_t v = ratings_value(d, cfg, id);
        memcpy((unsigned char *)cfg + off, &v, sizeof v);
    }
}

ratings_error ratings_derive_cfg(ctl_cfg *cfg, const ratings *r, const ratings_mask *set)
{
    ratings_derivation d;
    ratings_error e = ratings_prepare(&d, r);
    if (e.reason != RATINGS_OK)
        return e;
    ratings_mask none;
    memset(&none, 0, sizeof none);
    if (set == NULL)
        set = &none;
    /* The observer follows electrical speeds up to 0.3 / period (observer.h):
     * the overspeed trip's must be within it. */
    real_t overspeed = ratings_mask_has(set, RATINGS_ID_OVERSPEED) ? cfg->overspeed_rad_s
                                                                   : ratings_value(&d, cfg, RATINGS_ID_OVERSPEED);
    if (num_mul(num_mul(overspeed, d.base.pole_pairs), cfg->period_s) > R(0.3))
        return plate_error(RATINGS_FIELD_F_HZ, RATINGS_E_PERIOD);

    cfg->motor.pole_pairs = d.base.pole_pairs;
    cfg->vdc_nom_V = r->vdc_nom_V;
    derive_range(cfg, &d, set, RATINGS_ID_MOTOR_RS, RATINGS_ID_TE_MAX);
    ctl_cfg_derive(cfg); /* the pull-out per Wb^2 and the flux ramp of the values so far */
    derive_range(cfg, &d, set, RATINGS_ID_TE_MAX, RATINGS_ID_RBFN_M_W);
    rbfn_cfg rb;
    rbfn_sized(cfg, &rb);
    if (!ratings_mask_has(set, RATINGS_ID_RBFN_M_W))
        cfg->speed.rbfn.m_w = rb.m_w;
    if (!ratings_mask_has(set, RATINGS_ID_RBFN_CENTRES))
        memcpy(cfg->speed.rbfn.centre, rb.centre, sizeof rb.centre);
    if (!ratings_mask_has(set, RATINGS_ID_RBFN_WIDTHS))
        memcpy(cfg->speed.rbfn.width, rb.width, sizeof rb.width);
    derive_range(cfg, &d, set, RATINGS_ID_PREMAG, RATINGS_ID_DROP_BAND);
    ctl_cfg_derive(cfg);
    return e;
}

#undef PU_R
#undef PU_STR_
#undef PU_STR
#undef PU_SQRT2
#undef PU_FIELD
#undef PU_ENTRY
#undef PU_CFG
#undef PU_MOTOR
#undef PU_MACRO
