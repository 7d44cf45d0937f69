/**
 * @file dtc3l.h
 * @brief Three-level direct torque control: comparators, sector, 19-vector table,
 *        neutral-point balancing and low-speed torque-ripple reduction.
 *
 * The NPC inverter's states and space vectors are those of dtc/npc.h, the
 * sectors, directions and tables those of dtc/dtc3l_table.h, the choice among
 * redundant states that of dtc/dtc3l_np.h; this header is the DTC's step.
 *
 * Selection rule (dtc3l_select). To move the torque up the chosen vector lies
 * +60 deg (flux up) or +120 deg (flux down) from a reference direction, to move
 * it down -60 / -120 deg:
 *  - LOW level, demands +-1: the reference is the small vector nearest to the
 *    flux (6 sectors of 60 deg, dtc3l_sector6) and the vector is small; over
 *    the sector it is 30..90 deg (90..150 deg) from the flux. Small vectors are
 *    one commutation away from a zero state and all balance the neutral point.
 *  - HIGH level, and the strong demands +-2 at any level: the reference is the
 *    centre of the 30 deg sector (12 sectors, dtc3l_sector); the vector is
 *    large (even sectors) or medium (odd sectors), 45..75 deg (105..135 deg)
 *    from the flux over the whole sector.
 * Holding the torque uses a zero vector, or at the LOW level a small vector
 * along the flux (dtc3l_table_flux_hold) when the flux has dropped below its
 * band (the Rs is drop that zero vectors cause at low speed).
 * The LOW level is meant for a back-emf below about half of Vdc/3 (500 rpm at
 * rated flux and 311 V, up to about 12 N m at the sector edges; a larger
 * torque error calls the strong vectors); tests/unit/test_dtc3l.cpp checks
 * every entry there and at the HIGH level at 700..1100 rpm.
 *
 * Redundant states (dtc3l_choose_state): a small vector's P-type and N-type
 * states draw opposite neutral-point currents; outside np_band_V the one that
 * drives vc1 - vc2 towards zero is taken (d(vc1 - vc2)/dt = i_np / C), inside
 * the band the one with the fewest leg commutations. No leg ever steps
 * directly between P and N: states that would are excluded, and when the
 * wanted vector has no such state the offending legs are held at O. When
 * the balancing state of a small vector is such a step away (PPO -> ONN),
 * the P<->N-safe intermediate (OON) is used instead if it balances too.
 * At the HIGH level (large and medium vectors, which cannot balance) an
 * unbalanced link is pulled back during the holds, by the balancing state of
 * the small vector nearest to +-flux instead of a zero state (a zero state
 * when that one is out of reach). A state forced by the P<->N rule (the
 * medium vector between two adjacent large ones, a small state of the wrong
 * type) is held only as long as the NP prediction allows, then the wanted
 * state follows in the same period (dtc3l.c, cut_intermediate_short).
 *
 * Ripple reduction (below ripple_speed_max_rad_s): the torque comparator's
 * band edge crossing is placed inside the period instead of at its end. The
 * period is split into the running vector for the time the torque needs to
 * reach the band edge (from the predicted torque and the slope dTe/dt of that
 * vector) and the next vector for the rest, so the torque ripple is the band
 * itself and not band + one period of slope; switching events are not added,
 * only moved. When the vector after a hold would also overshoot the opposite
 * edge within the period, it starts later instead, so that the period ends on
 * that edge: d = (Te_edge - Te - s_hold T) / ((s_act - s_hold) T), the duty
 * from the torque error and the two slopes. The slopes come from the
 * observer model at the predicted state (dte0 + dte_dv . v).
 */
