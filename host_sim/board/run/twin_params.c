/* `dtc-board run`: the scenario's [control] keys written into the flashed image's parameter store
 * before power-on, the way a user configures a board (`dtctune set` for each key, then `dtctune
 * save`). Nothing here knows the store's format: the host build of the firmware's drive, its
 * dictionary and its store (persist.c through drive_params.c) do the work over a copy of the
 * image's NVM bytes, bound as the host HAL's NVM; the result is programmed into the board's flash
 * as a debug probe would. */
#include "twin_params.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "dtc/canopen/co_od.h"
#include "dtc/drive.h"
#include "dtc/drive_co.h"
#include "dtc/param_table.h"
#include "dtc/persist.h"
#include "hal_host/hal_host.h"
#include "sim/control_keys.h"

#define SIGNATURE_SAVE 0x65766173u /* "save", CiA 301 0x1010 */

/* The stored, writable dictionary entry bound to the ctl_cfg field of control key `k`, or NULL. */
static const co_param *key_param(const sim_control_key *k) {
  for (uint32_t i = 0; i < CO_PARAM_COUNT; i++) {
    const co_param *p = &co_params[i];
    if (p->bind == DRIVE_BIND_CFG && p->offset == k->offset && (p->flags & CO_F_PERSIST) != 0u &&
        (p->flags & CO_F_WRITE) != 0u)
      return p;
  }
  return NULL;
}

/* Where a key came from, for messages: "FILE:LINE: [control] KEY" or "--set control.KEY". */
static void where(char *out, size_t n, const scenario *sc, const scenario_control *c, const char *name) {
  if (c->line == SCENARIO_LINE_SET) snprintf(out, n, "--set control.%s", name);
  else snprintf(out, n, "%s:%d: [control] %s", sc->source, c->line, name);
}

/* The key's value as the entry's internal value (the C field's kind). */
static co_num internal_of(const co_param *p, double v) {
  co_num x;
  memset(&x, 0, sizeof x);
  if (p->ckind == CO_CK_FLOAT) x.f = (float)v;
  else if (p->ckind == CO_CK_SINT) x.i = (int32_t)v;
  else x.u = (uint32_t)v;
  return x;
}

static bool same_internal(const co_param *p, co_num a, co_num b) {
  if (p->ckind == CO_CK_FLOAT) return a.f == b.f;
  if (p->ckind == CO_CK_BOOL) return (a.u != 0u) == (b.u != 0u);
  return a.u == b.u;
}

static double as_double(const co_param *p, co_num x) {
  if (p->ckind == CO_CK_FLOAT) return (double)x.f;
  if (p->ckind == CO_CK_SINT) return (double)x.i;
  return (double)x.u;
}

