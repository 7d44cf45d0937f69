/* The ADC1/ADC2 pair and ADC3 with their common registers (RM0440 §21, analog-to-digital
 * converters), modelled for injected conversions:
 *  - power-up: DEEPPWD cleared, ADVREGEN then at least tADCVREG_STUP (20 us, datasheet) before
 *    ADCAL; calibration takes 116 ADC clocks (ADCAL reads 1 meanwhile); ADEN not during ADCAL
 *    nor within 4 ADC clocks after it (§21.4.8, §21.4.9); ADRDY a few clocks after ADEN; ADDIS only
 *    without a conversion in progress; JADSTP;
 *  - clock: synchronous HCLK/1, /2, /4 (ADC12_CCR / ADC345_CCR .CKMODE, §21.4.3; the asynchronous
 *    clock is refused), one per group;
 *  - injected sequence JSQR: JL, JEXTSEL, JEXTEN rising edge or software start, channels JSQ1-4 with
 *    their sampling times SMPR1/2 (+ 12.5 clocks of conversion, §21.4.12); JQDIS = 1 only (no queue).
 *    JEXTSEL is read through the group's own injected trigger table (RM0440 tables "ADC1/2 - External
 *    triggers for injected channels" and "ADC3/4/5 - ..."): the HRTIM ADC triggers are 19 = trg2,
 *    20 = trg4, 21-26 = trg5-10 in both, and in ADC3/4/5's only 27 = trg1, 28 = trg3 (27 and 28 are
 *    timer events for ADC1/2). A selection that names an HRTIM trigger converts when that trigger
 *    fires, and only then (a trigger nobody routes means no conversion at all); the non-HRTIM
 *    sources are not modelled and refused at JADSTART;
 *  - dual mode ADC12_CCR.DUAL = injected simultaneous (5) or independent (0): the slave follows the
 *    master's trigger (§21.4.31); ADC345_CCR.DUAL = independent only (ADC4 is not modelled); the
 *    common registers may be written only with the group's ADCs disabled;
 *  - results JDR1-4 (12 bit, right aligned) minus the offsets OFR1-4 when enabled for the channel;
 *    JEOC/JEOS flags and the interrupts ADC1_2 (IRQ 18) and ADC3 (IRQ 47).
 * A channel must reach a pin of docs/board.md's analog table and that pin must be in analog mode:
 * other channels are refused. The value converted is the pin voltage at the end of the rank's
 * sampling window, from the plant binding (twin_pin_voltage), quantised to 12 bits, saturating.
 * The sampling instants of the three phase-current pins are recorded per trigger
 * (adc_current_instants), so a test can see whether they are converted simultaneously. */
#include "board_priv.h"
#include <math.h>
#include <string.h>

#define IRQ_ADC1_2 18
#define IRQ_ADC3 47
#define VREF 3.3
#define TADCVREG_STUP 20e-6
#define CAL_CLOCKS 116.0
#define EPS_T 1e-12

static const double k_smp[8] = {2.5, 6.5, 12.5, 24.5, 47.5, 92.5, 247.5, 640.5};

typedef struct { int adc, ch; char port; int pin; } chan_pin;
/* STM32G474 datasheet pin table (LQFP64): the ADC inputs wired on this board */
static const chan_pin k_map[] = {
  {1, 1, 'A', 0}, {1, 2, 'A', 1}, {1, 6, 'C', 0}, {1, 7, 'C', 1}, {1, 12, 'B', 1},
  {2, 1, 'A', 0}, {2, 2, 'A', 1}, {2, 6, 'C', 0}, {2, 7, 'C', 1},
  {3, 1, 'B', 1}, /* PB1 = ADC3_IN1 as well as ADC1_IN12 */
};

/* The phase-current pins whose sampling instants are recorded: ia, ib, ic. */
static const struct { char port; int pin; } k_current_pins[3] = {{'A', 0}, {'A', 1}, {'B', 1}};

