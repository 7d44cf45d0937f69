/**
 * @file ratings.h
 * @brief Ratings in, everything else derived: the motor's plate and the
 *        inverter's label, their per-unit bases, a plate-only motor
 *        estimate and every derivable default of ctl_cfg.
 *
 * A user reads nine numbers (struct ratings): the motor's rated shaft power,
 * line voltage, line current, frequency and speed (cos phi if the plate has
 * it), the DC link's nominal voltage and the inverter's rated and peak
 * current. ratings_check() refuses an implausible set and names the first
 * offending field; ratings_base_of() turns a plausible one into per-unit
 * bases; ratings_derive_cfg() writes every derivable field of a ctl_cfg from
 * them, except the fields the user set (a ratings_mask, one bit per
 * derivable value, ratings_id). Each derived value is a per-unit constant
 * times its base: the constant is the 10 hp drive's tuned value over that
 * base (docs/commissioning.md, "Ratings and derived values", lists every id
 * with its formula and the values that stay absolute).
 *
 * The control law keeps working in physical units: the bases are worked out
 * here, in the background, once per configuration, and the tick reads only
 * the derived constants. Everything in this file runs in the background
 * (BG); none of it is called from the interrupt.
 */
#ifndef DTC_RATINGS_H
#define DTC_RATINGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "dtc/ctl.h"
#include "dtc/motor_model.h"
#include "dtc/num.h"
#include "dtc/ratings_types.h"

