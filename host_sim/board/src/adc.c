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
      u->cr = ADC_CR_DEEPPWD;   /* reset values */
      u->cfgr = ADC_CFGR_JQDIS;
      u->advregen_t = u->cal_done_t = u->rdy_t = u->dis_t = -1;
      u->cal_end_t = -1;
    }
  }
  for (int k = 0; k < 3; k++) a->cur.trig_t[k] = a->cur.sample_t[k] = -1;
  a->cur.counted_trig_t = -1;
}

static double adc_clk(board *b, const adc_group *g) {
  uint32_t ck = g->ccr & ADC_CCR_CKMODE;
  double h = rcc_hclk_hz(b);
  return ck == ADC_CCR_CKMODE_HCLK ? h : ck == ADC_CCR_CKMODE_HCLK_DIV2 ? h / 2 : ck == ADC_CCR_CKMODE_HCLK_DIV4 ? h / 4 : 0;
}

static void update_irq(board *b) {
  for (int gi = 0; gi < 2; gi++)
    for (int i = 0; i < 2; i++)
      if (b->adc.g[gi].u[i].isr & b->adc.g[gi].u[i].ier & ADC_ISR_ALL) {
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
        u->cr &= ~ADC_CR_ADCAL;
        u->cal_end_t = u->cal_done_t;
        u->cal_done_t = -1;
        u->calibrated = true;
      }
      if (u->rdy_t >= 0 && now >= u->rdy_t - EPS_T) { u->isr |= ADC_ISR_ADRDY; u->ready = true; u->rdy_t = -1; update_irq(b); }
    }
}

static bool dual(const adc_group *g) { return reg_field(g->ccr, ADC_CCR_DUAL) == ADC_DUAL_INJ_SIMULT; }

/* The injected sequence's length (JL + 1) and the channel of rank r (0..3). */
static int seq_len(uint32_t jsqr) { return (int)reg_field(jsqr, ADC_JSQR_JL) + 1; }

static int rank_channel(uint32_t jsqr, int r) {
  return (int)reg_field(jsqr >> (ADC_JSQ_STRIDE * (unsigned)r), ADC_JSQR_JSQ1);
}

/* Sampling time code (SMPx) of channel ch. */
static uint32_t smp_code(const adc_unit *u, int ch) {
  return reg_field(u->smpr[ch / ADC_SMPR_CHANNELS] >> (ADC_SMPR_BITS * (unsigned)(ch % ADC_SMPR_CHANNELS)), ADC_SMPR1_SMP0);
}

static const chan_pin *find_pin(int adc, int ch) {
  for (size_t i = 0; i < sizeof k_map / sizeof k_map[0]; i++)
    if (k_map[i].adc == adc && k_map[i].ch == ch) return &k_map[i];
  return NULL;
}

static bool check_sequence(board *b, adc_group *g, int i) {
  adc_unit *u = &g->u[i];
  int len = seq_len(u->jsqr);
  for (int r = 0; r < len; r++) {
    int ch = rank_channel(u->jsqr, r);
    const chan_pin *p = find_pin(g->first + i, ch);
    if (!p) {
      board_fault(b, "ADC%d_JSQR rank %d: channel %d is not wired to an analog input of this board (docs/board.md)",
                  g->first + i, r + 1, ch);
      return false;
    }
    gpio_port *gp = &b->gpio[p->port - 'A'];
    if (((gp->moder >> (2 * p->pin)) & GPIO_MODER_MODE0) != GPIO_MODE_ANALOG) {
      board_fault(b, "ADC%d channel %d: pin P%c%d is not in analog mode (GPIO MODER)", g->first + i, ch, p->port, p->pin);
      return false;
    }
  }
  return true;
}

static double rank_time(board *b, adc_group *g, int i, int r) { /* sampling + conversion, s */
  adc_unit *u = &g->u[i];
  return (k_smp[smp_code(u, rank_channel(u->jsqr, r))] + 12.5) / adc_clk(b, g);
}