int twin_apply_control(board *b, const scenario *sc, char *err, size_t n) {
  if (sc->n_control == 0) return 0;
  size_t n_keys = 0;
  const sim_control_key *keys = sim_control_keys(&n_keys);
  char at[1200];
  /* every key first: a stored entry for its field, or the run is refused before anything is written */
  for (int i = 0; i < sc->n_control; i++) {
    const scenario_control *c = &sc->control[i];
    const sim_control_key *k = &keys[c->key];
    if (!key_param(k)) {
      where(at, sizeof at, sc, c, k->name);
      snprintf(err, n, "%s: the image's parameter store cannot hold it (ctl_cfg.%s is no stored, writable "
               "parameter of the dictionary, so dtctune could not set and save it)", at, k->field);
      return 2;
    }
  }
  uint32_t nvm_addr = 0, nvm_len = 0, unused = 0;
  if (board_symbol(b, "__nvm_start", &nvm_addr, &unused) != 0 || board_symbol(b, "__nvm_size", &nvm_len, &unused) != 0) {
    snprintf(err, n, "the image has no parameter store (no __nvm_start/__nvm_size symbols): [control] keys need one");
    return 1;
  }
  if (nvm_len != HAL_HOST_NVM_SIZE) {
    snprintf(err, n, "the image's parameter store is %u bytes, the host build's %u: cannot write [control] keys",
             nvm_len, HAL_HOST_NVM_SIZE);
    return 1;
  }
  static hal_host_board hb; /* the image's NVM bytes as the host HAL's NVM (no mirror file) */
  hal_host_board_init(&hb);
  if (board_read_mem(b, nvm_addr, hb.nvm, nvm_len) != 0) {
    snprintf(err, n, "cannot read the image's parameter store at 0x%08X", nvm_addr);
    return 1;
  }
  hal_host_board *prev = hal_host_bound();
  hal_host_bind(&hb);
  static drive d;
  drive_init(&d); /* what the image loads at boot: its defaults, then its stored set */
  int rc = 0;
  for (int i = 0; i < sc->n_control && rc == 0; i++) {
    const scenario_control *c = &sc->control[i];
    const sim_control_key *k = &keys[c->key];
    const co_param *p = key_param(k);
    co_num raw = co_od_to_raw(p, internal_of(p, c->value));
    uint8_t bytes[4] = {0};
    co_num_encode(p->dtype, &raw, bytes);
    uint32_t abort = co_od_write(&d.co, p, bytes, co_dtype_size(p->dtype), CO_WR_SDO);
    where(at, sizeof at, sc, c, k->name);
    if (abort != CO_ABORT_NONE) {
      snprintf(err, n, "%s = %g refused by the image's dictionary (%s 0x%04X:%u, SDO abort 0x%08X)", at, c->value,
               p->name, p->index, p->sub, abort);
      rc = 2;
      break;
    }
    co_num got = co_field_get(drive_cfg(&d), p);
    if (!same_internal(p, got, internal_of(p, c->value))) {
      snprintf(err, n, "%s = %g cannot be held exactly by the image's parameter %s (0x%04X:%u): it would store %.9g",
               at, c->value, p->name, p->index, p->sub, as_double(p, got));
      rc = 2;
    }
  }
  if (rc == 0) { /* `dtctune save`: 0x1010:1 = "save" */
    co_num sig = {.u = SIGNATURE_SAVE};
    uint8_t bytes[4];
    co_num_encode(co_params[CO_P_STORE_ALL].dtype, &sig, bytes);
    uint32_t abort = co_od_write(&d.co, &co_params[CO_P_STORE_ALL], bytes, 4, CO_WR_SDO);
    if (abort != CO_ABORT_NONE) {
      snprintf(err, n, "saving the [control] keys in the image's parameter store failed (SDO abort 0x%08X)", abort);
      rc = 1;
    }
  }
  if (rc == 0) { /* the store as the image will load it at power-on: every key back with its value */
    drive_init(&d);
    if (d.persist.status != PERSIST_LOADED) {
      snprintf(err, n, "the parameter store written for the [control] keys does not load cleanly (persist_status %u)",
               d.persist.status);
      rc = 1;
    }
    for (int i = 0; i < sc->n_control && rc == 0; i++) {
      const scenario_control *c = &sc->control[i];
      const sim_control_key *k = &keys[c->key];
      const co_param *p = key_param(k);
      co_num got = co_field_get(drive_cfg(&d), p);
      if (!same_internal(p, got, internal_of(p, c->value))) {
        where(at, sizeof at, sc, c, k->name);
        snprintf(err, n, "%s = %g is not what the image loads back from its parameter store (%.9g)", at, c->value,
                 as_double(p, got));
        rc = 2;
      }
    }
  }
  hal_host_bind(prev);
  if (rc == 0 && board_flash_program(b, nvm_addr, hb.nvm, nvm_len) != 0) {
    snprintf(err, n, "cannot program the parameter store into the board's flash at 0x%08X (+%u)", nvm_addr, nvm_len);
    rc = 1;
  }
  return rc;
}
