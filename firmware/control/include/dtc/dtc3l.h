/**
 * @file dtc3l.h
 * @brief Three-level direct torque control: comparators, sector, 19-vector table,
 *        neutral-point balancing and low-speed torque-ripple reduction.
 *
 * Vocabulary
 *  - state: one of the 27 switching states, numbered a*9 + b*3 + c with the leg
 *    codes N = 0, O = 1, P = 2 (hal_leg_state).
 *  - space vector ("sv"): one of the 19 distinct voltage vectors:
 *      0       zero            (NNN, OOO, PPP)
 *      1..6    small  Vdc/3        at (sv-1)*60 deg  (two states: P-type, N-type)
 *      7..12   medium Vdc/sqrt(3)  at 30 + (sv-7)*60 deg (one state)
 *      13..18  large  2 Vdc/3      at (sv-13)*60 deg (one state)
 *  - direction: 0..11, the angle of a non-zero sv in steps of 30 deg; even
 *    directions hold small and large vectors, odd directions medium ones.
 *  - sector: 0..11, the stator-flux angle in 30 deg sectors centred on
 *    direction s (sector s spans s*30 - 15 .. s*30 + 15 deg); sector6: 0..5,
 *    60 deg sectors centred on the small vectors (s6*60 - 30 .. s6*60 + 30).
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
#include <string.h>

#include "dtc/num.h"
#include "dtc/observer.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DTC3L_N_STATES 27u   /**< switching states */
#define DTC3L_N_VECTORS 19u  /**< distinct space vectors */
#define DTC3L_N_SECTORS 12u  /**< flux sectors of 30 deg */
#define DTC3L_STATE_OOO 13u  /**< all legs at the neutral point */

/** Magnitude class of a space vector. */
typedef enum {
    DTC3L_CLASS_ZERO = 0,
    DTC3L_CLASS_SMALL = 1,
    DTC3L_CLASS_MEDIUM = 2,
    DTC3L_CLASS_LARGE = 3,
} dtc3l_class;

/** Voltage level chosen from the speed. */
typedef enum {
    DTC3L_LEVEL_LOW = 0,  /**< small vectors, 6 sectors */
    DTC3L_LEVEL_HIGH = 1, /**< large and medium vectors, 12 sectors */
} dtc3l_level;

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
                                   clamps: ctl.c counts others as OOO, as dtc3l_step does) */
    real_t band_scale;        /**< both torque bands are cfg x this, >= 1 (the caller clamps: the
                                   switching-frequency regulation of ctl.c keeps it in
                                   1..band_scale_max; dtc3l_step takes 0 or less as 1) */
    bool decide_level;        /**< decide the voltage level in this step (false: keep the last one;
                                   ctl.c decides it once per slot cycle, CTL_SLOT_LEVEL: the back-emf
                                   moves little in four periods; issue 11) */
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
                                   switching-frequency regulation of ctl.c widens them */
} dtc3l_in;

typedef struct {
    hal_actuation act;        /**< the two vectors and the duty of the first (dtc3l_step_predicted
                                   writes only duty0, in 0..1: the vectors are state[]'s leg codes) */
    uint8_t state[2];         /**< the same as state numbers */
    uint8_t level;            /**< dtc3l_level */
    /* no sector, comparator outputs or split flag: nothing read them, and
     * their stores cost every tick (issue 11); the comparators' memory is in dtc3l */
} dtc3l_out;

/* ------------------------------------------------ vectors (dtc3l_vectors.c) */

/* Facts about each of the 27 states, precomputed (const, in flash) so that the
 * interrupt looks a state up and never decomposes its index into base-3 digits.
 * tests/unit/test_dtc3l.cpp checks every entry against the plant's inverter
 * model and an independent base-3 decomposition. */

extern const hal_vector dtc3l_state_legs[DTC3L_N_STATES];        /**< leg codes of each state */
extern const uint32_t dtc3l_state_legs_packed[DTC3L_N_STATES]; /**< the leg codes a | b << 8 | c << 16 */
extern const real_t dtc3l_np_legs[DTC3L_N_STATES][3];           /**< 1 for a leg at O (its phase current
                                                                     flows from the neutral point), else 0 */
