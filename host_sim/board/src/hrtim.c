/* HRTIM1 (RM0440 §27, high-resolution timer), modelled for the use the NPC port makes of it:
 *
 *  - master timer and timers A-F in continuous mode (§27.3.3), low resolution only
 *    (CKPSC >= 5: fCOUNTER = fHRTIM x 32 / 2^CKPSC, §27.3.2), started together by one
 *    MCR write and sharing one period (the model refuses other schemes);
 *  - period, repetition and compare 1-4 registers with preload (PREEN) and transfer at the
 *    repetition/update event (MREPU/TxREPU, REP = 0: every period), TxUDIS hold (HRTIM_CR1)
 *    and the software update TxSWU (HRTIM_CR2), §27.3.8;
 *  - output set/reset crossbar from the timer's PER and CMP1-4 events (SETxyR/RSTxyR, §27.3.5),
 *    the software set of output 1 (SETx1R.SST: immediate, not preloaded, reads 0),
 *    and external event 6 as a reset source of output 1 (RSTx1R.EXTEVNT6). The crossbar is a
 *    set/reset latch; a reset request wins over a simultaneous set (§27.3.7). EEV6 is modelled
 *    level-sensitive only (EECR2.EE6SNS = 0): while it is active the reset request is present on
 *    every fHRTIM clock, so the output stays reset through any set event, and after it the output
 *    stays reset until the next set event;
 *  - external event 6 (EECR2/EECR3, §27.3.11): source 1 = the HRTIM_EEV6 pin (PB5 in AF13; any
 *    other pin mode gives the HRTIM a low input), polarity EE6POL, the digital filter EE6F (N
 *    consecutive samples at fHRTIM or fEEVS / 2..32, fEEVS = fHRTIM / 2^EEVSD): the filtered
 *    input changes at the N-th consecutive sample of the new level (a shorter pulse is ignored),
 *    then acts after the same 3 tHRTIM of resynchronisation as FLT3. EECR1-3 may not change while
 *    the counters run; the other events, their other sources, edge sensitivity and the external
 *    event as a set source are refused (not wired / not modelled);
 *  - the dead-time unit (OUTxR.DTEN, DTxR: rising/falling dead time in tDTG = 2^DTPRSC x
 *    tHRTIM / 8, §27.3.10): output 1 = reference with its rising edge delayed by DTR,
 *    output 2 = complement with its rising edge delayed by DTF; a pulse shorter than the
 *    dead time disappears;
 *  - output stage (§27.3.15): OENR/ODISR/ODSR, polarity POLx, idle state IDLESx, fault state
 *    FAULTx; fault input FLT3 (FLTINR1 FLT3E/FLT3P/FLT3SRC/FLT3F/FLT3LCK, FLTxR.FLT3EN/FLTLCK,
 *    §27.3.16) with the ISR.FLT3 flag and the HRTIM1_FLT interrupt (IRQ 73);
 *  - master compare events as ADC trigger 2 (ADC2R, §27.3.19) and the master interrupt flags
 *    (MISR, MICR, MDIER -> IRQ 67).
 * Everything else the firmware writes is refused with a board fault naming the register.
 * The 12 output levels are exposed as a piecewise-constant waveform (hrtim_levels /
 * hrtim_next_edge) for the plant binding and the logic analyser. */
#include "board_priv.h"
#include <math.h>
#include <string.h>

#define IRQ_HRTIM_MASTER 67
#define IRQ_HRTIM_FLT 73
#define EPS_T 1e-12
#define FLT_SYNC_TICKS 3.0 /* fault input synchronisation, in tHRTIM (docs/board.md: 20-60 ns) */
#define EEV_SYNC_TICKS 3.0 /* external event resynchronisation before acting on outputs, in tHRTIM */

/* The model's window starts at the master timer: offsets of the timers' and the common block. */
#define OFS_TIMA (HRTIM_TIMA_BASE - HRTIM_MASTER_BASE)
#define OFS_TIMS_END (OFS_TIMA + HRTIM_NTIM * HRTIM_TIM_STRIDE)
#define OFS_COMMON (HRTIM_COMMON_BASE - HRTIM_MASTER_BASE)
_Static_assert(OFS_TIMS_END == HRTIM_TIMF_BASE + HRTIM_TIM_STRIDE - HRTIM_MASTER_BASE, "timers A-F");
_Static_assert(OFS_TIMS_END == OFS_COMMON, "the common registers follow timer F");

static const char *k_tname = "ABCDEF";

void hrtim_reset(board *b) {
  hrtim_state *h = &b->hrtim;
  memset(h, 0, sizeof *h);
  h->mper = h->p_mper = HRTIM_PER_MAX; /* reset values of MPER and PERxR */
  for (int t = 0; t < HRTIM_NTIM; t++) h->tim[t].per = h->tim[t].p_per = HRTIM_PER_MAX;
  h->flt3_apply_t = -1;
  h->flt3_line_low = gpio_flt3_low(b);
  h->eev6_apply_t = -1;
  h->eev6_pin_low = gpio_eev6_low(b);
  for (int t = 0; t < HRTIM_NTIM; t++) h->tim[t].last_tr[0].t = h->tim[t].last_tr[1].t = -1;
}

static double f_hrtim(board *b) { return rcc_hclk_hz(b); } /* APB2 prescaler 1: fHRTIM = PCLK2 = HCLK */
static unsigned ckpsc(uint32_t cr) { return reg_field(cr, HRTIM_MCR_CK_PSC); } /* MCR and TIMxCR alike */

/* Dead times of a timer, s: rising (DTR) and falling (DTF) edges, in tDTG = 2^DTPRSC x tHRTIM / 8. */
static void dead_times(board *b, const hrtim_timer *x, double *dtr, double *dtf) {
  double tdtg = (double)(1u << reg_field(x->dtr, HRTIM_DTxR_DTPRSC)) / (8.0 * f_hrtim(b));
  *dtr = (double)reg_field(x->dtr, HRTIM_DTxR_DTRx) * tdtg;
  *dtf = (double)reg_field(x->dtr, HRTIM_DTxR_DTFx) * tdtg;
}

/* ---- waveform queue ---- */

static void wave_cut(hrtim_wave *w, double t) { /* drop queued edges at or after t */
  while (w->n > 0 && w->e[w->n - 1].t >= t - EPS_T) w->n--;
}

static uint8_t wave_level_end(const hrtim_wave *w) { return w->n ? w->e[w->n - 1].level : w->level; }

static void wave_push(board *b, hrtim_wave *w, double t, uint8_t level) {
  if (wave_level_end(w) == level) return;
  if (w->n == HRTIM_MAX_EDGES) { board_fault(b, "HRTIM model: more than %d output edges pending", HRTIM_MAX_EDGES); return; }
  w->e[w->n].t = t;
  w->e[w->n].level = level;
  w->n++;
}

