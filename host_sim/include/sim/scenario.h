/**
 * @file scenario.h
 * @brief A SIL scenario: plant, supply, controller, reference, load, events
 *        and metrics options, parsed from an INI file (docs/scenarios.md).
 *
 * Life cycle: scenario_default() -> scenario_parse_file() (or
 * scenario_parse_string()) -> scenario_set() for each `--set` -> scenario_finish()
 * (cross-checks, plant_check_config). Every function that can fail returns 0
 * or SCENARIO_EINPUT and writes ONE line "FILE:LINE: problem" (or
 * "--set section.key: problem") into the caller's buffer.
 *
 * Speeds in the file are in rpm (mechanical); everything in this struct is SI
 * except where the name says _rpm. The struct is plain data (no heap), so it
 * can be copied freely.
 */
#ifndef SIM_SCENARIO_H
#define SIM_SCENARIO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "dtc/ratings_types.h"
#include "plant/plant.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SCENARIO_EINPUT (-2)       /**< bad input: the caller exits with status 2 */
#define SCENARIO_MAX_ENTRIES 64    /**< entries per repeated list (reference, load, events) */
#define SCENARIO_MAX_CONTROL 64    /**< [control] keys per scenario */
#define SCENARIO_MAX_WINDOWS 16    /**< [metrics] windows */
#define SCENARIO_MAX_SCALAR_KEYS 80 /**< size of the line table of scalar keys */
#define SCENARIO_NAME_LEN 32       /**< window names, including the terminator */
#define SCENARIO_LINE_SET (-1)     /**< "line" of a value that came from --set */

/** Controllers the firmware offers (values equal the firmware's speed_mode). */
typedef enum {
    SCENARIO_CTL_IP = 0,
    SCENARIO_CTL_NOMINAL = 1,
    SCENARIO_CTL_RBFN = 2,
} scenario_controller;

/** One entry of the speed-reference profile. */
typedef struct {
    bool ramp;     /**< false: step at t0_s; true: linear from the value at t0_s to rpm at t1_s */
    double t0_s;   /**< step time or ramp start, s */
    double t1_s;   /**< ramp end, s (= t0_s for a step) */
    double rpm;    /**< value reached, rpm (mechanical) */
    int line;      /**< source line (SCENARIO_LINE_SET for --set) */
} scenario_ref_entry;

/** A load-torque entry: a step to nm at t_s, or a ramp from the value at t_s to nm at t1_s. */
typedef struct {
    bool ramp;     /**< false: step at t_s; true: linear from the value at t_s to nm at t1_s */
    double t_s;    /**< step time or ramp start, s */
    double t1_s;   /**< ramp end, s (= t_s for a step) */
    double nm;     /**< constant (active) load torque reached, N m */
    int line;
} scenario_load_entry;

/** Kinds of parameter events; each multiplies the plant's ORIGINAL value. */
typedef enum {
    SCENARIO_EV_J = 0,  /**< J_scale */
    SCENARIO_EV_B = 1,  /**< B_scale */
    SCENARIO_EV_RS = 2, /**< Rs_scale */
    SCENARIO_EV_RR = 3, /**< Rr_scale */
    SCENARIO_EV_LM = 4, /**< Lm_scale */
    SCENARIO_EV_KINDS = 5,
} scenario_event_kind;

/** A parameter change: a step (X_scale) or a ramp (X_ramp) of the factor on the ORIGINAL value. */
typedef struct {
    scenario_event_kind kind;
    bool ramp;     /**< false: step at t_s; true: linear from the factor at t_s to factor at t1_s */
    double t_s;    /**< step time or ramp start, s */
    double t1_s;   /**< ramp end, s (= t_s for a step) */
    double factor; /**< > 0 */
    int line;
} scenario_event;

