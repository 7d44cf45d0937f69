/**
 * @file ratings_types.h
 * @brief The types the configuration keeps of its ratings: the plate and
 *        the label (struct ratings), the derivable values' ids (ratings_id)
 *        and the mask of the values the user set (ratings_mask). The
 *        functions on them are in dtc/ratings.h; ctl_cfg holds one plate and
 *        one mask (dtc/ctl_cfg.h), so this header depends on nothing else.
 */
#ifndef DTC_RATINGS_TYPES_H
#define DTC_RATINGS_TYPES_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The plate and the label, SI. Ranges: ratings_field_min() .. ratings_field_max(). */
typedef struct {
    real_t P_W;           /**< motor rated shaft (output) power, W (500 W .. 5 MW) */
    real_t V_ll_V;        /**< motor rated line-to-line voltage, V rms (200 V .. 6.6 kV) */
    real_t I_A;           /**< motor rated line current, A rms (0.5 A .. 10 kA) */
    real_t f_Hz;          /**< motor rated frequency, Hz (5 .. 400) */
    real_t n_rpm;         /**< motor rated speed, rpm (below synchronous) */
    real_t cos_phi;       /**< motor rated power factor, 0 < x <= 1; 0 = not on the plate */
    real_t vdc_nom_V;     /**< nominal DC link voltage, V (200 V .. 12 kV) */
    real_t inv_I_rated_A; /**< inverter rated (continuous) output current, A rms */
    real_t inv_I_peak_A;  /**< inverter peak output current, A (instantaneous: the devices' limit) */
} ratings;

/**
 * Every value ratings_derive_cfg() derives, in the order it derives them
 * (a value depends only on values before it). Those with a ctl_cfg field
 * (ratings_derivables[id].cfg_offset != RATINGS_NO_FIELD) are written; the
 * others are constants of the control law that are compile-time macros
 * today (their names), listed so that they become fields with their formula.
 */
typedef enum {
    /* the motor model (plate-only estimates, replaced when identified or set) */
    RATINGS_ID_MOTOR_RS = 0,
    RATINGS_ID_MOTOR_RR,
    RATINGS_ID_MOTOR_LM,
    RATINGS_ID_MOTOR_LS,
    RATINGS_ID_MOTOR_LR,
    RATINGS_ID_MOTOR_J,
    RATINGS_ID_MOTOR_B,
    /* the DC link and protection */
    RATINGS_ID_C_DC,
    RATINGS_ID_PSI_REF,
    RATINGS_ID_I_TRIP,
    RATINGS_ID_VDC_MAX,
    RATINGS_ID_VDC_MIN,
    RATINGS_ID_NP_TRIP,
    RATINGS_ID_NP_BAND,
    RATINGS_ID_OVERSPEED,
    /* the DTC */
    RATINGS_ID_FLUX_BAND,
    RATINGS_ID_TORQUE_BAND,
    RATINGS_ID_TORQUE_BAND2,
    RATINGS_ID_RIPPLE_SPEED_MAX,
    /* the observer, the loss-of-control monitor, bring-up */
    RATINGS_ID_OBS_KP_SPEED,
    RATINGS_ID_OBS_KI_SPEED,
    RATINGS_ID_OBS_REGEN_SPEED,
    RATINGS_ID_GUARD_WC,
    RATINGS_ID_GUARD_TIME,
    RATINGS_ID_GUARD_V_TOL,
    RATINGS_ID_BRINGUP_HZ,
    /* the speed loop (from the mechanical time constant t_m = J w_mr / T_r) */
    RATINGS_ID_IP_WN,
    RATINGS_ID_REF_WN,
    RATINGS_ID_NOMINAL_K_X,
    RATINGS_ID_RBFN_K,
    RATINGS_ID_RBFN_GAMMA_W,
    RATINGS_ID_RBFN_GAMMA_ZETA,
    RATINGS_ID_RBFN_ZETA_LEAK,
    RATINGS_ID_SPEED_RAMP,
    RATINGS_ID_RBFN_BOUNDARY,
    RATINGS_ID_RBFN_DEAD_ZONE,
    RATINGS_ID_RBFN_ZETA_MAX,
    RATINGS_ID_STALL_TIME,
    RATINGS_ID_SPEED_DEV_BAND,
    RATINGS_ID_SPEED_DEV_TIME,
    /* after ctl_cfg_derive(): need the pull-out torque and the flux ramp */
    RATINGS_ID_TE_MAX,
    RATINGS_ID_RBFN_M_W,
    RATINGS_ID_RBFN_CENTRES,  /**< all n_nodes centres together */
    RATINGS_ID_RBFN_WIDTHS,   /**< all n_nodes widths together */
    RATINGS_ID_PREMAG,
    /* constants that are macros of the control law today (no ctl_cfg field yet) */
    RATINGS_ID_DROP_BAND,
    RATINGS_ID_LOWFLUX_MARGIN,
    RATINGS_ID_LOWFLUX_ENTER,
    RATINGS_ID_LOWFLUX_EXIT,
    RATINGS_ID_LOWFLUX_MIN_TE,
    RATINGS_ID_STALL_SPEED_ERR,
    RATINGS_ID_STALL_WINDOW,
    RATINGS_ID_BRAKE_STALL_SPEED,
    RATINGS_ID_BRAKE_STALL_TIME,
    RATINGS_ID_BRINGUP_BOOST,
    RATINGS_ID_OBS_REGEN_MIN_TE,
    RATINGS_ID_RSID_MAX_SPEED,
    RATINGS_ID_RSID_SPEED_FROM,
    RATINGS_ID_RSID_MIN_CHARGE,
    RATINGS_ID_DTC_PSI_TINY,
    RATINGS_ID_PLAUS_SUM_ABS,
    RATINGS_ID_PLAUS_CURRENT,
    RATINGS_ID_PLAUS_OPEN,
    RATINGS_ID_PLAUS_PHASE_MIN,
    RATINGS_ID_COUNT
} ratings_id;

/** One bit per ratings_id: set = the user's value, kept; clear = derived. */
#define RATINGS_MASK_WORDS (((unsigned)RATINGS_ID_COUNT + 31u) / 32u)
typedef struct {
    uint32_t w[RATINGS_MASK_WORDS];
} ratings_mask;

/** Mark @p id as set by the user. Context: any. */
static inline void ratings_mask_set(ratings_mask *m, ratings_id id)
{
    m->w[(unsigned)id / 32u] |= 1u << ((unsigned)id % 32u);
}

/** Mark @p id as derived again. Context: any. */
static inline void ratings_mask_clear(ratings_mask *m, ratings_id id)
{
    m->w[(unsigned)id / 32u] &= ~(1u << ((unsigned)id % 32u));
}

/** True when @p id is set by the user (the read-back's "set"; false: "derived"). Context: any. */
static inline bool ratings_mask_has(const ratings_mask *m, ratings_id id)
{
    return (m->w[(unsigned)id / 32u] >> ((unsigned)id % 32u)) & 1u;
}

#ifdef __cplusplus
}
#endif

#endif /* DTC_RATINGS_TYPES_H */
