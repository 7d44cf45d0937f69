/**
 * @file ident.h
 * @brief The motor identification run: a run state of the drive that
 *        measures the equivalent circuit (and, when the load allows, the
 *        mechanics) with the inverter it has. Method, sources, durations and
 *        current bounds: docs/commissioning.md, "Identification".
 *
 * Standstill part (dtc/ident_standstill.h): Rs, sigma Ls, Rr (Tr) and Lm
 * with the rotor at rest, from DC steps and pulse bursts along one axis.
 * Rotating part (dtc/ident_rotating.h, optional): the magnetising inductance
 * from the no-load state at half speed, the inertia from an acceleration and
 * a deceleration at a known torque, the friction from two speeds; it runs on
 * the drive's own control with the standstill results applied.
 *
 * How the drive runs it (its integration into ctl_step is a run state):
 *
 *   BG   ident_cfg_derive(&cfg)                      once, from the plate and the drive
 *   BG   ident_start(&id, &cfg, &start)              refused unless stopped, at rest, link ready
 *   ISR  ident_step(&id, &cfg, &in, &out)            every tick while the run lasts: out says
 *                                                    gates off, this actuation, or the drive's
 *                                                    own control with a torque / speed command
 *   BG   ident_background(&id, &cfg, &res)           every pass: fits when a part has ended
 *   BG   at IDENT_WAIT_APPLY: ident_apply(&id, &res, &orig, &trial), publish trial,
 *        ident_continue(&id, &res)                  (rotating part only)
 *   BG   at IDENT_DONE: ident_apply(&id, &res, &orig, &final), publish final
 *   BG   at IDENT_ABORTED: publish orig again (ident_apply refuses: nothing is written)
 *
 * Safety: every phase current stays below i_max_A (the standstill part aborts
 * above it, the rotating part runs under the drive's own limits); the run
 * aborts to gates off when the run command drops (a disable, a quick stop, a
 * lost master), on any fault the drive latches, when the rotor turns or the
 * link sags, and then writes nothing.
 *
 * Shared state: the interrupt alone writes the phase and the sums, the
 * background alone the results and the flags ss_fitted, rot_fitted,
 * rot_allowed and go_rotating; the background reads the sums only in the
 * phases where the interrupt has stopped writing them (IDENT_FIT_*).
 */
#ifndef DTC_IDENT_H
#define DTC_IDENT_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/ident_io.h"
#include "dtc/ident_plate.h"
#include "dtc/ident_rotating.h"
#include "dtc/ident_standstill.h"
#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Phases of the run (telemetry: ident_phase_name). */
typedef enum {
    IDENT_IDLE = 0,          /**< not started */
    IDENT_PROBE = 1,         /**< gates off, then the zero vector: offsets, a turning rotor */
    IDENT_MAGNETISE = 2,     /**< DC at i_hi: the rotor flux builds */
    IDENT_SIGMA = 3,         /**< pulse bursts at i_hi: sigma Ls */
    IDENT_ROTOR = 4,         /**< DC at i_lo: the rotor flux decays (Rr, Tr) */
    IDENT_FIT_STANDSTILL = 5, /**< gates off; the background fits */
    IDENT_WAIT_APPLY = 6,    /**< the drive applies the standstill results (ident_continue) */
    IDENT_ROT_START = 7,     /**< the drive's control magnetises */
    IDENT_ROT_ACCEL = 8,     /**< inertia: accelerating */
    IDENT_ROT_DECEL = 9,     /**< inertia: decelerating */
    IDENT_ROT_NO_LOAD = 10,  /**< no load at half speed: Lm, the no-load current */
    IDENT_ROT_FRICTION = 11, /**< a second speed: friction */
    IDENT_ROT_STOP = 12,     /**< back to rest */
    IDENT_FIT_ROTATING = 13, /**< gates off; the background computes */
    IDENT_DONE = 14,         /**< results ready (ident_apply) */
    IDENT_ABORTED = 15,      /**< stopped early (ident.abort_reason): nothing to apply */
} ident_phase;

