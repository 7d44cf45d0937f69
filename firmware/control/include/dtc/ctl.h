/**
 * @file ctl.h
 * @brief The 200 us control step: observer, speed controller, three-level DTC.
 *
 * ctl_step() is a function of structs: the host SIL, the PIL harness and the
 * target ISR all call it the same way. Configuration (ctl_cfg, written only by
 * the background) is kept apart from mutable state (ctl_state, touched only by
 * the interrupt). Units are SI; speeds are MECHANICAL rad/s unless named _elec.
 */
#ifndef DTC_CTL_H
#define DTC_CTL_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/num.h"
#include "dtc/observer.h"
#include "dtc/rs_ident.h"
#include "dtc/bringup.h"
#include "dtc/plausibility.h"
#include "dtc/speed_ctl.h"
#include "dtc/dtc3l.h"
#include "dtc/ctl_guard.h"
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
};

/** Fault bits that ctl_step latches (OVERRUN from ctl_in.overrun). */
#define CTL_FAULTS_DETECTED                                                                 \
    (CTL_FAULT_OVERCURRENT | CTL_FAULT_DC_OVERVOLT | CTL_FAULT_DC_UNDERVOLT |               \
     CTL_FAULT_NP_IMBALANCE | CTL_FAULT_OVERSPEED | CTL_FAULT_STALE_SAMPLE | CTL_FAULT_HW | \
     CTL_FAULT_OVERRUN | CTL_FAULT_SAMPLE_INVALID | CTL_FAULT_LOSS_OF_CONTROL | CTL_FAULT_CURRENT_SENSOR | \
     CTL_FAULT_PHASE_LOSS | CTL_FAULT_DC_DIVIDER | CTL_FAULT_STALL)

/** Error codes of ctl_cfg_check() (negative, first violated rule). */
enum ctl_cfg_error {
    CTL_CFG_OK = 0,
    CTL_CFG_E_MOTOR = -1,     /**< a motor parameter not > 0, or Ls, Lr not > Lm */
    CTL_CFG_E_PERIOD = -2,    /**< period_s outside 20e-6..2e-3 or vdc_nom_V not > 0 */
    CTL_CFG_E_DTC = -3,       /**< psi_ref not > 0, a band < 0, band2 <= band, level_down >= level_up, duty_min outside 0..0.45 */
    CTL_CFG_E_OBSERVER = -4,  /**< k_gain < 1, a gain < 0, speed_lpf_hz < 0 or regen_flux_min_frac outside 0.5..1 */
    CTL_CFG_E_PROTECTION = -5,/**< a trip level not > 0, or vdc_min_V >= vdc_max_V */
    CTL_CFG_E_SPEED = -6,     /**< speed_cfg_check failed */
};

/** All tunables of the control core. Written by the background only, through
 *  the parameter layer, which then calls ctl_cfg_derive(). */