/* HRTIM ADC trigger (1..10) selected by JEXTSEL in group g's injected table; 0: not an HRTIM trigger. */
static int hrtim_trigger_of(int g, uint32_t jextsel) {
  if (jextsel == 19u) return 2;
  if (jextsel == 20u) return 4;
  if (jextsel >= 21u && jextsel <= 26u) return (int)jextsel - 16;
  if (g == 1 && jextsel == 27u) return 1;
  if (g == 1 && jextsel == 28u) return 3;
  return 0;
}

void adc_reset(board *b) {
  adc_state *a = &b->adc;
  memset(a, 0, sizeof *a);
  for (int gi = 0; gi < 2; gi++) {
    adc_group *g = &a->g[gi];
    g->first = gi == 0 ? 1 : 3;
    g->n_modelled = gi == 0 ? 2 : 1;
    for (int i = 0; i < 2; i++) {
      adc_unit *u = &g->u[i];
      u->cr = 1u << 29;         /* DEEPPWD */
      u->cfgr = 1u << 31;       /* JQDIS */
      u->advregen_t = u->cal_done_t = u->rdy_t = u->dis_t = -1;
      u->cal_end_t = -1;
    }
  }
  for (int k = 0; k < 3; k++) a->cur.trig_t[k] = a->cur.sample_t[k] = -1;
  a->cur.counted_trig_t = -1;
}

static double adc_clk(board *b, const adc_group *g) {
  unsigned ck = (g->ccr >> 16) & 3u;
  double h = rcc_hclk_hz(b);
  return ck == 1 ? h : ck == 2 ? h / 2 : ck == 3 ? h / 4 : 0;
}

static void update_irq(board *b) {
  for (int gi = 0; gi < 2; gi++)
    for (int i = 0; i < 2; i++)
      if (b->adc.g[gi].u[i].isr & b->adc.g[gi].u[i].ier & 0x7FFu) {
        scs_set_pending(b, 16 + (gi == 0 ? IRQ_ADC1_2 : IRQ_ADC3));
        break;
      }
}

static void settle(board *b) { /* time-driven bits */
  double now = board_now(b);
  for (int gi = 0; gi < 2; gi++)
    for (int i = 0; i < 2; i++) {
      adc_unit *u = &b->adc.g[gi].u[i];
      if (u->cal_done_t >= 0 && now >= u->cal_done_t - EPS_T) {
        u->cr &= ~(1u << 31);
        u->cal_end_t = u->cal_done_t;
        u->cal_done_t = -1;
        u->calibrated = true;
      }
      if (u->rdy_t >= 0 && now >= u->rdy_t - EPS_T) { u->isr |= 1u; u->ready = true; u->rdy_t = -1; update_irq(b); }
    }
}

static bool dual(const adc_group *g) { return (g->ccr & 0x1Fu) == 5u; }

static const chan_pin *find_pin(int adc, int ch) {
  for (size_t i = 0; i < sizeof k_map / sizeof k_map[0]; i++)
    if (k_map[i].adc == adc && k_map[i].ch == ch) return &k_map[i];
  return NULL;
}

static bool check_sequence(board *b, adc_group *g, int i) {
  adc_unit *u = &g->u[i];
  int len = (int)(u->jsqr & 3u) + 1;
  for (int r = 0; r < len; r++) {
    int ch = (int)(u->jsqr >> (9 + 6 * r)) & 0x1F;
    const chan_pin *p = find_pin(g->first + i, ch);
    if (!p) {
      board_fault(b, "ADC%d_JSQR rank %d: channel %d is not wired to an analog input of this board (docs/board.md)",
                  g->first + i, r + 1, ch);
      return false;
    }
    gpio_port *gp = &b->gpio[p->port - 'A'];
    if (((gp->moder >> (2 * p->pin)) & 3u) != 3u) {
      board_fault(b, "ADC%d channel %d: pin P%c%d is not in analog mode (GPIO MODER)", g->first + i, ch, p->port, p->pin);
      return false;
    }
  }
  return true;
}

