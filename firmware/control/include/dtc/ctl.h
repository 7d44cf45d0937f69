/**
 * @file ctl.h
 * @brief The 200 us control step: observer, speed controller, three-level DTC.
 *
 * ctl_step() is a function of structs: the host SIL, the PIL harness and the
 * target ISR all call it the same way. Configuration (ctl_cfg, dtc/ctl_cfg.h,
 * written only by the background) is kept apart from mutable state (ctl_state,
 * touched only by the interrupt). Units are SI; speeds are MECHANICAL rad/s
 * unless named _elec.
 *
 * The step's parts, each in a file of its own: the configuration
 * (ctl_cfg.c), the protection and its sample checks (ctl_protect.c), the
 * slots of the slow tasks (dtc/ctl_schedule.h), the voltage the inverter
 * applies (dtc/inverter_model.h), the supervision of the operating point
 * (ctl_supervise.c), bring-up levels 1-4 (ctl_bringup.c); ctl.c runs them in
 * the order of a tick.
 */
#ifndef DTC_CTL_H
#define DTC_CTL_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/bringup.h"
#include "dtc/ctl_cfg.h"
#include "dtc/ctl_guard.h"
#include "dtc/ctl_schedule.h"
#include "dtc/dtc3l.h"
#include "dtc/inverter_model.h"
#include "dtc/num.h"
#include "dtc/observer.h"
#include "dtc/plausibility.h"
#include "dtc/rs_ident.h"
#include "dtc/speed_ctl.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Fault bits (see docs/faults.md for detection and reaction). */
enum ctl_fault {
    CTL_FAULT_OVERCURRENT = 1u << 0,  /**< |i| above i_trip_A: gates off this tick */
    CTL_FAULT_DC_OVERVOLT = 1u << 1,  /**< vc1 + vc2 above vdc_max_V */
    CTL_FAULT_DC_UNDERVOLT = 1u << 2, /**< vc1 + vc2 below vdc_min_V while running */
    CTL_FAULT_NP_IMBALANCE = 1u << 3, /**< |vc1 - vc2| above np_trip_V */
    CTL_FAULT_OVERSPEED = 1u << 4,    /**< |estimated speed| above overspeed_rad_s */
    CTL_FAULT_STALE_SAMPLE = 1u << 5, /**< the HAL gave no fresh sample this tick */
    CTL_FAULT_HW = 1u << 6,           /**< hardware fault input active */
    CTL_FAULT_OVERRUN = 1u << 7,      /**< the previous tick missed its deadline */
    CTL_FAULT_SAMPLE_INVALID = 1u << 8, /**< a sampled value is not a finite number */
    CTL_FAULT_LOSS_OF_CONTROL = 1u << 9, /**< the observer's flux is not the machine's (ctl_guard.h) */
    CTL_FAULT_CURRENT_SENSOR = 1u << 10, /**< current sum of the three sensors implausible, or a reading stuck */
    CTL_FAULT_PHASE_LOSS = 1u << 11,     /**< one motor phase carries no current while the others do */
    CTL_FAULT_DC_DIVIDER = 1u << 12,     /**< capacitor voltages unequal while stopped: divider or sensor error */
    CTL_FAULT_STALL = 1u << 13,          /**< the speed loop cannot hold the speed at its torque limit (docs/faults.md) */
    CTL_FAULT_SPEED_DEV = 1u << 14,      /**< the speed has stayed further from its reference than speed_dev_band_rad_s
                                              for speed_dev_time_s (docs/faults.md) */
};

/** Warning bits (ctl_telemetry.warnings): conditions that do not stop the drive (docs/faults.md). */
enum ctl_warning {
    CTL_WARN_SPEED_DEV = 1u << 0, /**< the speed-deviation count has passed half of speed_dev_time_s */
};

