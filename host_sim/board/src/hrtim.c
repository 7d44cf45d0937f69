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
#define RST_EEV6 (1u << 26) /* SETx1R/RSTx1R.EXTEVNT6 */

/* register offsets from 0x40016800 */
#define OFS_TIM(t) (0x80u + 0x80u * (unsigned)(t))
#define OFS_COMMON 0x380u

static const char *k_tname = "ABCDEF";

void hrtim_reset(board *b) {
  hrtim_state *h = &b->hrtim;
  memset(h, 0, sizeof *h);
  h->mper = h->p_mper = 0xFFDFu;
  for (int t = 0; t < 6; t++) h->tim[t].per = h->tim[t].p_per = 0xFFDFu;
  h->flt3_apply_t = -1;
  h->flt3_line_low = gpio_flt3_low(b);
  h->eev6_apply_t = -1;
  h->eev6_pin_low = gpio_eev6_low(b);
  for (int t = 0; t < 6; t++) h->tim[t].last_tr[0].t = h->tim[t].last_tr[1].t = -1;
}

static double f_hrtim(board *b) { return rcc_hclk_hz(b); } /* APB2 prescaler 1: fHRTIM = PCLK2 = HCLK */
static unsigned ckpsc(uint32_t cr) { return cr & 7u; }

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
  if (!(x->outr & (1u << 8))) { /* DTEN = 0: each output follows its own crossbar */
    hrtim_wave *w = out ? o2 : o1;
    wave_cut(w, when);
    wave_push(b, w, when, level);
    return;
  }
  if (out) return; /* DTEN = 1: output 2 is derived from output 1's reference (§27.3.10) */
  double tdtg = (double)(1u << ((x->dtr >> 10) & 7u)) / (8.0 * f_hrtim(b));
  double dtr = (double)(x->dtr & 0x1FFu) * tdtg, dtf = (double)((x->dtr >> 16) & 0x1FFu) * tdtg;
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
  unsigned sh = (o & 1) ? 16u : 0u; /* OUTxR fields of output 2 are 16 bits up */
  uint8_t pol = (x->outr >> (1u + sh)) & 1u;
  uint8_t active;
  if (h->oen & (1u << o)) {
    const hrtim_wave *w = &h->wave[o];
    active = w->level;
    for (int i = 0; i < w->n && w->e[i].t <= t + EPS_T; i++) active = w->e[i].level;
  } else if (h->fault_state & (1u << o)) {
    active = ((x->outr >> (4u + sh)) & 3u) == 1u; /* FAULTx = 1 active, 2 inactive */
  } else {
    active = (x->outr >> (3u + sh)) & 1u;          /* IDLESx */
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

/* Dead times of timer t, s: rising (DTR) and falling (DTF) edges. */
static void dead_times(board *b, const hrtim_timer *x, double *dtr, double *dtf) {
  double tdtg = (double)(1u << ((x->dtr >> 10) & 7u)) / (8.0 * f_hrtim(b));
  *dtr = (double)(x->dtr & 0x1FFu) * tdtg;
  *dtf = (double)((x->dtr >> 16) & 0x1FFu) * tdtg;
}

/* The reference transitions of timer t's output `out` over the present period: its set/reset
 * programme (plan) run through the set/reset latch together with the external event 6 reset
 * request, as known so far (active at the period start, then eev6_hist). A reset request beats a
 * set at the same instant (§27.3.7); an event-6 change at the instant of a set is taken first. */
static int ref_transitions(const hrtim_state *h, const hrtim_timer *x, int out, hrtim_edge *tr) {
  bool uses_eev = (x->rst[out] & RST_EEV6) != 0;
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
  bool dten = (x->outr & (1u << 8)) != 0;
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

/* Crossbar of timer t for the period starting at t0 (RM0440 §27.3.5): events PER (bit 2) and
 * CMP1-4 (bits 3-6); set and reset on one event is refused (the model does not arbitrate). */
static void plan_period(board *b, int t, double t0) {
  hrtim_state *h = &b->hrtim;
  hrtim_timer *x = &h->tim[t];
  for (int out = 0; out < 2; out++) {
    x->ref_start[out] = x->ref[out];
    x->n_plan[out] = 0;
    uint32_t s = x->set[out], r = x->rst[out] & ~RST_EEV6;
    if (s & r) {
      board_fault(b, "HRTIM_SET%c%dR/RST%c%dR 0x%08X/0x%08X: set and reset on the same event (not modelled)",
                  k_tname[t], out + 1, k_tname[t], out + 1, s, r);
      return;
    }
    struct { uint32_t c; uint32_t bit; } ev[5];
    int m = 0;
    for (int k = 0; k < 4; k++)
      if (((s | r) >> (3 + k)) & 1u) { ev[m].c = x->cmp[k]; ev[m].bit = 1u << (3 + k); m++; }
    if ((s | r) & 4u) { ev[m].c = x->per; ev[m].bit = 4u; m++; }
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
  for (int t = 0; t < 6; t++) /* the last reference transition of the period that ends: history */
    for (int out = 0; out < 2; out++) {
      hrtim_edge tr[8 + HRTIM_EEV_HIST + 1];
      int n = ref_transitions(h, &h->tim[t], out, tr);
      if (n) h->tim[t].last_tr[out] = tr[n - 1];
    }
  h->t_period = t0;
  h->periods++;
  /* repetition event with REP = 0 each period: update (transfer) unless held by TxUDIS */
  if ((h->mcr & (1u << 27)) && (h->mcr & (1u << 29)) && !(h->cr1 & 1u)) transfer(h, -1);
  h->misr |= (1u << 4) | (1u << 5); /* MREP, MUPD */
  for (int t = 0; t < 6; t++) {
    hrtim_timer *x = &h->tim[t];
    if ((x->cr & (1u << 27)) && (x->cr & (1u << 17)) && !(h->cr1 & (1u << (t + 1)))) transfer(h, t);
    if (x->per != h->mper)
      board_fault(b, "HRTIM timer %c period %u differs from the master's %u: the model runs all timers on the "
                  "master's period (the port's scheme)", k_tname[t], x->per, h->mper);
    plan_period(b, t, t0);
  }
  h->eev6_on_at_t0 = h->eev6_on; /* the new period's event-6 history starts here */
  h->n_eev6_hist = 0;
  for (int t = 0; t < 6; t++)
    for (int out = 0; out < 2; out++) emit_from(b, t, out, t0);
  if (h->mper < 3u) board_fault(b, "HRTIM_MPER %u: below the minimum period of 3 (RM0440 §27.5)", h->mper);
  h->next_period_t = t0 + (double)h->mper * h->t_count;
  for (int k = 0; k < 4; k++) {
    h->mcmp_done[k] = h->mcmp[k] == 0 || h->mcmp[k] > h->mper;
    h->next_mcmp_t[k] = t0 + (double)h->mcmp[k] * h->t_count;
  }
}

static void pend_master(board *b) {
  if (b->hrtim.misr & b->hrtim.mdier & 0x7Fu) scs_set_pending(b, 16 + IRQ_HRTIM_MASTER);
}

static void master_compare(board *b, int k, double when) {
  hrtim_state *h = &b->hrtim;
  h->mcmp_done[k] = true;
  h->misr |= 1u << k;
  pend_master(b);
  /* ADC triggers 1-4: master compare k -> ADCxR bit k (AD1MC1.. / AD2MC1..), §27.3.19 */
  for (int a = 0; a < 4; a++)
    if (h->adcr[a] & (1u << k)) adc_hrtim_trigger(b, a + 1, when);
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
  if (!(h->fltinr1 & (1u << 16))) return false;            /* FLT3E */
  bool pol_high = (h->fltinr1 >> 17) & 1u;                   /* FLT3P: 0 active low */
  return pol_high ? !h->flt3_line_low : h->flt3_line_low;
}

static void apply_fault(board *b) {
  hrtim_state *h = &b->hrtim;
  if (!flt3_active(h)) return;
  twin_sync(b, board_now(b));
  h->isr |= 1u << 2; /* FLT3 */
  if (h->ier & (1u << 2)) scs_set_pending(b, 16 + IRQ_HRTIM_FLT);
  for (int t = 0; t < 6; t++) {
    if (!(h->tim[t].fltr & (1u << 2))) continue; /* FLT3EN */
    for (int k = 0; k < 2; k++) {
      int o = 2 * t + k;
      uint32_t fault = (h->tim[t].outr >> (4u + 16u * (unsigned)k)) & 3u;
      if (fault == 0u) continue; /* "no action": the output keeps its waveform */
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
  bool pol_low = (h->eecr[1] >> 2) & 1u; /* EE6POL: 1 active low */
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
  for (int t = 0; t < 6; t++)
    if (h->tim[t].rst[0] & RST_EEV6) emit_from(b, t, 0, now);
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
  eev_filter(b, h->eecr[2] & 0xFu, (h->eecr[2] >> 30) & 3u, &ts, &n);
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

static bool check_cmp(board *b, const char *name, uint32_t v) {
  if (v & ~0xFFFFu) { board_fault(b, "%s 0x%08X: bits 31:16 are reserved", name, v); return false; }
  if (v != 0 && v < 3u) {
    board_fault(b, "%s = %u: compare values below 3 are not allowed in low resolution (RM0440 §27.5, "
                "HRTIM_CMPxR minimum value)", name, v);
    return false;
  }
  return true;
}

uint32_t hrtim_read(board *b, uint32_t off) {
  hrtim_state *h = &b->hrtim;
  hrtim_event(b);
  if (off < 0x80u) {
    switch (off) {
    case 0x00: return h->mcr;
    case 0x04: return h->misr;
    case 0x08: return 0;
    case 0x0C: return h->mdier;
    case 0x10: return counter(b, h->mper);
    case 0x14: return (h->mcr & (1u << 27)) ? h->p_mper : h->mper;
    case 0x18: return (h->mcr & (1u << 27)) ? h->p_mrep : h->mrep;
    case 0x1C: case 0x24: case 0x28: case 0x2C: {
      int k = off == 0x1C ? 0 : (int)(off - 0x24u) / 4 + 1;
      return (h->mcr & (1u << 27)) ? h->p_mcmp[k] : h->mcmp[k];
    }
    }
  } else if (off < OFS_COMMON) {
    int t = (int)(off - 0x80u) / 0x80;
    hrtim_timer *x = &h->tim[t];
    uint32_t r = (off - 0x80u) % 0x80u;
    bool pre = (x->cr & (1u << 27)) != 0;
    switch (r) {
    case 0x00: return x->cr;
    case 0x04: { /* TIMxISR: O1STAT/O2STAT copies of the output levels (bits 18/19) */
      uint32_t lv = hrtim_levels(b, board_now(b));
      return x->isr | (((lv >> (2 * t)) & 1u) << 18) | (((lv >> (2 * t + 1)) & 1u) << 19);
    }
    case 0x08: return 0;
    case 0x0C: return x->dier;
    case 0x10: return counter(b, x->per);
    case 0x14: return pre ? x->p_per : x->per;
    case 0x18: return pre ? x->p_rep : x->rep;
    case 0x1C: return pre ? x->p_cmp[0] : x->cmp[0];
    case 0x24: return pre ? x->p_cmp[1] : x->cmp[1];
    case 0x28: return pre ? x->p_cmp[2] : x->cmp[2];
    case 0x2C: return pre ? x->p_cmp[3] : x->cmp[3];
    case 0x38: return x->dtr;
    case 0x3C: return pre ? x->p_set[0] : x->set[0];
    case 0x40: return pre ? x->p_rst[0] : x->rst[0];
    case 0x44: return pre ? x->p_set[1] : x->set[1];
    case 0x48: return pre ? x->p_rst[1] : x->rst[1];
    case 0x64: return x->outr;
    case 0x68: return x->fltr;
    }
  } else {
    switch (off - OFS_COMMON) {
    case 0x00: return h->cr1;
    case 0x04: return 0; /* CR2: software update bits read as 0 once done */
    case 0x08: return h->isr;
    case 0x0C: return 0;
    case 0x10: return h->ier;
    case 0x14: return h->oen;             /* OENR reads the enable status (§27.5, HRTIM_OENR) */
    case 0x18: return 0;
    case 0x1C: return h->fault_state & ~h->oen; /* ODSR: 1 = disabled in the fault state */
    case 0x3C: case 0x40: case 0x44: case 0x48: return h->adcr[(off - OFS_COMMON - 0x3Cu) / 4u];
    case 0x30: case 0x34: case 0x38: return h->eecr[(off - OFS_COMMON - 0x30u) / 4u];
    case 0x50: return h->fltinr1;
    case 0x54: return h->fltinr2;
    }
  }
  board_fault(b, "read of HRTIM register at offset 0x%03X: not modelled", off);
  return 0;
}

static void start_stop(board *b, uint32_t old, uint32_t v) {
  hrtim_state *h = &b->hrtim;
  uint32_t en_old = old & (0x7Fu << 16), en_new = v & (0x7Fu << 16);
  if (en_old == en_new) return;
  if (en_old == 0 && en_new == (0x7Fu << 16)) {
    /* all counters start together: the port's synchronous scheme */
    unsigned psc = ckpsc(h->mcr);
    if (psc < 5u) { board_fault(b, "HRTIM_MCR CKPSC %u: high resolution needs the DLL, not modelled", psc); return; }
    for (int t = 0; t < 6; t++) {
      if (ckpsc(h->tim[t].cr) != psc) {
        board_fault(b, "HRTIM timer %c prescaler %u differs from the master's %u (not modelled)", k_tname[t],
                    ckpsc(h->tim[t].cr), psc);
        return;
      }
      if (!(h->tim[t].cr & 8u)) { board_fault(b, "HRTIM timer %c not in continuous mode (not modelled)", k_tname[t]); return; }
    }
    if (!(h->mcr & 8u)) { board_fault(b, "HRTIM master not in continuous mode (not modelled)"); return; }
    if (!(f_hrtim(b) > 0)) { board_fault(b, "HRTIM started without a clock"); return; }
    h->t_count = (double)(1u << psc) / (32.0 * f_hrtim(b));
    h->running = true;
    double t0 = board_now(b);
    /* the outputs take the crossbar's present level when the counters start: with dead time,
     * output 2 is the complement of output 1 (after its dead time, §27.3.10) */
    for (int t = 0; t < 6; t++) {
      if (h->tim[t].outr & (1u << 8)) {
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
  bool pre = (x->cr & (1u << 27)) != 0;
  char name[24];
  bool running_now = h->running;
  switch (r) {
  case 0x00: {
    const uint32_t ok = 7u | (1u << 3) | (1u << 17) | (1u << 27);
    if (v & ~ok) {
      board_fault(b, "HRTIM_TIM%cCR 0x%08X: bits 0x%08X not modelled (the port uses CKPSC, CONT, TxREPU, PREEN)",
                  k_tname[t], v, v & ~ok);
      return;
    }
    if (running_now && ckpsc(v) != ckpsc(x->cr)) { board_fault(b, "HRTIM_TIM%cCR: CKPSC changed while counting", k_tname[t]); return; }
    x->cr = v;
    return;
  }
  case 0x08: x->isr &= ~v; return;
  case 0x0C:
    if (v) { board_fault(b, "HRTIM_TIM%cDIER 0x%08X: timer interrupts/DMA not modelled", k_tname[t], v); return; }
    x->dier = v;
    return;
  case 0x14:
    if (v & ~0xFFFFu || v > 0xFFDFu || v < 3u) {
      board_fault(b, "HRTIM_PER%cR %u: outside 3..0xFFDF (RM0440 §27.5)", k_tname[t], v); return;
    }
    if (pre) x->p_per = v; else { x->per = x->p_per = v; }
    return;
  case 0x18:
    if (v & ~0xFFu) { board_fault(b, "HRTIM_REP%cR 0x%08X: bits 31:8 reserved", k_tname[t], v); return; }
    if (v) { board_fault(b, "HRTIM_REP%cR %u: repetition counts other than 0 not modelled", k_tname[t], v); return; }
    if (pre) x->p_rep = v; else x->rep = x->p_rep = v;
    return;
  case 0x1C: case 0x24: case 0x28: case 0x2C: {
    int k = r == 0x1C ? 0 : (int)(r - 0x24u) / 4 + 1;
    snprintf(name, sizeof name, "HRTIM_CMP%d%cR", k + 1, k_tname[t]);
    if (!check_cmp(b, name, v)) return;
    if (pre) x->p_cmp[k] = v; else x->cmp[k] = x->p_cmp[k] = v;
    return;
  }
  case 0x38:
    if (((x->dtr & (1u << 15)) && ((v ^ x->dtr) & 0x7FFFu)) || ((x->dtr & (1u << 31)) && ((v ^ x->dtr) & 0x7FFF0000u))) {
      board_fault(b, "HRTIM_DT%cR written while locked (DTRLK/DTFLK, RM0440 §27.5)", k_tname[t]);
      return;
    }
    if (v & ((1u << 9) | (1u << 25) | (1u << 14) | (1u << 30))) {
      board_fault(b, "HRTIM_DT%cR 0x%08X: negative dead time (SDTR/SDTF) or sign locks not modelled", k_tname[t], v);
      return;
    }
    if (((v >> 10) & 7u) < 3u) {
      board_fault(b, "HRTIM_DT%cR DTPRSC %u: a dead-time step finer than tHRTIM needs the high-resolution "
                  "delay line (DLL), not available in the low-resolution mode the model supports", k_tname[t], (v >> 10) & 7u);
      return;
    }
    if (running_now && (h->oen & (3u << (2 * t)))) {
      board_fault(b, "HRTIM_DT%cR changed while the timer's outputs are enabled", k_tname[t]);
      return;
    }
    x->dtr = v;
    return;
  case 0x3C: case 0x40: case 0x44: case 0x48: {
    int out = r >= 0x44u;
    bool is_set = r == 0x3Cu || r == 0x44u;
    /* PER, CMP1-4; external event 6 as a reset of output 1 (the fault line's second input); the
     * software set of output 1 (SST, bit 0) */
    const uint32_t ok = 0x7Cu | (!is_set && out == 0 ? RST_EEV6 : 0u) | (is_set && out == 0 ? 1u : 0u);
    if (v & ~ok) {
      board_fault(b, "HRTIM_%s%c%dR 0x%08X: event sources 0x%08X not modelled (PER, CMP1-4%s only)",
                  is_set ? "SET" : "RST", k_tname[t], out + 1, v, v & ~ok,
                  !is_set && out == 0 ? ", EXTEVNT6 (external event 6, PB5)" : "");
      return;
    }
    if (is_set && (v & 1u)) { /* SST: set output 1 now, whatever the preload (a reset request still wins) */
      software_set(b, t);
      v &= ~1u;
    }
    uint32_t *reg = is_set ? (pre ? &x->p_set[out] : &x->set[out]) : (pre ? &x->p_rst[out] : &x->rst[out]);
    *reg = v;
    if (!pre) { if (is_set) x->p_set[out] = v; else x->p_rst[out] = v; }
    return;
  }
  case 0x64: {
    const uint32_t ok = 0x003B003Bu | (1u << 8); /* POLx, IDLESx, FAULTx (bits 1,3,4,5 and +16), DTEN */
    if (v & ~ok) { board_fault(b, "HRTIM_OUT%cR 0x%08X: bits 0x%08X not modelled", k_tname[t], v, v & ~ok); return; }
    if (((v >> 4) & 3u) == 3u || ((v >> 20) & 3u) == 3u) {
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
  case 0x68:
    if (x->fltr & (1u << 31)) { board_fault(b, "HRTIM_FLT%cR written while FLTLCK is set (RM0440 §27.5)", k_tname[t]); return; }
    if (v & ~((1u << 31) | 0x3Fu)) { board_fault(b, "HRTIM_FLT%cR 0x%08X: reserved bits", k_tname[t], v); return; }
    x->fltr = v;
    return;
  }
  board_fault(b, "write 0x%08X to HRTIM timer %c register offset 0x%02X: not modelled", v, k_tname[t], r);
}

void hrtim_write(board *b, uint32_t off, uint32_t v) {
  hrtim_state *h = &b->hrtim;
  hrtim_event(b);
  if (off < 0x80u) {
    bool pre = (h->mcr & (1u << 27)) != 0;
    switch (off) {
    case 0x00: {
      const uint32_t ok = 7u | (1u << 3) | (0x7Fu << 16) | (1u << 27) | (1u << 29);
      if (v & ~ok) { board_fault(b, "HRTIM_MCR 0x%08X: bits 0x%08X not modelled", v, v & ~ok); return; }
      uint32_t old = h->mcr;
      if (h->running && ckpsc(v) != ckpsc(old)) { board_fault(b, "HRTIM_MCR: CKPSC changed while counting"); return; }
      h->mcr = v;
      start_stop(b, old, v);
      return;
    }
    case 0x08: h->misr &= ~v; return;
    case 0x0C:
      if (v & ~0x7Fu) { board_fault(b, "HRTIM_MDIER 0x%08X: DMA requests not modelled", v); return; }
      h->mdier = v;
      pend_master(b);
      return;
    case 0x14:
      if (v > 0xFFDFu || v < 3u) { board_fault(b, "HRTIM_MPER %u: outside 3..0xFFDF (RM0440 §27.5)", v); return; }
      if (pre) h->p_mper = v; else h->mper = h->p_mper = v;
      return;
    case 0x18:
      if (v) { board_fault(b, "HRTIM_MREP %u: repetition counts other than 0 not modelled", v); return; }
      h->mrep = h->p_mrep = 0;
      return;
    case 0x1C: case 0x24: case 0x28: case 0x2C: {
      int k = off == 0x1C ? 0 : (int)(off - 0x24u) / 4 + 1;
      char name[16];
      snprintf(name, sizeof name, "HRTIM_MCMP%dR", k + 1);
      if (!check_cmp(b, name, v)) return;
      if (pre) h->p_mcmp[k] = v; else h->mcmp[k] = h->p_mcmp[k] = v;
      return;
    }
    }
  } else if (off < OFS_COMMON) {
    write_timer(b, (int)(off - 0x80u) / 0x80, (off - 0x80u) % 0x80u, v);
    return;
  } else {
    switch (off - OFS_COMMON) {
    case 0x00:
      if (v & ~0x7Fu) { board_fault(b, "HRTIM_CR1 0x%08X: ADC update sources not modelled", v); return; }
      h->cr1 = v;
      return;
    case 0x04:
      if (v & ~0x7Fu) { board_fault(b, "HRTIM_CR2 0x%08X: counter software resets / swaps not modelled", v); return; }
      if (v & 1u) transfer(h, -1);
      for (int t = 0; t < 6; t++) if (v & (1u << (t + 1))) transfer(h, t);
      return;
    case 0x0C: h->isr &= ~(v & 0x3Fu); return; /* FLTxC, SYSFLTC */
    case 0x10:
      if (v & ~0x3Fu) { board_fault(b, "HRTIM_IER 0x%08X: burst/DLL interrupts not modelled", v); return; }
      h->ier = v;
      if (h->isr & h->ier & 0x3Fu) scs_set_pending(b, 16 + IRQ_HRTIM_FLT);
      return;
    case 0x14: { /* OENR: enable; an output whose fault is still active stays in its fault state */
      if (v & ~0xFFFu) { board_fault(b, "HRTIM_OENR 0x%08X: bits 31:12 reserved", v); return; }
      twin_sync(b, board_now(b));
      uint32_t blocked = 0;
      if (flt3_active(h))
        for (int o = 0; o < HRTIM_NOUT; o++)
          if ((h->tim[o / 2].fltr & 4u) && ((h->tim[o / 2].outr >> (4u + 16u * (unsigned)(o & 1))) & 3u)) blocked |= 1u << o;
      h->oen |= v & ~blocked;
      h->fault_state &= ~(v & ~blocked);
      return;
    }
    case 0x18:
      if (v & ~0xFFFu) { board_fault(b, "HRTIM_ODISR 0x%08X: bits 31:12 reserved", v); return; }
      twin_sync(b, board_now(b));
      h->oen &= ~v;
      return;
    case 0x3C: case 0x40: case 0x44: case 0x48: {
      const uint32_t ok = 0x1Fu; /* master CMP1-4, master period */
      if (v & ~ok) { board_fault(b, "HRTIM_ADC%uR 0x%08X: trigger sources other than the master not modelled", (off - OFS_COMMON - 0x3Cu) / 4u + 1u, v); return; }
      if (v & 0x10u) { board_fault(b, "HRTIM_ADCxR: master period trigger not modelled"); return; }
      h->adcr[(off - OFS_COMMON - 0x3Cu) / 4u] = v;
      return;
    }
    case 0x30: case 0x34: case 0x38: { /* EECR1-3, §27.5 (HRTIM_EECRx) */
      int k = (int)(off - OFS_COMMON - 0x30u) / 4;
      if (h->running) {
        board_fault(b, "HRTIM_EECR%d written while the counters run: the external event configuration must not "
                    "change once a timer using it is enabled (RM0440 §27.5, HRTIM_EECRx)", k + 1);
        return;
      }
      if (k == 0 && v) { board_fault(b, "HRTIM_EECR1 0x%08X: external events 1-5 are not wired on this board model", v); return; }
      if (k == 1) {
        for (int e = 0; e < 5; e++) { /* 6 bits per event: SRC 0-1, POL 2, SNS 3-4, bit 5 reserved */
          uint32_t f = (v >> (6 * e)) & 0x3Fu;
          if (e > 0 && f) { board_fault(b, "HRTIM_EECR2: external event %d is not wired on this board model", e + 6); return; }
          if (f & 0x20u) { board_fault(b, "HRTIM_EECR2 0x%08X: reserved bit", v); return; }
          if (f & 3u) { board_fault(b, "HRTIM_EECR2 EE6SRC %u: only source 1 (the HRTIM_EEV6 pin) is modelled", f & 3u); return; }
          if (f & 0x18u) { board_fault(b, "HRTIM_EECR2 EE6SNS %u: edge sensitivity not modelled (level only)", (f >> 3) & 3u); return; }
        }
        if (v & 0xC0000000u) { board_fault(b, "HRTIM_EECR2 0x%08X: reserved bits", v); return; }
      }
      if (k == 2) {
        if (v & ~(0xFu | (3u << 30))) { board_fault(b, "HRTIM_EECR3 0x%08X: filters of external events 7-10 (not wired on this board model) or reserved bits", v); return; }
      }
      h->eecr[k] = v;
      hrtim_eev_input_update(b, h->eev6_pin_low); /* a polarity change is an input change */
      return;
    }
    case 0x50: {
      uint32_t old = h->fltinr1;
      /* per input byte: FLTxE bit 0, FLTxP 1, FLTxSRC 2, FLTxF 3-6, FLTxLCK 7 */
      for (int k = 0; k < 4; k++) {
        uint32_t ob = (old >> (8 * k)) & 0xFFu, nb = (v >> (8 * k)) & 0xFFu;
        if ((ob & 0x80u) && ob != nb) { board_fault(b, "HRTIM_FLTINR1 FLT%d written while FLT%dLCK is set", k + 1, k + 1); return; }
        if ((ob & 1u) && (nb & 1u) && ((ob ^ nb) & 0x7Eu)) {
          board_fault(b, "HRTIM_FLTINR1 FLT%d: polarity, source or filter changed while FLT%dE = 1 (RM0440 §27.5, "
                      "HRTIM_FLTINR1)", k + 1, k + 1);
          return;
        }
        if ((nb & 1u) && k != 2) { board_fault(b, "HRTIM_FLTINR1: fault input FLT%d not wired on this board model", k + 1); return; }
        if ((nb & 4u)) { board_fault(b, "HRTIM_FLTINR1 FLT%dSRC: internal comparator source not modelled", k + 1); return; }
        if ((nb & 0x78u)) { board_fault(b, "HRTIM_FLTINR1 FLT%dF: digital filter not modelled", k + 1); return; }
      }
      h->fltinr1 = v;
      if (!(old & (1u << 16)) && (v & (1u << 16)) && flt3_active(h)) h->flt3_apply_t = board_now(b) + FLT_SYNC_TICKS / f_hrtim(b);
      return;
    }
    case 0x54:
      if (v & 0x0101u) { board_fault(b, "HRTIM_FLTINR2: FLT5/FLT6 not wired on this board model"); return; }
      if (v & ~(0x0101FFFFu | (3u << 24))) { board_fault(b, "HRTIM_FLTINR2 0x%08X: not modelled", v); return; }
      h->fltinr2 = v;
      return;
    }
  }
  board_fault(b, "write 0x%08X to HRTIM register at offset 0x%03X: not modelled", v, off);
}
