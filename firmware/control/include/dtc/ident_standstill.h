/**
 * @file ident_standstill.h
 * @brief The standstill part of the identification run: the excitation the
 *        interrupt applies and the sums it collects (docs/commissioning.md,
 *        "Identification").
 *
 * Every current of the part flows along the alpha axis (phase a), with one
 * sign: i_a = I > 0, i_b = i_c = -I / 2. The rotor produces no torque and
 * each leg's current keeps its sign, so the dead time and the device drops
 * take a constant voltage, which the estimators cancel (a two-level
 * difference, a constant in every regression). Stages:
 *
 *   PROBE_OFF    gates off: the current sensors' offsets (no current flows)
 *   PROBE_SHORT  the zero vector: a turning, magnetised rotor drives a current
 *   MAGNETISE    the current regulated to i_hi: the rotor flux builds (Tr)
 *   SIGMA        at i_hi, bursts of four pulses (+, -, -, +) between
 *                regulated periods: the transient inductance
 *   ROTOR        the current regulated to i_lo: the rotor flux decays (Tr)
 *
 * The regulator applies, per block of n_block periods, one pulse of a small
 * vector along alpha (POO or ONN, NOO or OPP, whichever moves the neutral
 * point towards balance) centred on the block's first sample: the second
 * half of one period and the first half of the next. The samples of a block
 * then average to the current's mean (a triangle sampled at the middle of
 * its rise and along its fall), so no current ripple biases the fit. A pulse
 * shorter than the dead time never turns its device on; n_block is chosen so
 * that the narrowest pulse (at i_lo) is at least 1.5 dead times + 1 us.
 *
 * The MAGNETISE, SIGMA and ROTOR stages are recorded in IDENT_BINS bins of
 * equal length (ident_bin: mean voltage and current), the bursts of SIGMA in
 * the sums of ident_hf_sums. Context: ISR (ident_ss_step), BG (the rest).
 */
#ifndef DTC_IDENT_STANDSTILL_H
#define DTC_IDENT_STANDSTILL_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/ident_fit.h"
#include "dtc/ident_io.h"
#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

#define IDENT_BINS 128u /**< bins of the DC record */

/** Stages of the standstill part (in the order run). */
typedef enum {
    IDENT_SS_PROBE_OFF = 0,
    IDENT_SS_PROBE_SHORT = 1,
    IDENT_SS_MAGNETISE = 2,
    IDENT_SS_SIGMA = 3,
    IDENT_SS_ROTOR = 4,
    IDENT_SS_END = 5,
} ident_ss_stage;

/** What one step of the standstill part ended with. */
typedef enum {
    IDENT_SS_RUNNING = 0,     /**< go on: the output is this tick's */
    IDENT_SS_FINISHED = 1,    /**< the record is complete: gates off, the fit may run */
    IDENT_SS_OVERCURRENT = 2, /**< a phase current above i_max_A */
    IDENT_SS_TURNING = 3,     /**< the rotor turns (a current in the zero vector, or along beta) */
    IDENT_SS_LINK = 4,        /**< the DC link below vdc_min_V */
} ident_ss_status;