/* Reference edge of timer t's output `out` (0/1) at time when: through the dead-time unit. */
static void ref_edge(board *b, int t, int out, double when, uint8_t level) {
  hrtim_state *h = &b->hrtim;
  hrtim_timer *x = &h->tim[t];
  hrtim_wave *o1 = &h->wave[2 * t], *o2 = &h->wave[2 * t + 1];
  if (!(x->outr & HRTIM_OUTxR_DTEN)) { /* each output follows its own crossbar */
    hrtim_wave *w = out ? o2 : o1;
    wave_cut(w, when);
    wave_push(b, w, when, level);
    return;
  }
  if (out) return; /* DTEN = 1: output 2 is derived from output 1's reference (§27.3.10) */
  double dtr, dtf;
  dead_times(b, x, &dtr, &dtf);
  wave_cut(o1, when);
  wave_cut(o2, when);
  if (level) {
    wave_push(b, o2, when, 0);
    wave_push(b, o1, when + dtr, 1);
  } else {
    wave_push(b, o1, when, 0);
    wave_push(b, o2, when + dtf, 1);
  }
}

/* ---- levels seen on the pins ---- */

static uint8_t out_level(const hrtim_state *h, int o, double t) {
  const hrtim_timer *x = &h->tim[o / 2];
  uint32_t outr = (o & 1) ? x->outr >> HRTIM_OUTxR_OUT2_SHIFT : x->outr; /* output 2's fields as output 1's */
  uint8_t pol = (outr & HRTIM_OUTxR_POL1) != 0;
  uint8_t active;
  if (h->oen & (1u << o)) {
    const hrtim_wave *w = &h->wave[o];
    active = w->level;
    for (int i = 0; i < w->n && w->e[i].t <= t + EPS_T; i++) active = w->e[i].level;
  } else if (h->fault_state & (1u << o)) {
    active = (outr & HRTIM_OUTxR_FAULT1) == HRTIM_OUTxR_FAULT1_ACTIVE; /* else inactive */
  } else {
    active = (outr & HRTIM_OUTxR_IDLES1) != 0;
  }
  return active ^ pol;
}

uint32_t hrtim_levels(board *b, double t) {
  uint32_t v = 0;
  for (int o = 0; o < HRTIM_NOUT; o++) v |= (uint32_t)out_level(&b->hrtim, o, t) << o;
  return v;
}

double hrtim_next_edge(board *b, double t) {
  double n = INFINITY;
  for (int o = 0; o < HRTIM_NOUT; o++) {
    const hrtim_wave *w = &b->hrtim.wave[o];
    for (int i = 0; i < w->n; i++)
      if (w->e[i].t > t + EPS_T) { if (w->e[i].t < n) n = w->e[i].t; break; }
  }
  return n;
}

void hrtim_prune(board *b, double t) {
  for (int o = 0; o < HRTIM_NOUT; o++) {
    hrtim_wave *w = &b->hrtim.wave[o];
    int k = 0;
    while (k < w->n && w->e[k].t <= t + EPS_T) w->level = w->e[k++].level;
    if (k) { memmove(w->e, w->e + k, (size_t)(w->n - k) * sizeof w->e[0]); w->n -= k; }
  }
}

/* ---- periods ---- */

static void transfer(hrtim_state *h, int which) { /* which: -1 master, 0..5 timers */
  if (which < 0) {
    h->mper = h->p_mper; h->mrep = h->p_mrep;
    memcpy(h->mcmp, h->p_mcmp, sizeof h->mcmp);
    return;
  }
  hrtim_timer *x = &h->tim[which];
  x->per = x->p_per; x->rep = x->p_rep;
  memcpy(x->cmp, x->p_cmp, sizeof x->cmp);
  memcpy(x->set, x->p_set, sizeof x->set);
  memcpy(x->rst, x->p_rst, sizeof x->rst);
}


/* The reference transitions of timer t's output `out` over the present period: its set/reset
 * programme (plan) run through the set/reset latch together with the external event 6 reset
 * request, as known so far (active at the period start, then eev6_hist). A reset request beats a
 * set at the same instant (§27.3.7); an event-6 change at the instant of a set is taken first. */
static int ref_transitions(const hrtim_state *h, const hrtim_timer *x, int out, hrtim_edge *tr) {
  bool uses_eev = (x->rst[out] & HRTIM_RST_EXTEVNT6) != 0;
  bool eev = uses_eev && h->eev6_on_at_t0;
  uint8_t level = x->ref_start[out];
  int n = 0;
  if (eev && level) { level = 0; tr[n].t = h->t_period; tr[n].level = 0; n++; }
  int i = 0, k = 0;
  while (i < x->n_plan[out] || k < h->n_eev6_hist) {
    bool take_eev = k < h->n_eev6_hist && (i >= x->n_plan[out] || h->eev6_hist[k].t <= x->plan[out][i].t + EPS_T);
    if (take_eev) {
      double tc = h->eev6_hist[k].t;
      if (uses_eev) eev = h->eev6_hist[k].level != 0;
      k++;
      if (eev && level) { level = 0; tr[n].t = tc; tr[n].level = 0; n++; }
      continue;
    }
    const hrtim_edge *e = &x->plan[out][i++];
    if (e->level && eev) continue; /* the reset request holds the output */
    if (e->level != level) { level = e->level; tr[n].t = e->t; tr[n].level = level; n++; }
  }
  return n;
}

/* (Re)emit timer t's output `out` from time `from` on: the queued edges at or after `from` are
 * replaced by those of the reference transitions after it; the dead-time edge of the last
 * transition before `from` is kept (it may still lie ahead). */
static void emit_from(board *b, int t, int out, double from) {
  hrtim_state *h = &b->hrtim;
  hrtim_timer *x = &h->tim[t];
  bool dten = (x->outr & HRTIM_OUTxR_DTEN) != 0;
  if (dten && out) return; /* output 2 is derived from output 1's reference (§27.3.10) */
  hrtim_edge tr[8 + HRTIM_EEV_HIST + 1];
  int n = ref_transitions(h, x, out, tr);
  hrtim_edge last = x->last_tr[out];
  int i = 0;
  for (; i < n && tr[i].t < from - EPS_T; i++) last = tr[i];
  hrtim_wave *o1 = &h->wave[2 * t], *o2 = &h->wave[2 * t + 1];
  if (dten) {
    wave_cut(o1, from);
    wave_cut(o2, from);
    double dtr, dtf;
    dead_times(b, x, &dtr, &dtf);
    if (last.t >= from - EPS_T) ref_edge(b, t, out, last.t, last.level); /* the counters' start, at `from` */
    else if (last.t >= 0 && last.level && last.t + dtr >= from - EPS_T) wave_push(b, o1, last.t + dtr, 1);
    else if (last.t >= 0 && !last.level && last.t + dtf >= from - EPS_T) wave_push(b, o2, last.t + dtf, 1);
  } else {
    wave_cut(out ? o2 : o1, from);
    if (last.t >= from - EPS_T) ref_edge(b, t, out, last.t, last.level);
  }
  for (; i < n; i++) ref_edge(b, t, out, tr[i].t, tr[i].level);
  x->ref[out] = n ? tr[n - 1].level : x->ref_start[out];
}

