/* ADC1 and ADC2 with their common registers (RM0440 §21, analog-to-digital converters),
 * modelled for injected conversions:
 *  - power-up: DEEPPWD cleared, ADVREGEN then at least tADCVREG_STUP (20 us, datasheet) before
 *    ADCAL; calibration takes 116 ADC clocks (ADCAL reads 1 meanwhile); ADEN not during ADCAL
 *    nor within 4 ADC clocks after it (§21.4.8, §21.4.9); ADRDY a few clocks after ADEN; ADDIS only
 *    without a conversion in progress; JADSTP;
 *  - clock: synchronous HCLK/1, /2, /4 (ADC12_CCR.CKMODE, §21.4.3; the asynchronous clock is refused);
 *  - injected sequence JSQR: JL, JEXTSEL (HRTIM ADC trigger 2 only, RM0440 table "ADC1/2 external
 *    triggers for injected channels"), JEXTEN rising edge or software start, channels JSQ1-4 with their
 *    sampling times SMPR1/2 (+ 12.5 clocks of conversion, §21.4.12); JQDIS = 1 only (no queue);
 *  - dual mode ADC12_CCR.DUAL = injected simultaneous (5) or independent (0): the slave follows the
 *    master's trigger (§21.4.31); the common registers may be written only with both ADCs disabled;
 *  - results JDR1-4 (12 bit, right aligned) minus the offsets OFR1-4 when enabled for the channel;
 *    JEOC/JEOS flags and the ADC1_2 interrupt (IRQ 18).
 * A channel must reach a pin of docs/board.md's analog table and that pin must be in analog mode:
 * other channels are refused. The value converted is the pin voltage at the end of the rank's
 * sampling window, from the plant binding (twin_pin_voltage), quantised to 12 bits, saturating. */
#include "board_priv.h"
#include <math.h>
#include <string.h>

#define IRQ_ADC1_2 18
#define VREF 3.3
#define TADCVREG_STUP 20e-6
#define CAL_CLOCKS 116.0
#define EPS_T 1e-12

static const double k_smp[8] = {2.5, 6.5, 12.5, 24.5, 47.5, 92.5, 247.5, 640.5};

typedef struct { int adc, ch; char port; int pin; } chan_pin;
/* STM32G474 datasheet pin table (LQFP64): the ADC1/2 inputs wired on this board */
static const chan_pin k_map[] = {
  {1, 1, 'A', 0}, {1, 2, 'A', 1}, {1, 6, 'C', 0}, {1, 7, 'C', 1}, {1, 12, 'B', 1},
  {2, 1, 'A', 0}, {2, 2, 'A', 1}, {2, 6, 'C', 0}, {2, 7, 'C', 1},
};

void adc_reset(board *b) {
  adc_state *a = &b->adc;
  memset(a, 0, sizeof *a);
  for (int i = 0; i < 2; i++) {
    adc_unit *u = &a->u[i];
    u->cr = 1u << 29;         /* DEEPPWD */
    u->cfgr = 1u << 31;       /* JQDIS */
    u->advregen_t = u->cal_done_t = u->rdy_t = u->dis_t = -1;
    u->cal_end_t = -1;
  }
}

static double adc_clk(board *b) {
  unsigned ck = (b->adc.ccr >> 16) & 3u;
  double h = rcc_hclk_hz(b);
  return ck == 1 ? h : ck == 2 ? h / 2 : ck == 3 ? h / 4 : 0;
}

static void update_irq(board *b) {
  for (int i = 0; i < 2; i++)
    if (b->adc.u[i].isr & b->adc.u[i].ier & 0x7FFu) { scs_set_pending(b, 16 + IRQ_ADC1_2); return; }
}

