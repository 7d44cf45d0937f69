/**
 * @file plant.h
 * @brief Plant model for the SIL: induction machine, three-level NPC inverter,
 *        DC link, mechanics and sensors. Portable C99, double precision, no
 *        globals (so it can be compiled for the emulated Cortex-M4 too).
 *
 * Units are SI throughout; rotor quantities are referred to the stator; the
 * stationary (alpha, beta) frame uses the amplitude-invariant Clarke transform
 * (x_alpha = x_a, x_beta = (x_b - x_c)/sqrt(3)), so torque is
 * Te = 1.5 * p * (psi_s_alpha * i_s_beta - psi_s_beta * i_s_alpha).
 *
 * Life cycle: plant_default_config() -> edit -> plant_init() -> per control
 * period: plant_sample() (what the board's ADC sees at the start of the
 * period), then plant_advance() over the period with the applied vectors.
 */
#ifndef PLANT_PLANT_H
#define PLANT_PLANT_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Leg codes accepted by plant_advance and plant_inverter_output. */
#define PLANT_LEG_N 0u   /**< leg tied to the negative rail: -vc2 */
#define PLANT_LEG_O 1u   /**< leg clamped to the neutral point: 0 V */
#define PLANT_LEG_P 2u   /**< leg tied to the positive rail: +vc1 */
/**
 * Gates off: the leg's switches are open and only its diodes conduct. A
 * current into the motor (i > 0) returns through the lower diodes (leg at N),
 * a current out of the motor (i < 0) through the upper diodes (leg at P). A
 * current reaching zero stays zero (a diode does not conduct backwards) and the
 * phase floats; it conducts again only if its open-circuit voltage would leave
 * the rails. Simplification: the diode state is decided at the start of each
 * integration step and a current that crosses zero inside the step is clamped
 * to zero at its end (the stator leakage flux is corrected; error O(h)).
 * Codes above 3 are treated as 3 (the safe state).
 */
#define PLANT_LEG_OFF 3u

/** Error code of plant_check_config / plant_init (same value as HAL_EINVAL). */
#define PLANT_EINVAL (-22)

/** T-equivalent circuit and mechanical parameters. */
typedef struct {
    double Rs_ohm, Rr_ohm;   /**< stator, rotor resistance (> 0) */
    double Lls_H, Llr_H;     /**< leakage inductances (> 0) */
    double Lm_H;             /**< magnetising inductance (> 0) */
    int pole_pairs;          /**< p (>= 1) */
    double J_kgm2;           /**< inertia (> 0) */
    double B_Nms;            /**< viscous friction, N m s/rad (>= 0) */
} plant_motor_params;

/** DC source and split DC link. */
typedef struct {
    double vdc_V;            /**< source voltage (> 0) */
    double r_src_ohm;        /**< series resistance source -> link (> 0) */
    double c1_F, c2_F;       /**< upper and lower capacitor (> 0) */
} plant_dc_params;

/** Sensor chain: ideal value -> gain/offset error -> noise -> ADC quantisation. */
typedef struct {
    int adc_bits;            /**< ADC resolution (1..16), 12 on the board */
    double i_fs_A;           /**< current full scale: the ADC spans -i_fs..+i_fs */
    double v_fs_V;           /**< voltage full scale: the ADC spans 0..v_fs */
    double i_gain[3];        /**< per-phase gain factor (1 = ideal) */
    double i_offset_A[3];    /**< per-phase offset, A */
    double v_gain[2];        /**< vc1, vc2 gain factor */
    double v_offset_V[2];    /**< vc1, vc2 offset, V */
    double i_noise_A;        /**< white noise rms on each current, A (0 = none) */
    double v_noise_V;        /**< white noise rms on each voltage, V */
    uint32_t seed;           /**< noise seed: equal seeds give equal runs */
} plant_sensor_params;