extern const uint32_t dtc3l_pn_step_mask[DTC3L_N_STATES];       /**< bit `to` set: from -> to steps a leg P<->N */
extern const uint8_t dtc3l_changes[DTC3L_N_STATES][DTC3L_N_STATES];    /**< leg commutations from -> to */
extern const uint8_t dtc3l_pn_safe_to[DTC3L_N_STATES][DTC3L_N_STATES]; /**< to with P<->N legs held at O */

/* Each accessor below comes twice: NAME_unchecked takes states 0..26 only
 * (the control step's own states, which come from these tables or were
 * clamped once; no test per call: issue 11, about 20 per tick), NAME handles
 * any value as documented. */

/** dtc3l_legs for @p state 0..26 (unchecked). Context: ANY. */
static inline void dtc3l_legs_unchecked(uint8_t state, hal_vector *v) { *v = dtc3l_state_legs[state]; }

/** vector[0] and vector[1] of @p a: the leg codes of @p st0 and @p st1 (both
 *  0..26, unchecked), written as one word and one half-word from
 *  dtc3l_state_legs_packed (the same six bytes as dtc3l_legs_unchecked for
 *  each; issue 11: 7 instructions instead of 12). Context: ANY. */
static inline void dtc3l_legs_pair_unchecked(uint8_t st0, uint8_t st1, hal_actuation *a)
{
    uint32_t w0 = dtc3l_state_legs_packed[st0], w1 = dtc3l_state_legs_packed[st1];
    uint32_t lo = w0 | w1 << 24;
    uint16_t hi = (uint16_t)(w1 >> 8);
    unsigned char *legs = (unsigned char *)a->vector;
    memcpy(legs, &lo, sizeof lo);
    memcpy(legs + sizeof lo, &hi, sizeof hi);
}

/** Leg codes of @p state (0..26; others: OOO) into @p v. Context: ANY. */
static inline void dtc3l_legs(uint8_t state, hal_vector *v)
{
    dtc3l_legs_unchecked(state < DTC3L_N_STATES ? state : DTC3L_STATE_OOO, v);
}

/** State number of @p v; 0xFF when a leg code is above HAL_LEG_P. Context: ANY. */
static inline uint8_t dtc3l_state_of(const hal_vector *v)
{
    if (v->leg[0] > HAL_LEG_P || v->leg[1] > HAL_LEG_P || v->leg[2] > HAL_LEG_P)
        return 0xFFu;
    return (uint8_t)(v->leg[0] * 9u + v->leg[1] * 3u + v->leg[2]);
}

extern const uint8_t dtc3l_state_sv_of[DTC3L_N_STATES];            /**< space vector of each state */
extern const uint8_t dtc3l_sv_state_list[DTC3L_N_VECTORS][3];      /**< states of each sv, preferred first; 0xFF pads */

/** dtc3l_state_sv for @p state 0..26 (unchecked). Context: ANY. */
static inline uint8_t dtc3l_state_sv_unchecked(uint8_t state) { return dtc3l_state_sv_of[state]; }

/** Space vector 0..18 of @p state (others: 0). Context: ANY. */
static inline uint8_t dtc3l_state_sv(uint8_t state)
{
    return state < DTC3L_N_STATES ? dtc3l_state_sv_unchecked(state) : 0u;
}

extern const uint8_t dtc3l_sv_class_of[DTC3L_N_VECTORS];          /**< dtc3l_class of each sv */

/** dtc3l_sv_class for @p sv 0..18 (unchecked): one load instead of three
 *  compares (issue 11; the step asks it several times a tick). Context: ANY. */
static inline dtc3l_class dtc3l_sv_class_unchecked(uint8_t sv) { return (dtc3l_class)dtc3l_sv_class_of[sv]; }

/** Class of space vector @p sv. Context: ANY. */
static inline dtc3l_class dtc3l_sv_class(uint8_t sv)
{
    if (sv == 0u || sv >= DTC3L_N_VECTORS)
        return DTC3L_CLASS_ZERO;
    if (sv <= 6u)
        return DTC3L_CLASS_SMALL;
    return sv <= 12u ? DTC3L_CLASS_MEDIUM : DTC3L_CLASS_LARGE;
}

