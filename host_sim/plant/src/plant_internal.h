/**
 * @file plant_internal.h
 * @brief Shared pieces of the plant implementation (not part of the API).
 *
 * The integrator works on a flat state vector x[PX_N]; every model file
 * contributes a part of its derivative. Coefficients that are constant over
 * one switching segment are gathered once in plant_seg so the derivative,
 * evaluated four times per RK4 step, does only multiply-adds.
 */
#ifndef PLANT_INTERNAL_H
#define PLANT_INTERNAL_H

#include <math.h>
#include <stddef.h>

#include "plant/plant.h"

/*
 * Internal leg codes beyond the API's 0..3: a leg inside the dead time of a
 * commutation between two adjacent levels (dead_time.c). Like gates off, its
 * current picks the level through the diodes: i > 0 (into the motor) the
 * lower one, i < 0 the upper one; zero current floats between the two.
 */
#define PLANT_LEG_DEAD_NO 4u /* between N and O */
#define PLANT_LEG_DEAD_OP 5u /* between O and P */
/* A disconnected motor phase (plant_set_phase_open): never conducts. */
#define PLANT_LEG_OPEN 6u

/* Integration state vector layout. */
enum {
    PX_PSA = 0, PX_PSB,  /* stator flux alpha, beta, Wb */
    PX_PRA, PX_PRB,      /* rotor flux alpha, beta, Wb */
    PX_W,                /* mechanical speed, rad/s */
    PX_TH,               /* mechanical angle, rad (unwrapped inside a period) */
    PX_VC1, PX_VC2,      /* capacitor voltages, V */
    PX_EIN, PX_ECU, PX_EMECH, /* energy accumulators, J */
    PX_N
};

#define PLANT_SQRT3 1.7320508075688772935
#define PLANT_INV_SQRT3 0.57735026918962576451
#define PLANT_TWO_PI 6.283185307179586477

/** Per-segment coefficients: machine, DC link and how the supply drives the stator. */
typedef struct {
    /* machine: i_s = cLr psi_s - cLm psi_r, i_r = cLs psi_r - cLm psi_s */
    double cLr, cLm, cLs;   /* Lr/D, Lm/D, Ls/D with D = Ls Lr - Lm^2, 1/H */
    double lm_lr;           /* Lm/Lr: rotor-flux emf seen by the stator */
    double d_lr;            /* D/Lr = sigma Ls, H: stator flux per stator current at fixed psi_r */
    double Rs, Rr, p;       /* ohm, ohm, pole pairs */
    /* main-flux saturation (induction_machine.c); sat = 0: the linear maps above */
    int sat;
    double inv_Lls, inv_Llr, inv_Lm0, inv_psik, sat_n;
    double inv_J, B, TL;    /* 1/(kg m^2), N m s/rad, N m */
    /* load models besides TL (load_model.c); load_ext = 0 skips them */
    int load_ext;
    double Tc, Bv, kf;      /* Coulomb N m, viscous N m s/rad, fan N m s^2/rad^2 */
    int coul_dir;           /* Coulomb direction for this step: +1, -1, 0 = stuck */
    /* DC link */
    double vdc, inv_r, inv_c1, inv_c2;
    /* supply: sine source, or inverter as a linear map from (vc1, vc2) */
    int sine;
    double v_pk, w_e, phase; /* sine: phase peak V, rad/s, rad */
    /* inverter, all legs connected: v_s = (va1 vc1 - va2 vc2, vb1 vc1 - vb2 vc2),
     * i_P = gP . i_s, i_N = gN . i_s (alpha-beta) */
    double va1, va2, vb1, vb2;
    double gP[2], gN[2];
    /* per-leg connection for this step: +1 at P, -1 at N, 0 at O, 2 floating */
    signed char conn[3];
    unsigned char diode[3]; /* 1: gates off or dead time, conducting through its diodes */
    signed char dsign[3];   /* diode legs: the current sign the diodes carry (+1, -1) */
    signed char lo[3], hi[3]; /* diode legs: the levels the diodes can reach (conn codes) */
    int n_float;            /* number of floating legs (slow path when > 0) */
    /* on-state voltage: leg voltage = level - vdrop[k], vdrop = 2 v_on sgn(i_k) at the step start */
    double v_on2;           /* 2 v_on: two devices conduct in every NPC path, V */
    int has_drop;           /* v_on2 > 0 */
    double vdrop[3];        /* per-leg drop, V */
    double dvs[2];          /* alpha-beta of -vdrop (common mode removed), V */
} plant_seg;