typedef enum {
    PLANT_SUPPLY_INVERTER = 0, /**< three-level NPC inverter on the DC link */
    PLANT_SUPPLY_SINE = 1,     /**< ideal balanced three-phase source, no inverter */
} plant_supply_mode;

/** Ideal sinusoidal source: va = sqrt(2/3) * V_ll * cos(2 pi f t + phase). */
typedef struct {
    double v_ll_rms_V;       /**< line-to-line rms voltage (>= 0) */
    double f_Hz;             /**< frequency (>= 0) */
    double phase_rad;        /**< phase of va at t = 0 */
} plant_sine_params;

typedef struct {
    plant_motor_params motor;
    plant_dc_params dc;
    plant_sensor_params sensor;
    plant_supply_mode supply;
    plant_sine_params sine;
    /**
     * Largest RK4 step inside a segment, s (1e-7..1e-4; default 40e-6). The
     * step used is the largest that divides the segment evenly and is also
     * no longer than the DC link's time constant R C1 C2/(C1+C2).
     */
    double h_max_s;
} plant_config;

/** Integration state and scheduled-change targets. Owned by the caller. */
typedef struct {
    plant_config cfg;        /**< working copy; parameter events edit it */
    double t_s;              /**< simulated time */
    double psi_s[2];         /**< stator flux alpha, beta, Wb */
    double psi_r[2];         /**< rotor flux alpha, beta (stator-referred), Wb */
    double omega_m;          /**< mechanical speed, rad/s */
    double theta_m;          /**< mechanical angle, rad (wrapped to -pi..pi) */
    double vc1, vc2;         /**< capacitor voltages, V */
    /**
     * Load torque, N m. Enters the mechanics as a plain constant:
     * J domega/dt = Te - B omega - T_L (it opposes positive speed; at
     * negative speed it keeps its sign, it is not sign(omega) * T_L).
     */
    double t_load_Nm;
    uint64_t rng;            /**< noise generator state */
    /* energy accounting since init (for the power-balance test and metrics) */
    double e_in_J;           /**< electrical energy into the motor terminals */
    double e_cu_J;           /**< stator + rotor copper losses */
    double e_mech_J;         /**< mechanical energy out of the air gap (Te * omega_m) */
    /**
     * Leg commutations between consecutive applied vectors (vec0 -> vec1 and
     * across periods; zero-length segments are not applied): for each leg,
     * |new code - old code| with N=0, O=1, P=2, so N<->O and O<->P count 1
     * (one complementary device pair commutates) and a direct P<->N step counts
     * 2. Changes to or from gates off (code 3) are not counted. Suggested metric
     * (the one the SIL uses): device switching frequency =
     * switch_count / (3 legs * elapsed time) / 2.
     */
    unsigned long switch_count;
    /* bookkeeping (added; read through plant_get_truth) */
    uint8_t legs_last[3];    /**< last applied vector as given (0..3) */
    uint8_t legs_valid;      /**< 1 once a vector has been applied */
    double v_last_V[3];      /**< phase-to-star voltages at the end of the last advance */
    double i_np_last_A;      /**< neutral-point current at the end of the last advance */
} plant_state;

/** A snapshot of true values, for metrics and tests (not seen by the firmware). */
typedef struct {
    double t_s;
    double ia_A, ib_A, ic_A;   /**< true phase currents */
    double va_V, vb_V, vc_V;   /**< phase-to-star-point voltages at the last instant */
    double is_alpha_A, is_beta_A, ir_alpha_A, ir_beta_A;
    double psi_s_alpha_Wb, psi_s_beta_Wb, psi_r_alpha_Wb, psi_r_beta_Wb;
    double te_Nm;              /**< electromagnetic torque */
    double omega_m_rad_s;      /**< mechanical speed */
    double theta_m_rad;
    double vc1_V, vc2_V;
    double i_np_A;             /**< neutral-point current at the last instant */
    double w_mag_J;            /**< magnetic energy stored in the inductances */
} plant_truth;

