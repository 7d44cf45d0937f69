/**
 * @file sim.h
 * @brief The SIL engine: runs a scenario with the firmware on the host HAL
 *        bound to the plant, and computes traces and metrics.
 *
 * One control period T (the tick) of the engine:
 *  1. the plant is sampled at the period start (plant_sample ->
 *     plant_adc_to_units -> hal_sample with seq + 1, speed_meas = true speed)
 *     and handed to the board (hal_host_set_sample); the board's simulated
 *     time is set to t;
 *  2. scenario events whose time has come are applied (reference ->
 *     drive_set_speed_ref in rad/s mechanical, whenever the profile's value
 *     changes, so a reference set over CAN holds until then; load and parameter events ->
 *     plant_set_*). Events are quantised to tick boundaries: an event at T_S
 *     acts from the first tick at or after T_S;
 *  3. the tick interrupt runs (hal_host_run_tick -> drive_isr), then one
 *     background pass (drive_background), then options.on_tick;
 *  4. the plant is integrated over the period with the actuation the firmware
 *     latched on the PREVIOUS tick: one period of computation delay, as on the
 *     board whose timers are preloaded during tick k for period k+1. Gates off
 *     (hal_gate_enabled false after the tick: disabling is immediate) means
 *     leg code 3 (diodes only) on all legs; while the gates are off the board
 *     holds the zero vector, so re-enabling applies O,O,O for one period;
 *  5. metrics accumulate every tick; a CSV row every trace interval.
 * Samples, telemetry, metrics and CSV rows of tick k all refer to t = k T
 * (the sample instant); the run has ticks k = 0 .. round(duration / T).
 *
 * In sine-supply mode the firmware is not run at all (the plant is fed from
 * the ideal source); on_tick then receives d = NULL.
 */
#ifndef SIM_SIM_H
#define SIM_SIM_H

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal_host/hal_host.h"
#include "sim/scenario.h"

