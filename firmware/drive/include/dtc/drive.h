/**
 * @file drive.h
 * @brief The drive: the object a board owns, and the board's three entry
 *        points (drive_init, drive_isr, drive_background).
 *
 * The object holds three parts, each with its own code, and the application
 * (drive_app.c) composes them:
 *   - the interrupt side (drive_isr.h, drive_isr.c): the 200 us tick, the
 *     double-buffered configuration, the commands, the telemetry snapshot and
 *     the scope; it knows nothing of the two below;
 *   - the CANopen binding (drive_co.h, drive_co.c): the dictionary's entries,
 *     the CiA 402 state, one CANopen pass per background loop;
 *   - the parameter store (persist.h, persist.c), which sees the drive's
 *     persistent values only through the narrow interface drive_params.c
 *     gives it (persist_params).
 */
#ifndef DTC_DRIVE_H
#define DTC_DRIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/canopen/co_dev.h"
#include "dtc/ctl.h"
#include "dtc/ctl_ident.h"
#include "dtc/drive_isr.h"
#include "dtc/persist.h"
#include "dtc/scope.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The drive's CiA 402 settings (parameters app.*; persisted). */
typedef struct {
    int16_t abort_option;      /**< 0x6007 on master loss, NMT stop or reset while enabled:
                                    0 none, 1 fault, 2 disable voltage, 3 quick stop */
    int16_t quick_stop_option; /**< 0x605A: 0 coast, 2 ramp down on 0x6049 then switch on disabled */
    uint32_t qs_delta_rpm;     /**< 0x6049:1 quick stop ramp, rpm per qs_delta_s */
    uint16_t qs_delta_s;       /**< 0x6049:2, s (>= 1) */
    int8_t mode;               /**< 0x6060 modes of operation: 2 (vl), the only one */
    uint32_t vl_min_rpm;       /**< 0x6046:1 least magnitude of a non-zero target velocity, rpm */
    uint32_t vl_max_rpm;       /**< 0x6046:2 largest magnitude of the target velocity, rpm */
} drive_app_cfg;

/** A drive-level fault bit in the published fault word, above the control core's (ctl_fault). */
#define DRIVE_FAULT_COMM (1u << 16) /**< master lost with abort connection option 1 (fault) */

/*
 * Whose members: the interrupt side's (cfg, cfg_active, period_cycles, ctl,
 * speed_ref_rad_s, run, clear_faults_req, quick_stop_req, qs, tick,
 * tick_missed, snap, snap_derived, timing, scope) follow the hand-over rules
 * of drive_isr.h; app, target_rad_s, halt, drive_faults, co, co_app,
 * reset_cause, reset_cause_sent and bg_snap are the binding's, persist and
 * params_edit the store's and its interface's (background only); the
 * identification run's (ident_*) follow dtc/drive_ident.h.
 */
typedef struct drive {
    ctl_cfg cfg[2];                 /**< configuration: the published copy and the one being edited */
    volatile uint32_t cfg_active;   /**< index of the copy the ISR uses (0 or 1) */
    uint32_t period_cycles[2];      /**< cfg[i].period_s in HAL cycles, derived by drive_cfg_commit
                                         (so the ISR's timing statistic needs no 64-bit division) */
    ctl_state ctl;                  /**< ISR-owned control state */
    volatile float speed_ref_rad_s; /**< command from background (scenario, CAN), rad/s */
    volatile bool run;              /**< run command from background */
    volatile bool clear_faults_req; /**< background asks the ISR to clear faults */
    volatile bool quick_stop_req;   /**< background asks the ISR to ramp down, then stop */
    /* the identification run's flags beside the other commands: the tick tests ident_on each time */
    volatile bool ident_on;         /**< BG: a run is going on: the interrupt calls ctl_ident_step, not ctl_step */
    volatile bool ident_run;        /**< BG: the run's command (false: the interrupt aborts the run) */
    drive_quick_stop qs;            /**< the quick stop ramp (decel set in BG, the rest ISR-owned) */
    drive_app_cfg app;              /**< CiA 402 settings (background) */
    float target_rad_s;             /**< the bus's target velocity before 0x6046 limits and halt, rad/s */
    bool halt;                      /**< controlword bit 8: hold the speed at 0, stay enabled */
    uint32_t drive_faults;          /**< DRIVE_FAULT_* bits latched by the background */
    uint32_t tick;                  /**< ISR tick counter */
    bool tick_missed;               /**< the last tick ended after the next one was due */
    union {
        drive_snapshot snap;        /**< published each tick */
        struct {
            uint32_t snap_seq_;     /* snap.seq */
            ctl_out out;            /**< outputs of the last tick: snap.out under its own name (ctl_step
                                         writes them in place, inside the snapshot's sequence window) */
        };
    };
    uint8_t snap_derived;           /**< DRIVE_SNAP_* the interrupt works out in snap (the armed scope's
                                         sources; written by drive_scope_arm while the scope is stopped;
                                         next to snap, so the tick reaches it with the snapshot's base) */
    drive_timing timing;
    scope scope;                    /**< triggered capture, sampled in drive_isr */
    co_dev co;                      /**< CANopen device, run by drive_background (drive_co.c) */
    co_app co_app;                  /**< the drive's side of the CANopen interface (drive_co.c) */
    persist_state persist;          /**< the parameter store (its status is 0x2510:1), bound to drive_params */
    ctl_cfg *params_edit;           /**< the configuration copy a load is filling (drive_params.c), else NULL */
    uint8_t reset_cause;            /**< hal_reset_cause() at drive_init (0x2510:7) */
    bool reset_cause_sent;          /**< the EMCY of a watchdog reset went out (once per start) */
    drive_snapshot bg_snap;         /**< background copy of snap, taken once per drive_background pass */
    uint32_t warnings_seen;         /**< ctl_warning bits of the last pass (a rising bit sends its EMCY once) */
    /* the identification run (drive_ident.c, dtc/drive_ident.h) */
    ident ident;                    /**< the run's state (shared as dtc/ident.h says) */
    ident_cfg ident_cfg;            /**< its constants (BG, fixed while the run lasts) */
    ctl_ident_call ident_call;      /**< ctl_ident_step's argument: pointers into this drive, set by
                                         drive_init (a drive is initialised in place, never copied), and
                                         the configuration, set by the interrupt before each call */
    ident_result ident_res;         /**< its results (BG) */
    int32_t ident_error;            /**< BG: the last start's refusal (enum ident_error, drive_ident_error) or 0 */
    uint8_t ident_outcome;          /**< BG: drive_ident_outcome of the last run */
    uint8_t ident_applied;          /**< BG: enum ident_applied bits the last run wrote */
} drive;

/**
 * Initialise with default configuration, stopped, then load the persisted
 * parameters (the newest valid NVM set; defaults if none). Bind the board
 * (and load any NVM image) before calling. Then start the tick with
 * hal_tick_start(drive_isr, d, ...) (drive_isr.h). Context: BG, before
 * hal_tick_start.
 */
void drive_init(drive *d);

/**
 * One pass of the background loop: one CANopen pass (the store's commands
 * 0x1010 / 0x1011 among it), then the watchdog. Never blocks. The SIL calls
 * it once per control period; the target calls it in its main loop.
 * Context: BG.
 */
void drive_background(drive *d);

#ifdef __cplusplus
}
#endif

#endif /* DTC_DRIVE_H */