/** Constants of the standstill part (ident_ss_cfg_derive). */
typedef struct {
    real_t period_s;         /**< control period T, s */
    real_t dead_time_s;      /**< the power stage's dead time, s */
    real_t w_min_s;          /**< narrowest pulse applied, s (1.5 dead times + 1 us) */
    real_t vdc_min_V;        /**< link voltage below which the part stops, V */
    real_t i_max_A;          /**< bound of every phase current, A (abort above) */
    real_t i_hi_A, i_lo_A;   /**< the two DC levels (alpha), A */
    real_t hf_di_A;          /**< the current step aimed at by each burst pulse, A */
    real_t hf_duty0;         /**< the burst pulses' first duty (from the plate's sigma Ls), 0..0.9 */
    real_t kp_V_A;           /**< regulator gain: block-mean voltage per ampere of error, V/A */
    real_t kp_hold_V_A;      /**< kp_V_A once a stage has settled (less of the current's noise), V/A */
    real_t ki_V_A;           /**< regulator integral gain per block, V/A */
    real_t turn_A;           /**< rms beta current (low-passed over ib_lpf_a), or rms current over the
                                  zero vector's ticks, above which the rotor turns, A */
    real_t ib_lpf_a;         /**< low-pass coefficient per tick of the squared beta current (10 ms), 0..1 */
    uint32_t n_block;        /**< periods per regulator block (one pulse each), 2..16 */
    uint32_t cycle;          /**< periods per SIGMA cycle: a burst of 4, then regulation */
    uint32_t bursts;         /**< SIGMA cycles */
    uint32_t probe_ticks;    /**< ticks of each probe stage */
    uint32_t bin_ticks;      /**< periods per bin (a multiple of n_block) */
    uint32_t g_sigma;        /**< first period of SIGMA, counted from the start of MAGNETISE */
    uint32_t g_rotor;        /**< first period of ROTOR */
    uint32_t g_end;          /**< the end of the record (IDENT_BINS x bin_ticks at most) */
    uint32_t settle_ticks;   /**< periods after a stage's start before its bins count */
} ident_ss_cfg;

/** State of the standstill part (caller owned; about 2.6 kB). */
typedef struct {
    uint32_t tick;           /**< ticks since the start of the part */
    real_t i_off_A[2];       /**< current offsets (alpha, beta) found in PROBE_OFF, A */
    real_t i_prev_A[2];      /**< offset-free alpha, beta current of the last tick, A */
    real_t v_prev_V;         /**< alpha voltage of the period that started at the last tick, V */
    uint8_t prev_kind;       /**< that period's kind (ident_standstill.c) */
    uint16_t prev_bin;       /**< that period's bin */
    real_t integ_V;          /**< the regulator's integral, V */
    real_t i_centre_A;       /**< alpha current at the last pulse centre, A */
    uint8_t half_state;      /**< the state of the pulse whose second half is latched next */
    real_t half_duty;        /**< that half's duty, 0..1 */
    uint8_t last_state;      /**< the state the last latched actuation ends on (P<->N guard) */
    uint8_t burst_n_type;    /**< this burst's small vectors: 0 P-type (POO, OPP), 1 N-type (ONN, NOO) */
    real_t hf_duty;          /**< the burst pulses' duty, adapted to hf_di_A, 0..0.9 */
    real_t d_cur;            /**< the burst duty of the period starting at this tick (0: not a burst) */
    real_t d_prev;           /**< the burst duty of the period that started at the last tick */
    real_t i_peak_A;         /**< the largest |phase current| sampled, A */
    real_t ib2_A2;           /**< low-passed square of the beta current (in PROBE_SHORT: the sum of the
                                  current's squares), A^2 */
    ident_hf_sums hf;        /**< the bursts' regression sums */
    ident_bin bins[IDENT_BINS]; /**< the DC record */
} ident_ss;

/** The stage of tick @p tick of the part. Context: any. */
ident_ss_stage ident_ss_stage_of(const ident_ss_cfg *c, uint32_t tick);

/** Ticks the part takes: the probe, the record, and the tick that records the
 *  record's last period (and turns the gates off). Context: any. */
uint32_t ident_ss_ticks(const ident_ss_cfg *c);

/** Start the part (zero sums, stage PROBE_OFF). Context: BG or ISR. */
void ident_ss_reset(ident_ss *s);

/**
 * One tick of the part: records this tick's sample and the voltage of the
 * period now starting (@p in), writes this tick's output (@p out: gates off,
 * or the actuation for t_{k+1}..t_{k+2}). Bounded: a few dozen operations.
 * Context: ISR.
 */
ident_ss_status ident_ss_step(ident_ss *s, const ident_ss_cfg *c, const ident_in *in, ident_out *out);

#ifdef __cplusplus
}
#endif

#endif /* DTC_IDENT_STANDSTILL_H */
