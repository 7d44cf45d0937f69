/**
 * @file tick_record.c
 * @brief Encoding of the recorded-tick file (tick_record.h), field by field,
 *        little-endian, identical on the host and the Cortex-M4F.
 */
#include "recording/tick_record.h"

#include <string.h>

#include "recording/control_keys.h"

/* ------------------------------------------------------------ primitives */

typedef struct {
    uint8_t *p;
} wcur;

typedef struct {
    const uint8_t *p;
} rcur;

static void put_u32(wcur *c, uint32_t v)
{
    c->p[0] = (uint8_t)v;
    c->p[1] = (uint8_t)(v >> 8);
    c->p[2] = (uint8_t)(v >> 16);
    c->p[3] = (uint8_t)(v >> 24);
    c->p += 4;
}

static void put_u8(wcur *c, uint8_t v) { *c->p++ = v; }

static void put_f32(wcur *c, float f)
{
    uint32_t v;
    memcpy(&v, &f, sizeof v);
    put_u32(c, v);
}

static uint32_t get_u32(rcur *c)
{
    uint32_t v = (uint32_t)c->p[0] | ((uint32_t)c->p[1] << 8) | ((uint32_t)c->p[2] << 16) | ((uint32_t)c->p[3] << 24);
    c->p += 4;
    return v;
}

static uint8_t get_u8(rcur *c) { return *c->p++; }

static float get_f32(rcur *c)
{
    uint32_t v = get_u32(c);
    float f;
    memcpy(&f, &v, sizeof f);
    return f;
}

static uint32_t f32_bits(float f)
{
    uint32_t v;
    memcpy(&v, &f, sizeof v);
    return v;
}

/* ------------------------------------------------------------ header */

void tick_rec_encode_header(const tick_rec_header *h, uint8_t *out)
{
    memset(out, 0, TICK_REC_HEADER_BYTES);
    memcpy(out, TICK_REC_MAGIC, 8u);
    wcur c = {out + 8};
    put_u32(&c, h->version);
    put_u32(&c, h->header_bytes);
    put_u32(&c, h->record_bytes);
    put_u32(&c, h->cfg_words);
    put_u32(&c, h->speed_mode);
    put_u32(&c, h->period_us);
    put_u32(&c, 0u);
    size_t n = strlen(h->name);
    memcpy(c.p, h->name, n < TICK_REC_NAME_LEN ? n : TICK_REC_NAME_LEN);
}

int tick_rec_decode_header(const uint8_t *in, tick_rec_header *h, const char **why)
{
    if (memcmp(in, TICK_REC_MAGIC, 8u) != 0) {
        *why = "not a tick record (magic)";
        return -1;
    }
    rcur c = {in + 8};
    h->version = get_u32(&c);
    h->header_bytes = get_u32(&c);
    h->record_bytes = get_u32(&c);
    h->cfg_words = get_u32(&c);
    h->speed_mode = get_u32(&c);
    h->period_us = get_u32(&c);
    (void)get_u32(&c);
    memcpy(h->name, c.p, TICK_REC_NAME_LEN);
    h->name[TICK_REC_NAME_LEN] = '\0';
    if (h->version != TICK_REC_VERSION) {
        *why = "unsupported version";
        return -1;
    }
    if (h->header_bytes != TICK_REC_HEADER_BYTES || h->record_bytes != TICK_REC_RECORD_BYTES) {
        *why = "header or record size differs from this build's";
        return -1;
    }
    if (h->cfg_words != tick_rec_cfg_words()) {
        *why = "configuration word count differs from this build's (control keys changed?)";
        return -1;
    }
    if (h->speed_mode > (uint32_t)SPEED_MODE_RBFN || h->period_us < 50u || h->period_us > 1000u) {
        *why = "speed mode or period out of range";
        return -1;
    }
    return 0;
}

/* ------------------------------------------------------------ records */