typedef struct {
    /* nominal motor model used by the observer and the controllers */
    motor_model motor;
    real_t period_s;          /**< control period, s (2e-4) */
    real_t vdc_nom_V;         /**< nominal DC link, V */
    real_t c_dc_F;            /**< each of the two DC-link capacitors, F (NP prediction; 0 = none) */

    speed_cfg speed;          /**< speed loop: mode, IP, nominal, RBFN, torque limit */
    dtc3l_cfg dtc;            /**< flux reference, bands, ripple reduction, NP balance */
    observer_cfg obs;         /**< observer gains and adaptation */

    /* protection */
    real_t i_trip_A;          /**< instantaneous phase-current trip, A */
    real_t vdc_max_V;         /**< DC-link over-voltage trip, V */
    real_t vdc_min_V;         /**< DC-link under-voltage trip while running, V */
    real_t np_trip_V;         /**< |vc1 - vc2| trip, V */
    real_t overspeed_rad_s;   /**< estimated-speed trip, rad/s; the speed reference is limited
                                   to overspeed_rad_s / 1.1 (speed_max_rad_s) */
    /* field weakening (docs/envelope.md section 3) */
    real_t fw_voltage_frac;   /**< flux reference <= this x (measured Vdc / sqrt 3) / |omega_e|, 0..1.2 */
    real_t te_pullout_frac;   /**< torque limit <= this x the pull-out torque at the flux reference, 0..1 */
    /* switching-frequency regulation (docs/envelope.md section 4) */
    real_t fsw_max_hz;        /**< device switching frequency above which the torque bands widen, Hz (0 = off) */
    uint32_t bringup_level;   /**< 1 gate test, 2 ADC readout, 3 V/f, 4 V/f + observer, 5 torque control,
                                   6 speed control (the drive); dtc/bringup.h, docs/bringup.md */
    real_t bringup_hz;        /**< V/f electrical frequency at levels 3 and 4, Hz (sign: direction) */
    real_t stall_time_s;      /**< the speed loop's torque command at the limit this long trips STALL, s (0: off) */
    real_t bringup_te_Nm;     /**< torque command at level 5, N m (limited to the torque limit) */
    real_t dead_time_comp_s;  /**< dead time of the power stage, s (0..10e-6, 0 = not compensated): its
                                   volt-seconds are added to the applied voltage the observer and the
                                   loss-of-control monitor use (ctl.c, apply_real_inverter) */
    real_t v_drop_V;          /**< on-state drop of one device, V: subtracted from the applied voltage the
                                   observer and the loss-of-control monitor use (0 = none) */
    real_t band_scale_max;    /**< largest widening of the torque bands, x (>= 1) */
    real_t regen_flux_min_frac; /**< lowest flux for low-speed regeneration, fraction of dtc.psi_ref_Wb,
                                   0.5..1 (1 = never lowered; ctl.c, regen_flux_factor) */
    real_t rs_ident_tol;      /**< Rs identified while magnetising replaces the model's when they differ by
                                   more than this fraction, 0..1 (1 = never; dtc/rs_ident.h) */
    ctl_guard_cfg guard;      /**< loss-of-control monitor (voltage-model flux check) */

    /* derived by ctl_cfg_derive() */
    real_t psi_ramp_Wb_s;     /**< flux-reference slew rate, Wb/s: keeps the magnetising
                                   current transient (the rotor flux lags the stator flux
                                   by sigma Tr) below a fifth of i_trip_A */
    real_t np_V_per_A;        /**< period_s / c_dc_F: change of vc1 - vc2 per ampere of NP current over one period */
    real_t inv_period_per_s;  /**< 1 / period_s */
    real_t dead_time_per_T;   /**< dead_time_comp_s x inv_period_per_s: the dead time per period (0..0.5) */
    bool real_inverter;       /**< v_drop_V > 0 or dead_time_comp_s > 0: the observer's voltage is built leg
                                   by leg (ctl.c, apply_real_inverter); false: the ideal inverter's */
    real_t drop4_V;           /**< -4 v_drop_V: the drop's slope in the late fraction of a leg's current
                                   (ctl.c, apply_real_inverter), V */
    real_t te_pullout_Nm_Wb2; /**< pull-out torque per Wb^2 of stator flux: 1.5 p (1 - sigma) / (2 sigma Ls) */
    real_t speed_max_rad_s;   /**< speed-reference limit, overspeed_rad_s / 1.1, rad/s */
    real_t fsw_per_change_hz; /**< device switching frequency per leg change per period: 1 / (6 T), Hz */
    real_t fsw_lpf_a;         /**< low-pass coefficient (20 ms) of the measured switching frequency per
                                   regulation step (CTL_SLOW_SLOTS periods, CTL_SLOT_FSW), 0..1 */
    real_t band_rate_T;       /**< adaptation step of the band scale per regulation step (5 1/s x CTL_SLOW_SLOTS T) */
    real_t sup_lpf_a;         /**< low-pass coefficient (20 ms) of the torque shortfall per supervision step
                                   (CTL_SLOW_SLOTS periods), 0..1 */
    real_t sup_rate_T;        /**< step of the field-weakening trim per supervision step (5 1/s x CTL_SLOW_SLOTS T) */
    real_t inv_fsw_max_s;     /**< 1 / fsw_max_hz, s (0 when the regulation is off) */
    real_t fw_v_per_vdc;      /**< fw_voltage_frac / sqrt 3: usable phase voltage per volt of DC link */
    real_t te_limit_Nm_Wb2;   /**< te_pullout_frac x te_pullout_Nm_Wb2, N m/Wb^2 */
    real_t slip_rad_s_per_Nm; /**< electrical slip per N m at the rated flux, (rad/s)/(N m) */
    real_t regen_k2_min;      /**< regen_flux_min_frac^2 */
    real_t psi_ramp_step_Wb;  /**< psi_ramp_Wb_s x period_s: the flux reference's slew per tick, Wb */
    real_t speed_T_s;         /**< CTL_RBFN_TICKS x period_s: the speed loop's step, s (0.8 ms) */
    real_t speed_ramp_step_rad_s; /**< speed.ramp_rad_s2 x speed_T_s: the speed reference's slew per
                                   speed-loop step, rad/s */
    real_t inv_speed_T_per_s; /**< inv_period_per_s / CTL_RBFN_TICKS (exact: a power of 2), 1/s */
    rs_ident_cfg rsid;        /**< constants of the Rs identification */
} ctl_cfg;

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
} ctl_telemetry;

