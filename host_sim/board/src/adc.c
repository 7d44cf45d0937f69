/* ADC1/ADC2 (ADC12 pair), a first subset (RM0440, ADC chapter; register map and reset values
 * from the SVD): the power-up sequence is enforced (DEEPPWD cleared, ADVREGEN and the
 * regulator start-up time, calibration with ADEN=0 before the first enable, ADEN -> ADRDY),
 * the ADC clock (CCR.CKMODE synchronous HCLK/1,2,4 or the RCC kernel clock) must exist and stay
 * within 60 MHz, and the injected group converts JL+1 channels on a software trigger
 * (JADSTART with JEXTEN=0) taking (sampling time + 12.5) ADC clocks each, then JDR1-4, JEOC,
 * JEOS and the ADC1_2 interrupt (IRQ 18). Values come from a host callback (the plant).
 * Hardware triggers (JEXTEN != 0, e.g. from the HRTIM), the regular group, offsets,
 * oversampling, watchdogs and dual mode are refused as not modelled yet. */
#include "board_priv.h"
#include <math.h>
#include <string.h>

#define ADC_IRQ 18
#define T_VREG_S 20e-6 /* regulator start-up, datasheet t_ADCVREG_STUP */
#define CR_ADEN 1u
#define CR_ADDIS 2u
#define CR_ADSTART 4u
#define CR_JADSTART 8u
#define CR_ADVREGEN (1u << 28)
#define CR_DEEPPWD (1u << 29)
#define CR_ADCAL (1u << 31)
#define ISR_ADRDY 1u
#define ISR_JEOC 0x20u
#define ISR_JEOS 0x40u

static const double k_smp[8] = {2.5, 6.5, 12.5, 24.5, 47.5, 92.5, 247.5, 640.5};

void adc_reset(board *b) {
  memset(&b->adc, 0, sizeof b->adc);
  for (int i = 0; i < 2; i++) {
    adc_unit *a = &b->adc.u[i];
    a->cr = CR_DEEPPWD;
    a->cfgr = 0x80000000u;
    a->tr[0] = 0x0FFF0000u; a->tr[1] = a->tr[2] = 0x00FF0000u;
    a->vreg_t = a->cal_done_t = a->rdy_t = a->jdone_t = -1;
  }
}

void board_set_adc_source(board *b, board_adc_source fn, void *ctx) { b->adc.source = fn; b->adc.ctx = ctx; }

/* ADC clock, 0 when there is none. */
static double adc_clock(board *b) {
  uint32_t ck = (b->adc.ccr >> 16) & 3u;
  if (ck != 0) {
    if (ck == 1u && ((b->rcc.cfgr >> 4) & 0xFu) >= 8u) return 0; /* HCLK/1 needs AHB prescaler 1 */
    return rcc_hclk_hz(b) / (double)(ck == 1u ? 1 : ck == 2u ? 2 : 4);
  }
  uint32_t sel = (b->rcc.ccipr >> 28) & 3u; /* ADC12SEL: 01 PLLP, 10 SYSCLK */
  if (sel == 2u) return rcc_sysclk_hz(b) / (double)(((b->adc.ccr >> 18) & 0xFu) ? (1u << ((b->adc.ccr >> 18) & 0xFu)) : 1u);
  return 0; /* PLL "P" output is not modelled */
}

static void start_injected(board *b, int i) {
  adc_unit *a = &b->adc.u[i];
  double f = adc_clock(b), t = 0;
  uint32_t n = (a->jsqr & 3u) + 1u;
  for (uint32_t k = 0; k < n; k++) {
    uint32_t ch = (a->jsqr >> (9 + 6 * k)) & 0x1Fu;
    uint32_t smp = ch < 10 ? (a->smpr[0] >> (3 * ch)) & 7u : (a->smpr[1] >> (3 * (ch - 10))) & 7u;
    double res_cycles = 12.5 - 2.0 * (double)((a->cfgr >> 3) & 3u);
    t += (k_smp[smp] + res_cycles) / f;
  }
  a->jdone_t = board_now(b) + t;
}

double adc_next_event(board *b) {
  double t = INFINITY;
  for (int i = 0; i < 2; i++) {
    adc_unit *a = &b->adc.u[i];
    if (a->cal_done_t >= 0 && a->cal_done_t < t) t = a->cal_done_t;
    if (a->rdy_t >= 0 && a->rdy_t < t) t = a->rdy_t;
    if (a->jdone_t >= 0 && a->jdone_t < t) t = a->jdone_t;
  }
  return t;
}

