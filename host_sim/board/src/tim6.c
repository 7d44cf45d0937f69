/* TIM6 basic timer (RM0440, basic timers TIM6/TIM7): up-counter on the APB1 timer clock
 * through PSC, update event at ARR (UIF, interrupt 54 TIM6_DAC when UIE), PSC and (with ARPE)
 * ARR preloaded and loaded at the update event, EGR.UG re-initialises (UIF only with URS=0),
 * SR is rc_w0. The interrupt line is level-sensitive: it re-pends while UIF and UIE stay set.
 * Counted in HCLK cycles: the APB1 timer clock is HCLK when PPRE1 = /1, else 2 x PCLK1
 * (RM0440 §7.2), an integer fraction of HCLK either way. */
#include "board_priv.h"
#include <string.h>

#define TIM6_IRQ 54
#define CR1_CEN TIM6_CR1_CEN
#define CR1_UDIS TIM6_CR1_UDIS
#define CR1_URS TIM6_CR1_URS
#define CR1_OPM TIM6_CR1_OPM
#define CR1_ARPE TIM6_CR1_ARPE
#define CR1_UIFREMAP TIM6_CR1_UIFREMAP
#define CR1_DITHEN TIM6_CR1_DITHEN

void tim6_reset(board *b) {
  memset(&b->tim6, 0, sizeof b->tim6);
  b->tim6.arr = b->tim6.arr_eff = TIM6_ARR_WHOLE; /* reset value */
  b->tim6.next_update = UINT64_MAX;
}

/* HCLK cycles per timer tick at the current prescaler. */
static uint64_t hclk_per_tick(board *b) {
  uint32_t ppre1 = reg_field(b->rcc.cfgr, RCC_CFGR_PPRE1);
  uint64_t ratio = ppre1 < 4 ? 1u : (uint64_t)(1u << (ppre1 - 3)) / 2u; /* /2 -> 1, /4 -> 2, ... */
  if (ratio == 0) ratio = 1;
  return ((uint64_t)b->tim6.psc_eff + 1u) * ratio;
}

static uint32_t cnt_now(board *b) {
  tim6_state *t = &b->tim6;
  if (!(t->cr1 & CR1_CEN)) return t->cnt0;
  return t->cnt0 + (uint32_t)((b->cycles - t->base) / hclk_per_tick(b));
}

static void schedule(board *b) {
  tim6_state *t = &b->tim6;
  t->next_update = UINT64_MAX;
  if (!(t->cr1 & CR1_CEN)) return;
  uint64_t left = t->arr_eff >= t->cnt0 ? (uint64_t)(t->arr_eff - t->cnt0) + 1u : 0x10000u - t->cnt0 + t->arr_eff + 1u;
  t->next_update = t->base + left * hclk_per_tick(b);
}

static void rebase(board *b) {
  tim6_state *t = &b->tim6;
  if (t->cr1 & CR1_CEN) {
    uint64_t per = hclk_per_tick(b), ticks = (b->cycles - t->base) / per;
    t->cnt0 = (t->cnt0 + (uint32_t)ticks) & TIM6_CNT_CNT;
    t->base += ticks * per;
  } else {
    t->base = b->cycles;
  }
}

static void update_event(board *b, bool set_uif) {
  tim6_state *t = &b->tim6;
  t->cnt0 = 0;
  t->psc_eff = t->psc;
  t->arr_eff = t->arr;
  if (set_uif) t->sr |= TIM6_SR_UIF;
  if (t->cr1 & CR1_OPM) t->cr1 &= ~CR1_CEN;
}

static void irq_line(board *b) {
  tim6_state *t = &b->tim6;
  if ((t->sr & TIM6_SR_UIF) && (t->dier & TIM6_DIER_UIE) && !b->scs.active[16 + TIM6_IRQ] && !b->scs.pending[16 + TIM6_IRQ])
    scs_set_pending(b, 16 + TIM6_IRQ);
}