/** Outputs of one control step. */
typedef struct {
    hal_actuation act;        /**< vectors and duty for the next period */
    bool gate_enable;         /**< false: the caller must disable the gates now */
    ctl_telemetry tel;
} ctl_out;

/**
 * The slow tasks take turns (issue 11): tick k has slot k mod CTL_SLOW_SLOTS
 * (an 8-tick cycle, 1.6 ms at 200 us), and each slow task does its heavy part
 * in its own slots only, so no tick carries two heavy ones (the RBFN's learning,
 * the supervision and the regulation are lighter than the command or a monitor):
 *
 *   slot   0      1        2        3           4      5        6        7
 *          guard  speed    plaus    RBFN learn  guard  speed    plaus    RBFN learn
 *                 command  + stall  + supervise        command  + stall  + FSW + level
 *
 * The loss-of-control monitor checks every CTL_GUARD_WINDOW_MAX (4) ticks,
 * in the slots that are CTL_SLOT_GUARD modulo 4 (ctl_guard.h; it sums its
 * inputs every tick), the current plausibility checks every PLAUS_CHECK_TICKS
 * (4) ticks, in the slots that are CTL_SLOT_PLAUS modulo 4 (plausibility.h):
 * their windows and latencies are those of a 4-tick cycle.
 */
#define CTL_SLOW_SLOTS 8u
#define CTL_MONITOR_SLOTS 4u /**< the monitors' cycle: CTL_GUARD_WINDOW_MAX = PLAUS_CHECK_TICKS */
#define CTL_SLOT_GUARD 0u    /**< modulo CTL_MONITOR_SLOTS: slots 0 and 4 */
#define CTL_SLOT_PLAUS 2u    /**< modulo CTL_MONITOR_SLOTS: slots 2 and 6 */
/** The speed loop steps every CTL_RBFN_TICKS ticks (800 us, 1.25 kHz),
 *  whatever the controller: its command in the slots that are CTL_SLOT_RBFN
 *  modulo it (1 and 5, never with a monitor), the RBFN's weight and bound
 *  updates of that command in the slots that are CTL_SLOT_RBFN_LEARN modulo
 *  it (3 and 7; before the next command: the same updates wherever they sit
 *  in between; only the telemetry's |W| and zeta_bar wait for them).
 *  docs/speed_control.md, "Rate". */
#define CTL_RBFN_TICKS 4u
#define CTL_SLOT_RBFN 1u
#define CTL_SLOT_RBFN_LEARN 3u
/** The stall windows (ctl.c stall_step) step once per speed-loop step, in the
 *  slots that are this modulo CTL_RBFN_TICKS (2 and 6, with the plausibility
 *  checks: the lightest slots), on the command held since slot 1 or 5. */
#define CTL_SLOT_STALL 2u
/** The supervision of the operating point (ctl.c supervise_flux(): the flux
 *  target with field weakening and its trim, the lowered flux while
 *  regenerating near zero stator frequency, the torque limit) steps once per
 *  slot cycle (every 8th tick) on what the ticks in between summed, in slot 3
 *  (with the RBFN's learning: beside neither a monitor nor the command). The
 *  flux reference ramps to its target every tick. */