static void settle(board *b) { /* time-driven bits */
  double now = board_now(b);
  for (int i = 0; i < 2; i++) {
    adc_unit *u = &b->adc.u[i];
    if (u->cal_done_t >= 0 && now >= u->cal_done_t - EPS_T) {
      u->cr &= ~(1u << 31);
      u->cal_end_t = u->cal_done_t;
      u->cal_done_t = -1;
      u->calibrated = true;
    }
    if (u->rdy_t >= 0 && now >= u->rdy_t - EPS_T) { u->isr |= 1u; u->ready = true; u->rdy_t = -1; update_irq(b); }
  }
}

static bool dual(const board *b) { return (b->adc.ccr & 0x1Fu) == 5u; }

static const chan_pin *find_pin(int adc, int ch) {
  for (size_t i = 0; i < sizeof k_map / sizeof k_map[0]; i++)
    if (k_map[i].adc == adc && k_map[i].ch == ch) return &k_map[i];
  return NULL;
}

static bool check_sequence(board *b, int i) {
  adc_unit *u = &b->adc.u[i];
  int len = (int)(u->jsqr & 3u) + 1;
  for (int r = 0; r < len; r++) {
    int ch = (int)(u->jsqr >> (9 + 6 * r)) & 0x1F;
    const chan_pin *p = find_pin(i + 1, ch);
    if (!p) {
      board_fault(b, "ADC%d_JSQR rank %d: channel %d is not wired to an analog input of this board (docs/board.md)",
                  i + 1, r + 1, ch);
      return false;
    }
    gpio_port *g = &b->gpio[p->port - 'A'];
    if (((g->moder >> (2 * p->pin)) & 3u) != 3u) {
      board_fault(b, "ADC%d channel %d: pin P%c%d is not in analog mode (GPIO MODER)", i + 1, ch, p->port, p->pin);
      return false;
    }
  }
  return true;
}

static double rank_time(board *b, int i, int r) { /* sampling + conversion, s */
  adc_unit *u = &b->adc.u[i];
  int ch = (int)(u->jsqr >> (9 + 6 * r)) & 0x1F;
  uint32_t smp = (u->smpr[ch / 10] >> (3 * (ch % 10))) & 7u;
  return (k_smp[smp] + 12.5) / adc_clk(b);
}

static double sample_time(board *b, int i, int r) {
  adc_unit *u = &b->adc.u[i];
  int ch = (int)(u->jsqr >> (9 + 6 * r)) & 0x1F;
  uint32_t smp = (u->smpr[ch / 10] >> (3 * (ch % 10))) & 7u;
  return k_smp[smp] / adc_clk(b);
}

static int n_units(board *b) { return dual(b) ? 2 : 1; }

static void schedule_rank(board *b, double t_start) {
  adc_state *a = &b->adc;
  double smp = 0, conv = 0;
  for (int i = 0; i < n_units(b); i++) { /* lockstep: the longer of the two */
    if (sample_time(b, i, a->rank) > smp) smp = sample_time(b, i, a->rank);
    if (rank_time(b, i, a->rank) > conv) conv = rank_time(b, i, a->rank);
  }
  a->rank_sample_t = t_start + smp;
  a->rank_end_t = t_start + conv;
}

static void start_sequence(board *b, double when) {
  adc_state *a = &b->adc;
  if (a->busy) return; /* a trigger during a conversion is ignored (§21.4.19) */
  for (int i = 0; i < n_units(b); i++)
    if (!check_sequence(b, i)) return;
  a->busy = true;
  a->rank = 0;
  a->len = (int)(a->u[0].jsqr & 3u) + 1;
  a->t_trig = when;
  a->rank_sample_t = -1;
  double t = when; /* sequence end, for the JEOS event */
  for (int r = 0; r < a->len; r++) {
    double conv = 0;
    for (int i = 0; i < n_units(b); i++) if (rank_time(b, i, r) > conv) conv = rank_time(b, i, r);
    t += conv;
  }
  a->seq_end_t = t;
  schedule_rank(b, when);
}