static double rank_time(board *b, adc_group *g, int i, int r) { /* sampling + conversion, s */
  adc_unit *u = &g->u[i];
  int ch = (int)(u->jsqr >> (9 + 6 * r)) & 0x1F;
  uint32_t smp = (u->smpr[ch / 10] >> (3 * (ch % 10))) & 7u;
  return (k_smp[smp] + 12.5) / adc_clk(b, g);
}

static double sample_time(board *b, adc_group *g, int i, int r) {
  adc_unit *u = &g->u[i];
  int ch = (int)(u->jsqr >> (9 + 6 * r)) & 0x1F;
  uint32_t smp = (u->smpr[ch / 10] >> (3 * (ch % 10))) & 7u;
  return k_smp[smp] / adc_clk(b, g);
}

static int n_units(const adc_group *g) { return dual(g) ? 2 : 1; }

static void schedule_rank(board *b, adc_group *g, double t_start) {
  double smp = 0, conv = 0;
  for (int i = 0; i < n_units(g); i++) { /* lockstep: the longer of the two */
    if (sample_time(b, g, i, g->rank) > smp) smp = sample_time(b, g, i, g->rank);
    if (rank_time(b, g, i, g->rank) > conv) conv = rank_time(b, g, i, g->rank);
  }
  g->rank_sample_t = t_start + smp;
  g->rank_end_t = t_start + conv;
}

static void start_sequence(board *b, adc_group *g, double when) {
  if (g->busy) return; /* a trigger during a conversion is ignored (§21.4.19) */
  for (int i = 0; i < n_units(g); i++)
    if (!check_sequence(b, g, i)) return;
  g->busy = true;
  g->rank = 0;
  g->len = (int)(g->u[0].jsqr & 3u) + 1;
  g->t_trig = when;
  g->rank_sample_t = -1;
  double t = when; /* sequence end, for the JEOS event */
  for (int r = 0; r < g->len; r++) {
    double conv = 0;
    for (int i = 0; i < n_units(g); i++) if (rank_time(b, g, i, r) > conv) conv = rank_time(b, g, i, r);
    t += conv;
  }
  g->seq_end_t = t;
  schedule_rank(b, g, when);
}

void adc_hrtim_trigger(board *b, int trg, double when) {
  for (int gi = 0; gi < 2; gi++) {
    adc_group *g = &b->adc.g[gi];
    adc_unit *m = &g->u[0];
    if (!(m->cr & (1u << 3))) continue;                 /* JADSTART = 0: triggers ignored */
    if (((m->jsqr >> 7) & 3u) == 0u) continue;          /* software trigger selected */
    if (hrtim_trigger_of(gi, (m->jsqr >> 2) & 0x1Fu) != trg) continue; /* not this ADC's trigger */
    start_sequence(b, g, when);
  }
}

static uint16_t convert(board *b, adc_group *g, int i, int r, double t) {
  adc_unit *u = &g->u[i];
  int ch = (int)(u->jsqr >> (9 + 6 * r)) & 0x1F;
  const chan_pin *p = find_pin(g->first + i, ch);
  double v = twin_pin_voltage(b, p->port, p->pin, t);
  double c = floor(v / VREF * 4096.0); /* ideal 12-bit transfer: 1 LSB = VREF / 4096 */
  if (!(c >= 0)) c = 0;
  if (c > 4095) c = 4095;
  int32_t code = (int32_t)c;
  for (int k = 0; k < 4; k++) { /* offsets, §21.4.26 */
    uint32_t o = u->ofr[k];
    if ((o & (1u << 31)) && (int)((o >> 26) & 0x1Fu) == ch) code -= (int32_t)(o & 0xFFFu);
  }
  /* the phase-current pins: remember when they were sampled, per trigger */
  adc_current_instants *ci = &b->adc.cur;
  for (int k = 0; k < 3; k++) {
    if (p->port != k_current_pins[k].port || p->pin != k_current_pins[k].pin) continue;
    ci->trig_t[k] = g->t_trig;
    ci->sample_t[k] = t;
    ci->after_trigger_s[k] = t - g->t_trig;
    /* every conversion of a current once all three belong to this trigger (a current converted
     * twice, by two ADCs, counts with both instants) */
    if (ci->trig_t[0] == g->t_trig && ci->trig_t[1] == g->t_trig && ci->trig_t[2] == g->t_trig) {
      double lo = fmin(fmin(ci->sample_t[0], ci->sample_t[1]), ci->sample_t[2]);
      double hi = fmax(fmax(ci->sample_t[0], ci->sample_t[1]), ci->sample_t[2]);
      if (hi - lo > ci->max_skew_s) ci->max_skew_s = hi - lo;
      if (ci->counted_trig_t != g->t_trig) ci->triples++;
      ci->counted_trig_t = g->t_trig;
    }
  }
  return (uint16_t)code;
}

