/**
 * @file npc_inverter.c
 * @brief Three-level neutral-point-clamped inverter: leg voltages, motor phase
 *        voltages for an isolated star, rail and neutral-point currents, and
 *        the diode behaviour of legs whose gates are off.
 *
 * A leg's output relative to the neutral point O is +vc1 at P, 0 at O and
 * -vc2 at N, less the on-state drop 2 v_on sgn(i) when configured (two
 * devices conduct in every path of an NPC leg: T1 T2 or D1 D2 at P, a clamp
 * diode and T2 or T3 at O, T3 T4 or D3 D4 at N). Dead time (dead_time.c)
 * reaches this file as legs in codes 4 and 5, handled like gates off but
 * between two adjacent levels. The star point n of the
 * motor is isolated, so with all legs connected the phase voltages are the leg
 * voltages less their mean (the common mode): v_a = v_aO - (v_aO+v_bO+v_cO)/3.
 * Currents are positive into the motor; a leg at P draws its phase current
 * from the P rail (i_P), at N from the N rail (i_N), at O from the neutral
 * point (i_np = sum of the O legs' currents).
 *
 * Floating legs (gates off, zero current): the phase carries no current and
 * its voltage is whatever the machine imposes, v_k = e_k (the stator emf
 * (Lm/Lr) dpsi_r/dt on that axis). The connected legs C then share the star
 * point: with zero current change in the floating phases and a zero current
 * sum, sum over C of di_k/dt = 0 gives v_nO = sum_C (v_kO - e_k) / |C|. With
 * fewer than two connected legs no current can flow: v_k = e_k for all.
 */
#include <stddef.h>

#include "plant_internal.h"

/* A gates-off current below this is zero (A): the leg floats. */
#define NPC_I_ZERO_A 1e-9

/* Amplitude-invariant Clarke rows for a zero-sum triple. */
static const double clarke_a[3] = {2.0 / 3.0, -1.0 / 3.0, -1.0 / 3.0};
static const double clarke_b[3] = {0.0, PLANT_INV_SQRT3, -PLANT_INV_SQRT3};

static double leg_voltage(signed char conn, double vc1, double vc2)
{
    return conn == 1 ? vc1 : (conn == -1 ? -vc2 : 0.0);
}

static double phase_current(int k, const double i_s[2])
{
    return plant_u[k][0] * i_s[0] + plant_u[k][1] * i_s[1];
}

/* Phase voltages when some legs float; e_k are the phase emfs, vdrop the
 * on-state drops of the connected legs. */
static void float_voltages(const signed char conn[3], double vc1, double vc2,
                           const double e_k[3], const double vdrop[3], double v_k[3])
{
    int k, n_c = 0;
    double v_nO = 0.0;
    for (k = 0; k < 3; ++k) {
        if (conn[k] != 2) {
            v_nO += leg_voltage(conn[k], vc1, vc2) - vdrop[k] - e_k[k];
            ++n_c;
        }
    }
    for (k = 0; k < 3; ++k) {
        if (n_c >= 2 && conn[k] != 2)
            v_k[k] = leg_voltage(conn[k], vc1, vc2) - vdrop[k] - v_nO / n_c;
        else
            v_k[k] = e_k[k];
    }
}

/* The two levels (conn codes) the diodes of a gates-off or dead-time leg reach. */
static void diode_levels(uint8_t code, signed char *lo, signed char *hi)
{
    if (code == PLANT_LEG_DEAD_NO) {
        *lo = -1;
        *hi = 0;
    } else if (code == PLANT_LEG_DEAD_OP) {
        *lo = 0;
        *hi = 1;
    } else { /* gates off: the outer diodes, rail to rail */
        *lo = -1;
        *hi = 1;
    }
}