/** Why a run stopped early. */
typedef enum {
    IDENT_ABORT_NONE = 0,
    IDENT_ABORT_STOPPED = 1,     /**< the run command dropped: disable, quick stop, lost master */
    IDENT_ABORT_FAULT = 2,       /**< the drive latched a fault */
    IDENT_ABORT_OVERCURRENT = 3, /**< a phase current above i_max_A */
    IDENT_ABORT_TURNING = 4,     /**< the rotor turns */
    IDENT_ABORT_LINK = 5,        /**< the DC link below vdc_min_V */
    IDENT_ABORT_TIMEOUT = 6,     /**< a rotating stage did not reach its speed in time */
} ident_abort;

/** Error codes of ident_cfg_derive and ident_start (negative). */
enum ident_error {
    IDENT_OK = 0,
    IDENT_E_PLATE = -1,       /**< the plate fails ident_plate_check */
    IDENT_E_DRIVE = -2,       /**< a drive value out of range (period, link, dead time, drop, bound) */
    IDENT_E_BUSY = -3,        /**< a run is going on */
    IDENT_E_NOT_STOPPED = -4, /**< the drive is not stopped */
    IDENT_E_TURNING = -5,     /**< the last speed estimate is not near zero */
    IDENT_E_LINK = -6,        /**< the DC link is below vdc_min_V */
    IDENT_E_PHASE = -7,       /**< not the phase the call belongs to */
    IDENT_E_REJECTED = -8,    /**< the configuration with the results fails its check */
};

/** Inputs and constants of a run. */
typedef struct {
    ident_plate plate;       /**< the rating plate */
    real_t i_max_A;          /**< bound of the phase currents at standstill, A peak (0: the rated peak) */
    real_t period_s;         /**< control period, s (2e-5..2e-3) */
    real_t vdc_nom_V;        /**< nominal DC link, V */
    real_t vdc_min_V;        /**< the run refuses to start, and stops, below this link, V (< vdc_nom_V) */
    real_t dead_time_s;      /**< the power stage's dead time, s (0..1e-5; ctl_cfg.dead_time_comp_s) */
    real_t v_drop_V;         /**< on-state drop of one device, V (ctl_cfg.v_drop_V) */
    bool rotating;           /**< run the rotating part too (the load must allow the shaft to turn) */
    real_t te_J_frac;        /**< torque of the inertia test, fraction of the rated (0: 0.3) */
    /* derived by ident_cfg_derive() */
    ident_plate_est est;     /**< the plate's estimates */
    ident_ss_cfg ss;         /**< constants of the standstill part */
    ident_rot_cfg rot;       /**< constants of the rotating part */
} ident_cfg;

/** Plausibility of one identified value. */
typedef enum {
    IDENT_VERDICT_NONE = 0,     /**< not measured (that part did not run) */
    IDENT_VERDICT_OK = 1,       /**< credible: applied by ident_apply */
    IDENT_VERDICT_DOUBTFUL = 2, /**< found, but outside the range usual for the plate or poorly fitted: not applied */
    IDENT_VERDICT_FAILED = 3,   /**< not found: not applied */
} ident_verdict;

/** One identified value with its verdict. */
typedef struct {
    real_t value;
    ident_verdict verdict;
} ident_value;

/** The results of a run (written by ident_background). */
typedef struct {
    ident_value rs_ohm;      /**< stator resistance, ohm */
    ident_value sigma_ls_H;  /**< transient inductance sigma Ls, H */
    ident_value rr_ohm;      /**< rotor resistance (T model, Lls = Llr), ohm */
    ident_value lm_H;        /**< magnetising inductance (T model), H */
    ident_value ls_H;        /**< stator (= rotor) inductance, H */
    ident_value tr_s;        /**< rotor time constant, s */
    ident_value rr_ref_ohm;  /**< R_R = Rr (Lm/Lr)^2, ohm */
    ident_value lm_ref_H;    /**< L_M = Lm^2/Lr, H (rotating part's when it ran, else the standstill's) */
    ident_value j_kgm2;      /**< inertia, kg m^2 */
    ident_value b_Nms;       /**< viscous friction, N m s/rad */
    ident_value i0_A;        /**< no-load current at half speed, A peak */
    real_t lm_ref_standstill_H; /**< L_M of the standstill part, H */
    real_t r_hf_ohm;         /**< resistance seen by the pulse bursts (Rs + R_R expected), ohm */
    real_t u_off_V;          /**< the inverter's constant voltage error the DC fit found, V */
    real_t fit_resid_V;      /**< rms residual of the DC fit, V */
    real_t i_peak_A;         /**< the largest phase current sampled at standstill, A */
    real_t t_standstill_s;   /**< drive time of the standstill part, s */
    real_t t_rotating_s;     /**< drive time of the rotating part, s */
    bool lm_from_rotation;   /**< Lm, Ls, Rr come from the rotating part's L_M */
} ident_result;