/** Fault bits that ctl_step latches (OVERRUN from ctl_in.overrun). */
#define CTL_FAULTS_DETECTED                                                                 \
    (CTL_FAULT_OVERCURRENT | CTL_FAULT_DC_OVERVOLT | CTL_FAULT_DC_UNDERVOLT |               \
     CTL_FAULT_NP_IMBALANCE | CTL_FAULT_OVERSPEED | CTL_FAULT_STALE_SAMPLE | CTL_FAULT_HW | \
     CTL_FAULT_OVERRUN | CTL_FAULT_SAMPLE_INVALID | CTL_FAULT_LOSS_OF_CONTROL | CTL_FAULT_CURRENT_SENSOR | \
     CTL_FAULT_PHASE_LOSS | CTL_FAULT_DC_DIVIDER | CTL_FAULT_STALL | CTL_FAULT_SPEED_DEV)

/** Inputs of one control step. */
typedef struct {
    hal_sample sample;        /**< this tick's measurements */
    bool sample_fresh;        /**< false when the HAL refused a stale sample */
    bool run;                 /**< run command: false forces zero torque and gates off */
    real_t speed_ref_rad_s;   /**< mechanical speed reference, rad/s */
    bool fault_input;         /**< hardware fault input active */
    bool overrun;             /**< the previous tick missed its deadline (set by the caller's timing) */
} ctl_in;

/** Signals published every tick for telemetry, traces and the scope. */
typedef struct {
    real_t speed_ref_rad_s;   /**< reference after the ramp limiter, rad/s */
    real_t omega_est_rad_s;   /**< estimated mechanical speed, rad/s */
    real_t te_ref_Nm;         /**< torque command, N m */
    real_t te_est_Nm;         /**< estimated torque, N m */
    real_t psi_s_est_Wb;      /**< estimated stator flux magnitude, Wb */
    real_t psi_ref_Wb;        /**< flux reference, Wb */
    real_t eps_hat;           /**< RBFN uncertainty estimate, rad/s^2 (eq. 5 units) */
    real_t w_norm;            /**< |W| of the RBFN */
    real_t zeta_bar;          /**< adaptive bound of the robust term */
    real_t rs_est_ohm;        /**< adapted stator resistance, ohm */
    real_t duty0;             /**< duty of the first vector, 0..1 */
    uint8_t vector_index;     /**< selected vector 0..26 (state number a*9 + b*3 + c) */
    uint8_t state;            /**< ctl_run_state */
    uint32_t faults;          /**< latched ctl_fault bits */
    uint32_t warnings;        /**< present ctl_warning bits (not latched) */
} ctl_telemetry;

/** Outputs of one control step. */
typedef struct {
    hal_actuation act;        /**< vectors and duty for the next period */
    bool gate_enable;         /**< false: the caller must disable the gates now */
    ctl_telemetry tel;
} ctl_out;

/** Run state of the control core. */
typedef enum {
    CTL_STOPPED = 0,          /**< gates off */
    CTL_MAGNETISING = 1,      /**< building flux at zero torque */
    CTL_RUNNING = 2,          /**< speed control active */
    CTL_FAULTED = 3,          /**< a fault latched; gates off until ctl_clear_faults */
} ctl_run_state;