static double sample_time(board *b, adc_group *g, int i, int r) {
  adc_unit *u = &g->u[i];
  return k_smp[smp_code(u, rank_channel(u->jsqr, r))] / adc_clk(b, g);
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
  g->len = seq_len(g->u[0].jsqr);
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
    if (!(m->cr & ADC_CR_JADSTART)) continue;           /* triggers ignored */
    if (!(m->jsqr & ADC_JSQR_JEXTEN)) continue;         /* software trigger selected */
    if (hrtim_trigger_of(gi, reg_field(m->jsqr, ADC_JSQR_JEXTSEL)) != trg) continue; /* not this ADC's trigger */
    start_sequence(b, g, when);
  }
}

static uint16_t convert(board *b, adc_group *g, int i, int r, double t) {
  adc_unit *u = &g->u[i];
  int ch = rank_channel(u->jsqr, r);
  const chan_pin *p = find_pin(g->first + i, ch);
  double v = twin_pin_voltage(b, p->port, p->pin, t);
  double c = floor(v / VREF * 4096.0); /* ideal 12-bit transfer: 1 LSB = VREF / 4096 */
  if (!(c >= 0)) c = 0;
  if (c > 4095) c = 4095;
  int32_t code = (int32_t)c;
  for (int k = 0; k < 4; k++) { /* offsets, §21.4.26 */
    uint32_t o = u->ofr[k];
    if ((o & ADC_OFR_EN) && (int)reg_field(o, ADC_OFR_CH) == ch) code -= (int32_t)reg_field(o, ADC_OFR_OFFSET);
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
      double n = (ie & ADC_IER_JEOCIE) ? g->rank_end_t : (ie & ADC_IER_JEOSIE) ? g->seq_end_t : INFINITY;
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
      u->isr |= ADC_ISR_JEOC;
    }
    double t_end = g->rank_end_t;
    g->rank++;
    if (g->rank >= g->len) {
      g->busy = false;
      for (int i = 0; i < n_units(g); i++) g->u[i].isr |= ADC_ISR_JEOS;
    } else {
      schedule_rank(b, g, t_end);
    }
    update_irq(b);
  }
  a->in_advance = false;
}

/* Which group and unit an offset from ADC1's base addresses; unit 3 = the common registers. NULL after a
 * refusal (ADC4/ADC5 and reserved space are not modelled). */
#define UNIT_COMMON (int)(ADC_COMMON_OFS / ADC_UNIT_STRIDE)
_Static_assert(ADC1_BASE + ADC_COMMON_OFS == ADC12_COMMON_BASE && ADC3_BASE + ADC_COMMON_OFS == ADC345_COMMON_BASE,
               "each group's common registers in the fourth 0x100 of its block");
_Static_assert(ADC3_BASE - ADC1_BASE == APB_AHB_BLOCK, "ADC3/4/5 in the block after ADC1/2");