/** States realising @p sv (others: the zero vector), preferred first (OOO;
 *  P-type small); returns the count 1..3. Context: ANY. */
static inline uint8_t dtc3l_sv_states(uint8_t sv, uint8_t states[3])
{
    const uint8_t *l = dtc3l_sv_state_list[sv < DTC3L_N_VECTORS ? sv : 0u];
    states[0] = l[0];
    states[1] = l[1];
    states[2] = l[2];
    return (uint8_t)(sv == 0u || sv >= DTC3L_N_VECTORS ? 3u : (sv <= 6u ? 2u : 1u));
}

/** dtc3l_state_voltage for @p state 0..26 (unchecked). Context: ANY. */
static inline void dtc3l_state_voltage_unchecked(uint8_t state, real_t vc1_V, real_t vc2_V, real_t v_ab[2])
{
    const hal_vector *l = &dtc3l_state_legs[state];
    real_t vn = -vc2_V; /* leg voltage by leg code N, O, P: -vc2, 0, vc1 */
    real_t va = l->leg[0] == HAL_LEG_P ? vc1_V : (l->leg[0] == HAL_LEG_N ? vn : R(0.0));
    real_t vb = l->leg[1] == HAL_LEG_P ? vc1_V : (l->leg[1] == HAL_LEG_N ? vn : R(0.0));
    real_t vc = l->leg[2] == HAL_LEG_P ? vc1_V : (l->leg[2] == HAL_LEG_N ? vn : R(0.0));
    /* Clarke of the leg voltages: the common mode drops out, as in an isolated star. */
    v_ab[0] = num_mul(R(0.333333333), R(2.0) * va - vb - vc);
    v_ab[1] = num_mul(NUM_INV_SQRT3, vb - vc);
}

/**
 * Stator voltage (alpha, beta) of the leg codes @p l (each 0..2, unchecked)
 * with @p leg_V the leg voltage by leg code {-vc2, 0, vc1}: the same values
 * as dtc3l_state_voltage, for a caller that has several states to work out
 * at the same capacitor voltages. Context: ANY.
 */
static inline void dtc3l_legs_voltage(const hal_vector *l, const real_t leg_V[3], real_t v_ab[2])
{
    real_t va = leg_V[l->leg[0]], vb = leg_V[l->leg[1]], vc = leg_V[l->leg[2]];
    v_ab[0] = num_mul(R(0.333333333), R(2.0) * va - vb - vc);
    v_ab[1] = num_mul(NUM_INV_SQRT3, vb - vc);
}

/**
 * Stator voltage (alpha, beta; isolated star) of @p state (others: OOO) for
 * the capacitor voltages @p vc1_V (P to O) and @p vc2_V (O to N). Context: ANY.
 */
static inline void dtc3l_state_voltage(uint8_t state, real_t vc1_V, real_t vc2_V, real_t v_ab[2])
{
    dtc3l_state_voltage_unchecked(state < DTC3L_N_STATES ? state : DTC3L_STATE_OOO, vc1_V, vc2_V, v_ab);
}

/** dtc3l_np_current for @p state 0..26 (unchecked). Context: ANY. */
static inline real_t dtc3l_np_current_unchecked(uint8_t state, const real_t i_abc[3])
{
    const real_t *k = dtc3l_np_legs[state];
    return num_mul(k[0], i_abc[0]) + num_mul(k[1], i_abc[1]) + num_mul(k[2], i_abc[2]);
}

/** Neutral-point current drawn by @p state (others: 0): the sum of the phase
 *  currents of its legs at O, A. Context: ANY. */
static inline real_t dtc3l_np_current(uint8_t state, const real_t i_abc[3])
{
    return state < DTC3L_N_STATES ? dtc3l_np_current_unchecked(state, i_abc) : R(0.0);
}

/** dtc3l_pn_step for @p from and @p to 0..26 (unchecked). Context: ANY. */
static inline bool dtc3l_pn_step_unchecked(uint8_t from, uint8_t to)
{
    return ((dtc3l_pn_step_mask[from] >> to) & 1u) != 0u;
}