/** State of a run (caller owned, about 3 kB). */
typedef struct {
    ident_phase phase;       /**< written by the interrupt (and ident_start while idle) */
    ident_abort abort_reason;
    uint32_t ticks_standstill; /**< ticks of the standstill part so far */
    ident_ss ss;
    ident_rot rot;
    bool ss_fitted;          /**< BG: the standstill results are in */
    bool rot_allowed;        /**< BG: the standstill results allow the rotating part */
    bool go_rotating;        /**< BG: the drive runs on the standstill results (ident_continue) */
    bool rot_fitted;         /**< BG: the rotating results are in */
    real_t rot_rs_ohm;       /**< BG: the Rs the rotating part's voltage model uses, ohm */
} ident;

/** What ident_background did. */
typedef enum {
    IDENT_BG_NONE = 0,       /**< nothing to do */
    IDENT_BG_STANDSTILL = 1, /**< the standstill results are in */
    IDENT_BG_ROTATING = 2,   /**< the rotating results are in */
} ident_bg_event;

/**
 * Derive the constants of @p c from its inputs (the plate and the drive's
 * values). @return IDENT_OK, IDENT_E_PLATE or IDENT_E_DRIVE. Context: BG.
 */
int ident_cfg_derive(ident_cfg *c);

/** Idle, nothing measured. Context: BG. */
void ident_init(ident *s);

/** What ident_start checks. */
typedef struct {
    bool drive_stopped;      /**< the drive is stopped (gates off, no other run state) */
    real_t omega_m_rad_s;    /**< its last speed estimate, rad/s (mechanical) */
    real_t vdc_V;            /**< the DC link now, V */
} ident_start_in;

/**
 * Start a run. Refused (the state unchanged) while one is going on, unless
 * the drive is stopped, when the last speed estimate is above 2 % of the
 * rated speed, or the link below vdc_min_V. @return IDENT_OK or the refusal
 * (enum ident_error). Context: BG, with the drive's interrupt not stepping
 * the run (it is idle, done or aborted).
 */
int ident_start(ident *s, const ident_cfg *c, const ident_start_in *in);

/**
 * One tick of the run (any phase; idle, done or aborted: gates off).
 * Bounded work: the standstill or the rotating part's step. Context: ISR.
 */
void ident_step(ident *s, const ident_cfg *c, const ident_in *in, ident_out *out);

/**
 * The background's share: at IDENT_FIT_STANDSTILL the fit of the standstill
 * part (a few hundred thousand operations, once), at IDENT_FIT_ROTATING the
 * rotating part's; the results into @p r. @return what it did. Context: BG.
 */
ident_bg_event ident_background(ident *s, const ident_cfg *c, ident_result *r);

/**
 * The drive now runs on the standstill results (IDENT_WAIT_APPLY): the
 * rotating part may start, its voltage model with the Rs of @p r.
 * @return IDENT_OK or IDENT_E_PHASE. Context: BG.
 */
int ident_continue(ident *s, const ident_result *r);

/** Progress of the run, 0..100 %. Context: any. */
uint32_t ident_progress(const ident *s, const ident_cfg *c);

/** The phase's name for telemetry ("probe", "magnetise", ...). Context: any. */
const char *ident_phase_name(ident_phase p);

/** The verdict's name ("ok", "doubtful", "failed", "-"). Context: any. */
const char *ident_verdict_name(ident_verdict v);

#ifdef __cplusplus
}
#endif

#endif /* DTC_IDENT_H */