/* Unit vectors of the phase axes in alpha-beta (amplitude-invariant: x_k = u_k . x_ab). */
static const double plant_u[3][2] = {
    {1.0, 0.0}, {-0.5, 0.5 * PLANT_SQRT3}, {-0.5, -0.5 * PLANT_SQRT3}};

/* --- load_model.c --- */
/** Fill the load-model coefficients of @p g. */
void plant_load_coeffs(const plant_load_params *l, plant_seg *g);
/**
 * Coulomb + viscous + fan torque at speed @p w, N m (opposing positive w).
 * The Coulomb direction is decided once per step (plant_load_decide), like
 * the diodes' state, so the RK4 stages of a step that reaches zero speed do
 * not see the sign flip. Stuck (coul_dir = 0): the friction balances
 * @p t_drive (every other torque on the shaft, Te - B w - T_L) up to its level.
 */
static inline double plant_load_extra(const plant_seg *g, double w, double t_drive)
{
    double tc;
    if (g->coul_dir != 0)
        tc = g->coul_dir > 0 ? g->Tc : -g->Tc;
    else
        tc = t_drive > g->Tc ? g->Tc : (t_drive < -g->Tc ? -g->Tc : t_drive);
    return tc + g->Bv * w + g->kf * w * fabs(w);
}
/**
 * Before a step: the Coulomb direction is the sign of the speed; a stopped
 * rotor stays stuck unless the other torques pass the Coulomb level, and
 * then moves their way.
 */
void plant_load_decide(plant_seg *g, const double *x);
/**
 * After a step: a Coulomb friction cannot reverse the rotor, so a speed that
 * reached or crossed zero inside the step stops at zero (error O(h) on the
 * stopping instant); from there plant_load_decide holds it or lets it go.
 */
void plant_load_stop(const plant_seg *g, double *x);

/* --- induction_machine.c --- */
/** Fill the machine and mechanical coefficients of @p g from @p m and the load. */
void plant_im_coeffs(const plant_motor_params *m, double t_load_Nm, plant_seg *g);
/*
 * The derivative pieces below are evaluated four times per RK4 step (about
 * a million times per simulated 5 s), so they are static inline here rather
 * than in their .c files: the integrator compiles to straight-line code.
 */

/** Currents with a saturating Lm (induction_machine.c). */
void plant_im_currents_sat(const plant_seg *g, const double *x, double i_s[2], double i_r[2]);

/** Stator and rotor currents (alpha-beta, A) from the fluxes in @p x. */
static inline void plant_im_currents(const plant_seg *g, const double *x,
                                     double i_s[2], double i_r[2])
{
    if (g->sat) {
        plant_im_currents_sat(g, x, i_s, i_r);
        return;
    }
    i_s[0] = g->cLr * x[PX_PSA] - g->cLm * x[PX_PRA];
    i_s[1] = g->cLr * x[PX_PSB] - g->cLm * x[PX_PRB];
    i_r[0] = g->cLs * x[PX_PRA] - g->cLm * x[PX_PSA];
    i_r[1] = g->cLs * x[PX_PRB] - g->cLm * x[PX_PSB];
}

/**
 * Machine, mechanics and energy derivatives for stator voltage @p v_s
 * (alpha-beta, V). Writes dx[PX_PSA..PX_TH] and dx[PX_EIN..PX_EMECH].
 * Equations: see induction_machine.c.
 */
static inline void plant_im_rhs(const plant_seg *restrict g, const double *restrict x,
                                const double *restrict i_s, const double *restrict i_r,
                                const double *restrict v_s, double *restrict dx)
{
    double w = x[PX_W];
    double pw = g->p * w;
    double te = 1.5 * g->p * (x[PX_PSA] * i_s[1] - x[PX_PSB] * i_s[0]);

    dx[PX_PSA] = v_s[0] - g->Rs * i_s[0];
    dx[PX_PSB] = v_s[1] - g->Rs * i_s[1];
    dx[PX_PRA] = -g->Rr * i_r[0] - pw * x[PX_PRB];
    dx[PX_PRB] = -g->Rr * i_r[1] + pw * x[PX_PRA];
    double tl = g->TL;
    if (g->load_ext)
        tl += plant_load_extra(g, w, te - g->B * w - g->TL);
    dx[PX_W] = (te - g->B * w - tl) * g->inv_J;
    dx[PX_TH] = w;
    dx[PX_EIN] = 1.5 * (v_s[0] * i_s[0] + v_s[1] * i_s[1]);
    dx[PX_ECU] = 1.5 * (g->Rs * (i_s[0] * i_s[0] + i_s[1] * i_s[1]) +
                        g->Rr * (i_r[0] * i_r[0] + i_r[1] * i_r[1]));
    dx[PX_EMECH] = te * w;
}
/** Stator emf (Lm/Lr) dpsi_r/dt in alpha-beta, V: what an open stator would show. */
void plant_im_emf(const plant_seg *g, const double *x, const double i_r[2], double e[2]);
/** Magnetic energy 0.75 (psi_s . i_s + psi_r . i_r), J. */
double plant_im_wmag(const double *x, const double i_s[2], const double i_r[2]);
/** Electromagnetic torque, N m. */
double plant_im_torque(const plant_seg *g, const double *x, const double i_s[2]);

