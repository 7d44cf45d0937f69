/**
 * @file drive.h
 * @brief The drive application: the 200 us interrupt and the background loop.
 *
 * Interrupt (drive_isr): sample -> ctl_step (observe, speed control, DTC,
 * protect) -> actuate -> publish a telemetry snapshot. It is timed with the
 * HAL cycle counter; a tick longer than the period sets CTL_FAULT_OVERRUN.
 *
 * Background (drive_background): communication, persistence, housekeeping.
 * The background never writes state the interrupt is using: configuration is
 * kept in two copies (edit the inactive one, then publish it with one store),
 * and the interrupt picks the published copy up at the start of its next tick.
 */
#ifndef DTC_DRIVE_H
#define DTC_DRIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/canopen/co_dev.h"
#include "dtc/ctl.h"
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

/** Quick stop: requested by the background, carried out in the interrupt. */
typedef struct {
    float decel_rad_s2;        /**< ramp rate, rad/s^2 (derived from 0x6049 in the background) */
    bool active;               /**< ISR: the ramp is running */
    float ref_rad_s;           /**< ISR: the ramped speed reference, rad/s */
    float held_s;              /**< ISR: time held at zero speed at the end of the ramp, s */
} drive_quick_stop;

/**
 * Telemetry snapshot guarded by a sequence counter (odd while the ISR writes).
 * The derived fields (speed_err_rad_s, vdc_diff_V, i_peak_A, vdc_V) are worked
 * out from the raw ones by drive_read_snapshot, so every copy has them; in the
 * interrupt's own d->snap only those the armed scope reads (issue 11: the
 * background reads at ms rates, the tick need not pay for them).
 */
typedef struct {
    volatile uint32_t seq;
    /* The control core's outputs of the tick, written by ctl_step in place
     * (issue 11: the telemetry is filled once, not filled and then copied);
     * tel is out.tel under its own name. */
    union {
        ctl_out out;
        struct {
            hal_actuation out_act_;  /* out.act */
            bool out_gate_enable_;   /* out.gate_enable */
            ctl_telemetry tel;       /**< the control core's telemetry (out.tel) */
        };
    };
    /* The control core's inputs of the tick, set in place (issue 11: the
     * sample is read once, straight into the snapshot, not read and then
     * copied); the six fields below are in.sample's first six under their
     * snapshot names. */
    union {
        ctl_in in;
        struct {
            float ia_A, ib_A, ic_A;   /**< measured currents, A */
            float vc1_V, vc2_V;       /**< measured capacitor voltages, V */
            float omega_meas_rad_s;   /**< board speed sensor (diagnostics), rad/s */
        };
    };
    uint32_t tick;            /**< ISR tick counter */
    float speed_err_rad_s;    /**< tel.speed_ref_rad_s - tel.omega_est_rad_s (the controllers' e_x), rad/s */
    float vdc_diff_V;         /**< vc1_V - vc2_V (neutral-point deviation), V */
    bool quick_stop_done;     /**< the quick stop ramp has brought the motor to a stop */
    float i_peak_A;           /**< stator current magnitude sqrt(2/3 (ia^2 + ib^2 + ic^2)), A */
    float vdc_V;              /**< DC link voltage vc1_V + vc2_V, V */
} drive_snapshot;

/** Derived snapshot fields the interrupt works out for the scope (drive.snap_derived). */
#define DRIVE_SNAP_SPEED_ERR (1u << 0) /**< speed_err_rad_s */
#define DRIVE_SNAP_VDC_DIFF (1u << 1)  /**< vdc_diff_V */
#define DRIVE_SNAP_I_PEAK (1u << 2)    /**< i_peak_A */
#define DRIVE_SNAP_VDC (1u << 3)       /**< vdc_V */

/** Interrupt timing statistics, in HAL cycles (hal_cycles_hz per second). */
typedef struct {
    uint32_t last_cycles;   /**< duration of the last tick */
    uint32_t max_cycles;    /**< longest tick since start */
    uint32_t overruns;      /**< ticks measured longer than the period (statistic only;
                                 the overrun fault comes from hal_tick_missed()) */
} drive_timing;

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
                                         next to snap: one load in the tick, issue 11) */
    drive_timing timing;
    scope scope;                    /**< triggered capture, sampled in drive_isr */
    co_dev co;                      /**< CANopen device, run by drive_background (drive_co.c) */
    co_app co_app;                  /**< the drive's side of the CANopen interface (drive_co.c) */
    persist_state persist;          /**< stored parameter set (status for 0x2510:1) */
    uint8_t reset_cause;            /**< hal_reset_cause() at drive_init (0x2510:7) */
    bool reset_cause_sent;          /**< the EMCY of a watchdog reset went out (once per start) */
    drive_snapshot bg_snap;         /**< background copy of snap, taken once per drive_background pass */
} drive;

/**
 * Initialise with default configuration, stopped, then load the persisted
 * parameters (the newest valid NVM set; defaults if none). Bind the board
 * (and load any NVM image) before calling. Context: BG, before hal_tick_start.
 */
void drive_init(drive *d);

/** The control interrupt; signature of hal_tick_handler (ctx is the drive). Context: ISR. */
void drive_isr(void *ctx);

/** The active configuration (read only). Context: ANY. */
const ctl_cfg *drive_cfg(const drive *d);

/**
 * Begin editing the configuration: returns the inactive copy, freshly copied
 * from the active one. Finish with drive_cfg_commit(). Context: BG.
 */
ctl_cfg *drive_cfg_edit(drive *d);

/** Derive gains in the edited copy and publish it to the ISR. Context: BG. */
void drive_cfg_commit(drive *d);

/**
 * Set the mechanical speed reference, rad/s, limited to the declared range of
 * speed_ref_rpm (the rule every source of the reference goes through,
 * dtc/speed_ref.h; the control law limits it to the envelope's top speed).
 * Context: BG.
 */
void drive_set_speed_ref(drive *d, float speed_ref_rad_s);

/** Start (true: magnetise then run) or stop (false: gates off). Context: BG. */
void drive_set_run(drive *d, bool run);

/**
 * One pass of the background loop: communication, persistence, housekeeping,
 * watchdog. Never blocks. The SIL calls it once per control period; the
 * target calls it in its main loop. Context: BG.
 */
void drive_background(drive *d);

/** Copy the latest consistent telemetry snapshot, derived fields included. Context: BG. */
void drive_read_snapshot(const drive *d, drive_snapshot *out);

/**
 * Arm the scope (scope_arm) on sources in the telemetry snapshot (byte
 * offsets in drive_snapshot), and have the interrupt work out the derived
 * snapshot fields among them. Context: BG.
 */
void drive_scope_arm(drive *d, const scope_src *src, uint8_t n_src);

#ifdef __cplusplus
}
#endif

#endif /* DTC_DRIVE_H */