/* Crossbar of timer t for the period starting at t0 (RM0440 §27.3.5): events PER and CMP1-4; set
 * and reset on one event is refused (the model does not arbitrate). */
static void plan_period(board *b, int t, double t0) {
  hrtim_state *h = &b->hrtim;
  hrtim_timer *x = &h->tim[t];
  for (int out = 0; out < 2; out++) {
    x->ref_start[out] = x->ref[out];
    x->n_plan[out] = 0;
    uint32_t s = x->set[out], r = x->rst[out] & ~HRTIM_RST_EXTEVNT6;
    if (s & r) {
      board_fault(b, "HRTIM_SET%c%dR/RST%c%dR 0x%08X/0x%08X: set and reset on the same event (not modelled)",
                  k_tname[t], out + 1, k_tname[t], out + 1, s, r);
      return;
    }
    struct { uint32_t c; uint32_t bit; } ev[5];
    int m = 0;
    for (int k = 0; k < 4; k++)
      if ((s | r) & (HRTIM_SET_CMP1 << k)) { ev[m].c = x->cmp[k]; ev[m].bit = HRTIM_SET_CMP1 << k; m++; }
    if ((s | r) & HRTIM_SET_PER) { ev[m].c = x->per; ev[m].bit = HRTIM_SET_PER; m++; }
    for (int i = 1; i < m; i++) /* insertion sort by count */
      for (int j = i; j > 0 && ev[j].c < ev[j - 1].c; j--) { __typeof__(ev[0]) tmp = ev[j]; ev[j] = ev[j - 1]; ev[j - 1] = tmp; }
    for (int i = 0; i < m; i++) {
      if (ev[i].c > x->per) continue; /* a compare beyond the period never matches */
      x->plan[out][x->n_plan[out]].t = t0 + (double)ev[i].c * h->t_count;
      x->plan[out][x->n_plan[out]].level = (s & ev[i].bit) ? 1u : 0u;
      x->n_plan[out]++;
    }
  }
}

static void period_start(board *b, double t0) {
  hrtim_state *h = &b->hrtim;
  twin_sync(b, t0); /* the plant runs up to the period boundary on the old programme */
  for (int t = 0; t < HRTIM_NTIM; t++) /* the last reference transition of the period that ends: history */
    for (int out = 0; out < 2; out++) {
      hrtim_edge tr[8 + HRTIM_EEV_HIST + 1];
      int n = ref_transitions(h, &h->tim[t], out, tr);
      if (n) h->tim[t].last_tr[out] = tr[n - 1];
    }
  h->t_period = t0;
  h->periods++;
  /* repetition event with REP = 0 each period: update (transfer) unless held by TxUDIS */
  if ((h->mcr & HRTIM_MCR_PREEN) && (h->mcr & HRTIM_MCR_MREPU) && !(h->cr1 & HRTIM_CR1_MUDIS)) transfer(h, -1);
  h->misr |= HRTIM_MISR_MREP | HRTIM_MISR_MUPD;
  for (int t = 0; t < HRTIM_NTIM; t++) {
    hrtim_timer *x = &h->tim[t];
    if ((x->cr & HRTIM_TIMxCR_PREEN) && (x->cr & HRTIM_TIMxCR_TxREPU) && !(h->cr1 & (HRTIM_CR1_TAUDIS << t))) transfer(h, t);
    if (x->per != h->mper)
      board_fault(b, "HRTIM timer %c period %u differs from the master's %u: the model runs all timers on the "
                  "master's period (the port's scheme)", k_tname[t], x->per, h->mper);
    plan_period(b, t, t0);
  }
  h->eev6_on_at_t0 = h->eev6_on; /* the new period's event-6 history starts here */
  h->n_eev6_hist = 0;
  for (int t = 0; t < HRTIM_NTIM; t++)
    for (int out = 0; out < 2; out++) emit_from(b, t, out, t0);
  if (h->mper < HRTIM_PER_MIN) board_fault(b, "HRTIM_MPER %u: below the minimum period of 3 (RM0440 §27.5)", h->mper);
  h->next_period_t = t0 + (double)h->mper * h->t_count;
  for (int k = 0; k < 4; k++) {
    h->mcmp_done[k] = h->mcmp[k] == 0 || h->mcmp[k] > h->mper;
    h->next_mcmp_t[k] = t0 + (double)h->mcmp[k] * h->t_count;
  }
}

static void pend_master(board *b) {
  if (b->hrtim.misr & b->hrtim.mdier & HRTIM_MISR_ALL) scs_set_pending(b, 16 + IRQ_HRTIM_MASTER);
}

static void master_compare(board *b, int k, double when) {
  hrtim_state *h = &b->hrtim;
  h->mcmp_done[k] = true;
  h->misr |= HRTIM_MISR_MCMP1 << k;
  pend_master(b);
  /* ADC triggers 1-4: master compare k -> ADCxR.ADxMCk, §27.3.19 */
  for (int a = 0; a < 4; a++)
    if (h->adcr[a] & (HRTIM_ADCxR_MC1 << k)) adc_hrtim_trigger(b, a + 1, when);
}

double hrtim_next_event(board *b) {
  hrtim_state *h = &b->hrtim;
  double t = h->flt3_apply_t >= 0 ? h->flt3_apply_t : INFINITY;
  if (h->eev6_apply_t >= 0 && h->eev6_apply_t < t) t = h->eev6_apply_t;
  if (!h->running) return t;
  if (h->next_period_t < t) t = h->next_period_t;
  for (int k = 0; k < 4; k++)
    if (!h->mcmp_done[k] && h->next_mcmp_t[k] < t) t = h->next_mcmp_t[k];
  return t;
}

static void apply_fault(board *b);
static void apply_eev6(board *b);

void hrtim_event(board *b) {
  hrtim_state *h = &b->hrtim;
  double now = board_now(b);
  if (h->flt3_apply_t >= 0 && now >= h->flt3_apply_t - EPS_T) { h->flt3_apply_t = -1; apply_fault(b); }
  if (h->eev6_apply_t >= 0 && now >= h->eev6_apply_t - EPS_T) { h->eev6_apply_t = -1; apply_eev6(b); }
  while (h->running && !b->fault) {
    double tn = INFINITY;
    int which = -1;
    for (int k = 0; k < 4; k++)
      if (!h->mcmp_done[k] && h->next_mcmp_t[k] < tn) { tn = h->next_mcmp_t[k]; which = k; }
    if (h->next_period_t <= tn) { tn = h->next_period_t; which = 4; }
    if (tn > now + EPS_T) break;
    if (which == 4) period_start(b, tn);
    else master_compare(b, which, tn);
  }
}

/* ---- fault input FLT3 (§27.3.16) ---- */