void adc_hrtim_trigger(board *b, int trg, double when) {
  adc_unit *m = &b->adc.u[0];
  if (!(m->cr & (1u << 3))) return;                 /* JADSTART = 0: triggers ignored */
  if (((m->jsqr >> 7) & 3u) == 0u) return;          /* software trigger selected */
  if (((m->jsqr >> 2) & 0x1Fu) != 19u || trg != 2) return; /* not this ADC's trigger */
  start_sequence(b, when);
}

static uint16_t convert(board *b, int i, int r, double t) {
  adc_unit *u = &b->adc.u[i];
  int ch = (int)(u->jsqr >> (9 + 6 * r)) & 0x1F;
  const chan_pin *p = find_pin(i + 1, ch);
  double v = twin_pin_voltage(b, p->port, p->pin, t);
  double c = floor(v / VREF * 4096.0); /* ideal 12-bit transfer: 1 LSB = VREF / 4096 */
  if (!(c >= 0)) c = 0;
  if (c > 4095) c = 4095;
  int32_t code = (int32_t)c;
  for (int k = 0; k < 4; k++) { /* offsets, §21.4.26 */
    uint32_t o = u->ofr[k];
    if ((o & (1u << 31)) && (int)((o >> 26) & 0x1Fu) == ch) code -= (int32_t)(o & 0xFFFu);
  }
  return (uint16_t)code;
}

/* CPU-visible events only: calibration/ready, and the end of the rank whose flag has its interrupt
 * enabled (JEOC) or of the sequence (JEOS). Sampling instants and other rank ends need no slice
 * boundary: they are processed in order whenever a register is read (adc_read) or the plant is
 * about to be integrated past them (twin_sync -> adc_advance), which gives the same result. */
double adc_next_event(board *b) {
  adc_state *a = &b->adc;
  double t = INFINITY;
  for (int i = 0; i < 2; i++) {
    if (a->u[i].cal_done_t >= 0 && a->u[i].cal_done_t < t) t = a->u[i].cal_done_t;
    if (a->u[i].rdy_t >= 0 && a->u[i].rdy_t < t) t = a->u[i].rdy_t;
  }
  if (a->busy) {
    uint32_t ie = a->u[0].ier | a->u[1].ier;
    double n = (ie & (1u << 5)) ? a->rank_end_t : (ie & (1u << 6)) ? a->seq_end_t : INFINITY;
    if (n < t) t = n;
  }
  return t;
}

void adc_event(board *b) {
  settle(b);
  adc_advance(b, board_now(b));
}

void adc_advance(board *b, double upto) {
  adc_state *a = &b->adc;
  if (a->in_advance) return;
  a->in_advance = true;
  while (a->busy && !b->fault) {
    if (a->rank_sample_t >= 0) {
      if (upto < a->rank_sample_t - EPS_T) break;
      twin_sync(b, a->rank_sample_t);
      for (int i = 0; i < n_units(b); i++) a->pending_code[i] = convert(b, i, a->rank, a->rank_sample_t);
      a->rank_sample_t = -1;
      continue;
    }
    if (upto < a->rank_end_t - EPS_T) break;
    for (int i = 0; i < n_units(b); i++) {
      adc_unit *u = &a->u[i];
      int16_t c = (int16_t)a->pending_code[i];
      u->jdr[a->rank] = (uint32_t)(int32_t)c; /* right aligned; a negative offset result is sign extended */
      u->isr |= 1u << 5;                      /* JEOC */
    }
    double t_end = a->rank_end_t;
    a->rank++;
    if (a->rank >= a->len) {
      a->busy = false;
      for (int i = 0; i < n_units(b); i++) a->u[i].isr |= 1u << 6; /* JEOS */
    } else {
      a->rank_sample_t = 0; /* placeholder, set by schedule_rank */
      schedule_rank(b, t_end);
    }
    update_irq(b);
  }
  a->in_advance = false;
}