void adc_event(board *b) {
  double now = board_now(b);
  for (int i = 0; i < 2; i++) {
    adc_unit *a = &b->adc.u[i];
    if (a->cal_done_t >= 0 && now >= a->cal_done_t) { a->cr &= ~CR_ADCAL; a->cal_done_t = -1; a->calibrated = true; }
    if (a->rdy_t >= 0 && now >= a->rdy_t) { a->isr |= ISR_ADRDY; a->rdy_t = -1; }
    if (a->jdone_t >= 0 && now >= a->jdone_t) {
      uint32_t n = (a->jsqr & 3u) + 1u;
      for (uint32_t k = 0; k < n; k++) {
        int ch = (int)((a->jsqr >> (9 + 6 * k)) & 0x1Fu);
        int code = b->adc.source ? b->adc.source(b->adc.ctx, i + 1, ch, now) : 2048;
        a->jdr[k] = code < 0 ? 0u : code > 4095 ? 4095u : (uint32_t)code;
      }
      a->isr |= ISR_JEOC | ISR_JEOS;
      a->cr &= ~CR_JADSTART;
      a->jdone_t = -1;
    }
    if ((a->isr & a->ier & (ISR_JEOC | ISR_JEOS)) && !b->scs.pending[16 + ADC_IRQ] && !b->scs.active[16 + ADC_IRQ])
      b->scs.pending[16 + ADC_IRQ] = 1;
  }
}

static void write_cr(board *b, int i, uint32_t v) {
  adc_unit *a = &b->adc.u[i];
  double now = board_now(b);
  if (v & ~0xF000003Fu) { board_fault(b, "ADC%d_CR 0x%08X writes reserved bits", i + 1, v); return; }
  if ((v & CR_ADVREGEN) && (v & CR_DEEPPWD)) {
    board_fault(b, "ADC%d_CR: ADVREGEN with DEEPPWD=1; leave deep power-down first (RM0440, ADC voltage regulator)", i + 1);
    return;
  }
  if (v & (CR_ADSTART | 0x10u)) { board_fault(b, "ADC%d: the regular group is not modelled yet", i + 1); return; }
  bool vreg_ok = (a->cr & CR_ADVREGEN) && a->vreg_t >= 0 && now - a->vreg_t >= T_VREG_S;
  if ((v & CR_ADVREGEN) && !(a->cr & CR_ADVREGEN)) a->vreg_t = now;
  if (v & CR_ADCAL) {
    if (a->cr & CR_ADEN) { board_fault(b, "ADC%d_CR.ADCAL with ADEN=1: calibrate while disabled", i + 1); return; }
    if (!vreg_ok) { board_fault(b, "ADC%d_CR.ADCAL before the regulator start-up time (%.0f us after ADVREGEN)", i + 1, T_VREG_S * 1e6); return; }
    if (adc_clock(b) == 0) { board_fault(b, "ADC%d_CR.ADCAL with no ADC clock (ADC12_CCR.CKMODE / RCC_CCIPR.ADC12SEL)", i + 1); return; }
    a->cal_done_t = now + 116.0 / adc_clock(b);
    a->cr = (a->cr & ~0x3Fu) | (v & (CR_ADVREGEN | CR_DEEPPWD | (1u << 30))) | CR_ADCAL;
    return;
  }
  if ((v & CR_ADEN) && !(a->cr & CR_ADEN)) {
    double f = adc_clock(b);
    if (!vreg_ok) { board_fault(b, "ADC%d_CR.ADEN before the regulator is ready", i + 1); return; }
    if (a->cr & CR_ADCAL) { board_fault(b, "ADC%d_CR.ADEN while the calibration runs", i + 1); return; }
    if (!a->calibrated) { board_fault(b, "ADC%d_CR.ADEN without a calibration since power-up (ADCAL)", i + 1); return; }
    if (f == 0) { board_fault(b, "ADC%d_CR.ADEN with no ADC clock", i + 1); return; }
    if (f > 60e6 + 1.0) { board_fault(b, "ADC%d clock %.3f MHz exceeds 60 MHz", i + 1, f / 1e6); return; }
    a->rdy_t = now + 1e-6;
  }
  if (v & CR_ADDIS) { a->cr &= ~CR_ADEN; a->isr &= ~ISR_ADRDY; a->rdy_t = -1; v &= ~(CR_ADDIS | CR_ADEN); }
  if (v & CR_JADSTART) {
    if (!(a->isr & ISR_ADRDY)) { board_fault(b, "ADC%d_CR.JADSTART before ADRDY", i + 1); return; }
    if (a->jsqr & 0x180u) {
      board_fault(b, "ADC%d_JSQR.JEXTEN=%u (hardware trigger, JEXTSEL=%u): not modelled yet", i + 1,
                  (a->jsqr >> 7) & 3u, (a->jsqr >> 2) & 0x1Fu);
      return;
    }
    start_injected(b, i);
  }
  a->cr = (a->cr & (CR_ADCAL | CR_JADSTART)) | (v & ~(CR_ADCAL | CR_ADDIS));
  if (a->jdone_t >= 0) a->cr |= CR_JADSTART;
}