/** True when going from @p from to @p to steps some leg directly between P and N
 *  (false when either is not a state). Context: ANY. */
static inline bool dtc3l_pn_step(uint8_t from, uint8_t to)
{
    return from < DTC3L_N_STATES && to < DTC3L_N_STATES && dtc3l_pn_step_unchecked(from, to);
}

/** dtc3l_leg_changes for @p from and @p to 0..26 (unchecked). Context: ANY. */
static inline uint8_t dtc3l_leg_changes_unchecked(uint8_t from, uint8_t to) { return dtc3l_changes[from][to]; }

/** Number of leg commutations from @p from to @p to (N<->O and O<->P count 1;
 *  0 when either is not a state). Context: ANY. */
static inline uint8_t dtc3l_leg_changes(uint8_t from, uint8_t to)
{
    return from < DTC3L_N_STATES && to < DTC3L_N_STATES ? dtc3l_leg_changes_unchecked(from, to) : 0u;
}

/** dtc3l_pn_safe for @p from and @p to 0..26 (unchecked). Context: ANY. */
static inline uint8_t dtc3l_pn_safe_unchecked(uint8_t from, uint8_t to) { return dtc3l_pn_safe_to[from][to]; }

/** @p to with every leg that would step between P and N from @p from held at O
 *  (OOO when either is not a state). Context: ANY. */
static inline uint8_t dtc3l_pn_safe(uint8_t from, uint8_t to)
{
    return from < DTC3L_N_STATES && to < DTC3L_N_STATES ? dtc3l_pn_safe_unchecked(from, to) : (uint8_t)DTC3L_STATE_OOO;
}

/* ---------------------------------------------------- table (dtc3l_table.c) */

/* The sectors and tables are small and run several times per tick: inline
 * (the geometric rules are explained in dtc3l_table.c). */

/* tan(15), tan(30), tan(75) deg: sector boundaries inside a quadrant */
#define DTC3L_TAN15 R(0.267949192)
#define DTC3L_TAN30 R(0.577350269)
#define DTC3L_TAN75 R(3.732050808)

/** Sector 0..11 of the flux (psi_alpha, psi_beta): 30 deg sectors centred on
 *  30 deg * sector. No trigonometry. Context: ANY. */
static inline uint8_t dtc3l_sector(real_t psi_alpha, real_t psi_beta)
{
    real_t ax = num_abs(psi_alpha), ay = num_abs(psi_beta);
    /* q: 30 deg step nearest to the angle folded into the first quadrant */
    unsigned q;
    if (ay < num_mul(DTC3L_TAN15, ax))
        q = 0u;
    else if (ay < ax)
        q = 1u;
    else if (ay < num_mul(DTC3L_TAN75, ax))
        q = 2u;
    else
        q = 3u;
    if (psi_alpha >= R(0.0))
        return (uint8_t)(psi_beta >= R(0.0) ? q : (12u - q) % 12u);
    return (uint8_t)(psi_beta >= R(0.0) ? 6u - q : 6u + q);
}

/** Sector 0..5 of the flux: 60 deg sectors centred on the small vectors,
 *  60 deg * sector. No trigonometry. Context: ANY. */
static inline uint8_t dtc3l_sector6(real_t psi_alpha, real_t psi_beta)
{
    /* within a quadrant the only boundary is at 30 deg from the alpha axis */
    bool near_axis = num_abs(psi_beta) < num_mul(DTC3L_TAN30, num_abs(psi_alpha));
    if (psi_alpha >= R(0.0))
        return (uint8_t)(near_axis ? 0u : (psi_beta >= R(0.0) ? 1u : 5u));
    return (uint8_t)(near_axis ? 3u : (psi_beta >= R(0.0) ? 2u : 4u));
}

/** dtc3l_sector (@p sector) and dtc3l_sector6 (@p sector6) of the same flux
 *  with one set of compares: the 60 deg sectors' boundary at 30 deg from the
 *  alpha axis lies inside 12-sector 1 of the quadrant, so it is the one more
 *  compare there (below 15 deg it is near the axis, from 45 deg on it is not;
 *  the products by tan15 < tan30 < 1 keep that order in floats). Context: ANY. */
