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
  w->rlr = w->rlr_eff = IWDG_RLR_RL; /* reset values: all ones */
  w->winr = IWDG_WINR_WIN;
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
  case IWDG_KR_OFS: return 0;
  case IWDG_PR_OFS: return w->pr;
  case IWDG_RLR_OFS: return w->rlr;
  case IWDG_SR_OFS:
    return (w->pvu_until >= 0 ? IWDG_SR_PVU : 0u) | (w->rvu_until >= 0 ? IWDG_SR_RVU : 0u) |
           (w->wvu_until >= 0 ? IWDG_SR_WVU : 0u);
  case IWDG_WINR_OFS: return w->winr;
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
  case IWDG_KR_OFS:
    if (v & ~IWDG_KR_KEY) { board_fault(b, "IWDG_KR 0x%08X: bits 31:16 are reserved", v); return; }
    if (v == IWDG_KEY_START) {
      if (!w->started) { w->started = true; reload(b); }
      b->rcc.csr |= RCC_CSR_LSION | RCC_CSR_LSIRDY; /* starting the IWDG forces LSI on */
      w->write_access = false;
    } else if (v == IWDG_KEY_UNLOCK) {
      w->write_access = true;
    } else if (v == IWDG_KEY_REFRESH) {
      if (w->started && w->winr < IWDG_WINR_WIN && counter(b) > w->winr) {
        board_request_reset(b, RCC_CSR_IWDGRSTF | RCC_CSR_PINRSTF); /* refresh outside the window */
        return;
      }
      reload(b);
      w->write_access = false;
    } else {
      w->write_access = false;
    }
    return;
  case IWDG_PR_OFS:
    if (v & ~IWDG_PR_PR) { board_fault(b, "IWDG_PR 0x%08X: bits 31:3 are reserved", v); return; }
    if (!protected_write(b, "PR", w->pvu_until)) return;
    w->pr = v;
    w->pvu_until = now + SYNC_S;
    return;
  case IWDG_RLR_OFS:
    if (v & ~IWDG_RLR_RL) { board_fault(b, "IWDG_RLR 0x%08X: bits 31:12 are reserved", v); return; }
    if (!protected_write(b, "RLR", w->rvu_until)) return;
    w->rlr = v;
    w->rvu_until = now + SYNC_S;
    return;
  case IWDG_WINR_OFS:
    if (v & ~IWDG_WINR_WIN) { board_fault(b, "IWDG_WINR 0x%08X: bits 31:12 are reserved", v); return; }
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
    board_request_reset(b, RCC_CSR_IWDGRSTF | RCC_CSR_PINRSTF); /* NRST is pulsed too */
}
