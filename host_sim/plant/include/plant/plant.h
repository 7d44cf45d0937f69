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
    /**
     * Main-flux saturation (off when Lm_sat_psi_Wb = 0, the default). The
     * magnetising curve is i_m = (psi_m / Lm_H) (1 + (|psi_m| / Lm_sat_psi_Wb)^n),
     * n = Lm_sat_exponent, i.e. Lm(psi_m) = Lm_H / (1 + (|psi_m|/Lm_sat_psi_Wb)^n):
     * Lm_H for small flux, half of it at the knee flux. See induction_machine.c.
     */
    double Lm_sat_psi_Wb;    /**< knee flux where Lm has halved, Wb (0 = no saturation) */
    double Lm_sat_exponent;  /**< n, sharpness of the knee (2..20; default 6) */
} plant_motor_params;

/** DC source and split DC link. */
typedef struct {
    double vdc_V;            /**< source voltage (> 0) */
    double r_src_ohm;        /**< series resistance source -> link (> 0) */
    double c1_F, c2_F;       /**< upper and lower capacitor (> 0) */
} plant_dc_params;

/**
 * Inverter non-idealities (both 0 = the ideal inverter, the plant default).
 * Dead time: at every commutation of a leg between two levels the outgoing
 * device turns off at once and the incoming one dead_time_s later; in
 * between the leg's current flows through the freewheeling/clamp diodes, so
 * the leg sits at the level the current direction picks (see dead_time.c).
 * On-state voltage: every conducting path of an NPC leg is two devices in
 * series, so the leg voltage drops by 2 v_on_V in the direction of the current.
 */
typedef struct {
    double dead_time_s;      /**< blanking time per commutation, s (0 .. 50e-6) */
    double v_on_V;           /**< on-state voltage of one device (switch or diode), V (0 .. 50) */
} plant_inverter_params;

/** Sensor channels (plant_set_sensor_* and plant_adc order). */
enum { PLANT_CH_IA = 0, PLANT_CH_IB = 1, PLANT_CH_IC = 2, PLANT_CH_VC1 = 3, PLANT_CH_VC2 = 4, PLANT_N_CH = 5 };

/** Sensor channel faults (plant_set_sensor_fault). */
typedef enum {
    PLANT_SENSOR_OK = 0,     /**< normal conversion */
    PLANT_SENSOR_STUCK = 1,  /**< the channel repeats the code of its last conversion */
    PLANT_SENSOR_LOST = 2,   /**< the signal is gone: the channel reads exactly 0 A / 0 V */
} plant_sensor_fault;

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

/**
 * Load models besides the constant torque (plant_state.t_load_Nm); all 0 by
 * default. The shaft sees, opposing positive speed w (rad/s):
 *   T_load = t_load_Nm + coulomb_Nm sgn(w) + viscous_Nms w + fan_Nms2 w |w|
 * so the friction-like and fan parts follow the sign of the speed (they only
 * brake) while t_load_Nm is active (it keeps its sign, e.g. a hoist). At
 * w = 0 the Coulomb part holds the rotor while the other torques stay within
 * +-coulomb_Nm (static friction = Coulomb level, no Stribeck dip).
 */
typedef struct {
    double coulomb_Nm;       /**< Coulomb (dry) friction level, N m (>= 0) */
    double viscous_Nms;      /**< viscous load on top of motor.B_Nms, N m s/rad (>= 0) */
    double fan_Nms2;         /**< fan/pump coefficient k of T = k w^2, N m s^2/rad^2 (>= 0) */
} plant_load_params;

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
    plant_load_params load;
    plant_dc_params dc;
    plant_inverter_params inverter;
    plant_sensor_params sensor;
    plant_supply_mode supply;
    plant_sine_params sine;
    /**
     * Largest RK4 step inside a segment, s (1e-7..1e-4; default 40e-6). The
     * step used is the largest that divides the segment evenly and is also
     * no longer than the DC link's time constant R C1 C2/(C1+C2).
     */
    double h_max_s;
    /**
     * The state at t = 0 (a shaft that turns before the drive starts): the
     * mechanical speed, rad/s (|x| <= 2000; default 0), and a residual rotor
     * flux as a fraction of the nameplate supply's stator flux
     * sqrt(2/3) sine.v_ll_rms_V / (2 pi sine.f_Hz) (0..1.2; default 0), with no
     * stator current (stator flux Lm / Lr of it), along the alpha axis.
     */
    double initial_omega_m_rad_s;
    double initial_flux_frac;
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
     * Constant (active) load torque, N m. Enters the mechanics as a plain
     * constant: J domega/dt = Te - B omega - T_L - (the load models of
     * cfg.load) (it opposes positive speed; at negative speed it keeps its
     * sign, it is not sign(omega) * T_L).
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
    /* sensor faults (plant_set_sensor_fault) */
    uint8_t sensor_fault[PLANT_N_CH]; /**< plant_sensor_fault per channel */
    uint16_t code_last[PLANT_N_CH];   /**< codes of the last plant_sample (for a stuck channel) */
    uint8_t code_valid;               /**< 1 once plant_sample has run */
    /* dead time (dead_time.c): per leg, end of the blanking interval (absolute s) and its code */
    double dead_until_s[3];
    uint8_t dead_code[3];
    uint8_t phase_open[3];   /**< 1: motor phase disconnected (plant_set_phase_open) */
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

/**
 * Raw converter codes, as the board's ADC delivers them at the start of a period.
 * A channel with a sensor fault reads as plant_sensor_fault says.
 */
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
 * Every switching instant is honoured exactly (one segment per vector); with
 * cfg.inverter.dead_time_s > 0 each commutation edge of a leg is followed by
 * its blanking interval (plant_inverter_params), also across periods.
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

void plant_set_lm(plant_state *s, double Lm_H);
/** DC source voltage (a sag or a surge of the supply); must be > 0. */
void plant_set_vdc(plant_state *s, double vdc_V);
/** Gain (> 0) of sensor channel @p ch (PLANT_CH_...). */
void plant_set_sensor_gain(plant_state *s, int ch, double gain);
/** Offset of sensor channel @p ch, A or V (finite). */
void plant_set_sensor_offset(plant_state *s, int ch, double offset);
/** Fault of sensor channel @p ch from the next plant_sample on (PLANT_SENSOR_OK clears it). */
void plant_set_sensor_fault(plant_state *s, int ch, plant_sensor_fault f);

/**
 * Disconnect (@p open = 1) or reconnect motor phase @p k (0..2) from its
 * inverter leg: a broken cable or a blown fuse. The phase carries no current
 * (its voltage is the machine's emf); the leg keeps switching (switch_count).
 * Inverter supply only (the sine source ignores it).
 */
void plant_set_phase_open(plant_state *s, int k, int open);

/**
 * Total load torque (constant + Coulomb + viscous + fan, not motor.B_Nms) at
 * speed @p omega_m_rad_s, N m, opposing positive speed. At zero speed the
 * Coulomb part is reported as 0 (its holding value depends on the drive torque).
 */
double plant_load_torque(const plant_state *s, double omega_m_rad_s);

/* Building blocks exposed for unit tests. */

/**
 * Motor phase voltages (isolated star) and neutral-point current for one
 * switching state of the IDEAL inverter (no dead time, no on-state drop).
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