#ifndef DTC_DTC3L_H
#define DTC_DTC3L_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/dtc3l_table.h"
#include "dtc/npc.h"
#include "dtc/num.h"
#include "dtc/observer.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    real_t psi_ref_Wb;        /**< stator-flux reference, Wb */
    real_t premag_s;          /**< pre-magnetisation time before speed control, s */
    real_t flux_band_Wb;      /**< flux hysteresis band (half width), Wb */
    real_t torque_band_Nm;    /**< torque comparator band (half width of the inner level), N m */
    bool ripple_reduction;    /**< duty-split ripple reduction at low speed */
    real_t ripple_speed_max_rad_s; /**< apply ripple reduction below this |speed|, rad/s (mechanical) */
    real_t np_band_V;         /**< |vc1 - vc2| below which the small vector is left to alternate, V */
    /* added by the DTC implementation */
    real_t torque_band2_Nm;   /**< |torque error| above which the comparator asks for the strong
                                   vectors (level +-2), N m; > torque_band_Nm */
    real_t level_up;          /**< back-emf |omega_e| psi_ref over Vdc/3 above which the HIGH level is used */
    real_t level_down;        /**< ... below which the LOW level returns (< level_up) */
    real_t duty_min;          /**< shortest vector segment, fraction of the period (0..0.5) */
    real_t np_V_per_A;        /**< derived (ctl_cfg_derive): change of vc1 - vc2 per ampere of NP
                                   current over one period, V/A (0: no NP prediction) */
} dtc3l_cfg;

/** Comparator and level memory (caller owned). */
typedef struct {
    int8_t torque_state;      /**< -2..+2: down strong, down, hold, up, up strong */
    int8_t flux_state;        /**< +1 raise, -1 lower */
    uint8_t level;            /**< dtc3l_level */
} dtc3l;

/** Inputs of one DTC step besides the observer's prediction (dtc3l_step_predicted
 *  reads that where the observer left it, in its observer_out). */
typedef struct {
    real_t te_ref_Nm;         /**< torque command, N m */
    real_t psi_ref_Wb;        /**< flux command, Wb */
    real_t rs_ohm;            /**< stator resistance, ohm */
    real_t omega_e_rad_s;     /**< electrical speed estimate, rad/s (voltage level) */
    real_t vc1_V, vc2_V;      /**< capacitor voltages, V */
    real_t np_dev_V;          /**< vc1 - vc2 predicted for the start of the chosen period, V */
    uint8_t prev_state;       /**< state in force when the chosen period starts, 0..26 (the caller
                                   clamps: the control step's states are 0..26; dtc3l_step counts
                                   others as OOO) */
    real_t band_scale;        /**< both torque bands are cfg x this, >= 1 (the caller clamps: the
                                   switching-frequency regulation of the control step keeps it in
                                   1..band_scale_max; dtc3l_step takes 0 or less as 1) */
    bool decide_level;        /**< decide the voltage level in this step (false: keep the last one;
                                   the control step decides it once per slot cycle, ctl_slot_level:
                                   the back-emf moves little in eight periods) */
} dtc3l_cmd;

/** Inputs of one DTC step in one flat struct (dtc3l_step): the observer's
 *  prediction for the start of the period being chosen and the rest as in dtc3l_cmd. */
typedef struct {
    real_t te_ref_Nm;         /**< torque command, N m */
    real_t psi_ref_Wb;        /**< flux command, Wb */
    real_t te_Nm;             /**< predicted torque, N m */
    real_t psi_s_Wb[2];       /**< predicted stator flux alpha, beta, Wb */
    real_t is_A[2];           /**< predicted stator current alpha, beta, A */
    real_t dte0_Nm_s;         /**< dTe/dt under the zero vector, N m/s */
    real_t dte_dv[2];         /**< dTe/dt per volt of v_alpha, v_beta, N m/(s V) */
    real_t rs_ohm;            /**< stator resistance, ohm */
    real_t omega_e_rad_s;     /**< electrical speed estimate, rad/s (voltage level) */
    real_t omega_m_rad_s;     /**< mechanical speed estimate, rad/s (ripple-reduction range) */
    real_t vc1_V, vc2_V;      /**< capacitor voltages, V */
    real_t np_dev_V;          /**< vc1 - vc2 predicted for the start of the chosen period, V */
    uint8_t prev_state;       /**< state in force when the chosen period starts (0..26; others count as OOO) */
    real_t band_scale;        /**< both torque bands are cfg x this (>= 1; 0 or less: 1): the
                                   switching-frequency regulation of the control step widens them */
} dtc3l_in;