#define CTL_SLOT_SUPERVISE 3u
/** The switching-frequency regulation (ctl.c regulate_switching_frequency())
 *  sums the leg changes every tick and steps the band scale once per slot
 *  cycle on their mean, in this slot (issue 11: its float work in one tick of
 *  eight). */
#define CTL_SLOT_FSW 7u
/** The DTC's voltage level (dtc3l_cmd.decide_level: the back-emf against
 *  the link voltage, with hysteresis) is decided in this slot (a division and
 *  two compares: beside the RBFN's learning, the lightest of the slow tasks). */
#define CTL_SLOT_LEVEL 7u
#ifndef __cplusplus
_Static_assert(CTL_GUARD_WINDOW_MAX == CTL_MONITOR_SLOTS && PLAUS_CHECK_TICKS == CTL_MONITOR_SLOTS &&
                   CTL_SLOW_SLOTS % CTL_MONITOR_SLOTS == 0u && CTL_SLOW_SLOTS % CTL_RBFN_TICKS == 0u &&
                   CTL_SLOT_RBFN < CTL_RBFN_TICKS && CTL_SLOT_RBFN_LEARN < CTL_RBFN_TICKS && CTL_SLOT_STALL < CTL_RBFN_TICKS &&
                   CTL_SLOT_STALL != CTL_SLOT_RBFN && CTL_SLOT_STALL != CTL_SLOT_RBFN_LEARN,
               "the slow tasks' own rates are the schedule's");
#endif

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
    hal_actuation last_act;   /**< actuation applied during the current period (latched at tick k-1) */
    uint8_t last_state[2];    /**< last_act's two vectors as state numbers 0..26 (kept with it, so the
                                   tick never converts legs back to a state) */
    uint8_t end_state;        /**< the state 0..26 the period that just ended ended on (the last vector of
                                   the actuation latched at k-2): the current period's dead-time edges
                                   start there (dead_time.h); observe() sets it for the next tick */
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
    real_t psi_target_Wb;     /**< flux the reference ramps to (supervise()), Wb */
    real_t short_sum_Nm;      /**< |te_ref| - |te_est| summed since the last supervision step, N m */
    ctl_guard guard;          /**< loss-of-control monitor */
    uint32_t monitor_faults;  /**< the slow monitors' verdicts at their last steps: CTL_FAULT_LOSS_OF_CONTROL
                                   (the guard's check), CTL_FAULT_STALL (the stall windows, with
                                   stall_time_s as it was then); detect_faults() adds them every tick */
    real_t t_at_limit_s;      /**< time at the torque limit, off speed, in windows whose speed error did not shrink (STALL), s */
    real_t t_stall_win_s;     /**< time in the present stall window, s */
    real_t err_win_start_rad_s; /**< |speed error| (filtered estimate) at the start of that window, rad/s */
    real_t t_brake_limit_s;   /**< time in the present window braking at the torque limit off speed, s */
    real_t w_brake_start_rad_s; /**< |filtered speed estimate| at the start of that window, rad/s */
    bool brake_stall;         /**< braking at the limit did not slow the machine: STALL */
    speed_out speed_held;     /**< the speed loop's outputs of its last step (held between its steps) */
    uint8_t slow_slot;        /**< this tick's slot of the slow tasks, 0..CTL_SLOW_SLOTS - 1 (CTL_SLOT_*) */
} ctl_state;

/** Fill @p cfg with the defaults for the 10 hp motor. Context: BG. */
void ctl_cfg_default(ctl_cfg *cfg);

/** Recompute derived quantities (IP gains from wn and zeta, ...) after a change. Context: BG. */
void ctl_cfg_derive(ctl_cfg *cfg);

/**
 * Check a configuration before it is published (ctl_step stays bounded with a
 * bad one, but it would not control). @return CTL_CFG_OK or the first
 * violated rule (enum ctl_cfg_error). Context: BG.
 */
int ctl_cfg_check(const ctl_cfg *cfg);

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