/** Raw converter codes, as the board's ADC delivers them at the start of a period. */
typedef struct {
    uint16_t i_code[3];        /**< currents: code = (i / i_fs + 1) / 2 * (2^bits - 1), rounded, clamped */
    uint16_t v_code[2];        /**< vc1, vc2: code = v / v_fs * (2^bits - 1), rounded, clamped */
    double omega_m_rad_s;      /**< true speed (a board speed sensor; diagnostics only) */
} plant_adc;

/** Fill @p cfg with the 10 hp motor and drive of docs/motor-10hp.json, inverter supply. */
void plant_default_config(plant_config *cfg);

/**
 * Check @p cfg for physical sense.
 * @return 0, or a negative code with *what set to a static description of the
 *         first bad field (for example "motor.J_kgm2 must be > 0").
 */
int plant_check_config(const plant_config *cfg, const char **what);

/** Initialise at standstill, demagnetised, capacitors at vdc/2 each, t = 0. @return 0 or plant_check_config's code. */
int plant_init(plant_state *s, const plant_config *cfg);

/**
 * Integrate over one control period with the inverter applying @p vec0 for
 * duty0 * period_s and then @p vec1 for the rest (each leg: 0 = N, 1 = O, 2 = P).
 * Every switching instant is honoured exactly (one segment per vector).
 * In PLANT_SUPPLY_SINE mode the vectors are ignored.
 * Bad input changes nothing or is made safe: a period that is not finite and
 * > 0 does nothing; duty0 is clamped to 0..1 (NaN -> 0); a NULL vector or a
 * leg code above 3 means gates off. Segments shorter than 1 ps are skipped
 * (not applied, not counted in switch_count).
 */
void plant_advance(plant_state *s, const uint8_t vec0[3], const uint8_t vec1[3],
                   double duty0, double period_s);

/**
 * Sample the sensors now. Measured value = gain * true + offset + noise, then
 * quantised as documented in plant_adc. The noise generator advances only when
 * a noise rms is configured (> 0), so runs without noise draw nothing.
 */
void plant_sample(plant_state *s, plant_adc *out);

/** Convert codes back to engineering units with the nominal (ideal) scaling, as the board firmware does. */
void plant_adc_to_units(const plant_config *cfg, const plant_adc *adc, double i_A[3], double v_V[2]);

/** True values now. */
void plant_get_truth(const plant_state *s, plant_truth *out);

/*
 * Scheduled changes (the scenario engine calls these at the event times).
 * They edit the working copy s->cfg; a value outside the range
 * plant_check_config accepts (or not finite) is ignored and the old value kept.
 */
void plant_set_load(plant_state *s, double t_load_Nm);
void plant_set_inertia(plant_state *s, double J_kgm2);
void plant_set_friction(plant_state *s, double B_Nms);
void plant_set_rs(plant_state *s, double Rs_ohm);
void plant_set_rr(plant_state *s, double Rr_ohm);

/* Building blocks exposed for unit tests. */

/**
 * Motor phase voltages (isolated star) and neutral-point current for one
 * switching state.
 * @param legs  leg states a, b, c (0 = N, 1 = O, 2 = P, 3 = gates off: the
 *              sign of its current picks N or P; with zero current the leg
 *              floats, is left out of the star-point average and reported as
 *              0 V, because its true voltage needs the machine's emf, which
 *              the integration in plant_advance does use)
 * @param vc1, vc2 capacitor voltages, V
 * @param i_abc phase currents, A (for the neutral-point current)
 * @param[out] v_abc phase-to-star voltages, V
 * @param[out] i_np current drawn from the neutral point (sum of the currents of legs in O), A
 */
void plant_inverter_output(const uint8_t legs[3], double vc1, double vc2,
                           const double i_abc[3], double v_abc[3], double *i_np);

#ifdef __cplusplus
}
#endif

#endif /* PLANT_PLANT_H */