void plant_npc_connect(plant_seg *g, const uint8_t legs[3], const double *x)
{
    int k;
    double i_s[2], i_r[2];

    plant_im_currents(g, x, i_s, i_r);

    g->n_float = 0;
    for (k = 0; k < 3; ++k) {
        g->diode[k] = 0;
        if (legs[k] <= PLANT_LEG_P) {
            g->conn[k] = (signed char)((int)legs[k] - 1);
        } else if (legs[k] == PLANT_LEG_OPEN) {
            g->diode[k] = 1; /* so the clamp keeps its current at zero */
            g->dsign[k] = 0;
            g->conn[k] = 2;
            ++g->n_float;
        } else {
            double i_k = phase_current(k, i_s);
            g->diode[k] = 1;
            diode_levels(legs[k], &g->lo[k], &g->hi[k]);
            if (i_k > NPC_I_ZERO_A) {
                g->conn[k] = g->lo[k]; /* into the motor: through the diodes of the lower level */
                g->dsign[k] = 1;
            } else if (i_k < -NPC_I_ZERO_A) {
                g->conn[k] = g->hi[k]; /* out of the motor: through those of the upper level */
                g->dsign[k] = -1;
            } else {
                g->conn[k] = 2;
                ++g->n_float;
            }
        }
    }

    if (g->n_float > 0) {
        /* A floating phase starts conducting when its open-circuit voltage
         * would pass one of the levels its diodes reach (for gates off: a rail). */
        double e[2], e_k[3];
        double vc1 = x[PX_VC1], vc2 = x[PX_VC2];
        int n_c = 3 - g->n_float;
        plant_im_emf(g, x, i_r, e);
        for (k = 0; k < 3; ++k)
            e_k[k] = phase_current(k, e);
        if (n_c == 0) {
            int kmax = -1, kmin = -1;
            for (k = 0; k < 3; ++k) {
                if (legs[k] == PLANT_LEG_OPEN)
                    continue;
                if (kmax < 0 || e_k[k] > e_k[kmax]) kmax = k;
                if (kmin < 0 || e_k[k] < e_k[kmin]) kmin = k;
            }
            if (kmax >= 0 && kmax != kmin && e_k[kmax] - e_k[kmin] >
                leg_voltage(g->hi[kmax], vc1, vc2) - leg_voltage(g->lo[kmin], vc1, vc2)) {
                g->conn[kmax] = g->hi[kmax];
                g->dsign[kmax] = -1;
                g->conn[kmin] = g->lo[kmin];
                g->dsign[kmin] = 1;
                g->n_float -= 2;
            }
        } else {
            double v_nO = 0.0;
            for (k = 0; k < 3; ++k)
                if (g->conn[k] != 2)
                    v_nO += leg_voltage(g->conn[k], vc1, vc2) - e_k[k];
            v_nO /= n_c;
            for (k = 0; k < 3; ++k) {
                if (g->conn[k] != 2 || legs[k] == PLANT_LEG_OPEN)
                    continue;
                if (v_nO + e_k[k] > leg_voltage(g->hi[k], vc1, vc2)) {
                    g->conn[k] = g->hi[k];
                    g->dsign[k] = -1;
                    --g->n_float;
                } else if (v_nO + e_k[k] < leg_voltage(g->lo[k], vc1, vc2)) {
                    g->conn[k] = g->lo[k];
                    g->dsign[k] = 1;
                    --g->n_float;
                }
            }
        }
    }

    /* On-state drops from the current directions now (constant over the step). */
    g->dvs[0] = g->dvs[1] = 0.0;
    for (k = 0; k < 3; ++k) {
        double i_k = phase_current(k, i_s);
        g->vdrop[k] = 0.0;
        if (g->has_drop && g->conn[k] != 2 && (i_k > NPC_I_ZERO_A || i_k < -NPC_I_ZERO_A)) {
            g->vdrop[k] = i_k > 0.0 ? g->v_on2 : -g->v_on2;
            g->dvs[0] -= clarke_a[k] * g->vdrop[k];
            g->dvs[1] -= clarke_b[k] * g->vdrop[k];
        }
    }

    /* Linear maps for the connected legs (floating legs carry no current). */
    g->va1 = g->va2 = g->vb1 = g->vb2 = 0.0;
    g->gP[0] = g->gP[1] = g->gN[0] = g->gN[1] = 0.0;
    for (k = 0; k < 3; ++k) {
        if (g->conn[k] == 1) {
            g->va1 += clarke_a[k];
            g->vb1 += clarke_b[k];
            g->gP[0] += plant_u[k][0];
            g->gP[1] += plant_u[k][1];
        } else if (g->conn[k] == -1) {
            g->va2 += clarke_a[k];
            g->vb2 += clarke_b[k];
            g->gN[0] += plant_u[k][0];
            g->gN[1] += plant_u[k][1];
        }
    }
}