/** Kinds of timed faults ([faults] section). */
typedef enum {
    SCENARIO_FAULT_GAIN = 0,    /**< sensor channel gain := value */
    SCENARIO_FAULT_OFFSET = 1,  /**< sensor channel offset := value (A or V) */
    SCENARIO_FAULT_STUCK = 2,   /**< sensor channel holds its last conversion */
    SCENARIO_FAULT_LOST = 3,    /**< sensor channel reads 0 A / 0 V */
    SCENARIO_FAULT_INVALID = 4, /**< the sample the firmware reads is NaN on this channel */
    SCENARIO_FAULT_RESTORE = 5, /**< channel back to its [sensors] gain and offset, no fault */
    SCENARIO_FAULT_VDC = 6,     /**< DC source voltage := value (sag, surge) */
    SCENARIO_FAULT_STALE = 7,   /**< no fresh sample at that tick (the ADC did not convert) */
    SCENARIO_FAULT_HW = 8,      /**< the board's hardware-fault input := value (1 on, 0 off) */
    SCENARIO_FAULT_OPEN_PHASE = 9, /**< motor phase (channel a, b or c) disconnected from its leg */
    SCENARIO_FAULT_OVERRUN = 10,   /**< the tick at that time misses its deadline (hal_tick_missed) */
    SCENARIO_FAULT_KINDS = 11,
} scenario_fault_kind;

/** Sensor channels as the faults name them: a, b, c (currents), vc1, vc2. */
#define SCENARIO_N_CHANNELS 5

typedef struct {
    scenario_fault_kind kind;
    double t_s;
    int channel;   /**< 0..4 = a, b, c, vc1, vc2; -1 when the kind takes none */
    double value;  /**< gain, offset, volts or on/off; 0 when the kind takes none */
    int line;
} scenario_fault;

/** A metrics window: mean true speed and stator rms current over [t0_s, t1_s). */
typedef struct {
    char name[SCENARIO_NAME_LEN];
    double t0_s, t1_s;
    int line;
} scenario_window;

/** A [control] assignment: one firmware tunable (see sim/control_keys.h). */
typedef struct {
    int key;       /**< index into sim_control_keys() */
    double value;  /**< in the key's unit */
    int line;
} scenario_control;

/** What the firmware is told of the motor ([commission] model). */
typedef enum {
    SCENARIO_MODEL_EXACT = 0, /**< the plant's [motor] model, as identified exactly (the default) */
    SCENARIO_MODEL_PLATE = 1, /**< the [ratings] plate only: the firmware's model is its plate estimate */
} scenario_model;

/** The [ratings] section: the motor's plate and the inverter's label (dtc/ratings.h, SI). */
typedef struct {
    double P_W, V_ll_V, I_A, f_Hz, n_rpm, cos_phi, vdc_nom_V, inv_I_rated_A, inv_I_peak_A;
} scenario_ratings;
/** [commission] identify: the identification run before the profile starts. */
typedef enum {
    SCENARIO_IDENTIFY_NONE = 0,       /**< none: the firmware keeps the model it was given */
    SCENARIO_IDENTIFY_STANDSTILL = 1, /**< standstill: the drive's standstill run, its results written */
    SCENARIO_IDENTIFY_FULL = 2,       /**< full: with the rotating part (refused: the drive runs the standstill part only) */
} scenario_identify;

typedef struct {
    char source[1024];            /**< file name used in messages */

    plant_config plant;           /**< motor, DC link, sensors, supply, h_max_s */
    int supply_mode;              /**< plant_supply_mode (copied into plant by scenario_finish) */
    double phase_rad;             /**< sine supply phase (file: phase_deg) */
    double seed;                  /**< noise seed (integer 0..2^32-1, copied into plant) */

    double duration_s;            /**< simulated time, s (0 < x <= 600) */
    double period_s;              /**< control tick, s (50e-6..1e-3, whole microseconds) */
    double trace_interval_s;      /**< CSV row interval, s (>= period_s) */

    int controller;               /**< scenario_controller */

    bool has_ratings;             /**< a [ratings] section: the firmware is derived from the plate */
    scenario_ratings ratings;     /**< the plate and the label (cos_phi 0: not on the plate) */
    int model;                    /**< scenario_model ([commission] model; exact by default) */

    scenario_control control[SCENARIO_MAX_CONTROL];
    int n_control;

    scenario_ref_entry ref[SCENARIO_MAX_ENTRIES];
    int n_ref;
    scenario_load_entry load[SCENARIO_MAX_ENTRIES];
    int n_load;
    scenario_event events[SCENARIO_MAX_ENTRIES];
    int n_events;
    scenario_fault faults[SCENARIO_MAX_ENTRIES];
    int n_faults;

    bool has_disturbance;         /**< [metrics] disturbance_t_s given (else derived) */
    double disturbance_t_s;
    bool has_startup_end;         /**< [metrics] startup_end_s given (else derived) */
    double startup_end_s;
    scenario_window windows[SCENARIO_MAX_WINDOWS];
    int n_windows;

    /* [commission] identify (the drive's identification run before the profile; keep apart) */
    int identify;                 /**< scenario_identify */
    int identify_line;            /**< its source line (0: not given, SCENARIO_LINE_SET: --set) */

    /** Source line of each scalar key (index = key table index; 0 = default). */
    int key_line[SCENARIO_MAX_SCALAR_KEYS];
} scenario;

