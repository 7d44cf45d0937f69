/**
 * @file tick_record.h
 * @brief The recorded-tick file: what the control interrupt saw and produced
 *        in a closed-loop SIL run, replayed by the PIL programs.
 *
 * `dtc-sim run FILE --record-samples OUT.rec` writes it (host_sim/src/
 * tick_recorder.c); hal/pil/pil_bench.c reads it on the Cortex-M4F under QEMU
 * (semihosting), feeds every tick's inputs to the real interrupt (drive_isr)
 * and compares its outputs with the recorded ones. Both ends compile this
 * encoding (recording/src/tick_record.c) from the same source, so they agree
 * byte for byte. Written to the firmware's rules (C11, no 64-bit floating
 * point, no heap, no mutable state); background context only.
 * Format (docs/pil.md), all little-endian, every field written one by one
 * (no struct images, except the configuration, see below):
 *
 *   header, TICK_REC_HEADER_BYTES:
 *     0  char[8] magic "DTCTREC1"
 *     8  u32 version (1)          12 u32 header bytes (this header, 96)
 *    16  u32 record bytes (124)   20 u32 cfg words (n)
 *    24  u32 speed mode (0 ip, 1 nominal, 2 rbfn)
 *    28  u32 period_us            32 u32 reserved (0)
 *    36  char[60] scenario name, NUL padded
 *   configuration: n u32 words, the committed ctl_cfg's settable fields in a
 *     fixed order (tick_rec_cfg_encode): motor (8), period_s, vdc_nom_V,
 *     speed.mode, then every [control] key of recording/control_keys.def in
 *     its order (float bits, u32, or 0/1). Not a struct image: the
 *     layouts differ (arm-none-eabi uses 1-byte enums, x86-64 4-byte ones).
 *     The reader sets these fields on the default configuration and derives
 *     the rest (drive_cfg_commit), as dtc-sim's configure_firmware does.
 *   then one record per tick (tick_rec below, TICK_REC_RECORD_BYTES each),
 *   the fields in the order of the struct, u8 legs and flags, 3 pad bytes
 *   after vector_index.
 */
#ifndef RECORDING_TICK_RECORD_H
#define RECORDING_TICK_RECORD_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/ctl.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TICK_REC_MAGIC "DTCTREC1"
#define TICK_REC_VERSION 1u
#define TICK_REC_HEADER_BYTES 96u
#define TICK_REC_RECORD_BYTES 124u
#define TICK_REC_CFG_FIXED_WORDS 11u
#define TICK_REC_NAME_LEN 60u

/** File header (decoded). */
typedef struct {
    uint32_t version;
    uint32_t header_bytes;
    uint32_t record_bytes;
    uint32_t cfg_words;
    uint32_t speed_mode;
    uint32_t period_us;
    char name[TICK_REC_NAME_LEN + 1u];
} tick_rec_header;

/* Input flags */
#define TICK_REC_SAMPLE_NEW (1u << 0)   /**< the board converted a sample this tick (else stale) */
#define TICK_REC_SPEED_VALID (1u << 1)  /**< hal_sample.speed_meas_valid */
#define TICK_REC_FAULT_INPUT (1u << 2)  /**< hardware fault input active */
#define TICK_REC_TICK_MISSED (1u << 3)  /**< the board reports a missed deadline in this tick */
#define TICK_REC_RUN (1u << 4)          /**< drive.run as the interrupt finds it */
#define TICK_REC_CLEAR_REQ (1u << 5)    /**< drive.clear_faults_req */
#define TICK_REC_QSTOP_REQ (1u << 6)    /**< drive.quick_stop_req */

/** Everything the interrupt reads from outside in one tick, and what it produced. */
typedef struct {
    /* ---- inputs (before the interrupt) ---- */
    uint32_t tick;              /**< tick index k in the run (t = k T) */
    uint32_t flags;             /**< TICK_REC_* */
    hal_sample sample;          /**< the board's sample buffer (read only if SAMPLE_NEW) */
    float speed_ref_rad_s;      /**< drive.speed_ref_rad_s */
    float qs_decel_rad_s2;      /**< drive.qs.decel_rad_s2 */
    /* ---- outputs (after the interrupt) ---- */
    hal_actuation act;          /**< ctl_out.act */
    uint8_t gate_enable;        /**< ctl_out.gate_enable */
    uint8_t state;              /**< ctl_run_state */
    uint8_t vector_index;       /**< tel.vector_index */
    uint32_t faults;            /**< tel.faults */
    float te_ref_Nm;            /**< tel.te_ref_Nm */
    float te_est_Nm;            /**< tel.te_est_Nm */
    float psi_s_est_Wb;         /**< tel.psi_s_est_Wb */
    float psi_ref_Wb;           /**< tel.psi_ref_Wb */
    float omega_est_rad_s;      /**< tel.omega_est_rad_s */
    float speed_ref_out_rad_s;  /**< tel.speed_ref_rad_s (after the ramp) */
    float eps_hat;              /**< tel.eps_hat */
    float w_norm;               /**< tel.w_norm */
    float psi_r_Wb[2];          /**< observer rotor flux (state), Wb */
    float is_hat_A[2];          /**< observer current estimate (state), A */
    float omega_e_rad_s;        /**< observer electrical speed (state), rad/s */
    float omega_int_rad_s;      /**< observer adaptation integral (state), rad/s */
    float rs_ohm;               /**< observer stator resistance (state), ohm */
} tick_rec;

/** Encode @p h into @p out (TICK_REC_HEADER_BYTES). */
void tick_rec_encode_header(const tick_rec_header *h, uint8_t *out);

/** Decode and check magic, version and sizes. @return 0, or -1 with @p why set. */
int tick_rec_decode_header(const uint8_t *in, tick_rec_header *h, const char **why);

/** Encode @p r into @p out (TICK_REC_RECORD_BYTES). */
void tick_rec_encode(const tick_rec *r, uint8_t *out);

/** Decode @p in into @p r. */
void tick_rec_decode(const uint8_t *in, tick_rec *r);

/** Fill the output half of @p r from the interrupt's outputs @p out and the observer state @p obs. */
void tick_rec_set_outputs(tick_rec *r, const ctl_out *out, const observer *obs);

/**
 * Compare the output halves of @p got and @p want bit for bit.
 * @return NULL when identical, else the name of the first differing field.
 */
const char *tick_rec_diff(const tick_rec *got, const tick_rec *want);

/** Number of configuration words (fixed fields + [control] keys). */
uint32_t tick_rec_cfg_words(void);

/** Encode the settable fields of @p cfg into @p words (tick_rec_cfg_words() of them). */
void tick_rec_cfg_encode(const ctl_cfg *cfg, uint32_t *words);

/** Set the settable fields of @p cfg from @p words (the derived ones are left to ctl_cfg_derive). */
void tick_rec_cfg_apply(ctl_cfg *cfg, const uint32_t *words);

#ifdef __cplusplus
}
#endif

#endif /* RECORDING_TICK_RECORD_H */