static bool flt3_active(const hrtim_state *h) {
  if (!(h->fltinr1 & HRTIM_FLTINR1_FLT3E)) return false;
  bool pol_high = (h->fltinr1 & HRTIM_FLTINR1_FLT3P) != 0; /* 0: active low */
  return pol_high ? !h->flt3_line_low : h->flt3_line_low;
}

static void apply_fault(board *b) {
  hrtim_state *h = &b->hrtim;
  if (!flt3_active(h)) return;
  twin_sync(b, board_now(b));
  h->isr |= HRTIM_ISR_FLT3;
  if (h->ier & HRTIM_IER_FLT3IE) scs_set_pending(b, 16 + IRQ_HRTIM_FLT);
  for (int t = 0; t < HRTIM_NTIM; t++) {
    if (!(h->tim[t].fltr & HRTIM_FLTxR_FLT3EN)) continue;
    for (int k = 0; k < 2; k++) {
      int o = 2 * t + k;
      uint32_t outr = k ? h->tim[t].outr >> HRTIM_OUTxR_OUT2_SHIFT : h->tim[t].outr;
      if ((outr & HRTIM_OUTxR_FAULT1) == HRTIM_OUTxR_FAULT1_NONE) continue; /* the output keeps its waveform */
      h->fault_state |= 1u << o;
      h->oen &= ~(1u << o);
    }
  }
}

/* The FLT3 pin (PB10, AF13) changed or its mux did: seen after the input synchronisation. */
void hrtim_fault_input_update(board *b, bool line_low) {
  hrtim_state *h = &b->hrtim;
  if (line_low == h->flt3_line_low) return;
  h->flt3_line_low = line_low;
  if (flt3_active(h)) {
    double f = f_hrtim(b) > 0 ? f_hrtim(b) : 16e6;
    h->flt3_apply_t = board_now(b) + FLT_SYNC_TICKS / f;
  }
}

/* SETx1R.SST: a set of output 1's latch at this instant, added to the period's programme. */
static void software_set(board *b, int t) {
  hrtim_state *h = &b->hrtim;
  hrtim_timer *x = &h->tim[t];
  double now = board_now(b);
  twin_sync(b, now);
  if (!h->running) { /* no period programme: the latch (and the outputs' dead-time unit) directly */
    if (!x->ref[0]) { x->ref[0] = 1; ref_edge(b, t, 0, now, 1); x->last_tr[0].t = now; x->last_tr[0].level = 1; }
    return;
  }
  if (x->n_plan[0] == 8) { board_fault(b, "HRTIM model: more than 3 software sets of timer %c in one period", k_tname[t]); return; }
  int i = x->n_plan[0];
  while (i > 0 && x->plan[0][i - 1].t > now + EPS_T) { x->plan[0][i] = x->plan[0][i - 1]; i--; }
  x->plan[0][i].t = now;
  x->plan[0][i].level = 1;
  x->n_plan[0]++;
  emit_from(b, t, 0, now);
}

/* ---- external event 6: the fault line's second input (§27.3.11) ---- */

/* fSAMPLING period (s) and length N of the EExF digital filter code f; f = 0: no filter. */
static void eev_filter(board *b, uint32_t f, uint32_t eevsd, double *ts, int *n) {
  static const int k_div[16] = {0, 1, 1, 1, 2, 2, 4, 4, 8, 8, 16, 16, 16, 32, 32, 32};
  static const int k_n[16] = {0, 2, 4, 8, 6, 8, 6, 8, 6, 8, 5, 6, 8, 5, 6, 8};
  double fh = f_hrtim(b) > 0 ? f_hrtim(b) : 16e6;
  double feevs = fh / (double)(1u << eevsd);
  *n = k_n[f & 15u];
  *ts = f == 0 ? 0 : f <= 3u ? 1.0 / fh : (double)k_div[f] / feevs; /* codes 1-3 sample at fHRTIM */
}

static bool eev6_active_level(const hrtim_state *h) {
  bool pol_low = (h->eecr[1] & HRTIM_EECR2_EE6POL) != 0; /* 1: active low */
  return pol_low ? h->eev6_pin_low : !h->eev6_pin_low;
}

/* The filtered, resynchronised event 6 changes: the timers resetting output 1 on it re-emit the
 * rest of their period (only while the counters run; the latch state is kept meanwhile). */
static void apply_eev6(board *b) {
  hrtim_state *h = &b->hrtim;
  double now = board_now(b);
  if (h->eev6_on == h->eev6_raw) return;
  twin_sync(b, now);
  h->eev6_on = h->eev6_raw;
  if (!h->running) return;
  if (h->n_eev6_hist == HRTIM_EEV_HIST) { board_fault(b, "HRTIM model: external event 6 changed more than %d times in one period", HRTIM_EEV_HIST); return; }
  h->eev6_hist[h->n_eev6_hist].t = now;
  h->eev6_hist[h->n_eev6_hist].level = h->eev6_on;
  h->n_eev6_hist++;
  for (int t = 0; t < HRTIM_NTIM; t++)
    if (h->tim[t].rst[0] & HRTIM_RST_EXTEVNT6) emit_from(b, t, 0, now);
}

/* The EEV6 pin (PB5, AF13) changed or its mux did: through the polarity and the digital filter. */
void hrtim_eev_input_update(board *b, bool pin_low) {
  hrtim_state *h = &b->hrtim;
  h->eev6_pin_low = pin_low;
  bool raw = eev6_active_level(h);
  if (raw == h->eev6_raw) return;
  h->eev6_raw = raw;
  if (raw == h->eev6_on) { h->eev6_apply_t = -1; return; } /* back before the filter let it through */
  double ts;
  int n;
  eev_filter(b, reg_field(h->eecr[2], HRTIM_EECR3_EE6F), reg_field(h->eecr[2], HRTIM_EECR3_EEVSD), &ts, &n);
  double now = board_now(b), fh = f_hrtim(b) > 0 ? f_hrtim(b) : 16e6;
  double t_out = now;
  if (n > 0) { /* the N-th consecutive sample of the new level, on the sampling clock's grid */
    double first = ceil(now / ts - 1e-6) * ts;
    t_out = first + (double)(n - 1) * ts;
  }
  h->eev6_apply_t = t_out + EEV_SYNC_TICKS / fh;
}

/* ---- registers ---- */

static uint32_t counter(board *b, uint32_t per) {
  hrtim_state *h = &b->hrtim;
  if (!h->running) return 0;
  double c = floor((board_now(b) - h->t_period) / h->t_count + 1e-6);
  return c < 0 ? 0 : (uint32_t)c % (per + 1u);
}

/* Compare register k (0..3) at offset r: CMP1 first, then CMP2-4 one word apart after a gap
 * (CMP1CxR / the master's reserved word). */
static int cmp_index(uint32_t r, uint32_t cmp1, uint32_t cmp2) {
  return r == cmp1 ? 0 : (int)(r - cmp2) / 4 + 1;
}