#ifdef __cplusplus
extern "C" {
#endif


/** The fields of struct ratings, in the order ratings_check() judges them. */
typedef enum {
    RATINGS_FIELD_NONE = 0,
    RATINGS_FIELD_P_W,
    RATINGS_FIELD_V_LL_V,
    RATINGS_FIELD_I_A,
    RATINGS_FIELD_F_HZ,
    RATINGS_FIELD_N_RPM,
    RATINGS_FIELD_COS_PHI,
    RATINGS_FIELD_VDC_NOM_V,
    RATINGS_FIELD_INV_I_RATED_A,
    RATINGS_FIELD_INV_I_PEAK_A,
    RATINGS_FIELD_COUNT
} ratings_field;

/** Why a set of ratings is refused (ratings_abort_code() gives the SDO abort code of each). */
typedef enum {
    RATINGS_OK = 0,
    RATINGS_E_NOT_FINITE,         /**< NaN or infinite */
    RATINGS_E_NOT_POSITIVE,       /**< zero or negative (cos phi: negative) */
    RATINGS_E_BELOW_RANGE,        /**< below ratings_field_min() */
    RATINGS_E_ABOVE_RANGE,        /**< above ratings_field_max() (cos phi above 1) */
    RATINGS_E_SPEED_SYNCHRONOUS,  /**< n_rpm at or above synchronous speed (60 f), or a rated slip below
                                       RATINGS_SLIP_MIN for its pole count (at synchronous speed) */
    RATINGS_E_POLES,              /**< n_rpm so low for f_Hz that the machine has more than
                                       RATINGS_POLE_PAIRS_MAX pole pairs */
    RATINGS_E_LINK_TOO_LOW,       /**< vdc_nom_V: sqrt 2 V_ll above 1.10 vdc, the line voltage a
                                       three-level inverter gives in six-step */
    RATINGS_E_POWER_ABOVE_INPUT,  /**< P_W above sqrt 3 V I (x cos phi when given): an efficiency above 1 */
    RATINGS_E_POWER_TOO_LOW,      /**< P_W below RATINGS_ETA_PF_MIN x sqrt 3 V I: efficiency x power
                                       factor below any induction motor's (a unit mistyped) */
    RATINGS_E_PEAK_BELOW_RATED,   /**< inv_I_peak_A below sqrt 2 inv_I_rated_A */
    RATINGS_E_PEAK_BELOW_MOTOR,   /**< inv_I_peak_A below RATINGS_PEAK_MARGIN x the motor's rated peak
                                       current sqrt 2 I_A: the trip would sit at the rated torque */
    RATINGS_E_MOTOR_ABOVE_INVERTER, /**< I_A above RATINGS_MOTOR_OVER_INVERTER_MAX x inv_I_rated_A */
    RATINGS_E_PERIOD,             /**< f_Hz: the electrical speed at the overspeed trip is beyond what the
                                       control period follows (observer.h: omega T <= 0.3) */
} ratings_reason;

/** The first offending field and why; {RATINGS_FIELD_NONE, RATINGS_OK} when there is none. */
typedef struct {
    ratings_field field;
    ratings_reason reason;
} ratings_error;

/** Rules of ratings_check() that are numbers (docs/commissioning.md says why each). */
#define RATINGS_SLIP_MIN R(0.001)             /**< smallest rated slip of an induction motor, 1 */
#define RATINGS_POLE_PAIRS_MAX 32             /**< largest pole-pair count (64 poles) */
#define RATINGS_SIX_STEP_LL R(1.10)           /**< largest line-voltage peak per volt of DC link (six-step) */
#define RATINGS_ETA_PF_MIN R(0.25)            /**< smallest efficiency x power factor at the rated point */
#define RATINGS_MOTOR_OVER_INVERTER_MAX R(1.5) /**< largest motor current per ampere of inverter rating */
#define RATINGS_PEAK_MARGIN R(1.5)            /**< inverter peak over the motor's rated peak current, at least */

/**
 * Judge a set of ratings: every field finite, > 0 (cos phi: 0 = unknown, or
 * 0 < cos phi <= 1) and within its range, in field order; then the relations
 * between fields (synchronous speed and pole count, the link against the
 * line voltage, the power against the electrical input, the inverter's peak
 * against its rating, the motor against the inverter), each naming the field
 * listed with its reason. Pure; context: BG (any).
 * @return the first offending field and its reason, or {RATINGS_FIELD_NONE, RATINGS_OK}
 */
ratings_error ratings_check(const ratings *r);

/**
 * The SDO abort code (CiA 301) a write of a refused set answers with:
 * 0x06090030 not a number, 0x06090032 too low, 0x06090031 too high,
 * 0x06090036 a relation between two values broken; 0 for RATINGS_OK.
 * (A write while the drive runs is the CAN layer's 0x08000022.) Pure; context: any.
 */
uint32_t ratings_abort_code(ratings_reason reason);

/** The field's name as in struct ratings ("P_W", ...); "" for NONE. Pure; context: any. */
const char *ratings_field_name(ratings_field field);

/** The reason as a short phrase ("must be finite", ...); "" for RATINGS_OK. Pure; context: any. */
const char *ratings_reason_text(ratings_reason reason);

/** The range of a field, in its unit (0 for NONE; cos phi: 0 .. 1). Pure; context: any. */
real_t ratings_field_min(ratings_field field);
real_t ratings_field_max(ratings_field field);

/**
 * Per-unit bases of a plate (docs/commissioning.md). The fixed-point backend
 * will scale every quantity by these; the derivation uses them for its
 * constants. Units as named.
 */
typedef struct {
    real_t pole_pairs;    /**< p = floor(60 f / n) (the rated speed is below synchronous) */
    real_t slip;          /**< rated slip 1 - p n / (60 f), 0.001..0.5 */
    real_t cos_phi;       /**< the plate's power factor, or the estimate when it has none */
    real_t V_b;           /**< voltage base: phase peak, sqrt(2/3) V_ll, V */
    real_t I_b;           /**< current base: phase peak, sqrt 2 I, A */
    real_t w_b;           /**< speed base: rated electrical angular frequency 2 pi f, rad/s */
    real_t psi_b;         /**< flux base V_b / w_b, Wb */
    real_t Z_b;           /**< impedance base V_b / I_b, ohm */
    real_t L_b;           /**< inductance base Z_b / w_b, H */
    real_t T_b;           /**< torque base 1.5 p psi_b I_b, N m */
    real_t S_b;           /**< power base 1.5 V_b I_b = sqrt 3 V_ll I, VA */
    real_t w_mb;          /**< mechanical speed base w_b / p (synchronous), rad/s */
    real_t w_mr;          /**< rated mechanical speed 2 pi n / 60, rad/s */
    real_t T_r;           /**< rated torque P / w_mr, N m */
    real_t vdc_b;         /**< DC-link base: vdc_nom_V, V */
} ratings_base;

/** The bases of @p r, which ratings_check() has passed. Pure; context: BG. */
void ratings_base_of(const ratings *r, ratings_base *b);

/**
 * A plate-only motor model, for running before the identification
 * (docs/commissioning.md, "Motor estimate"; every value is an estimate):
 * Rr from the rated slip and the active current, Rs and the leakages as
 * per-unit values of Z_b, Lm from the reactive power left after the
 * leakages, J from the inertia constant of a drive train (motor and load,
 * erring high), B from a friction loss of 1 % of P at rated speed. Pole pairs are the
 * plate's own (exact). Pure; context: BG.
 */
void ratings_motor_estimate(const ratings *r, const ratings_base *b, motor_model *m);


/** ratings_derivable.cfg_offset of a value with no ctl_cfg field (yet). */
#define RATINGS_NO_FIELD SIZE_MAX

/** One derivable value: what it is and how it is derived (the read-back's and the docs' text). */
typedef struct {
    ratings_id id;
    const char *name;     /**< the ctl_cfg field ("dtc.psi_ref_Wb"), or the macro it is today ("ctl.c DROP_BAND_A") */
    const char *unit;     /**< its unit ("Wb", "1/s", ...) */
    const char *rule;     /**< its formula in the bases ("0.0857 T_r") */
    size_t cfg_offset;    /**< offsetof(ctl_cfg, field) of its real_t field (the first element for
                               the centres and widths); RATINGS_NO_FIELD when it has none */
    bool estimate;        /**< a plate-only estimate of the motor (the identification replaces it) */
} ratings_derivable;

/**
 * The id whose ctl_cfg field holds the byte at @p offset (offsetof(ctl_cfg,
 * ...); a centre or width of any node gives RBFN_CENTRES / RBFN_WIDTHS), or
 * RATINGS_ID_COUNT when the field is not derivable. Pure; context: BG.
 */
ratings_id ratings_id_at(size_t offset);

/** The table, indexed by ratings_id. */
extern const ratings_derivable ratings_derivables[RATINGS_ID_COUNT];

/** What a derivation works from: the plate, its bases and the plate-only motor estimate. */
typedef struct {
    ratings plate;
    ratings_base base;
    motor_model estimate;
    ratings ref_plate;       /**< the reference drive's plate (ratings_reference()) */
    ratings_base ref_base;   /**< its bases */
    motor_model ref_model;   /**< the reference drive's motor */
} ratings_derivation;

/**
 * The reference drive the tuned values are for: the 10 hp plate
 * (docs/motor-10hp.json: 7457 W, 220 V, 24.4 A, 60 Hz, 1744 rpm, cos phi
 * 0.886), its 311 V link and the board's inverter label (30 A rated, 100 A
 * peak) into @p r, the motor's own model into @p m. Every derived value is
 * that drive's tuned value times the ratio of its base to the reference's
 * (a per-unit constant computed, not rounded), so the reference plate
 * derives the tuned values bit for bit. Pure; context: BG.
 */
void ratings_reference(ratings *r, motor_model *m);

/**
 * Check @p r (ratings_check()) and, when it passes, fill @p d with it, its
 * bases and its motor estimate. @p d is written only when the set passes.
 * Context: BG.
 */
ratings_error ratings_prepare(ratings_derivation *d, const ratings *r);

/**
 * The derived value of @p id, from @p d and the values of @p cfg it depends
 * on (those before it in ratings_id, and for TE_MAX .. PREMAG the quantities
 * ctl_cfg_derive() works out: read them from a cfg ratings_derive_cfg() left).
 * For RBFN_CENTRES and RBFN_WIDTHS: the outermost centre and the width.
 * Pure; context: BG.
 */
real_t ratings_value(const ratings_derivation *d, const ctl_cfg *cfg, ratings_id id);

/**
 * Write every derivable field of @p cfg whose bit is clear in @p set from
 * the ratings @p r, then ctl_cfg_derive(). The other fields (the set ones,
 * and those that are not derivable: the period, the controller's mode, the
 * inverter's dead time and device drop, dimensionless tunings) keep their
 * values, so @p cfg must hold a whole configuration (ctl_cfg_default()).
 * The pole pairs and vdc_nom_V are the plate's, always. @p set NULL: nothing
 * set. Every rule is judged first: on an error @p cfg is not touched.
 * Context: BG.
 * @return the first offending field of @p r (ratings_check(), then the
 *         control period against f_Hz: RATINGS_E_PERIOD), or {NONE, OK}
 */
ratings_error ratings_derive_cfg(ctl_cfg *cfg, const ratings *r, const ratings_mask *set);

#ifdef __cplusplus
}
#endif

#endif /* DTC_RATINGS_H */