static adc_group *locate(board *b, uint32_t off, bool write, int *unit, uint32_t *r) {
  int gi = (int)(off / APB_AHB_BLOCK);
  uint32_t local = off % APB_AHB_BLOCK;
  *unit = (int)(local / ADC_UNIT_STRIDE);
  *r = local % ADC_UNIT_STRIDE;
  if (gi > 1) { board_fault(b, "%s of ADC offset 0x%03X: outside ADC1-5", write ? "write" : "read", off); return NULL; }
  adc_group *g = &b->adc.g[gi];
  if (*unit < UNIT_COMMON && *unit >= g->n_modelled) {
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
  if (i == UNIT_COMMON) {
    switch (r) {
    case ADC_CSR_OFS: return (g->u[0].isr & ADC_ISR_ALL) | ((g->u[1].isr & ADC_ISR_ALL) << ADC_CSR_SLV_SHIFT);
    case ADC_CCR_OFS: return g->ccr;
    }
    board_fault(b, "read of ADC%s common register offset 0x%02X: not modelled", g->first == 1 ? "12" : "345", r);
    return 0;
  }
  adc_unit *u = &g->u[i];
  switch (r) {
  case ADC_ISR_OFS: return u->isr;
  case ADC_IER_OFS: return u->ier;
  case ADC_CR_OFS: return u->cr;
  case ADC_CFGR_OFS: return u->cfgr;
  case ADC_CFGR2_OFS: return u->cfgr2;
  case ADC_SMPR1_OFS: return u->smpr[0];
  case ADC_SMPR2_OFS: return u->smpr[1];
  case ADC_JSQR_OFS: return u->jsqr;
  case ADC_OFR1_OFS: case ADC_OFR1_OFS + 4u: case ADC_OFR1_OFS + 8u: case ADC_OFR4_OFS: return u->ofr[(r - ADC_OFR1_OFS) / 4u];
  case ADC_JDR1_OFS: case ADC_JDR1_OFS + 4u: case ADC_JDR1_OFS + 8u: case ADC_JDR4_OFS: return u->jdr[(r - ADC_JDR1_OFS) / 4u];
  case ADC_DIFSEL_OFS: return u->difsel;
  case ADC_CALFACT_OFS: return u->calfact;
  }
  board_fault(b, "read of ADC%d register offset 0x%02X: not modelled", g->first + i, r);
  return 0;
}

static bool any_enabled(const adc_group *g) { return (g->u[0].cr & ADC_CR_ADEN) || (g->u[1].cr & ADC_CR_ADEN); }

static void write_cr(board *b, adc_group *g, int i, uint32_t v) {
  adc_unit *u = &g->u[i];
  const int n = g->first + i;
  double now = board_now(b);
  const uint32_t ok = ADC_CR_START_STOP | ADC_CR_ADVREGEN | ADC_CR_DEEPPWD | ADC_CR_ADCALDIF | ADC_CR_ADCAL;
  if (v & ~ok) { board_fault(b, "ADC%d_CR 0x%08X: reserved bits", n, v); return; }
  uint32_t cr = u->cr;
  bool en = cr & ADC_CR_ADEN;
  if (v & ADC_CR_ADSTART) { board_fault(b, "ADC%d_CR ADSTART: regular conversions not modelled", n); return; }
  /* rw bits, only while disabled (§21.7, ADC_CR) */
  uint32_t rw = ADC_CR_ADVREGEN | ADC_CR_DEEPPWD | ADC_CR_ADCALDIF;
  if ((v & rw) != (cr & rw)) {
    if (en || (cr & ADC_CR_ADCAL)) { board_fault(b, "ADC%d_CR: DEEPPWD/ADVREGEN/ADCALDIF changed while enabled or calibrating", n); return; }
    if ((v & ADC_CR_ADVREGEN) && (v & ADC_CR_DEEPPWD)) { board_fault(b, "ADC%d_CR: ADVREGEN set while DEEPPWD = 1 (§21.4.6)", n); return; }
    if ((v & ADC_CR_ADVREGEN) && !(cr & ADC_CR_ADVREGEN)) u->advregen_t = now;
    if (!(v & ADC_CR_ADVREGEN)) { u->advregen_t = -1; u->calibrated = false; }
    cr = (cr & ~rw) | (v & rw);
  }
  if (v & ADC_CR_ADCAL) {
    if (en) { board_fault(b, "ADC%d_CR: ADCAL set while ADEN = 1 (§21.4.8)", n); return; }
    if (u->advregen_t < 0 || now - u->advregen_t < TADCVREG_STUP - 1e-9) {
      board_fault(b, "ADC%d_CR: ADCAL %.2f us after ADVREGEN: the regulator needs tADCVREG_STUP = 20 us (§21.4.6)",
                  n, u->advregen_t < 0 ? -1.0 : (now - u->advregen_t) * 1e6);
      return;
    }
    if (!(adc_clk(b, g) > 0)) { board_fault(b, "ADC%d_CR: ADCAL with the asynchronous ADC clock (CKMODE = 0, not modelled)", n); return; }
    cr |= ADC_CR_ADCAL;
    u->cal_done_t = now + CAL_CLOCKS / adc_clk(b, g);
  }
  if ((v & ADC_CR_ADEN) && !en) {
    if (cr & ADC_CR_ADCAL) { board_fault(b, "ADC%d_CR: ADEN set during calibration (§21.4.9)", n); return; }
    if (u->cal_end_t >= 0 && now - u->cal_end_t < 4.0 / adc_clk(b, g) - 1e-12) {
      board_fault(b, "ADC%d_CR: ADEN within 4 ADC clocks of the end of the calibration (§21.4.9)", n); return;
    }
    if (!(cr & ADC_CR_ADVREGEN) || now - u->advregen_t < TADCVREG_STUP - 1e-9) { board_fault(b, "ADC%d_CR: ADEN without the regulator started (§21.4.6)", n); return; }
    if (!u->calibrated) { board_fault(b, "ADC%d_CR: ADEN before any calibration (the model asks for ADCAL first, §21.4.8)", n); return; }
    cr |= ADC_CR_ADEN;
    u->rdy_t = now + 4.0 / adc_clk(b, g);
  }
  if (v & ADC_CR_JADSTART) {
    if (!(cr & ADC_CR_ADEN) || !u->ready || (cr & ADC_CR_ADDIS)) { board_fault(b, "ADC%d_CR: JADSTART while not enabled and ready (ADEN/ADRDY, §21.4.16)", n); return; }
    if (i == 1 && dual(g)) { board_fault(b, "ADC%d_CR: JADSTART on the slave in dual mode (the master starts both, §21.4.31)", n); return; }
    if (!(u->cfgr & ADC_CFGR_JQDIS)) { board_fault(b, "ADC%d: JADSTART with the injected queue enabled (JQDIS = 0, not modelled)", n); return; }
    if (dual(g)) {
      adc_unit *s = &g->u[1];
      if (!(s->cr & ADC_CR_ADEN) || !s->ready) { board_fault(b, "ADC%d_CR: JADSTART in dual mode with ADC%d not enabled and ready", n, n + 1); return; }
      if (seq_len(s->jsqr) != seq_len(u->jsqr)) { board_fault(b, "dual injected mode: ADC%d and ADC%d JSQR lengths differ (JL)", n, n + 1); return; }
      if (s->jsqr & ADC_JSQR_JEXTEN) { board_fault(b, "dual injected mode: ADC%d has its own trigger enabled (JEXTEN must be 0 on the slave)", n + 1); return; }
    }
    uint32_t jextsel = reg_field(u->jsqr, ADC_JSQR_JEXTSEL), jexten = u->jsqr & ADC_JSQR_JEXTEN;
    if (jexten && jexten != ADC_JSQR_JEXTEN_RISING) {
      board_fault(b, "ADC%d_JSQR JEXTEN %u: only the rising edge is modelled", n, reg_field(jexten, ADC_JSQR_JEXTEN));
      return;
    }
    if (jexten && hrtim_trigger_of(g->first == 1 ? 0 : 1, jextsel) == 0) {
      board_fault(b, "ADC%d_JSQR JEXTSEL %u: not an HRTIM ADC trigger in ADC%s's injected trigger table (other sources are not modelled)",
                  n, jextsel, g->first == 1 ? "1/2" : "3/4/5");
      return;
    }
    for (int k = 0; k < n_units(g); k++) if (!check_sequence(b, g, k)) return;
    cr |= ADC_CR_JADSTART;
    u->cr = cr;
    if (!jexten) start_sequence(b, g, now);
  }
  if (v & ADC_CR_JADSTP) {
    g->busy = false;
    cr &= ~(ADC_CR_JADSTART | ADC_CR_JADSTP);
  }
  if (v & ADC_CR_ADDIS) {
    if (!(cr & ADC_CR_ADEN)) { board_fault(b, "ADC%d_CR: ADDIS while ADEN = 0 (§21.4.9)", n); return; }
    if (cr & (ADC_CR_ADSTART | ADC_CR_JADSTART)) { board_fault(b, "ADC%d_CR: ADDIS with a conversion started (JADSTART, §21.4.9)", n); return; }
    cr &= ~(ADC_CR_ADEN | ADC_CR_ADDIS);
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
  if (i == UNIT_COMMON) {
    if (r == ADC_CCR_OFS) {
      if (any_enabled(g)) { board_fault(b, "ADC%s_CCR written with an ADC of the group enabled (RM0440 §21.7, ADC_CCR)", gname); return; }
      uint32_t d = reg_field(v, ADC_CCR_DUAL);
      if (d != ADC_DUAL_INDEPENDENT && (d != ADC_DUAL_INJ_SIMULT || g->n_modelled < 2)) {
        board_fault(b, "ADC%s_CCR DUAL %u: only %s modelled", gname, d,
                    g->n_modelled < 2 ? "independent (0) is (ADC4 is not)" : "independent (0) and injected simultaneous (5) are");
        return;
      }
      if ((v & ADC_CCR_CKMODE) == ADC_CCR_CKMODE_ASYNC) { board_fault(b, "ADC%s_CCR CKMODE 0: the asynchronous clock is not modelled", gname); return; }
      if (v & ~(ADC_CCR_DUAL | ADC_CCR_CKMODE | ADC_CCR_DELAY)) { board_fault(b, "ADC%s_CCR 0x%08X: bits not modelled", gname, v); return; }
      g->ccr = v;
      return;
    }
    board_fault(b, "write to ADC%s common register offset 0x%02X: not modelled", gname, r);
    return;
  }
  adc_unit *u = &g->u[i];
  const int n = g->first + i;
  bool jstarted = (u->cr & ADC_CR_JADSTART) != 0;
  switch (r) {
  case ADC_ISR_OFS: u->isr &= ~(v & ADC_ISR_ALL); return;
  case ADC_IER_OFS:
    if (v & ~(ADC_IER_JEOCIE | ADC_IER_JEOSIE | ADC_IER_ADRDYIE)) { board_fault(b, "ADC%d_IER 0x%08X: only ADRDYIE, JEOCIE, JEOSIE modelled", n, v); return; }
    u->ier = v;
    update_irq(b);
    return;
  case ADC_CR_OFS: write_cr(b, g, i, v); return;
  case ADC_CFGR_OFS:
    if ((u->cr & ADC_CR_ADEN) && (v ^ u->cfgr)) { board_fault(b, "ADC%d_CFGR changed while ADEN = 1 is not modelled", n); return; }
    if (v & ~ADC_CFGR_JQDIS) { board_fault(b, "ADC%d_CFGR 0x%08X: only JQDIS modelled (12-bit, right aligned, no auto/discontinuous)", n, v); return; }
    u->cfgr = v;
    return;
  case ADC_CFGR2_OFS:
    if (v) { board_fault(b, "ADC%d_CFGR2 0x%08X: oversampling/gain not modelled", n, v); return; }
    return;
  case ADC_SMPR1_OFS: case ADC_SMPR2_OFS:
    if (jstarted) { board_fault(b, "ADC%d_SMPR%u changed with JADSTART = 1 (§21.4.12)", n, (r - ADC_SMPR1_OFS) / 4u + 1u); return; }
    if (r == ADC_SMPR1_OFS && (v & ADC_SMPR1_SMPPLUS)) { board_fault(b, "ADC%d_SMPR1 SMPPLUS not modelled", n); return; }
    u->smpr[(r - ADC_SMPR1_OFS) / 4u] = v;
    return;
  case ADC_JSQR_OFS:
    if (jstarted) { board_fault(b, "ADC%d_JSQR written with JADSTART = 1 and JQDIS = 1 (§21.4.21)", n); return; }
    u->jsqr = v;
    return;
  case ADC_OFR1_OFS: case ADC_OFR1_OFS + 4u: case ADC_OFR1_OFS + 8u: case ADC_OFR4_OFS:
    if (jstarted) { board_fault(b, "ADC%d_OFR%u written with a conversion started", n, (r - ADC_OFR1_OFS) / 4u + 1u); return; }
    if (v & (ADC_OFR_OFFSETPOS | ADC_OFR_SATEN)) { board_fault(b, "ADC%d_OFR: OFFSETPOS/SATEN not modelled", n); return; }
    u->ofr[(r - ADC_OFR1_OFS) / 4u] = v;
    return;
  case ADC_DIFSEL_OFS:
    if (v) { board_fault(b, "ADC%d_DIFSEL 0x%08X: differential inputs not wired on this board", n, v); return; }
    u->difsel = v;
    return;
  }
  board_fault(b, "write 0x%08X to ADC%d register offset 0x%02X: not modelled", v, n, r);
}