static bool check_cmp(board *b, const char *name, uint32_t v) {
  if (v & ~HRTIM_CMP_VALUE) { board_fault(b, "%s 0x%08X: bits 31:16 are reserved", name, v); return false; }
  if (v != 0 && v < HRTIM_PER_MIN) {
    board_fault(b, "%s = %u: compare values below 3 are not allowed in low resolution (RM0440 §27.5, "
                "HRTIM_CMPxR minimum value)", name, v);
    return false;
  }
  return true;
}

uint32_t hrtim_read(board *b, uint32_t off) {
  hrtim_state *h = &b->hrtim;
  hrtim_event(b);
  if (off < OFS_TIMA) {
    bool pre = (h->mcr & HRTIM_MCR_PREEN) != 0;
    switch (off) {
    case HRTIM_MCR_OFS: return h->mcr;
    case HRTIM_MISR_OFS: return h->misr;
    case HRTIM_MICR_OFS: return 0;
    case HRTIM_MDIER_OFS: return h->mdier;
    case HRTIM_MCNTR_OFS: return counter(b, h->mper);
    case HRTIM_MPER_OFS: return pre ? h->p_mper : h->mper;
    case HRTIM_MREP_OFS: return pre ? h->p_mrep : h->mrep;
    case HRTIM_MCMP1R_OFS: case HRTIM_MCMP2R_OFS: case HRTIM_MCMP3R_OFS: case HRTIM_MCMP4R_OFS: {
      int k = cmp_index(off, HRTIM_MCMP1R_OFS, HRTIM_MCMP2R_OFS);
      return pre ? h->p_mcmp[k] : h->mcmp[k];
    }
    }
  } else if (off < OFS_COMMON) {
    int t = (int)((off - OFS_TIMA) / HRTIM_TIM_STRIDE);
    hrtim_timer *x = &h->tim[t];
    uint32_t r = (off - OFS_TIMA) % HRTIM_TIM_STRIDE;
    bool pre = (x->cr & HRTIM_TIMxCR_PREEN) != 0;
    switch (r) {
    case HRTIM_TIMxCR_OFS: return x->cr;
    case HRTIM_TIMxISR_OFS: { /* O1STAT/O2STAT: copies of the output levels */
      uint32_t lv = hrtim_levels(b, board_now(b));
      return x->isr | (((lv >> (2 * t)) & 1u) ? HRTIM_TIMxISR_O1STAT : 0u) |
             (((lv >> (2 * t + 1)) & 1u) ? HRTIM_TIMxISR_O2STAT : 0u);
    }
    case HRTIM_TIMxICR_OFS: return 0;
    case HRTIM_TIMxDIER_OFS: return x->dier;
    case HRTIM_CNTxR_OFS: return counter(b, x->per);
    case HRTIM_PERxR_OFS: return pre ? x->p_per : x->per;
    case HRTIM_REPxR_OFS: return pre ? x->p_rep : x->rep;
    case HRTIM_CMP1xR_OFS: case HRTIM_CMP2xR_OFS: case HRTIM_CMP3xR_OFS: case HRTIM_CMP4xR_OFS: {
      int k = cmp_index(r, HRTIM_CMP1xR_OFS, HRTIM_CMP2xR_OFS);
      return pre ? x->p_cmp[k] : x->cmp[k];
    }
    case HRTIM_DTxR_OFS: return x->dtr;
    case HRTIM_SETx1R_OFS: return pre ? x->p_set[0] : x->set[0];
    case HRTIM_RSTx1R_OFS: return pre ? x->p_rst[0] : x->rst[0];
    case HRTIM_SETx2R_OFS: return pre ? x->p_set[1] : x->set[1];
    case HRTIM_RSTx2R_OFS: return pre ? x->p_rst[1] : x->rst[1];
    case HRTIM_OUTxR_OFS: return x->outr;
    case HRTIM_FLTxR_OFS: return x->fltr;
    }
  } else {
    uint32_t r = off - OFS_COMMON;
    switch (r) {
    case HRTIM_CR1_OFS: return h->cr1;
    case HRTIM_CR2_OFS: return 0; /* software update bits read as 0 once done */
    case HRTIM_ISR_OFS: return h->isr;
    case HRTIM_ICR_OFS: return 0;
    case HRTIM_IER_OFS: return h->ier;
    case HRTIM_OENR_OFS: return h->oen;             /* OENR reads the enable status (§27.5, HRTIM_OENR) */
    case HRTIM_ODISR_OFS: return 0;
    case HRTIM_ODSR_OFS: return h->fault_state & ~h->oen; /* 1 = disabled in the fault state */
    case HRTIM_ADC1R_OFS: case HRTIM_ADC1R_OFS + 4u: case HRTIM_ADC1R_OFS + 8u: case HRTIM_ADC4R_OFS:
      return h->adcr[(r - HRTIM_ADC1R_OFS) / 4u];
    case HRTIM_EECR1_OFS: case HRTIM_EECR2_OFS: case HRTIM_EECR3_OFS: return h->eecr[(r - HRTIM_EECR1_OFS) / 4u];
    case HRTIM_FLTINR1_OFS: return h->fltinr1;
    case HRTIM_FLTINR2_OFS: return h->fltinr2;
    }
  }
  board_fault(b, "read of HRTIM register at offset 0x%03X: not modelled", off);
  return 0;
}

static void start_stop(board *b, uint32_t old, uint32_t v) {
  hrtim_state *h = &b->hrtim;
  uint32_t en_old = old & HRTIM_MCR_CEN_ALL, en_new = v & HRTIM_MCR_CEN_ALL;
  if (en_old == en_new) return;
  if (en_old == 0 && en_new == HRTIM_MCR_CEN_ALL) {
    /* all counters start together: the port's synchronous scheme */
    unsigned psc = ckpsc(h->mcr);
    if (psc < HRTIM_CKPSC_LOW_RES) { board_fault(b, "HRTIM_MCR CKPSC %u: high resolution needs the DLL, not modelled", psc); return; }
    for (int t = 0; t < HRTIM_NTIM; t++) {
      if (ckpsc(h->tim[t].cr) != psc) {
        board_fault(b, "HRTIM timer %c prescaler %u differs from the master's %u (not modelled)", k_tname[t],
                    ckpsc(h->tim[t].cr), psc);
        return;
      }
      if (!(h->tim[t].cr & HRTIM_TIMxCR_CONT)) { board_fault(b, "HRTIM timer %c not in continuous mode (not modelled)", k_tname[t]); return; }
    }
    if (!(h->mcr & HRTIM_MCR_CONT)) { board_fault(b, "HRTIM master not in continuous mode (not modelled)"); return; }
    if (!(f_hrtim(b) > 0)) { board_fault(b, "HRTIM started without a clock"); return; }
    h->t_count = (double)(1u << psc) / (32.0 * f_hrtim(b));
    h->running = true;
    double t0 = board_now(b);
    /* the outputs take the crossbar's present level when the counters start: with dead time,
     * output 2 is the complement of output 1 (after its dead time, §27.3.10) */
    for (int t = 0; t < HRTIM_NTIM; t++) {
      if (h->tim[t].outr & HRTIM_OUTxR_DTEN) {
        h->tim[t].ref[0] ^= 1u;
        ref_edge(b, t, 0, t0, h->tim[t].ref[0]);
        h->tim[t].ref[0] ^= 1u;
        ref_edge(b, t, 0, t0, h->tim[t].ref[0]);
        h->tim[t].last_tr[0].t = t0;
        h->tim[t].last_tr[0].level = h->tim[t].ref[0];
      }
      h->tim[t].n_plan[0] = h->tim[t].n_plan[1] = 0;
    }
    h->n_eev6_hist = 0;
    period_start(b, t0);
    return;
  }
  if (en_new == 0) { /* counters stop; the outputs keep their levels */
    twin_sync(b, board_now(b));
    h->running = false;
    return;
  }
  board_fault(b, "HRTIM_MCR 0x%08X: timers started or stopped separately (the model runs the master and "
              "timers A-F together)", v);
}