uint32_t adc_read(board *b, uint32_t off) {
  if (off >= 0x300u) {
    switch (off - 0x300u) {
    case 0x00: return (b->adc.u[0].isr & 0x7FFu) | (b->adc.u[1].isr & 0x7FFu) << 16; /* CSR */
    case 0x08: return b->adc.ccr;
    }
    board_fault(b, "read of ADC12 common offset 0x%02X: not modelled", off - 0x300u);
    return 0;
  }
  if (off >= 0x200u) { board_fault(b, "read of ADC12 offset 0x%03X: reserved", off); return 0; }
  int i = (int)(off / 0x100u);
  adc_unit *a = &b->adc.u[i];
  uint32_t r = off % 0x100u;
  switch (r) {
  case 0x00: return a->isr;
  case 0x04: return a->ier;
  case 0x08: return a->cr;
  case 0x0C: return a->cfgr;
  case 0x10: return a->cfgr2;
  case 0x14: return a->smpr[0];
  case 0x18: return a->smpr[1];
  case 0x20: case 0x24: case 0x28: return a->tr[(r - 0x20) / 4];
  case 0x4C: return a->jsqr;
  case 0x80: case 0x84: case 0x88: case 0x8C: return a->jdr[(r - 0x80) / 4];
  case 0xB0: return a->difsel;
  case 0xB4: return a->calfact;
  }
  board_fault(b, "read of ADC%d offset 0x%02X: not modelled", i + 1, r);
  return 0;
}

void adc_write(board *b, uint32_t off, uint32_t v) {
  if (off >= 0x300u) {
    if (off - 0x300u == 0x08) {
      if ((b->adc.u[0].cr | b->adc.u[1].cr) & CR_ADEN) { board_fault(b, "ADC12_CCR written while an ADC is enabled"); return; }
      if (v & ~0x01FF0000u) { board_fault(b, "ADC12_CCR 0x%08X: dual mode and DMA are not modelled", v); return; }
      b->adc.ccr = v;
      return;
    }
    board_fault(b, "write to ADC12 common offset 0x%02X: not modelled", off - 0x300u);
    return;
  }
  if (off >= 0x200u) { board_fault(b, "write to ADC12 offset 0x%03X: reserved", off); return; }
  int i = (int)(off / 0x100u);
  adc_unit *a = &b->adc.u[i];
  uint32_t r = off % 0x100u;
  bool busy = a->cr & (CR_JADSTART | CR_ADSTART);
  switch (r) {
  case 0x00: a->isr &= ~(v & 0x7FFu); return; /* write 1 to clear */
  case 0x04: if (v & ~0x7FFu) { board_fault(b, "ADC%d_IER reserved bits", i + 1); return; } a->ier = v; return;
  case 0x08: write_cr(b, i, v); return;
  case 0x0C:
    if (busy) { board_fault(b, "ADC%d_CFGR written during a conversion", i + 1); return; }
    if (v & ~0x80000018u) { board_fault(b, "ADC%d_CFGR 0x%08X: only RES, ALIGN=0 and JQDIS are modelled", i + 1, v); return; }
    a->cfgr = v;
    return;
  case 0x10: if (v) { board_fault(b, "ADC%d_CFGR2 0x%08X: oversampling and gain compensation are not modelled", i + 1, v); return; } return;
  case 0x14: case 0x18:
    if (busy) { board_fault(b, "ADC%d_SMPR written during a conversion", i + 1); return; }
    if (v & 0xC0000000u) { board_fault(b, "ADC%d_SMPR 0x%08X writes reserved bits", i + 1, v); return; }
    a->smpr[(r - 0x14) / 4] = v;
    return;
  case 0x4C: {
    if (a->cr & CR_JADSTART) { board_fault(b, "ADC%d_JSQR written while JADSTART=1", i + 1); return; }
    for (uint32_t k = 0; k <= (v & 3u); k++)
      if (((v >> (9 + 6 * k)) & 0x1Fu) > 18u) { board_fault(b, "ADC%d_JSQR: channel %u does not exist", i + 1, (v >> (9 + 6 * k)) & 0x1Fu); return; }
    a->jsqr = v;
    return;
  }
  case 0xB0:
    if (a->cr & CR_ADEN) { board_fault(b, "ADC%d_DIFSEL written with ADEN=1", i + 1); return; }
    if (v) { board_fault(b, "ADC%d_DIFSEL: differential inputs are not modelled", i + 1); return; }
    a->difsel = v;
    return;
  }
  board_fault(b, "write 0x%08X to ADC%d offset 0x%02X: not modelled", v, i + 1, r);
}