#ifdef __cplusplus
extern "C" {
#endif

struct drive;

/** Return codes of sim_run (equal to the dtc-sim exit status). */
enum sim_status {
    SIM_OK = 0,
    SIM_ERUNTIME = 1, /**< the run failed (diverged, watchdog, output write error, interrupted batch run) */
    SIM_EINPUT = 2,   /**< bad input (options, output path, CAN interface, NVM file) */
};

typedef struct {
    const char *csv_path;      /**< trace file (written to PATH.partial, renamed at the end); NULL: none */
    const char *metrics_path;  /**< metrics JSON (same .partial scheme); NULL: none */
    /** Recorded-tick file (recording/tick_record.h; same .partial scheme): every tick's
     *  interrupt inputs and outputs, for the PIL replay (tools/pil_bench.sh). NULL: none. */
    const char *record_path;
    /** Seconds before the run command (drive_set_run(true)); until then the drive
     *  stays stopped (gates off) while the plant and the scenario run. 0: from the start. */
    double start_delay_s;
    int controller;            /**< -1: the scenario's [controller]; else scenario_controller */
    bool realtime;             /**< pace ticks to the wall clock (absolute deadlines) */
    bool run_forever;          /**< realtime only: ignore the duration, run until *stop is set */
    const char *can_iface;     /**< realtime only: bind the HAL CAN to this SocketCAN interface */
    /** Optional CAN backend (for tests, e.g. hal_host_can_loopback); used
     *  when can_iface is NULL. NULL: no CAN (frames sent are dropped). */
    const hal_host_can_backend *can;
    /** Mirror the drive's NVM to this file: loaded at start (missing file:
     *  erased NVM) and rewritten (PATH.tmp + rename) on every write. NULL: memory only. */
    const char *nvm_path;
    /** Optional hook called every tick after the background pass, with the
     *  tick time t_s = k T and the drive (NULL in sine mode). It may inject
     *  CAN frames, read snapshots or call drive_* background functions. */
    void (*on_tick)(void *user, double t_s, struct drive *d);
    void *user;                /**< passed to on_tick and on_plant */
    /** Optional hook called every tick after the events due (load,
     *  parameters, faults) were applied, with the plant's state (read-only;
     *  for tests and instrumentation). */
    void (*on_plant)(void *user, double t_s, const plant_state *ps);
    /** Optional stop request (set from a signal handler). In realtime mode
     *  the run ends cleanly (outputs written, SIM_OK); in batch mode it is
     *  abandoned (SIM_ERUNTIME, no outputs). */
    volatile sig_atomic_t *stop;
    /** Benchmark only: > 0 bypasses the firmware and applies a rotating
     *  sequence of small vectors at this electrical frequency, Hz (inverter supply). */
    double open_loop_hz;
} sim_options;

/** Set @p o to the defaults: no outputs, the scenario's controller, batch, no CAN. */
void sim_options_default(sim_options *o);

/** One [metrics] window: mean true speed and stator rms current over [t0, t1). */
typedef struct {
    char name[SCENARIO_NAME_LEN];
    bool valid;            /**< false when the run never reached the window */
    double speed_rpm;
    double is_rms_a;
} sim_window_result;

/**
 * Metrics of a run. Speeds and torque are the plant's TRUE values; the
 * reference is the scenario's command (before the firmware's ramp limiter).
 * Means "over the last X s" use the last round(X / T) ticks.
 */
typedef struct {
    double sim_seconds;        /**< simulated time, s */
    double wall_seconds;       /**< wall time of the tick loop, s */
    char controller[16];       /**< "ip", "nominal", "rbfn", or "none" (sine / open loop) */
    bool firmware;             /**< the firmware ran (inverter supply, not open loop) */

    double speed_final_rad_s;  /**< mean true speed over the last 0.1 s, rad/s */
    double speed_final_rpm;    /**< same, rpm */
    double te_final_nm;        /**< mean true torque over the last 0.1 s, N m */
    double is_rms_final_a;     /**< stator rms current (per phase) over the last 0.1 s, A */
    double speed_true_end_rpm; /**< the plant's true speed at the last tick, rpm */
    double speed_true_max_abs_rpm; /**< largest |true speed| over the run, rpm */
    double runaway_limit_rpm;  /**< 1.5 x the largest |reference| of the run + 300 rpm */
    bool runaway;              /**< |true speed| exceeded runaway_limit_rpm at some tick */

    bool has_disturbance;      /**< a disturbance time exists (see scenario_disturbance) */
    double disturbance_t_s;
    double recovery_time_s;    /**< disturbance -> last instant |ref - true| > 1 % |ref|; 0 if never */
    bool recovered;            /**< the error was back within 1 % at the end of the run */
    double max_dip_rpm;        /**< largest |ref - true| after the disturbance, rpm */

    bool has_rise;             /**< the last reference change was followed to 90 % */
    double rise_time_s;        /**< 10-90 % rise after the last reference change, s */

    double steady_error_rpm;   /**< mean |ref - true| over the last 0.5 s, rpm */
    double speed_est_error_rpm;/**< mean |estimated - true| over the last 0.5 s, rpm */
    double eps_hat_final;      /**< mean telemetry eps_hat over the last 0.5 s, rad/s^2 */
    double eps_true;           /**< mean true eq.-5 uncertainty over the last 0.5 s, rad/s^2 */

    bool has_steady_window;    /**< the run went past startup_end_s */
    double startup_end_s;
    double np_dev_max_v;       /**< max |vc1 - vc2| (true) after startup_end_s, V */
    double np_dev_limit_v;     /**< 2 % of vdc, V */
    double switching_freq_hz;  /**< device switching frequency after startup_end_s, Hz:
                                    (leg transitions) / (3 legs * seconds) / 2 */

    double w_norm_max;         /**< max telemetry |W| */
    double m_w;                /**< configured projection bound M_w */
    uint32_t faults;           /**< telemetry fault bits at the end */
    uint32_t warnings_seen;    /**< telemetry warning bits (ctl_warning) present at any tick of the run */
    double isr_max_us;         /**< longest drive_isr, us (host time) */
    uint32_t isr_overruns;     /**< ticks longer than the period */

    int n_windows;
    sim_window_result windows[SCENARIO_MAX_WINDOWS];
} sim_metrics;

typedef struct {
    int status;                /**< enum sim_status */
    char error[1536];          /**< one line when status != SIM_OK */
    uint64_t ticks;            /**< control ticks run */
    sim_metrics metrics;       /**< valid when status == SIM_OK */
} sim_result;

/**
 * Run @p sc (already passed through scenario_finish) with @p opt.
 * The engine owns a hal_host_board for the run: it binds it (hal_host_bind)
 * before drive_init and leaves NO board bound when it returns, so HAL calls
 * from on_tick act on the engine's board. Not reentrant (one board per process).
 * @return the status (also in res->status); outputs exist only on SIM_OK.
 */
int sim_run(const scenario *sc, const sim_options *opt, sim_result *res);

/**
 * Write @p m as JSON to @p path (via PATH.partial and rename).
 * @return SIM_OK, or SIM_ERUNTIME with a message in @p err.
 */
int sim_write_metrics_json(const sim_metrics *m, const char *path, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif /* SIM_SIM_H */