uint64_t tim6_next_event(board *b) { return b->tim6.next_update; }

void tim6_event(board *b) {
  tim6_state *t = &b->tim6;
  while (t->next_update <= b->cycles) {
    t->base = t->next_update;
    bool udis = t->cr1 & CR1_UDIS;
    if (!udis) update_event(b, true);
    else t->cnt0 = 0;
    schedule(b);
  }
  irq_line(b);
}

uint32_t tim6_read(board *b, uint32_t off) {
  tim6_state *t = &b->tim6;
  switch (off) {
  case TIM6_CR1_OFS: return t->cr1;
  case TIM6_CR2_OFS: return t->cr2;
  case TIM6_DIER_OFS: return t->dier;
  case TIM6_SR_OFS: return t->sr;
  case TIM6_EGR_OFS: return 0;
  case TIM6_CNT_OFS: return cnt_now(b) | ((t->cr1 & CR1_UIFREMAP) && (t->sr & TIM6_SR_UIF) ? TIM6_CNT_UIFCPY : 0u);
  case TIM6_PSC_OFS: return t->psc;
  case TIM6_ARR_OFS: return t->arr;
  }
  board_fault(b, "read of reserved TIM6 offset 0x%02X", off);
  return 0;
}

void tim6_write(board *b, uint32_t off, uint32_t v) {
  tim6_state *t = &b->tim6;
  rebase(b);
  switch (off) {
  case TIM6_CR1_OFS:
    if (v & ~(CR1_CEN | CR1_UDIS | CR1_URS | CR1_OPM | CR1_ARPE | CR1_UIFREMAP | CR1_DITHEN)) { board_fault(b, "TIM6_CR1 0x%08X writes reserved bits", v); return; }
    if (v & CR1_DITHEN) { board_fault(b, "TIM6_CR1.DITHEN: dithering is not modelled"); return; }
    t->cr1 = v;
    break;
  case TIM6_CR2_OFS:
    if (v & ~TIM6_CR2_MMS) { board_fault(b, "TIM6_CR2 0x%08X writes reserved bits", v); return; }
    t->cr2 = v;
    break;
  case TIM6_DIER_OFS:
    if (v & ~(TIM6_DIER_UIE | TIM6_DIER_UDE)) { board_fault(b, "TIM6_DIER 0x%08X writes reserved bits", v); return; }
    if (v & TIM6_DIER_UDE) { board_fault(b, "TIM6_DIER.UDE: DMA is not modelled"); return; }
    t->dier = v;
    break;
  case TIM6_SR_OFS: t->sr &= v & TIM6_SR_UIF; break; /* rc_w0 */
  case TIM6_EGR_OFS:
    if (v & ~TIM6_EGR_UG) { board_fault(b, "TIM6_EGR 0x%08X writes reserved bits", v); return; }
    if (v & TIM6_EGR_UG) update_event(b, !(t->cr1 & CR1_URS));
    t->base = b->cycles;
    break;
  case TIM6_CNT_OFS:
    if (v & ~TIM6_CNT_CNT) { board_fault(b, "TIM6_CNT 0x%08X: bits 31:16 are read-only or reserved", v); return; }
    t->cnt0 = v;
    t->base = b->cycles;
    break;
  case TIM6_PSC_OFS:
    if (v & ~TIM6_PSC_PSC) { board_fault(b, "TIM6_PSC 0x%08X writes reserved bits", v); return; }
    t->psc = v; /* preloaded: effective at the next update event */
    break;
  case TIM6_ARR_OFS:
    if (v & ~TIM6_ARR_WHOLE) { board_fault(b, "TIM6_ARR 0x%08X: bits 19:16 are only for dithering", v); return; }
    t->arr = v;
    if (!(t->cr1 & CR1_ARPE)) t->arr_eff = v;
    break;
  default: board_fault(b, "write 0x%08X to reserved TIM6 offset 0x%02X", v, off); return;
  }
  schedule(b);
  irq_line(b);
}