static inline void dtc3l_sectors(real_t psi_alpha, real_t psi_beta, uint8_t *sector, uint8_t *sector6)
{
    real_t ax = num_abs(psi_alpha), ay = num_abs(psi_beta);
    unsigned q;
    bool near_axis;
    if (ay < num_mul(DTC3L_TAN15, ax)) {
        q = 0u;
        near_axis = true;
    } else if (ay < ax) {
        q = 1u;
        near_axis = ay < num_mul(DTC3L_TAN30, ax);
    } else {
        q = ay < num_mul(DTC3L_TAN75, ax) ? 2u : 3u;
        near_axis = false;
    }
    if (psi_alpha >= R(0.0)) {
        *sector = (uint8_t)(psi_beta >= R(0.0) ? q : (12u - q) % 12u);
        *sector6 = (uint8_t)(near_axis ? 0u : (psi_beta >= R(0.0) ? 1u : 5u));
    } else {
        *sector = (uint8_t)(psi_beta >= R(0.0) ? 6u - q : 6u + q);
        *sector6 = (uint8_t)(near_axis ? 3u : (psi_beta >= R(0.0) ? 2u : 4u));
    }
}

/** Space vector at direction @p dir (0..11 after mod 12, 30 deg steps); even
 *  directions hold small (@p large false) or large vectors. Context: ANY. */
static inline uint8_t dtc3l_sv_at(unsigned dir, bool large)
{
    dir %= 12u;
    if (dir & 1u)
        return (uint8_t)(7u + (dir - 1u) / 2u);
    return (uint8_t)((large ? 13u : 1u) + dir / 2u);
}

/** Offset of the demanded vector from the reference direction, in 30 deg
 *  steps mod 12 (+60 / +120 deg up, -60 / -120 deg down). Context: ANY. */
static inline unsigned dtc3l_demand_offset(int8_t torque, int8_t flux)
{
    if (torque > 0)
        return flux > 0 ? 2u : 4u;
    return flux > 0 ? 10u : 8u;
}

/** Column of the written-out tables for @p torque (> 0 up, else down) and
 *  @p flux (> 0 raise, else lower): the order of dtc3l_demand_offset's four
 *  cases (+60, +120, -60, -120 deg). Context: ANY. */
static inline unsigned dtc3l_demand_index(int8_t torque, int8_t flux)
{
    return (torque > 0 ? 0u : 2u) + (flux > 0 ? 0u : 1u);
}

/** dtc3l_sv_at(sector + dtc3l_demand_offset(...), true) by sector 0..11 and
 *  dtc3l_demand_index (dtc3l_table.c). */
extern const uint8_t dtc3l_table12_sv[DTC3L_N_SECTORS][4];
/** dtc3l_sv_at(2 sector6 + dtc3l_demand_offset(...), false) by sector6 0..5 and
 *  dtc3l_demand_index (dtc3l_table.c). */
extern const uint8_t dtc3l_table6_sv[6][4];

/**
 * The 12-sector table of the large and medium vectors: space vector for
 * @p sector (0..11), torque demand @p torque (-2..2; 0 = hold: the zero
 * vector), flux demand @p flux (+1 raise, -1 lower). @p level is accepted for
 * symmetry with dtc3l_select and does not change the result. Context: ANY.
 */
static inline uint8_t dtc3l_table(uint8_t sector, int8_t torque, int8_t flux, uint8_t level)
{
    if (torque == 0)
        return 0u;
    (void)level; /* the HIGH level and the strong demands share this table */
    return dtc3l_table12_sv[sector % 12u][dtc3l_demand_index(torque, flux)];
}

/** The 6-sector table of the small vectors (LOW level): space vector for
 *  @p sector6 (0..5), @p torque (sign only; 0 = zero vector), @p flux. Context: ANY. */
static inline uint8_t dtc3l_table6(uint8_t sector6, int8_t torque, int8_t flux)
{
    if (torque == 0)
        return 0u;
    return dtc3l_table6_sv[sector6 % 6u][dtc3l_demand_index(torque, flux)];
}

