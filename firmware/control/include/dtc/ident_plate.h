/**
 * @file ident_plate.h
 * @brief The motor's rating plate and the first estimates the
 *        identification run sizes its steps with (docs/commissioning.md,
 *        "Identification").
 *
 * The identification run measures the equivalent circuit, but it has to
 * choose its test currents, its durations and its regulator gains before it
 * knows it. It takes them from the plate: rated power, voltage, current,
 * frequency, speed and power factor, the data every induction motor's plate
 * carries. The estimates are rough on purpose (within about a factor of 1.5
 * for the motors of the Krause, Wasynczuk and Sudhoff table, 3 hp to
 * 2250 hp): they size the run, they are never written to the motor model.
 *
 *   base impedance     Zb = V_phase / I                      (rms values)
 *   leakage            sigma Ls ~ 0.15 Zb / omega_e          (0.1..0.2 per unit is typical)
 *   magnetising        I0 ~ I (sin phi - 0.15)               (the reactive current less the leakage's share)
 *   rotor time const.  Tr ~ (cos phi / (sin phi - 0.15)) / omega_slip   (rated slip = iq / (id Tr))
 *
 * Context: BG (configuration).
 */
#ifndef DTC_IDENT_PLATE_H
#define DTC_IDENT_PLATE_H

#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The rating plate (rated values, as the plate states them). */
typedef struct {
    real_t p_W;          /**< rated shaft power, W (> 0) */
    real_t v_ll_V;       /**< rated line-to-line voltage, V rms (> 0) */
    real_t i_A;          /**< rated current, A rms (> 0) */
    real_t f_Hz;         /**< rated frequency, Hz (> 0) */
    real_t speed_rpm;    /**< rated speed, rpm (below the synchronous speed) */
    real_t cos_phi;      /**< rated power factor, 0.3..0.99 */
} ident_plate;

/** What the run derives from the plate (ident_plate_estimate). */
typedef struct {
    real_t pole_pairs;   /**< p: the largest whose synchronous speed is above the rated speed */
    real_t w_e_rad_s;    /**< rated electrical angular frequency, rad/s */
    real_t w_m_rad_s;    /**< rated mechanical speed, rad/s */
    real_t w_slip_rad_s; /**< rated slip frequency (electrical), rad/s */
    real_t te_Nm;        /**< rated torque p_W / w_m, N m */
    real_t i_peak_A;     /**< rated current, peak, A */
    real_t v_peak_V;     /**< rated phase voltage, peak, V */
    real_t psi_s_Wb;     /**< rated stator flux v_peak / w_e, Wb */
    real_t z_base_ohm;   /**< base impedance V_phase / I, ohm */
    real_t i_mag_A;      /**< magnetising current estimate, peak, A */
    real_t sigma_ls_H;   /**< transient inductance estimate, H */
    real_t tr_s;         /**< rotor time constant estimate, s */
} ident_plate_est;

/** Error codes of ident_plate_check (negative, first violated rule). */
enum ident_plate_error {
    IDENT_PLATE_OK = 0,
    IDENT_PLATE_E_VALUE = -1, /**< a value not > 0 (or not finite), or cos_phi outside 0.3..0.99 */
    IDENT_PLATE_E_SPEED = -2, /**< the rated speed is not below a synchronous speed 60 f / p, p = 1..12 */
};

/** Check @p p. @return IDENT_PLATE_OK or the first violated rule. Context: BG. */
int ident_plate_check(const ident_plate *p);

/**
 * The estimates of @p p (which must pass ident_plate_check) into @p e.
 * Context: BG.
 */
void ident_plate_estimate(const ident_plate *p, ident_plate_est *e);

#ifdef __cplusplus
}
#endif

#endif /* DTC_IDENT_PLATE_H */