uint32_t adc_read(board *b, uint32_t off) {
  adc_event(b);
  if (off >= 0x300u) {
    switch (off - 0x300u) {
    case 0x00: return (b->adc.u[0].isr & 0xFFFu) | ((b->adc.u[1].isr & 0xFFFu) << 16); /* CSR */
    case 0x08: return b->adc.ccr;
    }
    board_fault(b, "read of ADC12 common register offset 0x%02X: not modelled", off - 0x300u);
    return 0;
  }
  int i = (int)(off / 0x100u);
  uint32_t r = off % 0x100u;
  if (i > 1) { board_fault(b, "read of ADC12 offset 0x%03X: reserved", off); return 0; }
  adc_unit *u = &b->adc.u[i];
  switch (r) {
  case 0x00: return u->isr;
  case 0x04: return u->ier;
  case 0x08: return u->cr;
  case 0x0C: return u->cfgr;
  case 0x10: return u->cfgr2;
  case 0x14: return u->smpr[0];
  case 0x18: return u->smpr[1];
  case 0x4C: return u->jsqr;
  case 0x60: case 0x64: case 0x68: case 0x6C: return u->ofr[(r - 0x60u) / 4u];
  case 0x80: case 0x84: case 0x88: case 0x8C: return u->jdr[(r - 0x80u) / 4u];
  case 0xB0: return u->difsel;
  case 0xB4: return u->calfact;
  }
  board_fault(b, "read of ADC%d register offset 0x%02X: not modelled", i + 1, r);
  return 0;
}

static bool any_enabled(board *b) { return (b->adc.u[0].cr & 1u) || (b->adc.u[1].cr & 1u); }