static void write_timer(board *b, int t, uint32_t r, uint32_t v) {
  hrtim_state *h = &b->hrtim;
  hrtim_timer *x = &h->tim[t];
  bool pre = (x->cr & HRTIM_TIMxCR_PREEN) != 0;
  char name[24];
  bool running_now = h->running;
  switch (r) {
  case HRTIM_TIMxCR_OFS: {
    const uint32_t ok = HRTIM_TIMxCR_CK_PSCx | HRTIM_TIMxCR_CONT | HRTIM_TIMxCR_TxREPU | HRTIM_TIMxCR_PREEN;
    if (v & ~ok) {
      board_fault(b, "HRTIM_TIM%cCR 0x%08X: bits 0x%08X not modelled (the port uses CKPSC, CONT, TxREPU, PREEN)",
                  k_tname[t], v, v & ~ok);
      return;
    }
    if (running_now && ckpsc(v) != ckpsc(x->cr)) { board_fault(b, "HRTIM_TIM%cCR: CKPSC changed while counting", k_tname[t]); return; }
    x->cr = v;
    return;
  }
  case HRTIM_TIMxICR_OFS: x->isr &= ~v; return;
  case HRTIM_TIMxDIER_OFS:
    if (v) { board_fault(b, "HRTIM_TIM%cDIER 0x%08X: timer interrupts/DMA not modelled", k_tname[t], v); return; }
    x->dier = v;
    return;
  case HRTIM_PERxR_OFS:
    if (v & ~HRTIM_PER_VALUE || v > HRTIM_PER_MAX || v < HRTIM_PER_MIN) {
      board_fault(b, "HRTIM_PER%cR %u: outside 3..0xFFDF (RM0440 §27.5)", k_tname[t], v); return;
    }
    if (pre) x->p_per = v; else { x->per = x->p_per = v; }
    return;
  case HRTIM_REPxR_OFS:
    if (v & ~HRTIM_REP_VALUE) { board_fault(b, "HRTIM_REP%cR 0x%08X: bits 31:8 reserved", k_tname[t], v); return; }
    if (v) { board_fault(b, "HRTIM_REP%cR %u: repetition counts other than 0 not modelled", k_tname[t], v); return; }
    if (pre) x->p_rep = v; else x->rep = x->p_rep = v;
    return;
  case HRTIM_CMP1xR_OFS: case HRTIM_CMP2xR_OFS: case HRTIM_CMP3xR_OFS: case HRTIM_CMP4xR_OFS: {
    int k = cmp_index(r, HRTIM_CMP1xR_OFS, HRTIM_CMP2xR_OFS);
    snprintf(name, sizeof name, "HRTIM_CMP%d%cR", k + 1, k_tname[t]);
    if (!check_cmp(b, name, v)) return;
    if (pre) x->p_cmp[k] = v; else x->cmp[k] = x->p_cmp[k] = v;
    return;
  }
  case HRTIM_DTxR_OFS:
    if (((x->dtr & HRTIM_DTxR_DTRLKx) && ((v ^ x->dtr) & HRTIM_DTxR_RISING_FIELDS)) ||
        ((x->dtr & HRTIM_DTxR_DTFLKx) && ((v ^ x->dtr) & HRTIM_DTxR_FALLING_FIELDS))) {
      board_fault(b, "HRTIM_DT%cR written while locked (DTRLK/DTFLK, RM0440 §27.5)", k_tname[t]);
      return;
    }
    if (v & (HRTIM_DTxR_SDTRx | HRTIM_DTxR_SDTFx | HRTIM_DTxR_DTRSLKx | HRTIM_DTxR_DTFSLKx)) {
      board_fault(b, "HRTIM_DT%cR 0x%08X: negative dead time (SDTR/SDTF) or sign locks not modelled", k_tname[t], v);
      return;
    }
    if (reg_field(v, HRTIM_DTxR_DTPRSC) < HRTIM_DTPRSC_MIN_LOW_RES) {
      board_fault(b, "HRTIM_DT%cR DTPRSC %u: a dead-time step finer than tHRTIM needs the high-resolution "
                  "delay line (DLL), not available in the low-resolution mode the model supports", k_tname[t],
                  reg_field(v, HRTIM_DTxR_DTPRSC));
      return;
    }
    if (running_now && (h->oen & (3u << (2 * t)))) {
      board_fault(b, "HRTIM_DT%cR changed while the timer's outputs are enabled", k_tname[t]);
      return;
    }
    x->dtr = v;
    return;
  case HRTIM_SETx1R_OFS: case HRTIM_RSTx1R_OFS: case HRTIM_SETx2R_OFS: case HRTIM_RSTx2R_OFS: {
    int out = r >= HRTIM_SETx2R_OFS;
    bool is_set = r == HRTIM_SETx1R_OFS || r == HRTIM_SETx2R_OFS;
    /* PER, CMP1-4; external event 6 as a reset of output 1 (the fault line's second input); the
     * software set of output 1 (SST) */
    const uint32_t ok = HRTIM_EVENTS_PER_CMP | (!is_set && out == 0 ? HRTIM_RST_EXTEVNT6 : 0u) |
                        (is_set && out == 0 ? HRTIM_SET_SST : 0u);
    if (v & ~ok) {
      board_fault(b, "HRTIM_%s%c%dR 0x%08X: event sources 0x%08X not modelled (PER, CMP1-4%s only)",
                  is_set ? "SET" : "RST", k_tname[t], out + 1, v, v & ~ok,
                  !is_set && out == 0 ? ", EXTEVNT6 (external event 6, PB5)" : "");
      return;
    }
    if (is_set && (v & HRTIM_SET_SST)) { /* set output 1 now, whatever the preload (a reset request still wins) */
      software_set(b, t);
      v &= ~HRTIM_SET_SST;
    }
    uint32_t *reg = is_set ? (pre ? &x->p_set[out] : &x->set[out]) : (pre ? &x->p_rst[out] : &x->rst[out]);
    *reg = v;
    if (!pre) { if (is_set) x->p_set[out] = v; else x->p_rst[out] = v; }
    return;
  }
  case HRTIM_OUTxR_OFS: {
    const uint32_t ok = HRTIM_OUTxR_POL1 | HRTIM_OUTxR_IDLES1 | HRTIM_OUTxR_FAULT1 | HRTIM_OUTxR_DTEN |
                        HRTIM_OUTxR_POL2 | HRTIM_OUTxR_IDLES2 | HRTIM_OUTxR_FAULT2;
    if (v & ~ok) { board_fault(b, "HRTIM_OUT%cR 0x%08X: bits 0x%08X not modelled", k_tname[t], v, v & ~ok); return; }
    if ((v & HRTIM_OUTxR_FAULT1) == HRTIM_OUTxR_FAULT1_HIGH_Z ||
        ((v >> HRTIM_OUTxR_OUT2_SHIFT) & HRTIM_OUTxR_FAULT1) == HRTIM_OUTxR_FAULT1_HIGH_Z) {
      board_fault(b, "HRTIM_OUT%cR: FAULTx = high impedance not modelled", k_tname[t]); return;
    }
    if (h->oen & (3u << (2 * t))) {
      board_fault(b, "HRTIM_OUT%cR written while the timer's outputs are enabled: POLx, IDLESx, FAULTx and "
                  "DTEN may change only with the outputs disabled (RM0440 §27.5, HRTIM_OUTxR)", k_tname[t]);
      return;
    }
    x->outr = v;
    return;
  }
  case HRTIM_FLTxR_OFS:
    if (x->fltr & HRTIM_FLTxR_FLTLCK) { board_fault(b, "HRTIM_FLT%cR written while FLTLCK is set (RM0440 §27.5)", k_tname[t]); return; }
    if (v & ~(HRTIM_FLTxR_FLTLCK | HRTIM_FLTxR_FLTEN_ALL)) { board_fault(b, "HRTIM_FLT%cR 0x%08X: reserved bits", k_tname[t], v); return; }
    x->fltr = v;
    return;
  }
  board_fault(b, "write 0x%08X to HRTIM timer %c register offset 0x%02X: not modelled", v, k_tname[t], r);
}