/** Mutable state of the control core, owned by the interrupt. */
typedef struct {
    observer obs;
    rs_ident rsid;            /**< Rs identification while magnetising */
    plaus_state plaus;        /**< sensor plausibility history */
    real_t bringup_theta_rad; /**< V/f angle at bring-up levels 3 and 4, rad */
    speed_ctl speed;
    dtc3l dtc;
    ctl_run_state run_state;
    real_t t_magnetise_s;     /**< time spent magnetising */
    real_t speed_ref_ramped_rad_s;
    uint32_t faults;
    inverter_period applied;  /**< the period now applied: the actuation latched at tick k-1 (act), its two
                                   vectors as state numbers 0..26 (state, kept with it, so the tick never
                                   converts legs back to a state), and the state the period that just ended
                                   ended on (end_state: the last vector of the actuation latched at k-2; the
                                   current period's dead-time edges start there; ctl_observe() sets it for the
                                   next tick) */
    uint32_t faults_active;   /**< fault conditions present at the last step (ctl_clear_faults keeps these) */
    real_t te_ref_Nm;         /**< torque command of the last step */
    observer_out obs_out;     /**< observer outputs of the last step */
    dtc3l_out dtc_out;        /**< DTC outputs of the last step */
    real_t te_limit_Nm;       /**< torque limit of the last step (te_max, field weakening), N m */
    real_t fsw_hz;            /**< low-passed device switching frequency of the actuation, Hz */
    uint8_t fsw_changes;      /**< leg changes of the actuations since the last regulation step (0..96) */
    dtc3l_cmd dtc_cmd;        /**< the DTC's command of the last step, kept between steps: its band_scale
                                   is the present widening of the torque bands (1..band_scale_max, written
                                   by the regulation only, reset by start()), its psi_ref_Wb the flux
                                   reference after the slew-rate limit, Wb (written by the ramp only,
                                   reset by start()); the other fields are set every step */
    real_t te_short_Nm;       /**< low-passed |te_ref| - |te_est|: the torque the DTC falls short by, N m */
    real_t fw_trim;           /**< voltage-margin trim of the field-weakening flux (0.7..1) */
    real_t psi_target_Wb;     /**< flux the reference ramps to (ctl_supervise_operating_point()), Wb */
    real_t short_sum_Nm;      /**< |te_ref| - |te_est| summed since the last supervision step, N m */
    ctl_guard guard;          /**< loss-of-control monitor */
    uint32_t monitor_faults;  /**< the slow monitors' verdicts at their last steps: CTL_FAULT_LOSS_OF_CONTROL
                                   (the guard's check), CTL_FAULT_STALL (the stall windows, with
                                   stall_time_s as it was then); the protection adds them every tick */
    real_t t_at_limit_s;      /**< time at the torque limit, off speed, in windows whose speed error did not shrink (STALL), s */
    real_t t_stall_win_s;     /**< time in the present stall window, s */
    real_t err_win_start_rad_s; /**< |speed error| (filtered estimate) at the start of that window, rad/s */
    real_t t_brake_limit_s;   /**< time in the present window braking at the torque limit off speed, s */
    real_t w_brake_start_rad_s; /**< |filtered speed estimate| at the start of that window, rad/s */
    bool brake_stall;         /**< braking at the limit did not slow the machine: STALL */
    /* speed-deviation supervision (ctl_speed_dev_step) */
    real_t t_dev_s;           /**< time beyond the band, ramp at rest, in windows whose error did not shrink, s */
    real_t t_dev_win_s;       /**< time in the present speed-deviation window, s */
    real_t err_dev_win_start_rad_s; /**< |speed error| at the start of that window, rad/s */
    real_t dev_ref_prev_rad_s; /**< the ramped reference at the last step: another value means the ramp moves, rad/s */
    uint32_t warnings;        /**< present ctl_warning bits */
    speed_out speed_held;     /**< the speed loop's outputs of its last step (held between its steps) */
    uint8_t slow_slot;        /**< this tick's slot of the slow tasks, 0..CTL_SLOW_SLOTS - 1 (dtc/ctl_schedule.h) */
} ctl_state;

/** Initialise the state (stopped, no faults). Context: BG. */
void ctl_init(ctl_state *s, const ctl_cfg *cfg);

/**
 * Clear latched faults if their cause is gone (judged by the conditions of the
 * last ctl_step); a FAULTED core with nothing left goes to STOPPED and starts
 * again (magnetising) at the next step with run set. Returns the remaining
 * fault bits. Context: BG, or the ISR before ctl_step (never concurrently).
 */
uint32_t ctl_clear_faults(ctl_state *s);

/**
 * One control period. Context: ISR. Constant time apart from the bounded RBFN loop.
 * Order: protect (a fault turns the gates off in this call) -> run state ->
 * observer (advanced to t_{k+1} with the actuation latched at k-1, which the
 * inverter applies during the period now starting) -> speed loop (filtered
 * estimate; zero torque while magnetising) -> DTC on the state predicted for
 * t_{k+1} -> P<->N guard -> the actuation for t_{k+1}..t_{k+2}.
 * @param s   state, updated
 * @param cfg configuration, read only
 * @param in  this tick's inputs
 * @param out actuation for the next period and telemetry
 * The four are distinct objects (the definition declares them restrict).
 */
void ctl_step(ctl_state *s, const ctl_cfg *cfg, const ctl_in *in, ctl_out *out);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CTL_H */
