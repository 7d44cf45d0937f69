/* Independent watchdog (RM0440, IWDG chapter): KR keys 0xCCCC start, 0x5555 register
 * access, 0xAAAA reload; PR/RLR/WINR write-protected and synchronised into the LSI domain
 * (SR.PVU/RVU/WVU busy meanwhile); a 12-bit down-counter on LSI (32 kHz) / (4 << PR);
 * reaching 0, or a reload above the window, resets the MCU with RCC_CSR.IWDGRSTF. */
#include "board_priv.h"
#include <math.h>
#include <string.h>

#define LSI_HZ 32e3
#define SYNC_S (5.0 / LSI_HZ) /* register update into the LSI domain: about five LSI cycles */

void iwdg_reset(board *b) {
  iwdg_state *w = &b->iwdg;
  memset(w, 0, sizeof *w);
  w->rlr = w->rlr_eff = 0xFFFu;
  w->winr = 0xFFFu;
  w->pvu_until = w->rvu_until = w->wvu_until = -1;
}

static double tick_s(const iwdg_state *w) { return (double)(4u << (w->pr_eff > 6 ? 6 : w->pr_eff)) / LSI_HZ; }

static uint32_t counter(board *b) {
  iwdg_state *w = &b->iwdg;
  double n = floor((board_now(b) - w->reload_t) / tick_s(w));
  return n >= (double)w->rlr_eff ? 0u : w->rlr_eff - (uint32_t)n;
}

static void reload(board *b) {
  iwdg_state *w = &b->iwdg;
  w->reload_t = board_now(b);
}

/* Latch PR/RLR once their synchronisation has finished. */
static void sync(board *b) {
  iwdg_state *w = &b->iwdg;
  double now = board_now(b);
  if (w->pvu_until >= 0 && now >= w->pvu_until) { w->pr_eff = w->pr; w->pvu_until = -1; }
  if (w->rvu_until >= 0 && now >= w->rvu_until) { w->rlr_eff = w->rlr; w->rvu_until = -1; }
  if (w->wvu_until >= 0 && now >= w->wvu_until) w->wvu_until = -1;
}

uint32_t iwdg_read(board *b, uint32_t off) {
  iwdg_state *w = &b->iwdg;
  sync(b);
  switch (off) {
  case 0x00: return 0;
  case 0x04: return w->pr;
  case 0x08: return w->rlr;
  case 0x0C: return (w->pvu_until >= 0 ? 1u : 0u) | (w->rvu_until >= 0 ? 2u : 0u) | (w->wvu_until >= 0 ? 4u : 0u);
  case 0x10: return w->winr;
  }
  board_fault(b, "read of reserved IWDG offset 0x%02X", off);
  return 0;
}

static bool protected_write(board *b, const char *name, double busy_until) {
  if (!b->iwdg.write_access) {
    board_fault(b, "IWDG_%s written without the 0x5555 key: the write is ignored by the hardware", name);
    return false;
  }
  if (busy_until >= 0) {
    board_fault(b, "IWDG_%s written while its previous update is in progress (IWDG_SR)", name);
    return false;
  }
  return true;
}

void iwdg_write(board *b, uint32_t off, uint32_t v) {
  iwdg_state *w = &b->iwdg;
  sync(b);
  double now = board_now(b);
  switch (off) {
  case 0x00:
    if (v & 0xFFFF0000u) { board_fault(b, "IWDG_KR 0x%08X: bits 31:16 are reserved", v); return; }
    if (v == 0xCCCCu) {
      if (!w->started) { w->started = true; reload(b); }
      b->rcc.csr |= 3u; /* starting the IWDG forces LSI on */
      w->write_access = false;
    } else if (v == 0x5555u) {
      w->write_access = true;
    } else if (v == 0xAAAAu) {
      if (w->started && w->winr < 0xFFFu && counter(b) > w->winr) {
        board_request_reset(b, (1u << 29) | (1u << 26)); /* refresh outside the window */
        return;
      }
      reload(b);
      w->write_access = false;
    } else {
      w->write_access = false;
    }
    return;
  case 0x04:
    if (v & ~7u) { board_fault(b, "IWDG_PR 0x%08X: bits 31:3 are reserved", v); return; }
    if (!protected_write(b, "PR", w->pvu_until)) return;
    w->pr = v;
    w->pvu_until = now + SYNC_S;
    return;
  case 0x08:
    if (v & ~0xFFFu) { board_fault(b, "IWDG_RLR 0x%08X: bits 31:12 are reserved", v); return; }
    if (!protected_write(b, "RLR", w->rvu_until)) return;
    w->rlr = v;
    w->rvu_until = now + SYNC_S;
    return;
  case 0x10:
    if (v & ~0xFFFu) { board_fault(b, "IWDG_WINR 0x%08X: bits 31:12 are reserved", v); return; }
    if (!protected_write(b, "WINR", w->wvu_until)) return;
    w->winr = v;
    w->wvu_until = now + SYNC_S;
    if (w->started) reload(b); /* writing WINR reloads the counter */
    return;
  }
  board_fault(b, "write 0x%08X to reserved IWDG offset 0x%02X", v, off);
}

double iwdg_next_event(board *b) {
  iwdg_state *w = &b->iwdg;
  double t = INFINITY;
  if (w->pvu_until >= 0) t = w->pvu_until;
  if (w->rvu_until >= 0 && w->rvu_until < t) t = w->rvu_until;
  if (w->wvu_until >= 0 && w->wvu_until < t) t = w->wvu_until;
  if (w->started) {
    double exp = w->reload_t + (double)w->rlr_eff * tick_s(w);
    if (exp < t) t = exp;
  }
  return t;
}

void iwdg_event(board *b) {
  iwdg_state *w = &b->iwdg;
  double pr_before = w->pr_eff;
  double elapsed_ticks = w->started ? (board_now(b) - w->reload_t) / tick_s(w) : 0;
  sync(b);
  /* a prescaler change takes effect mid-count: keep the remaining count */
  if (w->started && (double)w->pr_eff != pr_before) w->reload_t = board_now(b) - elapsed_ticks * tick_s(w);
  if (w->started && board_now(b) >= w->reload_t + (double)w->rlr_eff * tick_s(w) - 1e-12)
    board_request_reset(b, (1u << 29) | (1u << 26)); /* IWDGRSTF, and NRST pulsed: PINRSTF */
}