void tick_rec_encode(const tick_rec *r, uint8_t *out)
{
    wcur c = {out};
    put_u32(&c, r->tick);
    put_u32(&c, r->flags);
    put_f32(&c, r->sample.ia_A);
    put_f32(&c, r->sample.ib_A);
    put_f32(&c, r->sample.ic_A);
    put_f32(&c, r->sample.vc1_V);
    put_f32(&c, r->sample.vc2_V);
    put_f32(&c, r->sample.speed_meas_rad_s);
    put_u32(&c, r->sample.seq);
    put_f32(&c, r->speed_ref_rad_s);
    put_f32(&c, r->qs_decel_rad_s2);
    for (unsigned v = 0u; v < 2u; v++)
        for (unsigned k = 0u; k < 3u; k++)
            put_u8(&c, r->act.vector[v].leg[k]);
    put_u8(&c, r->gate_enable);
    put_u8(&c, r->state);
    put_u8(&c, r->vector_index);
    put_u8(&c, 0u);
    put_u8(&c, 0u);
    put_u8(&c, 0u);
    put_u32(&c, r->faults);
    put_f32(&c, r->act.duty0);
    put_f32(&c, r->te_ref_Nm);
    put_f32(&c, r->te_est_Nm);
    put_f32(&c, r->psi_s_est_Wb);
    put_f32(&c, r->psi_ref_Wb);
    put_f32(&c, r->omega_est_rad_s);
    put_f32(&c, r->speed_ref_out_rad_s);
    put_f32(&c, r->eps_hat);
    put_f32(&c, r->w_norm);
    put_f32(&c, r->psi_r_Wb[0]);
    put_f32(&c, r->psi_r_Wb[1]);
    put_f32(&c, r->is_hat_A[0]);
    put_f32(&c, r->is_hat_A[1]);
    put_f32(&c, r->omega_e_rad_s);
    put_f32(&c, r->omega_int_rad_s);
    put_f32(&c, r->rs_ohm);
}

void tick_rec_decode(const uint8_t *in, tick_rec *r)
{
    rcur c = {in};
    memset(r, 0, sizeof *r);
    r->tick = get_u32(&c);
    r->flags = get_u32(&c);
    r->sample.ia_A = get_f32(&c);
    r->sample.ib_A = get_f32(&c);
    r->sample.ic_A = get_f32(&c);
    r->sample.vc1_V = get_f32(&c);
    r->sample.vc2_V = get_f32(&c);
    r->sample.speed_meas_rad_s = get_f32(&c);
    r->sample.seq = get_u32(&c);
    r->sample.speed_meas_valid = (r->flags & TICK_REC_SPEED_VALID) != 0u;
    r->speed_ref_rad_s = get_f32(&c);
    r->qs_decel_rad_s2 = get_f32(&c);
    for (unsigned v = 0u; v < 2u; v++)
        for (unsigned k = 0u; k < 3u; k++)
            r->act.vector[v].leg[k] = get_u8(&c);
    r->gate_enable = get_u8(&c);
    r->state = get_u8(&c);
    r->vector_index = get_u8(&c);
    c.p += 3;
    r->faults = get_u32(&c);
    r->act.duty0 = get_f32(&c);
    r->te_ref_Nm = get_f32(&c);
    r->te_est_Nm = get_f32(&c);
    r->psi_s_est_Wb = get_f32(&c);
    r->psi_ref_Wb = get_f32(&c);
    r->omega_est_rad_s = get_f32(&c);
    r->speed_ref_out_rad_s = get_f32(&c);
    r->eps_hat = get_f32(&c);
    r->w_norm = get_f32(&c);
    r->psi_r_Wb[0] = get_f32(&c);
    r->psi_r_Wb[1] = get_f32(&c);
    r->is_hat_A[0] = get_f32(&c);
    r->is_hat_A[1] = get_f32(&c);
    r->omega_e_rad_s = get_f32(&c);
    r->omega_int_rad_s = get_f32(&c);
    r->rs_ohm = get_f32(&c);
}

void tick_rec_set_outputs(tick_rec *r, const ctl_out *out, const observer *obs)
{
    r->act = out->act;
    r->gate_enable = out->gate_enable ? 1u : 0u;
    r->state = out->tel.state;
    r->vector_index = out->tel.vector_index;
    r->faults = out->tel.faults;
    r->te_ref_Nm = out->tel.te_ref_Nm;
    r->te_est_Nm = out->tel.te_est_Nm;
    r->psi_s_est_Wb = out->tel.psi_s_est_Wb;
    r->psi_ref_Wb = out->tel.psi_ref_Wb;
    r->omega_est_rad_s = out->tel.omega_est_rad_s;
    r->speed_ref_out_rad_s = out->tel.speed_ref_rad_s;
    r->eps_hat = out->tel.eps_hat;
    r->w_norm = out->tel.w_norm;
    r->psi_r_Wb[0] = obs->psi_r_Wb[0];
    r->psi_r_Wb[1] = obs->psi_r_Wb[1];
    r->is_hat_A[0] = obs->is_A[0];
    r->is_hat_A[1] = obs->is_A[1];
    r->omega_e_rad_s = obs->omega_e_rad_s;
    r->omega_int_rad_s = obs->omega_int_rad_s;
    r->rs_ohm = obs->rs_ohm;
}