/** Flux-holding small vector: the small vector nearest to the flux, whose
 *  tangential part is at most half of it. Context: ANY. */
static inline uint8_t dtc3l_table_flux_hold(uint8_t sector6)
{
    return (uint8_t)(1u + sector6 % 6u); /* dtc3l_sv_at(2 (sector6 mod 6), false) */
}

/**
 * The switching table as the DTC uses it: the 6-sector small-vector table for
 * the LOW level and demands +-1, the 12-sector table otherwise.
 * @return space vector 0..18. Context: ANY.
 */
uint8_t dtc3l_select(real_t psi_alpha, real_t psi_beta, int8_t torque, int8_t flux, uint8_t level);

/* ------------------------------------------- neutral point (dtc3l_np.c) */

/**
 * Pick the switching state for space vector @p sv after @p prev_state:
 * never a direct P<->N leg step; for small vectors with |np_dev_V| > np_band_V
 * the state whose neutral-point current drives np_dev_V = vc1 - vc2 towards 0
 * (possibly the small intermediate described above, a different vector);
 * otherwise the fewest leg commutations (NP direction breaks ties). For the
 * zero vector with |np_dev_V| above half the band, the zero state on the way to
 * the balancing state of the small vector @p prev_state belongs to.
 * @param i_abc phase currents during the segment, A
 * Context: ANY.
 */
uint8_t dtc3l_choose_state(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                           const real_t i_abc[3]);

/** dtc3l_choose_state for @p sv 0..18 and @p prev_state 0..26 (unchecked; the
 *  step's own vectors and states). Context: ANY. */
uint8_t dtc3l_choose_state_unchecked(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                                     const real_t i_abc[3]);

/** dtc3l_choose_state_unchecked that also reports, for a small vector @p sv
 *  outside the NP band whose first (P-type) state is within reach of
 *  @p prev_state, that state's NP current x @p np_dev_V, A V (*@p push0_VA,
 *  *@p push0_known true; otherwise *@p push0_known false and *@p push0_VA
 *  unspecified). For dtc3l_choose_zero_unchecked after it. Context: ANY. */
uint8_t dtc3l_choose_state_push0_unchecked(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                                           const real_t i_abc[3], bool *push0_known, real_t *push0_VA);

/** dtc3l_choose_state_unchecked(0, @p prev_state, ...): the zero state after
 *  @p prev_state 0..26. @p push0_known: @p push0_VA is the NP current of the
 *  first state of @p prev_state's vector x @p np_dev_V, A V, already worked
 *  out (dtc3l_choose_state_push0_unchecked when @p prev_state is one of its
 *  vector's states); the NP look-ahead then reuses it instead of working it
 *  out again (the same product: the same choice). Context: ANY. */
uint8_t dtc3l_choose_zero_unchecked(uint8_t prev_state, real_t np_dev_V, real_t np_band_V, const real_t i_abc[3],
                                    bool push0_known, real_t push0_VA);

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
     * on the quotient instead of three on gap and reach (issue 11; a quotient
     * that rounds up to 1 now counts as not within the period) */
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
    dtc3l_state_voltage(state, in->vc1_V, in->vc2_V, v);
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
 * left it (no copy per tick, issue 11): from @p pred its te_pred_Nm,
 * psi_s_pred_Wb, is_pred_A, dte0_Nm_s, dte_dv and omega_m_rad_s (the
 * ripple-reduction range), in place of dtc3l_in's te_Nm, psi_s_Wb, is_A,
 * dte0_Nm_s, dte_dv and omega_m_rad_s; the rest from @p in. Writes @p out except
 * out->act.vector (its caller, ctl.c, actuates state[] through its own P<->N
 * guard and writes the leg codes there; issue 11). Context: ISR.
 */
void dtc3l_step_predicted(dtc3l *s, const dtc3l_cfg *cfg, real_t dt_s, const dtc3l_cmd *in,
                          const observer_out *pred, dtc3l_out *out);

#ifdef __cplusplus
}
#endif

#endif /* DTC_DTC3L_H */
