/**
 * @file tick_recorder.c
 * @brief The SIL side of the recorded-tick file (tick_recorder.h).
 */
#include "tick_recorder.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

static char *dup_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    char *p = malloc(n + m + 1u);
    if (p != NULL) {
        memcpy(p, s, n);
        memcpy(p + n, suffix, m + 1u);
    }
    return p;
}

int tick_recorder_open(tick_recorder *r, const char *path, const char *scenario_name, const struct drive *d,
                       uint32_t period_us, char *err, size_t errlen)
{
    memset(r, 0, sizeof *r);
    r->path = dup_suffix(path, "");
    r->partial = dup_suffix(path, ".partial");
    if (r->path == NULL || r->partial == NULL) {
        snprintf(err, errlen, "out of memory");
        goto fail;
    }
    r->f = fopen(r->partial, "wbx"); /* x: never truncate a file this run did not create */
    if (r->f == NULL) {
        snprintf(err, errlen, "--record-samples %s: cannot create: %s", r->partial, strerror(errno));
        goto fail;
    }
    const ctl_cfg *cfg = drive_cfg(d);
    tick_rec_header h;
    memset(&h, 0, sizeof h);
    h.version = TICK_REC_VERSION;
    h.header_bytes = TICK_REC_HEADER_BYTES;
    h.record_bytes = TICK_REC_RECORD_BYTES;
    h.cfg_words = tick_rec_cfg_words();
    h.speed_mode = (uint32_t)cfg->speed.mode;
    h.period_us = period_us;
    snprintf(h.name, sizeof h.name, "%s", scenario_name);
    uint8_t hdr[TICK_REC_HEADER_BYTES];
    tick_rec_encode_header(&h, hdr);
    uint32_t *words = calloc(h.cfg_words, sizeof *words);
    if (words == NULL) {
        snprintf(err, errlen, "out of memory");
        goto fail;
    }
    tick_rec_cfg_encode(cfg, words);
    /* Little-endian words, whatever the host's order. */
    bool ok = fwrite(hdr, 1, sizeof hdr, r->f) == sizeof hdr;
    for (uint32_t i = 0; ok && i < h.cfg_words; i++) {
        uint8_t b[4] = {(uint8_t)words[i], (uint8_t)(words[i] >> 8), (uint8_t)(words[i] >> 16),
                        (uint8_t)(words[i] >> 24)};
        ok = fwrite(b, 1, 4, r->f) == 4;
    }
    free(words);
    if (!ok) {
        snprintf(err, errlen, "--record-samples %s: write failed: %s", r->partial, strerror(errno));
        goto fail;
    }
    return 0;
fail:
    if (r->f != NULL) {
        fclose(r->f);
        remove(r->partial);
    }
    free(r->path);
    free(r->partial);
    memset(r, 0, sizeof *r);
    return -1;
}

void tick_recorder_inputs(tick_recorder *r, uint64_t k, const hal_host_board *b, const struct drive *d)
{
    tick_rec *x = &r->rec;
    memset(x, 0, sizeof *x);
    x->tick = (uint32_t)k;
    uint32_t fl = 0u;
    if (b->sample_pending)
        fl |= TICK_REC_SAMPLE_NEW;
    if (b->sample.speed_meas_valid)
        fl |= TICK_REC_SPEED_VALID;
    if (b->fault_input)
        fl |= TICK_REC_FAULT_INPUT;
    if (b->tick_missed)
        fl |= TICK_REC_TICK_MISSED;
    if (d->run)
        fl |= TICK_REC_RUN;
    if (d->clear_faults_req)
        fl |= TICK_REC_CLEAR_REQ;
    if (d->quick_stop_req)
        fl |= TICK_REC_QSTOP_REQ;
    x->flags = fl;
    x->sample = b->sample;
    x->speed_ref_rad_s = d->speed_ref_rad_s;
    x->qs_decel_rad_s2 = d->qs.decel_rad_s2;
}

void tick_recorder_outputs(tick_recorder *r, const struct drive *d)
{
    if (r->f == NULL || r->failed)
        return;
    tick_rec_set_outputs(&r->rec, &d->out, &d->ctl.obs);
    uint8_t buf[TICK_REC_RECORD_BYTES];
    tick_rec_encode(&r->rec, buf);
    if (fwrite(buf, 1, sizeof buf, r->f) != sizeof buf)
        r->failed = true;
}

int tick_recorder_close(tick_recorder *r, bool keep, char *err, size_t errlen)
{
    if (r->f == NULL)
        return 0;
    bool ok = !r->failed;
    if (fclose(r->f) != 0)
        ok = false;
    r->f = NULL;
    int rc = 0;
    if (keep && !ok) {
        snprintf(err, errlen, "--record-samples %s: write failed", r->partial);
        rc = -1;
    }
    if (keep && ok && rename(r->partial, r->path) != 0) {
        snprintf(err, errlen, "--record-samples %s: cannot rename to %s: %s", r->partial, r->path, strerror(errno));
        rc = -1;
    }
    if (!keep || rc != 0)
        remove(r->partial);
    free(r->path);
    free(r->partial);
    r->path = r->partial = NULL;
    return rc;
}