const char *tick_rec_diff(const tick_rec *got, const tick_rec *want)
{
    for (unsigned v = 0u; v < 2u; v++)
        for (unsigned k = 0u; k < 3u; k++)
            if (got->act.vector[v].leg[k] != want->act.vector[v].leg[k])
                return v == 0u ? "act.vector[0] (chosen state)" : "act.vector[1] (chosen state)";
    if (f32_bits(got->act.duty0) != f32_bits(want->act.duty0))
        return "act.duty0 (duty split)";
    if (got->gate_enable != want->gate_enable)
        return "gate_enable";
    if (got->state != want->state)
        return "run state";
    if (got->vector_index != want->vector_index)
        return "tel.vector_index";
    if (got->faults != want->faults)
        return "tel.faults";
    static const struct {
        const char *name;
        size_t off;
    } f[] = {
        {"tel.te_ref_Nm (torque reference)", offsetof(tick_rec, te_ref_Nm)},
        {"tel.te_est_Nm", offsetof(tick_rec, te_est_Nm)},
        {"tel.psi_s_est_Wb (stator flux)", offsetof(tick_rec, psi_s_est_Wb)},
        {"tel.psi_ref_Wb", offsetof(tick_rec, psi_ref_Wb)},
        {"tel.omega_est_rad_s (speed estimate)", offsetof(tick_rec, omega_est_rad_s)},
        {"tel.speed_ref_rad_s", offsetof(tick_rec, speed_ref_out_rad_s)},
        {"tel.eps_hat", offsetof(tick_rec, eps_hat)},
        {"tel.w_norm", offsetof(tick_rec, w_norm)},
        {"observer psi_r_Wb[0] (rotor flux)", offsetof(tick_rec, psi_r_Wb)},
        {"observer psi_r_Wb[1] (rotor flux)", offsetof(tick_rec, psi_r_Wb) + sizeof(float)},
        {"observer is_A[0]", offsetof(tick_rec, is_hat_A)},
        {"observer is_A[1]", offsetof(tick_rec, is_hat_A) + sizeof(float)},
        {"observer omega_e_rad_s", offsetof(tick_rec, omega_e_rad_s)},
        {"observer omega_int_rad_s", offsetof(tick_rec, omega_int_rad_s)},
        {"observer rs_ohm", offsetof(tick_rec, rs_ohm)},
    };
    for (size_t i = 0u; i < sizeof f / sizeof f[0]; i++) {
        float a, b;
        memcpy(&a, (const uint8_t *)got + f[i].off, sizeof a);
        memcpy(&b, (const uint8_t *)want + f[i].off, sizeof b);
        if (f32_bits(a) != f32_bits(b))
            return f[i].name;
    }
    return NULL;
}

/* ------------------------------------------------------------ configuration */

uint32_t tick_rec_cfg_words(void)
{
    size_t n;
    (void)control_keys(&n);
    return TICK_REC_CFG_FIXED_WORDS + (uint32_t)n;
}

/* The fields dtc-sim's configure_firmware sets besides the [control] keys. */
static float *fixed_field(ctl_cfg *cfg, unsigned i)
{
    float *const f[TICK_REC_CFG_FIXED_WORDS - 1u] = {
        &cfg->motor.Rs_ohm, &cfg->motor.Rr_ohm, &cfg->motor.Ls_H,       &cfg->motor.Lr_H,
        &cfg->motor.Lm_H,   &cfg->motor.pole_pairs, &cfg->motor.J_kgm2, &cfg->motor.B_Nms,
        &cfg->period_s,     &cfg->vdc_nom_V,
    };
    return f[i];
}

void tick_rec_cfg_encode(const ctl_cfg *cfg, uint32_t *words)
{
    ctl_cfg tmp = *cfg;
    unsigned i = 0u;
    for (; i < TICK_REC_CFG_FIXED_WORDS - 1u; i++)
        words[i] = f32_bits(*fixed_field(&tmp, i));
    words[i++] = (uint32_t)cfg->speed.mode;
    size_t n;
    const control_key *k = control_keys(&n);
    for (size_t j = 0u; j < n; j++, i++) {
        const uint8_t *p = (const uint8_t *)cfg + k[j].offset;
        if (k[j].type == CONTROL_KEY_BOOL) {
            bool b;
            memcpy(&b, p, sizeof b);
            words[i] = b ? 1u : 0u;
        } else {
            memcpy(&words[i], p, sizeof words[i]); /* float bits or u32 */
        }
    }
}

void tick_rec_cfg_apply(ctl_cfg *cfg, const uint32_t *words)
{
    unsigned i = 0u;
    for (; i < TICK_REC_CFG_FIXED_WORDS - 1u; i++)
        memcpy(fixed_field(cfg, i), &words[i], sizeof(float));
    cfg->speed.mode = (speed_mode)words[i++];
    size_t n;
    const control_key *k = control_keys(&n);
    for (size_t j = 0u; j < n; j++, i++) {
        uint8_t *p = (uint8_t *)cfg + k[j].offset;
        if (k[j].type == CONTROL_KEY_BOOL) {
            bool b = words[i] != 0u;
            memcpy(p, &b, sizeof b);
        } else {
            memcpy(p, &words[i], sizeof words[i]);
        }
    }
}