typedef struct {
    hal_actuation act;        /**< the two vectors and the duty of the first (dtc3l_step_predicted
                                   writes only duty0, in 0..1: the vectors are state[]'s leg codes) */
    uint8_t state[2];         /**< the same as state numbers */
    uint8_t level;            /**< dtc3l_level */
    /* no sector, comparator outputs or split flag: nothing reads them, and
     * their stores would cost every tick; the comparators' memory is in dtc3l */
} dtc3l_out;

/* ------------------------------------------------------- ripple reduction
 * Over one period the torque under a fixed vector is close to a straight line
 * whose slope is dTe/dt = dte0 + dte_dv . v (linear in the stator voltage,
 * from the observer model at the predicted state). The time at which that line
 * meets a band edge gives the duty of the vector. Inline: several calls a tick. */

/**
 * Fraction of the period @p period_s after which a torque starting at
 * @p te_Nm with slope @p slope_Nm_s reaches @p edge_Nm: in 0..1 (0 when it is
 * on the edge; below 1 otherwise), or 2 when it does not get there within the period, stands
 * still or moves away from the edge. Context: ANY.
 */
static inline real_t dtc3l_edge_fraction(real_t te_Nm, real_t slope_Nm_s, real_t edge_Nm, real_t period_s)
{
    real_t gap = edge_Nm - te_Nm;
    real_t reach = num_mul(slope_Nm_s, period_s);
    /* at the edge now */
    if (gap == R(0.0))
        return R(0.0);
    /* standing still, moving away (or already beyond it), or not getting there
     * within the period: the quotient is not in (0, 1) (a zero slope gives
     * +-inf); the comparator deals with a torque beyond an edge. Two compares
     * on the quotient, not three on gap and reach (a quotient that rounds up
     * to 1 counts as not within the period) */
    real_t f = num_div(gap, reach);
    return f > R(0.0) && f < R(1.0) ? f : R(2.0);
}

/** dTe/dt under the stator voltage @p v (alpha, beta), N m/s (dte0 + dte_dv . v). Context: ANY. */
static inline real_t dtc3l_voltage_slope(const dtc3l_in *in, const real_t v[2])
{
    return in->dte0_Nm_s + num_mul(in->dte_dv[0], v[0]) + num_mul(in->dte_dv[1], v[1]);
}

/** dTe/dt under space vector state @p state, N m/s (dte0 + dte_dv . v). Context: ANY. */
static inline real_t dtc3l_state_slope(const dtc3l_in *in, uint8_t state)
{
    real_t v[2];
    npc_state_voltage(state, in->vc1_V, in->vc2_V, v);
    return dtc3l_voltage_slope(in, v);
}

/* ----------------------------------------------------- step (dtc3l.c) */

/** Reset the comparators (hold, raise flux, LOW level). Context: ANY. */
void dtc3l_init(dtc3l *s);

/**
 * One DTC decision for the period starting one control period from now
 * (the voltage level decided in every step).
 * @param dt_s control period, s. Context: ISR.
 */
void dtc3l_step(dtc3l *s, const dtc3l_cfg *cfg, real_t dt_s, const dtc3l_in *in, dtc3l_out *out);

/**
 * The same decision with the observer's prediction read where the observer
 * left it (no copy per tick): from @p pred its te_pred_Nm,
 * psi_s_pred_Wb, is_pred_A, dte0_Nm_s, dte_dv and omega_m_rad_s (the
 * ripple-reduction range), in place of dtc3l_in's te_Nm, psi_s_Wb, is_A,
 * dte0_Nm_s, dte_dv and omega_m_rad_s; the rest from @p in. Writes @p out except
 * out->act.vector (its caller, the control step, actuates state[] through its
 * own P<->N guard and writes the leg codes there). Context: ISR.
 */
void dtc3l_step_predicted(dtc3l *s, const dtc3l_cfg *cfg, real_t dt_s, const dtc3l_cmd *in,
                          const observer_out *pred, dtc3l_out *out);

#ifdef __cplusplus
}
#endif

#endif /* DTC_DTC3L_H */