/** Fill @p sc with the defaults (the plant's default config, 200 us tick, ...). */
void scenario_default(scenario *sc);

/** Parse the INI file @p path over @p sc (start from scenario_default()). */
int scenario_parse_file(scenario *sc, const char *path, char *err, size_t errlen);

/** Parse INI text; @p name is used as FILE in messages. */
int scenario_parse_string(scenario *sc, const char *name, const char *text, char *err, size_t errlen);

/**
 * Apply one `--set section.key=value` override. Scalar keys are replaced;
 * a repeated key replaces its whole list with one entry (reference.step and
 * reference.ramp replace the whole reference profile; events.X_scale replaces
 * the events of that kind).
 */
int scenario_set(scenario *sc, const char *assignment, char *err, size_t errlen);

/**
 * Cross-checks after parsing and overrides: time order, windows, trace
 * interval, plant_check_config (mapped back to the line of the failing key).
 * Copies supply, phase and seed into sc->plant.
 */
int scenario_finish(scenario *sc, char *err, size_t errlen);

/** The line scalar key [@p section] @p key was set on, 0 when it was not
 *  (or came from --set: SCENARIO_LINE_SET). */
int scenario_key_line(const scenario *sc, const char *section, const char *key);

/** The [ratings] section as the firmware's struct ratings (dtc/ratings.h). */
void scenario_ratings_to_plate(const scenario *sc, ratings *r);

/** Reference at @p t_s, rpm: 0 before the first entry, then the profile. */
double scenario_ref_rpm(const scenario *sc, double t_s);

/** Constant (active) load torque of the [load] step/ramp profile at @p t_s, N m (0 before the first entry). */
double scenario_load_nm(const scenario *sc, double t_s);

/** Factor on the original value of parameter @p kind at @p t_s (1 before its first event). */
double scenario_param_factor(const scenario *sc, scenario_event_kind kind, double t_s);

/** Time of the first load or parameter event after t = 0 (or [metrics]
 *  disturbance_t_s); returns false when there is none. */
bool scenario_disturbance(const scenario *sc, double *t_s);

/** Start of the steady window for np_dev_max_v and switching_freq_hz, s:
 *  [metrics] startup_end_s, else the later of 1.0 s and the end of the first ramp. */
double scenario_startup_end(const scenario *sc);

/**
 * The last change of the reference: from @p from_rpm to @p to_rpm, starting
 * at @p t_s (step time or ramp start). @return false when the reference never changes.
 */
bool scenario_last_ref_change(const scenario *sc, double *t_s, double *from_rpm, double *to_rpm);

/** Name of a controller ("ip", "nominal", "rbfn"), or NULL. */
const char *scenario_controller_name(int controller);

/** Parse a controller name. @return scenario_controller, or -1 if unknown. */
int scenario_controller_parse(const char *name);

/** One documented scalar key of the file format (for docs checks and --help). */
typedef struct {
    const char *section;
    const char *key;
    const char *unit;
} scenario_key_info;

/** Describe scalar key @p i (0-based). @return false past the end. */
bool scenario_key_info_at(size_t i, scenario_key_info *out);

/** Names of the repeated keys of section @p i ("reference", "step") ... @return false past the end. */
bool scenario_list_key_at(size_t i, scenario_key_info *out);

#ifdef __cplusplus
}
#endif

#endif /* SIM_SCENARIO_H */