/* One fault input's byte of FLTINR1 (inputs 1-4): its fields at input 1's positions. */
static uint32_t flt_input(uint32_t fltinr1, int k) {
  return (fltinr1 >> (HRTIM_FLTINR1_INPUT_BITS * (unsigned)k)) & 0xFFu;
}

/* One external event's six bits of EECR2 (events 6-10): its fields at event 6's positions. */
static uint32_t eev_fields(uint32_t eecr2, int e) {
  return (eecr2 >> (HRTIM_EECR2_EVENT_BITS * (unsigned)e)) & 0x3Fu;
}

static void write_common(board *b, uint32_t r, uint32_t v) {
  hrtim_state *h = &b->hrtim;
  switch (r) {
  case HRTIM_CR1_OFS:
    if (v & ~HRTIM_CR1_UDIS_ALL) { board_fault(b, "HRTIM_CR1 0x%08X: ADC update sources not modelled", v); return; }
    h->cr1 = v;
    return;
  case HRTIM_CR2_OFS:
    if (v & ~HRTIM_CR2_SWU_ALL) { board_fault(b, "HRTIM_CR2 0x%08X: counter software resets / swaps not modelled", v); return; }
    if (v & HRTIM_CR2_MSWU) transfer(h, -1);
    for (int t = 0; t < HRTIM_NTIM; t++) if (v & (HRTIM_CR2_TASWU << t)) transfer(h, t);
    return;
  case HRTIM_ICR_OFS: h->isr &= ~(v & HRTIM_ISR_FAULTS); return; /* FLTxC, SYSFLTC */
  case HRTIM_IER_OFS:
    if (v & ~HRTIM_ISR_FAULTS) { board_fault(b, "HRTIM_IER 0x%08X: burst/DLL interrupts not modelled", v); return; }
    h->ier = v;
    if (h->isr & h->ier & HRTIM_ISR_FAULTS) scs_set_pending(b, 16 + IRQ_HRTIM_FLT);
    return;
  case HRTIM_OENR_OFS: { /* enable; an output whose fault is still active stays in its fault state */
    if (v & ~HRTIM_OUT_ALL) { board_fault(b, "HRTIM_OENR 0x%08X: bits 31:12 reserved", v); return; }
    twin_sync(b, board_now(b));
    uint32_t blocked = 0;
    if (flt3_active(h))
      for (int o = 0; o < HRTIM_NOUT; o++) {
        const hrtim_timer *x = &h->tim[o / 2];
        uint32_t outr = (o & 1) ? x->outr >> HRTIM_OUTxR_OUT2_SHIFT : x->outr;
        if ((x->fltr & HRTIM_FLTxR_FLT3EN) && (outr & HRTIM_OUTxR_FAULT1) != HRTIM_OUTxR_FAULT1_NONE) blocked |= 1u << o;
      }
    h->oen |= v & ~blocked;
    h->fault_state &= ~(v & ~blocked);
    return;
  }
  case HRTIM_ODISR_OFS:
    if (v & ~HRTIM_OUT_ALL) { board_fault(b, "HRTIM_ODISR 0x%08X: bits 31:12 reserved", v); return; }
    twin_sync(b, board_now(b));
    h->oen &= ~v;
    return;
  case HRTIM_ADC1R_OFS: case HRTIM_ADC1R_OFS + 4u: case HRTIM_ADC1R_OFS + 8u: case HRTIM_ADC4R_OFS: {
    unsigned a = (r - HRTIM_ADC1R_OFS) / 4u;
    if (v & ~HRTIM_ADCxR_MASTER) { board_fault(b, "HRTIM_ADC%uR 0x%08X: trigger sources other than the master not modelled", a + 1u, v); return; }
    if (v & HRTIM_ADCxR_MPER) { board_fault(b, "HRTIM_ADCxR: master period trigger not modelled"); return; }
    h->adcr[a] = v;
    return;
  }
  case HRTIM_EECR1_OFS: case HRTIM_EECR2_OFS: case HRTIM_EECR3_OFS: { /* §27.5 (HRTIM_EECRx) */
    int k = (int)(r - HRTIM_EECR1_OFS) / 4;
    if (h->running) {
      board_fault(b, "HRTIM_EECR%d written while the counters run: the external event configuration must not "
                  "change once a timer using it is enabled (RM0440 §27.5, HRTIM_EECRx)", k + 1);
      return;
    }
    if (r == HRTIM_EECR1_OFS && v) { board_fault(b, "HRTIM_EECR1 0x%08X: external events 1-5 are not wired on this board model", v); return; }
    if (r == HRTIM_EECR2_OFS) {
      for (int e = 0; e < 5; e++) { /* events 6-10 */
        uint32_t f = eev_fields(v, e);
        if (e > 0 && f) { board_fault(b, "HRTIM_EECR2: external event %d is not wired on this board model", e + 6); return; }
        if (f & HRTIM_EECR2_EVENT_RESERVED) { board_fault(b, "HRTIM_EECR2 0x%08X: reserved bit", v); return; }
        if (f & HRTIM_EECR2_EE6SRC) { board_fault(b, "HRTIM_EECR2 EE6SRC %u: only source 1 (the HRTIM_EEV6 pin) is modelled", reg_field(f, HRTIM_EECR2_EE6SRC)); return; }
        if (f & HRTIM_EECR2_EE6SNS) { board_fault(b, "HRTIM_EECR2 EE6SNS %u: edge sensitivity not modelled (level only)", reg_field(f, HRTIM_EECR2_EE6SNS)); return; }
      }
      if (v & HRTIM_EECR2_RESERVED) { board_fault(b, "HRTIM_EECR2 0x%08X: reserved bits", v); return; }
    }
    if (r == HRTIM_EECR3_OFS) {
      if (v & ~(HRTIM_EECR3_EE6F | HRTIM_EECR3_EEVSD)) { board_fault(b, "HRTIM_EECR3 0x%08X: filters of external events 7-10 (not wired on this board model) or reserved bits", v); return; }
    }
    h->eecr[k] = v;
    hrtim_eev_input_update(b, h->eev6_pin_low); /* a polarity change is an input change */
    return;
  }
  case HRTIM_FLTINR1_OFS: {
    uint32_t old = h->fltinr1;
    for (int k = 0; k < 4; k++) {
      uint32_t ob = flt_input(old, k), nb = flt_input(v, k);
      if ((ob & HRTIM_FLTINR1_FLT1LCK) && ob != nb) { board_fault(b, "HRTIM_FLTINR1 FLT%d written while FLT%dLCK is set", k + 1, k + 1); return; }
      const uint32_t configuration = HRTIM_FLTINR1_FLT1P | HRTIM_FLTINR1_FLT1SRC | HRTIM_FLTINR1_FLT1F;
      if ((ob & HRTIM_FLTINR1_FLT1E) && (nb & HRTIM_FLTINR1_FLT1E) && ((ob ^ nb) & configuration)) {
        board_fault(b, "HRTIM_FLTINR1 FLT%d: polarity, source or filter changed while FLT%dE = 1 (RM0440 §27.5, "
                    "HRTIM_FLTINR1)", k + 1, k + 1);
        return;
      }
      if ((nb & HRTIM_FLTINR1_FLT1E) && k != 2) { board_fault(b, "HRTIM_FLTINR1: fault input FLT%d not wired on this board model", k + 1); return; }
      if (nb & HRTIM_FLTINR1_FLT1SRC) { board_fault(b, "HRTIM_FLTINR1 FLT%dSRC: internal comparator source not modelled", k + 1); return; }
      if (nb & HRTIM_FLTINR1_FLT1F) { board_fault(b, "HRTIM_FLTINR1 FLT%dF: digital filter not modelled", k + 1); return; }
    }
    h->fltinr1 = v;
    if (!(old & HRTIM_FLTINR1_FLT3E) && (v & HRTIM_FLTINR1_FLT3E) && flt3_active(h)) h->flt3_apply_t = board_now(b) + FLT_SYNC_TICKS / f_hrtim(b);
    return;
  }
  case HRTIM_FLTINR2_OFS:
    if (v & (HRTIM_FLTINR2_FLT5E | HRTIM_FLTINR2_FLT6E)) { board_fault(b, "HRTIM_FLTINR2: FLT5/FLT6 not wired on this board model"); return; }
    if (v & ~(HRTIM_FLTINR2_MODELLED | HRTIM_FLTINR2_FLTSD)) { board_fault(b, "HRTIM_FLTINR2 0x%08X: not modelled", v); return; }
    h->fltinr2 = v;
    return;
  }
  board_fault(b, "write 0x%08X to HRTIM register at offset 0x%03X: not modelled", v, OFS_COMMON + r);
}

