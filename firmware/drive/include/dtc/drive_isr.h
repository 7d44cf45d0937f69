/**
 * @file drive_isr.h
 * @brief The drive's interrupt side: the 200 us tick and what the background
 *        hands to it or takes from it (drive_isr.c).
 *
 * Interrupt (drive_isr): sample -> ctl_step (observe, speed control, DTC,
 * protect) -> actuate -> publish a telemetry snapshot and a scope sample. It
 * is timed with the HAL cycle counter; the board's deadline flag
 * (hal_tick_missed) latches CTL_FAULT_OVERRUN in the next tick.
 *
 * The background never writes state the interrupt is using: configuration is
 * kept in two copies (edit the inactive one, then publish it with one store),
 * and the interrupt picks the published copy up at the start of its next
 * tick; commands are single words; the snapshot is guarded by a sequence
 * counter. Nothing here knows the CANopen binding or the parameter store.
 */
#ifndef DTC_DRIVE_ISR_H
#define DTC_DRIVE_ISR_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/ctl.h"
#include "dtc/scope.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The drive object (dtc/drive.h); these functions use its interrupt side only. */
typedef struct drive drive;

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
 * interrupt's own d->snap only those the armed scope reads (the background
 * reads at ms rates; the tick need not pay for them).
 */
typedef struct {
    volatile uint32_t seq;
    /* The control core's outputs of the tick, written by ctl_step in place
     * (the telemetry is filled once, not filled and then copied); tel is
     * out.tel under its own name. */
    union {
        ctl_out out;
        struct {
            hal_actuation out_act_;  /* out.act */
            bool out_gate_enable_;   /* out.gate_enable */
            ctl_telemetry tel;       /**< the control core's telemetry (out.tel) */
        };
    };
    /* The control core's inputs of the tick, set in place (the sample is
     * read once, straight into the snapshot, not read and then copied); the
     * six fields below are in.sample's first six under their snapshot names. */
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

/**
 * The interrupt side at its defaults: both configuration copies from
 * ctl_cfg_default (derived), the scope idle. The rest of the drive must be
 * zeroed before (drive_init does both). Context: BG, before hal_tick_start.
 */
void drive_isr_init(drive *d);

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

#endif /* DTC_DRIVE_ISR_H */