static void write_cr(board *b, int i, uint32_t v) {
  adc_unit *u = &b->adc.u[i];
  double now = board_now(b);
  const uint32_t ok = 0x3Fu | (1u << 28) | (1u << 29) | (1u << 30) | (1u << 31);
  if (v & ~ok) { board_fault(b, "ADC%d_CR 0x%08X: reserved bits", i + 1, v); return; }
  uint32_t cr = u->cr;
  bool en = cr & 1u;
  if (v & (1u << 2)) { board_fault(b, "ADC%d_CR ADSTART: regular conversions not modelled", i + 1); return; }
  /* rw bits: DEEPPWD, ADVREGEN, ADCALDIF; only while disabled (§21.7, ADC_CR) */
  uint32_t rw = (1u << 28) | (1u << 29) | (1u << 30);
  if ((v & rw) != (cr & rw)) {
    if (en || (cr & (1u << 31))) { board_fault(b, "ADC%d_CR: DEEPPWD/ADVREGEN/ADCALDIF changed while enabled or calibrating", i + 1); return; }
    if ((v & (1u << 28)) && (v & (1u << 29))) { board_fault(b, "ADC%d_CR: ADVREGEN set while DEEPPWD = 1 (§21.4.6)", i + 1); return; }
    if ((v & (1u << 28)) && !(cr & (1u << 28))) u->advregen_t = now;
    if (!(v & (1u << 28))) { u->advregen_t = -1; u->calibrated = false; }
    cr = (cr & ~rw) | (v & rw);
  }
  if (v & (1u << 31)) { /* ADCAL */
    if (en) { board_fault(b, "ADC%d_CR: ADCAL set while ADEN = 1 (§21.4.8)", i + 1); return; }
    if (u->advregen_t < 0 || now - u->advregen_t < TADCVREG_STUP - 1e-9) {
      board_fault(b, "ADC%d_CR: ADCAL %.2f us after ADVREGEN: the regulator needs tADCVREG_STUP = 20 us (§21.4.6)",
                  i + 1, u->advregen_t < 0 ? -1.0 : (now - u->advregen_t) * 1e6);
      return;
    }
    if (!(adc_clk(b) > 0)) { board_fault(b, "ADC%d_CR: ADCAL with the asynchronous ADC clock (CKMODE = 0, not modelled)", i + 1); return; }
    cr |= 1u << 31;
    u->cal_done_t = now + CAL_CLOCKS / adc_clk(b);
  }
  if (v & 1u && !en) { /* ADEN */
    if (cr & (1u << 31)) { board_fault(b, "ADC%d_CR: ADEN set during calibration (§21.4.9)", i + 1); return; }
    if (u->cal_end_t >= 0 && now - u->cal_end_t < 4.0 / adc_clk(b) - 1e-12) {
      board_fault(b, "ADC%d_CR: ADEN within 4 ADC clocks of the end of the calibration (§21.4.9)", i + 1); return;
    }
    if (!(cr & (1u << 28)) || now - u->advregen_t < TADCVREG_STUP - 1e-9) { board_fault(b, "ADC%d_CR: ADEN without the regulator started (§21.4.6)", i + 1); return; }
    if (!u->calibrated) { board_fault(b, "ADC%d_CR: ADEN before any calibration (the model asks for ADCAL first, §21.4.8)", i + 1); return; }
    cr |= 1u;
    u->rdy_t = now + 4.0 / adc_clk(b);
  }
  if (v & (1u << 3)) { /* JADSTART */
    if (!(cr & 1u) || !u->ready || (cr & 2u)) { board_fault(b, "ADC%d_CR: JADSTART while not enabled and ready (ADEN/ADRDY, §21.4.16)", i + 1); return; }
    if (i == 1 && dual(b)) { board_fault(b, "ADC2_CR: JADSTART on the slave in dual mode (the master starts both, §21.4.31)"); return; }
    if (!(u->cfgr & (1u << 31))) { board_fault(b, "ADC%d: JADSTART with the injected queue enabled (JQDIS = 0, not modelled)", i + 1); return; }
    if (dual(b)) {
      adc_unit *s = &b->adc.u[1];
      if (!(s->cr & 1u) || !s->ready) { board_fault(b, "ADC1_CR: JADSTART in dual mode with ADC2 not enabled and ready"); return; }
      if ((s->jsqr & 3u) != (u->jsqr & 3u)) { board_fault(b, "dual injected mode: ADC1 and ADC2 JSQR lengths differ (JL)"); return; }
      if ((s->jsqr >> 7) & 3u) { board_fault(b, "dual injected mode: ADC2 has its own trigger enabled (JEXTEN must be 0 on the slave)"); return; }
    }
    uint32_t jextsel = (u->jsqr >> 2) & 0x1Fu, jexten = (u->jsqr >> 7) & 3u;
    if (jexten > 1u) { board_fault(b, "ADC%d_JSQR JEXTEN %u: only the rising edge is modelled", i + 1, jexten); return; }
    if (jexten == 1u && jextsel != 19u) { board_fault(b, "ADC%d_JSQR JEXTSEL %u: only HRTIM ADC trigger 2 (19) is modelled", i + 1, jextsel); return; }
    for (int k = 0; k < n_units(b); k++) if (!check_sequence(b, k)) return;
    cr |= 1u << 3;
    u->cr = cr;
    if (jexten == 0u) start_sequence(b, now);
  }
  if (v & (1u << 5)) { /* JADSTP */
    b->adc.busy = false;
    cr &= ~((1u << 3) | (1u << 5));
  }
  if (v & 2u) { /* ADDIS */
    if (!(cr & 1u)) { board_fault(b, "ADC%d_CR: ADDIS while ADEN = 0 (§21.4.9)", i + 1); return; }
    if (cr & ((1u << 2) | (1u << 3))) { board_fault(b, "ADC%d_CR: ADDIS with a conversion started (JADSTART, §21.4.9)", i + 1); return; }
    cr &= ~3u;
    u->ready = false;
  }
  u->cr = cr;
}