void board_current_sampling_get(board *b, board_current_sampling *out) {
  adc_event(b);
  const adc_current_instants *ci = &b->adc.cur;
  out->triples = ci->triples;
  out->max_skew_s = ci->max_skew_s;
  for (int k = 0; k < 3; k++) out->after_trigger_s[k] = ci->after_trigger_s[k];
}

/* The group's next sequence event: the pending sampling instant, else the rank end; INFINITY: idle. */
static double group_next(const adc_group *g) {
  if (!g->busy) return INFINITY;
  return g->rank_sample_t >= 0 ? g->rank_sample_t : g->rank_end_t;
}

/* CPU-visible events only: calibration/ready, and the end of the rank whose flag has its interrupt
 * enabled (JEOC) or of the sequence (JEOS). Sampling instants and other rank ends need no slice
 * boundary: they are processed in order whenever a register is read (adc_read) or the plant is
 * about to be integrated past them (twin_sync -> adc_advance), which gives the same result. */
double adc_next_event(board *b) {
  double t = INFINITY;
  for (int gi = 0; gi < 2; gi++) {
    adc_group *g = &b->adc.g[gi];
    for (int i = 0; i < 2; i++) {
      if (g->u[i].cal_done_t >= 0 && g->u[i].cal_done_t < t) t = g->u[i].cal_done_t;
      if (g->u[i].rdy_t >= 0 && g->u[i].rdy_t < t) t = g->u[i].rdy_t;
    }
    if (g->busy) {
      uint32_t ie = g->u[0].ier | g->u[1].ier;
      double n = (ie & (1u << 5)) ? g->rank_end_t : (ie & (1u << 6)) ? g->seq_end_t : INFINITY;
      if (n < t) t = n;
    }
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
  while (!b->fault) {
    /* the two groups run their sequences independently: always the earliest event first */
    adc_group *g = NULL;
    for (int gi = 0; gi < 2; gi++)
      if (group_next(&a->g[gi]) < INFINITY && (!g || group_next(&a->g[gi]) < group_next(g))) g = &a->g[gi];
    if (!g || upto < group_next(g) - EPS_T) break;
    if (g->rank_sample_t >= 0) {
      double ts = g->rank_sample_t;
      twin_sync(b, ts);
      for (int i = 0; i < n_units(g); i++) g->pending_code[i] = convert(b, g, i, g->rank, ts);
      g->rank_sample_t = -1;
      continue;
    }
    for (int i = 0; i < n_units(g); i++) {
      adc_unit *u = &g->u[i];
      int16_t c = (int16_t)g->pending_code[i];
      u->jdr[g->rank] = (uint32_t)(int32_t)c; /* right aligned; a negative offset result is sign extended */
      u->isr |= 1u << 5;                      /* JEOC */
    }
    double t_end = g->rank_end_t;
    g->rank++;
    if (g->rank >= g->len) {
      g->busy = false;
      for (int i = 0; i < n_units(g); i++) g->u[i].isr |= 1u << 6; /* JEOS */
    } else {
      schedule_rank(b, g, t_end);
    }
    update_irq(b);
  }
  a->in_advance = false;
}

/* Which group and unit an offset from 0x50000000 addresses; unit 3 = the common registers. NULL after a
 * refusal (ADC4/ADC5 and reserved space are not modelled). */
static adc_group *locate(board *b, uint32_t off, bool write, int *unit, uint32_t *r) {
  int gi = (int)(off / 0x400u);
  uint32_t local = off % 0x400u;
  *unit = (int)(local / 0x100u);
  *r = local % 0x100u;
  if (gi > 1) { board_fault(b, "%s of ADC offset 0x%03X: outside ADC1-5", write ? "write" : "read", off); return NULL; }
  adc_group *g = &b->adc.g[gi];
  if (*unit < 3 && *unit >= g->n_modelled) {
    board_fault(b, "%s of ADC%d register offset 0x%02X: ADC%d is not modelled (not used on this board)",
                write ? "write" : "read", g->first + *unit, *r, g->first + *unit);
    return NULL;
  }
  return g;
}

uint32_t adc_read(board *b, uint32_t off) {
  adc_event(b);
  int i;
  uint32_t r;
  adc_group *g = locate(b, off, false, &i, &r);
  if (!g) return 0;
  if (i == 3) {
    switch (r) {
    case 0x00: return (g->u[0].isr & 0xFFFu) | ((g->u[1].isr & 0xFFFu) << 16); /* CSR */
    case 0x08: return g->ccr;
    }
    board_fault(b, "read of ADC%s common register offset 0x%02X: not modelled", g->first == 1 ? "12" : "345", r);
    return 0;
  }
  adc_unit *u = &g->u[i];
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
  board_fault(b, "read of ADC%d register offset 0x%02X: not modelled", g->first + i, r);
  return 0;
}

static bool any_enabled(const adc_group *g) { return (g->u[0].cr & 1u) || (g->u[1].cr & 1u); }

static void write_cr(board *b, adc_group *g, int i, uint32_t v) {
  adc_unit *u = &g->u[i];
  const int n = g->first + i;
  double now = board_now(b);
  const uint32_t ok = 0x3Fu | (1u << 28) | (1u << 29) | (1u << 30) | (1u << 31);
  if (v & ~ok) { board_fault(b, "ADC%d_CR 0x%08X: reserved bits", n, v); return; }
  uint32_t cr = u->cr;
  bool en = cr & 1u;
  if (v & (1u << 2)) { board_fault(b, "ADC%d_CR ADSTART: regular conversions not modelled", n); return; }
  /* rw bits: DEEPPWD, ADVREGEN, ADCALDIF; only while disabled (§21.7, ADC_CR) */
  uint32_t rw = (1u << 28) | (1u << 29) | (1u << 30);
  if ((v & rw) != (cr & rw)) {
    if (en || (cr & (1u << 31))) { board_fault(b, "ADC%d_CR: DEEPPWD/ADVREGEN/ADCALDIF changed while enabled or calibrating", n); return; }
    if ((v & (1u << 28)) && (v & (1u << 29))) { board_fault(b, "ADC%d_CR: ADVREGEN set while DEEPPWD = 1 (§21.4.6)", n); return; }
    if ((v & (1u << 28)) && !(cr & (1u << 28))) u->advregen_t = now;
    if (!(v & (1u << 28))) { u->advregen_t = -1; u->calibrated = false; }
    cr = (cr & ~rw) | (v & rw);
  }
  if (v & (1u << 31)) { /* ADCAL */
    if (en) { board_fault(b, "ADC%d_CR: ADCAL set while ADEN = 1 (§21.4.8)", n); return; }
    if (u->advregen_t < 0 || now - u->advregen_t < TADCVREG_STUP - 1e-9) {
      board_fault(b, "ADC%d_CR: ADCAL %.2f us after ADVREGEN: the regulator needs tADCVREG_STUP = 20 us (§21.4.6)",
                  n, u->advregen_t < 0 ? -1.0 : (now - u->advregen_t) * 1e6);
      return;
    }
    if (!(adc_clk(b, g) > 0)) { board_fault(b, "ADC%d_CR: ADCAL with the asynchronous ADC clock (CKMODE = 0, not modelled)", n); return; }
    cr |= 1u << 31;
    u->cal_done_t = now + CAL_CLOCKS / adc_clk(b, g);
  }
  if (v & 1u && !en) { /* ADEN */
    if (cr & (1u << 31)) { board_fault(b, "ADC%d_CR: ADEN set during calibration (§21.4.9)", n); return; }
    if (u->cal_end_t >= 0 && now - u->cal_end_t < 4.0 / adc_clk(b, g) - 1e-12) {
      board_fault(b, "ADC%d_CR: ADEN within 4 ADC clocks of the end of the calibration (§21.4.9)", n); return;
    }
    if (!(cr & (1u << 28)) || now - u->advregen_t < TADCVREG_STUP - 1e-9) { board_fault(b, "ADC%d_CR: ADEN without the regulator started (§21.4.6)", n); return; }
    if (!u->calibrated) { board_fault(b, "ADC%d_CR: ADEN before any calibration (the model asks for ADCAL first, §21.4.8)", n); return; }
    cr |= 1u;
    u->rdy_t = now + 4.0 / adc_clk(b, g);
  }
  if (v & (1u << 3)) { /* JADSTART */
    if (!(cr & 1u) || !u->ready || (cr & 2u)) { board_fault(b, "ADC%d_CR: JADSTART while not enabled and ready (ADEN/ADRDY, §21.4.16)", n); return; }
    if (i == 1 && dual(g)) { board_fault(b, "ADC%d_CR: JADSTART on the slave in dual mode (the master starts both, §21.4.31)", n); return; }
    if (!(u->cfgr & (1u << 31))) { board_fault(b, "ADC%d: JADSTART with the injected queue enabled (JQDIS = 0, not modelled)", n); return; }
    if (dual(g)) {
      adc_unit *s = &g->u[1];
      if (!(s->cr & 1u) || !s->ready) { board_fault(b, "ADC%d_CR: JADSTART in dual mode with ADC%d not enabled and ready", n, n + 1); return; }
      if ((s->jsqr & 3u) != (u->jsqr & 3u)) { board_fault(b, "dual injected mode: ADC%d and ADC%d JSQR lengths differ (JL)", n, n + 1); return; }
      if ((s->jsqr >> 7) & 3u) { board_fault(b, "dual injected mode: ADC%d has its own trigger enabled (JEXTEN must be 0 on the slave)", n + 1); return; }
    }
    uint32_t jextsel = (u->jsqr >> 2) & 0x1Fu, jexten = (u->jsqr >> 7) & 3u;
    if (jexten > 1u) { board_fault(b, "ADC%d_JSQR JEXTEN %u: only the rising edge is modelled", n, jexten); return; }
    if (jexten == 1u && hrtim_trigger_of(g->first == 1 ? 0 : 1, jextsel) == 0) {
      board_fault(b, "ADC%d_JSQR JEXTSEL %u: not an HRTIM ADC trigger in ADC%s's injected trigger table (other sources are not modelled)",
                  n, jextsel, g->first == 1 ? "1/2" : "3/4/5");
      return;
    }
    for (int k = 0; k < n_units(g); k++) if (!check_sequence(b, g, k)) return;
    cr |= 1u << 3;
    u->cr = cr;
    if (jexten == 0u) start_sequence(b, g, now);
  }
  if (v & (1u << 5)) { /* JADSTP */
    g->busy = false;
    cr &= ~((1u << 3) | (1u << 5));
  }
  if (v & 2u) { /* ADDIS */
    if (!(cr & 1u)) { board_fault(b, "ADC%d_CR: ADDIS while ADEN = 0 (§21.4.9)", n); return; }
    if (cr & ((1u << 2) | (1u << 3))) { board_fault(b, "ADC%d_CR: ADDIS with a conversion started (JADSTART, §21.4.9)", n); return; }
    cr &= ~3u;
    u->ready = false;
  }
  u->cr = cr;
}

void adc_write(board *b, uint32_t off, uint32_t v) {
  adc_event(b);
  int i;
  uint32_t r;
  adc_group *g = locate(b, off, true, &i, &r);
  if (!g) return;
  const char *gname = g->first == 1 ? "12" : "345";
  if (i == 3) {
    if (r == 0x08) {
      if (any_enabled(g)) { board_fault(b, "ADC%s_CCR written with an ADC of the group enabled (RM0440 §21.7, ADC_CCR)", gname); return; }
      uint32_t d = v & 0x1Fu, ck = (v >> 16) & 3u;
      if (d != 0u && (d != 5u || g->n_modelled < 2)) {
        board_fault(b, "ADC%s_CCR DUAL %u: only %s modelled", gname, d,
                    g->n_modelled < 2 ? "independent (0) is (ADC4 is not)" : "independent (0) and injected simultaneous (5) are");
        return;
      }
      if (ck == 0u) { board_fault(b, "ADC%s_CCR CKMODE 0: the asynchronous clock is not modelled", gname); return; }
      if (v & ~(0x1Fu | (3u << 16) | (0xFu << 8))) { board_fault(b, "ADC%s_CCR 0x%08X: bits not modelled", gname, v); return; }
      g->ccr = v;
      return;
    }
    board_fault(b, "write to ADC%s common register offset 0x%02X: not modelled", gname, r);
    return;
  }
  adc_unit *u = &g->u[i];
  const int n = g->first + i;
  bool jstarted = (u->cr & (1u << 3)) != 0;
  switch (r) {
  case 0x00: u->isr &= ~(v & 0x7FFu); return;
  case 0x04:
    if (v & ~((1u << 5) | (1u << 6) | 1u)) { board_fault(b, "ADC%d_IER 0x%08X: only ADRDYIE, JEOCIE, JEOSIE modelled", n, v); return; }
    u->ier = v;
    update_irq(b);
    return;
  case 0x08: write_cr(b, g, i, v); return;
  case 0x0C:
    if (u->cr & 1u && (v ^ u->cfgr)) { board_fault(b, "ADC%d_CFGR changed while ADEN = 1 is not modelled", n); return; }
    if (v & ~(1u << 31)) { board_fault(b, "ADC%d_CFGR 0x%08X: only JQDIS modelled (12-bit, right aligned, no auto/discontinuous)", n, v); return; }
    u->cfgr = v;
    return;
  case 0x10:
    if (v) { board_fault(b, "ADC%d_CFGR2 0x%08X: oversampling/gain not modelled", n, v); return; }
    return;
  case 0x14: case 0x18:
    if (jstarted) { board_fault(b, "ADC%d_SMPR%u changed with JADSTART = 1 (§21.4.12)", n, (r - 0x14u) / 4u + 1u); return; }
    if (r == 0x14u && (v & (1u << 31))) { board_fault(b, "ADC%d_SMPR1 SMPPLUS not modelled", n); return; }
    u->smpr[(r - 0x14u) / 4u] = v;
    return;
  case 0x4C:
    if (jstarted) { board_fault(b, "ADC%d_JSQR written with JADSTART = 1 and JQDIS = 1 (§21.4.21)", n); return; }
    u->jsqr = v;
    return;
  case 0x60: case 0x64: case 0x68: case 0x6C:
    if (jstarted) { board_fault(b, "ADC%d_OFR%u written with a conversion started", n, (r - 0x60u) / 4u + 1u); return; }
    if (v & ((1u << 24) | (1u << 25))) { board_fault(b, "ADC%d_OFR: OFFSETPOS/SATEN not modelled", n); return; }
    u->ofr[(r - 0x60u) / 4u] = v;
    return;
  case 0xB0:
    if (v) { board_fault(b, "ADC%d_DIFSEL 0x%08X: differential inputs not wired on this board", n, v); return; }
    u->difsel = v;
    return;
  }
  board_fault(b, "write 0x%08X to ADC%d register offset 0x%02X: not modelled", v, n, r);
}