void plant_npc_drive(const plant_seg *g, const double *x, const double i_s[2],
                     const double i_r[2], double v_s[2], double *i_P, double *i_N)
{
    double vc1 = x[PX_VC1], vc2 = x[PX_VC2];
    double e[2], e_k[3], v_k[3];
    int k;
    if (g->n_float == 0) {
        plant_npc_drive_connected(g, x, i_s, v_s, i_P, i_N);
        return;
    }
    plant_im_emf(g, x, i_r, e);
    for (k = 0; k < 3; ++k)
        e_k[k] = phase_current(k, e);
    float_voltages(g->conn, vc1, vc2, e_k, g->vdrop, v_k);
    v_s[0] = (2.0 * v_k[0] - v_k[1] - v_k[2]) / 3.0;
    v_s[1] = (v_k[1] - v_k[2]) * PLANT_INV_SQRT3;
    /* floating legs are in neither gP nor gN: they carry no current */
    *i_P = g->gP[0] * i_s[0] + g->gP[1] * i_s[1];
    *i_N = g->gN[0] * i_s[0] + g->gN[1] * i_s[1];
}

void plant_npc_phase(const plant_seg *g, const double *x, const double i_s[2],
                     const double i_r[2], double v_abc[3], double *i_np)
{
    double v_s[2], i_P, i_N;
    int k;
    plant_npc_drive(g, x, i_s, i_r, v_s, &i_P, &i_N);
    *i_np = 0.0;
    for (k = 0; k < 3; ++k) {
        v_abc[k] = phase_current(k, v_s); /* inverse Clarke of a zero-sum triple */
        if (g->conn[k] == 0)
            *i_np += phase_current(k, i_s);
    }
}

void plant_npc_clamp(const plant_seg *g, double *x)
{
    double i_s[2], i_r[2], d0, d1;
    int k, n_f = 0, k_f = 0;

    plant_im_currents(g, x, i_s, i_r);
    for (k = 0; k < 3; ++k) {
        double i_k = phase_current(k, i_s);
        int fl = g->conn[k] == 2 || (g->diode[k] && (double)g->dsign[k] * i_k <= 0.0);
        if (fl) {
            ++n_f;
            k_f = k;
        }
    }
    if (n_f == 0)
        return;
    if (n_f == 1) {
        double i_k = phase_current(k_f, i_s);
        d0 = -i_k * plant_u[k_f][0];
        d1 = -i_k * plant_u[k_f][1];
    } else {
        d0 = -i_s[0];
        d1 = -i_s[1];
    }
    /* Change i_s at fixed psi_r: only the stator leakage flux moves. */
    x[PX_PSA] += g->d_lr * d0;
    x[PX_PSB] += g->d_lr * d1;
}

void plant_inverter_output(const uint8_t legs[3], double vc1, double vc2,
                           const double i_abc[3], double v_abc[3], double *i_np)
{
    signed char conn[3];
    double zero_e[3] = {0.0, 0.0, 0.0};
    double v_k[3];
    int k;

    for (k = 0; k < 3; ++k) {
        double i_k = i_abc != NULL ? i_abc[k] : 0.0;
        if (legs[k] <= PLANT_LEG_P)
            conn[k] = (signed char)((int)legs[k] - 1);
        else
            conn[k] = (signed char)(i_k > NPC_I_ZERO_A ? -1 : (i_k < -NPC_I_ZERO_A ? 1 : 2));
    }
    /* Floating legs are reported at the star point (0 V): their true voltage
     * needs the machine emf, which only the integration knows. */
    float_voltages(conn, vc1, vc2, zero_e, zero_e, v_k);
    if (i_np != NULL)
        *i_np = 0.0;
    for (k = 0; k < 3; ++k) {
        if (v_abc != NULL)
            v_abc[k] = v_k[k];
        if (i_np != NULL && conn[k] == 0 && i_abc != NULL)
            *i_np += i_abc[k];
    }
}
