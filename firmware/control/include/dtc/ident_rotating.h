/**
 * @file ident_rotating.h
 * @brief The rotating part of the identification run: a sequencer on top of
 *        the drive's own torque and speed control (docs/commissioning.md,
 *        "Identification").
 *
 * The drive runs its own control with the standstill results applied; the
 * sequencer asks it for a torque command or a speed reference and measures,
 * with the stator flux of the voltage model (the applied voltage less Rs i,
 * integrated: no rotor model, no speed), the electromagnetic torque
 * Te = 1.5 p psi_s x i_s and the no-load products psi_s . i_s, psi_s x i_s.
 * Stages:
 *
 *   START     zero torque until the drive's control runs (it magnetises first)
 *   ACCEL     torque +te_J: the window from w_a to w_b (up), on to w_top
 *   DECEL     torque -te_J: the window from w_b to w_a (down), on to w_bottom
 * (Each new speed is approached at the torque te_J until within w_near,
 * then held by the drive's speed loop.)
 *
 *   NO_LOAD   speed w1 (half the rated speed): settle, then a window of
 *             psi . i, psi x i, |i|^2, |psi|^2 and Te (L_M, the no-load current)
 *   FRICTION  speed w2: settle, then a window of Te (B from the two speeds)
 *   STOP      speed 0 until the shaft is nearly at rest
 *
 * The voltage model integrates with a leak wc (drift of an offset stays
 * bounded), whose gain and phase at the stator frequency w are undone:
 * psi = psi_leaky (1 - j wc / w), exact for a sinusoid; the stator frequency
 * is the flux's own rotation, low-passed. Context: ISR (ident_rot_step), BG
 * (the rest).
 */
#ifndef DTC_IDENT_ROTATING_H
#define DTC_IDENT_ROTATING_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/ident_fit.h"
#include "dtc/ident_io.h"
#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Stages of the rotating part (in the order run). */
typedef enum {
    IDENT_ROTATING_START = 0,
    IDENT_ROTATING_ACCEL = 1,
    IDENT_ROTATING_DECEL = 2,
    IDENT_ROTATING_NO_LOAD = 3,
    IDENT_ROTATING_FRICTION = 4,
    IDENT_ROTATING_STOP = 5,
    IDENT_ROTATING_END = 6,
} ident_rot_stage;

/** What one step of the rotating part ended with. */
typedef enum {
    IDENT_ROT_RUNNING = 0,  /**< go on: the output is this tick's */
    IDENT_ROT_FINISHED = 1, /**< the windows are complete and the shaft is nearly at rest */
    IDENT_ROT_TIMEOUT = 2,  /**< a stage did not reach its speed in time */
} ident_rot_status;

/** Constants of the rotating part (derived with ident_cfg_derive). */
typedef struct {
    real_t period_s;        /**< control period T, s */
    real_t pole_pairs;      /**< p */
    real_t te_J_Nm;         /**< torque of the inertia test, N m */
    real_t w_a_rad_s, w_b_rad_s;  /**< the inertia windows' speeds, rad/s (mechanical) */
    real_t w_top_rad_s;     /**< acceleration ends here, rad/s */
    real_t w_bottom_rad_s;  /**< deceleration ends here, rad/s */
    real_t w1_rad_s;        /**< no-load speed, rad/s */
    real_t w2_rad_s;        /**< second speed for the friction, rad/s */
    real_t w_tol_rad_s;     /**< a speed within this of its reference is reached, rad/s */
    real_t w_near_rad_s;    /**< farther than this from a new speed: there at te_J, then the speed loop, rad/s */
    real_t wc_rad_s;        /**< leak of the voltage model, rad/s */
    real_t w_lpf_a;         /**< low-pass coefficient of the stator frequency per tick, 0..1 */
    uint32_t start_ticks;   /**< ticks the drive's control must have run before ACCEL */
    uint32_t settle_ticks;  /**< ticks within w_tol before a window opens */
    uint32_t window_ticks;  /**< ticks of each speed window */
    uint32_t timeout_ticks; /**< the longest a stage may take */
} ident_rot_cfg;

/** Sums of one steady-speed window. */
typedef struct {
    real_t p_VsA;   /**< sum of psi_s . i_s, Wb A */
    real_t q_VsA;   /**< sum of psi_s x i_s, Wb A */
    real_t i2_A2;   /**< sum of |i_s|^2, A^2 */
    real_t psi2_Wb2; /**< sum of |psi_s|^2, Wb^2 */
    real_t te_Nm;   /**< sum of Te, N m */
    real_t te2_Nm2; /**< sum of Te^2 (the torque ripple: the uncertainty of the mean), N^2 m^2 */
    real_t w_rad_s; /**< sum of the speed estimate, rad/s */
    real_t w_late_rad_s;  /**< sum of the speed estimate over the window's second half (its mean less
                               the first half's: the acceleration left, whose J dw/dt is not friction), rad/s */
    uint32_t n;     /**< ticks summed */
} ident_rot_window;

/** State of the rotating part (caller owned). */
typedef struct {
    ident_rot_stage stage;
    uint32_t tick;           /**< ticks in the present stage */
    uint32_t ticks_total;    /**< ticks since the part's start */
    uint32_t held;           /**< consecutive ticks within w_tol of the reference */
    real_t rs_ohm;           /**< the stator resistance of the voltage model, ohm */
    real_t psi_Wb[2];        /**< the voltage model's (leaky) stator flux at the last sample, Wb */
    real_t v_prev_V[2];      /**< the voltage of the period that started at the last tick, V */
    real_t i_prev_A[2];      /**< the current of the last tick, A */
    real_t w_e_rad_s;        /**< low-passed stator frequency (electrical), rad/s */
    bool flux_on;            /**< the voltage model integrates (seeded once the drive's control runs) */
    bool win_open;           /**< a speed-change window is open */
    real_t win_w0_rad_s;     /**< speed at its opening, rad/s */
    real_t win_t_s;          /**< time since its opening, s */
    ident_speed_window up;   /**< the acceleration window (t_s 0: not yet complete) */
    ident_speed_window down; /**< the deceleration window */
    ident_rot_window no_load;  /**< the no-load window at w1 */
    ident_rot_window friction; /**< the window at w2 */
} ident_rot;

/** Start the part with the voltage model's @p rs_ohm (from the standstill part). Context: BG or ISR. */
void ident_rot_reset(ident_rot *s, real_t rs_ohm);

/**
 * One tick: integrates the voltage model, steps the sequencer, writes the
 * command for the drive's control into @p out (mode TORQUE, SPEED, or OFF
 * at the end). Bounded: a few dozen operations. Context: ISR.
 */
ident_rot_status ident_rot_step(ident_rot *s, const ident_rot_cfg *c, const ident_in *in, ident_out *out);

#ifdef __cplusplus
}
#endif

#endif /* DTC_IDENT_ROTATING_H */