/* --- npc_inverter.c --- */
/**
 * Decide every leg's connection for the next step: driven legs as coded,
 * gates-off and dead-time legs (codes 3..5) from their current sign or, with
 * zero current, floating unless their open-circuit voltage would pass one of
 * the two levels their diodes reach. Fills g->conn, g->n_float, the linear
 * maps and the on-state drops (sign of each current at this instant).
 */
void plant_npc_connect(plant_seg *g, const uint8_t legs[3], const double *x);
/** Stator voltage (alpha-beta) and rail currents i_P, i_N for the state @p x. */
void plant_npc_drive(const plant_seg *g, const double *x, const double i_s[2],
                     const double i_r[2], double v_s[2], double *i_P, double *i_N);
/** plant_npc_drive when every leg is connected (g->n_float == 0): a linear map. */
static inline void plant_npc_drive_connected(const plant_seg *g, const double *x,
                                             const double i_s[2], double v_s[2],
                                             double *i_P, double *i_N)
{
    v_s[0] = g->va1 * x[PX_VC1] - g->va2 * x[PX_VC2];
    v_s[1] = g->vb1 * x[PX_VC1] - g->vb2 * x[PX_VC2];
    if (g->has_drop) {
        v_s[0] += g->dvs[0];
        v_s[1] += g->dvs[1];
    }
    *i_P = g->gP[0] * i_s[0] + g->gP[1] * i_s[1];
    *i_N = g->gN[0] * i_s[0] + g->gN[1] * i_s[1];
}
/** Phase-to-star voltages and NP current in the present connection (for the truth). */
void plant_npc_phase(const plant_seg *g, const double *x, const double i_s[2],
                     const double i_r[2], double v_abc[3], double *i_np);
/**
 * After a step: legs conducting through diodes whose current reversed, and
 * floating legs, get their current set to exactly zero (projection of i_s,
 * correcting the stator leakage flux in @p x).
 */
void plant_npc_clamp(const plant_seg *g, double *x);

/* --- dead_time.c --- */
/* Segments shorter than this (s) are not applied: no step, no commutation. */
#define PLANT_MIN_SEGMENT_S 1e-12
/**
 * A vector @p legs is applied from absolute time @p t_s (after the one in
 * s->legs_last): every leg that commutates between two driven levels starts
 * its blanking interval.
 */
void plant_dead_edge(plant_state *s, const uint8_t legs[3], double t_s);
/**
 * Effective leg codes from @p t_s on for the commanded @p cmd: legs inside
 * their blanking interval get its dead code. @return the end of the first
 * blanking interval before @p t_end_s (then the codes change), else t_end_s.
 */
double plant_dead_legs(const plant_state *s, const uint8_t cmd[3], double t_s, double t_end_s, uint8_t eff[3]);

/* --- dc_link.c --- */
/** Capacitor derivatives for rail currents i_P, i_N drawn by the inverter (see dc_link.c). */
static inline void plant_dc_rhs(const plant_seg *restrict g, const double *restrict x,
                                double i_P, double i_N, double *restrict dx)
{
    double i_src = (g->vdc - x[PX_VC1] - x[PX_VC2]) * g->inv_r;
    dx[PX_VC1] = (i_src - i_P) * g->inv_c1;
    dx[PX_VC2] = (i_src + i_N) * g->inv_c2;
}
/** Fill the DC-link coefficients of @p g. */
void plant_dc_coeffs(const plant_dc_params *d, plant_seg *g);

/* --- sensors.c --- */
/** Reseed the noise generator. */
void plant_rng_seed(plant_state *s, uint32_t seed);

#endif /* PLANT_INTERNAL_H */