void hrtim_write(board *b, uint32_t off, uint32_t v) {
  hrtim_state *h = &b->hrtim;
  hrtim_event(b);
  if (off >= OFS_COMMON) { write_common(b, off - OFS_COMMON, v); return; }
  if (off >= OFS_TIMA) {
    write_timer(b, (int)((off - OFS_TIMA) / HRTIM_TIM_STRIDE), (off - OFS_TIMA) % HRTIM_TIM_STRIDE, v);
    return;
  }
  bool pre = (h->mcr & HRTIM_MCR_PREEN) != 0;
  switch (off) {
  case HRTIM_MCR_OFS: {
    const uint32_t ok = HRTIM_MCR_CK_PSC | HRTIM_MCR_CONT | HRTIM_MCR_CEN_ALL | HRTIM_MCR_PREEN | HRTIM_MCR_MREPU;
    if (v & ~ok) { board_fault(b, "HRTIM_MCR 0x%08X: bits 0x%08X not modelled", v, v & ~ok); return; }
    uint32_t old = h->mcr;
    if (h->running && ckpsc(v) != ckpsc(old)) { board_fault(b, "HRTIM_MCR: CKPSC changed while counting"); return; }
    h->mcr = v;
    start_stop(b, old, v);
    return;
  }
  case HRTIM_MICR_OFS: h->misr &= ~v; return;
  case HRTIM_MDIER_OFS:
    if (v & ~HRTIM_MDIER_IE_ALL) { board_fault(b, "HRTIM_MDIER 0x%08X: DMA requests not modelled", v); return; }
    h->mdier = v;
    pend_master(b);
    return;
  case HRTIM_MPER_OFS:
    if (v > HRTIM_PER_MAX || v < HRTIM_PER_MIN) { board_fault(b, "HRTIM_MPER %u: outside 3..0xFFDF (RM0440 §27.5)", v); return; }
    if (pre) h->p_mper = v; else h->mper = h->p_mper = v;
    return;
  case HRTIM_MREP_OFS:
    if (v) { board_fault(b, "HRTIM_MREP %u: repetition counts other than 0 not modelled", v); return; }
    h->mrep = h->p_mrep = 0;
    return;
  case HRTIM_MCMP1R_OFS: case HRTIM_MCMP2R_OFS: case HRTIM_MCMP3R_OFS: case HRTIM_MCMP4R_OFS: {
    int k = cmp_index(off, HRTIM_MCMP1R_OFS, HRTIM_MCMP2R_OFS);
    char name[16];
    snprintf(name, sizeof name, "HRTIM_MCMP%dR", k + 1);
    if (!check_cmp(b, name, v)) return;
    if (pre) h->p_mcmp[k] = v; else h->mcmp[k] = h->p_mcmp[k] = v;
    return;
  }
  }
  board_fault(b, "write 0x%08X to HRTIM register at offset 0x%03X: not modelled", v, off);
}