void adc_write(board *b, uint32_t off, uint32_t v) {
  adc_event(b);
  if (off >= 0x300u) {
    if (off - 0x300u == 0x08) {
      if (any_enabled(b)) { board_fault(b, "ADC12_CCR written with ADC1 or ADC2 enabled (RM0440 §21.7, ADC_CCR)"); return; }
      uint32_t d = v & 0x1Fu, ck = (v >> 16) & 3u;
      if (d != 0u && d != 5u) { board_fault(b, "ADC12_CCR DUAL %u: only independent (0) and injected simultaneous (5) are modelled", d); return; }
      if (ck == 0u) { board_fault(b, "ADC12_CCR CKMODE 0: the asynchronous clock is not modelled"); return; }
      if (v & ~(0x1Fu | (3u << 16) | (0xFu << 8))) { board_fault(b, "ADC12_CCR 0x%08X: bits not modelled", v); return; }
      b->adc.ccr = v;
      return;
    }
    board_fault(b, "write to ADC12 common register offset 0x%02X: not modelled", off - 0x300u);
    return;
  }
  int i = (int)(off / 0x100u);
  uint32_t r = off % 0x100u;
  if (i > 1) { board_fault(b, "write to ADC12 offset 0x%03X: reserved", off); return; }
  adc_unit *u = &b->adc.u[i];
  bool jstarted = (u->cr & (1u << 3)) != 0;
  switch (r) {
  case 0x00: u->isr &= ~(v & 0x7FFu); return;
  case 0x04:
    if (v & ~((1u << 5) | (1u << 6) | 1u)) { board_fault(b, "ADC%d_IER 0x%08X: only ADRDYIE, JEOCIE, JEOSIE modelled", i + 1, v); return; }
    u->ier = v;
    update_irq(b);
    return;
  case 0x08: write_cr(b, i, v); return;
  case 0x0C:
    if (u->cr & 1u && (v ^ u->cfgr)) { board_fault(b, "ADC%d_CFGR changed while ADEN = 1 is not modelled", i + 1); return; }
    if (v & ~(1u << 31)) { board_fault(b, "ADC%d_CFGR 0x%08X: only JQDIS modelled (12-bit, right aligned, no auto/discontinuous)", i + 1, v); return; }
    u->cfgr = v;
    return;
  case 0x10:
    if (v) { board_fault(b, "ADC%d_CFGR2 0x%08X: oversampling/gain not modelled", i + 1, v); return; }
    return;
  case 0x14: case 0x18:
    if (jstarted) { board_fault(b, "ADC%d_SMPR%u changed with JADSTART = 1 (§21.4.12)", i + 1, (r - 0x14u) / 4u + 1u); return; }
    if (r == 0x14u && (v & (1u << 31))) { board_fault(b, "ADC%d_SMPR1 SMPPLUS not modelled", i + 1); return; }
    u->smpr[(r - 0x14u) / 4u] = v;
    return;
  case 0x4C:
    if (jstarted) { board_fault(b, "ADC%d_JSQR written with JADSTART = 1 and JQDIS = 1 (§21.4.21)", i + 1); return; }
    u->jsqr = v;
    return;
  case 0x60: case 0x64: case 0x68: case 0x6C:
    if (jstarted) { board_fault(b, "ADC%d_OFR%u written with a conversion started", i + 1, (r - 0x60u) / 4u + 1u); return; }
    if (v & ((1u << 24) | (1u << 25))) { board_fault(b, "ADC%d_OFR: OFFSETPOS/SATEN not modelled", i + 1); return; }
    u->ofr[(r - 0x60u) / 4u] = v;
    return;
  case 0xB0:
    if (v) { board_fault(b, "ADC%d_DIFSEL 0x%08X: differential inputs not wired on this board", i + 1, v); return; }
    u->difsel = v;
    return;
  }
  board_fault(b, "write 0x%08X to ADC%d register offset 0x%02X: not modelled", v, i + 1, r);
}
