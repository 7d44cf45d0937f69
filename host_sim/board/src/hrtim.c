/* HRTIM, a first subset (RM0440, HRTIM chapter; register map and reset values from the SVD):
 * DLL calibration (DLLCR.CAL -> ISR.DLLRDY), timers A-F in continuous up-counting mode with
 * prescaler CKPSC (f = 32 x fHRTIM / 2^CKPSC), period PER (period = PER counter ticks, as in
 * ST's HRTIM cookbook AN4539), compares 1-4, set/reset crossbar from PER and CMP1-4 (reset wins
 * on a tie), software set/reset (SST/SRT), dead time on output pairs (DTEN, DTR/DTF, DTPRSC),
 * polarity, output enable/disable (OENR/ODISR/ODSR) with the idle level, fault inputs 1-6 as a
 * host input (FLTINR1/2 enable, FLTxR per timer, OUTxR.FAULTx state, outputs disabled, ISR.FLTn),
 * repetition counters with REP interrupts (master IRQ 67, timers 68-72, 74), the master timer
 * (period, compares, MSTPER/MSTCMPx as set/reset sources), and preload (PREEN) with the
 * transfer on the repetition event (TxREPU/MREPU). Everything else (half/interleaved/push-pull
 * modes, external events, capture, burst mode, ADC triggers, counter reset sources) is refused
 * as not modelled rather than guessed. Index 6 of the timer array is the master timer. */
#include "board_priv.h"
#include <math.h>
#include <string.h>

#define MST_OFF 0x000u
#define TIM_OFF(x) (0x080u + 0x80u * (uint32_t)(x))
#define CMN_OFF 0x380u
static const int k_irq[7] = {68, 69, 70, 71, 72, 74, 67};
#define MST 6
#define DLL_CAL_S 14e-6 /* calibration time: order of the datasheet's t_DLL */

void hrtim_reset(board *b) {
  memset(&b->hr, 0, sizeof b->hr);
  for (int x = 0; x < 7; x++) {
    b->hr.t[x].per = b->hr.t[x].pre_per = 0xFFFFu;
    b->hr.t[x].sw_t[0] = b->hr.t[x].sw_t[1] = -INFINITY;
  }
  b->hr.dll_ready_t = -1;
}

static double f_hrtim(board *b) {
  uint32_t ppre2 = (b->rcc.cfgr >> 11) & 7u;
  double hclk = rcc_hclk_hz(b);
  return ppre2 < 4 ? hclk : 2.0 * hclk / (double)(1u << (ppre2 - 3)); /* APB2 timer clock */
}

static uint32_t ckpsc(const board *b, int x) { return (x == MST ? b->hr.mcr : b->hr.t[x].cr) & 7u; }
static double tick_s(board *b, int x) { return (double)(1u << ckpsc(b, x)) / (32.0 * f_hrtim(b)); }
static double period_s(board *b, int x) { return (double)b->hr.t[x].per * tick_s(b, x); }
static bool running(const board *b, int x) { return (b->hr.mcr >> (x == MST ? 16 : 17 + x)) & 1u; }

/* Time of the latest period (is_per) or compare-at-pos event of timer x at or before t;
 * -INFINITY if none yet. The counter starts at 0 at start_t and rolls over every PER ticks. */
static double last_event(board *b, int x, bool is_per, uint32_t pos, double t) {
  hrtim_timer *T = &b->hr.t[x];
  if (!running(b, x) || t < T->start_t || T->per == 0) return -INFINITY;
  double per = period_s(b, x);
  if (is_per) {
    double k = floor((t - T->start_t) / per);
    return k < 1 ? -INFINITY : T->start_t + k * per;
  }
  if (pos >= T->per) return -INFINITY; /* never matched */
  double off = (double)pos * tick_s(b, x);
  if (t < T->start_t + off) return -INFINITY;
  return T->start_t + off + floor((t - T->start_t - off) / per) * per;
}

/* Level of output o (0/1) of timer x from the crossbar, before dead time and polarity: the
 * latest set or reset event at or before t decides (reset wins a tie). Sources: the timer's
 * PER and CMP1-4, the master's MSTPER and MSTCMP1-4, software SST/SRT. */
static int crossbar(board *b, int x, int o, double t) {
  hrtim_timer *T = &b->hr.t[x];
  double best = T->sw_t[o] <= t ? T->sw_t[o] : -INFINITY;
  int level = T->sw_level[o];
  for (int act = 0; act < 2; act++) {
    uint32_t reg = act == 0 ? T->set[o] : T->rst[o];
    for (int bit = 2; bit <= 11; bit++) {
      if (!((reg >> bit) & 1u)) continue;
      int src = bit <= 6 ? x : MST;
      int k = bit <= 6 ? bit - 2 : bit - 7; /* 0 = PER, 1..4 = CMP1..4 */
      double e = last_event(b, src, k == 0, k == 0 ? 0u : b->hr.t[src].cmp[k - 1], t);
      if (e > best || (e == best && e > -INFINITY && act == 1)) { best = e; level = act == 0; }
    }
  }
  return level;
}

int board_hrtim_output(board *b, int x, int o, double t) {
  hrtim_timer *T = &b->hr.t[x];
  uint32_t outr = T->outr, pol = o ? (outr >> 17) & 1u : (outr >> 1) & 1u;
  uint32_t idles = o ? (outr >> 19) & 1u : (outr >> 3) & 1u;
  int ch = 2 * x + o;
  if (b->hr.faulted[ch]) {
    uint32_t f = o ? (outr >> 20) & 3u : (outr >> 4) & 3u;
    if (f == 1u) return (int)(1u ^ pol);
    if (f == 2u) return (int)pol;
    if (f == 3u) return -1; /* high impedance */
  }
  if (!((b->hr.oen >> ch) & 1u)) return (int)(idles ^ pol);
  int lv;
  if (outr & (1u << 8)) { /* dead time: out2 is the complement of out1, rising edges delayed */
    uint32_t dt = T->dt;
    double tdtg = (double)(1u << ((dt >> 10) & 7u)) / (8.0 * f_hrtim(b));
    double dtr = (double)(dt & 0x1FFu) * tdtg, dtf = (double)((dt >> 16) & 0x1FFu) * tdtg;
    int now1 = crossbar(b, x, 0, t);
    lv = o == 0 ? (now1 && crossbar(b, x, 0, t - dtr)) : (!now1 && !crossbar(b, x, 0, t - dtf));
  } else {
    lv = crossbar(b, x, o, t);
  }
  return (int)((uint32_t)lv ^ pol);
}

void board_hrtim_fault(board *b, int n, int active) {
  if (n < 1 || n > 6) return;
  uint32_t fltinr = n <= 4 ? b->hr.fltinr1 >> (8 * (n - 1)) : b->hr.fltinr2 >> (8 * (n - 5));
  if (!active || !(fltinr & 1u)) return; /* FLTnE */
  b->hr.isr |= 1u << (n == 6 ? 6 : n - 1);
  for (int x = 0; x < 6; x++)
    if ((b->hr.t[x].flt >> (n - 1)) & 1u)
      for (int o = 0; o < 2; o++) {
        b->hr.faulted[2 * x + o] = 1;
        b->hr.oen &= ~(1u << (2 * x + o)); /* ODSR shows the fault-disabled state */
      }
}

static bool rep_tracked(const board *b, int x) {
  const hrtim_timer *T = &b->hr.t[x];
  return running(b, x) && ((T->dier & 0x10u) || T->preload_pending);
}

double hrtim_next_event(board *b) {
  double t = b->hr.dll_ready_t >= 0 ? b->hr.dll_ready_t : INFINITY;
  for (int x = 0; x < 7; x++)
    if (rep_tracked(b, x) && b->hr.t[x].next_rep_t < t) t = b->hr.t[x].next_rep_t;
  return t;
}

/* Preloaded PER/CMP/REP become active at the repetition event when TxREPU/MREPU is set; the
 * counter rolls over to 0 there, so the timebase restarts at that instant. */
static void rep_event(board *b, int x, double when) {
  hrtim_timer *T = &b->hr.t[x];
  uint32_t repu = x == MST ? (b->hr.mcr >> 29) & 1u : (T->cr >> 17) & 1u;
  T->isr |= 0x10u; /* REP */
  if (T->preload_pending && repu) {
    T->per = T->pre_per;
    memcpy(T->cmp, T->pre_cmp, sizeof T->cmp);
    T->rep = T->pre_rep;
    T->preload_pending = false;
    T->start_t = when;
  }
  T->next_rep_t = when + period_s(b, x) * (double)(T->rep + 1u);
}

void hrtim_event(board *b) {
  double now = board_now(b);
  if (b->hr.dll_ready_t >= 0 && now >= b->hr.dll_ready_t) { b->hr.isr |= 1u << 16; b->hr.dll_ready_t = -1; }
  for (int x = 0; x < 7; x++) {
    hrtim_timer *T = &b->hr.t[x];
    if (!running(b, x)) continue;
    while (T->next_rep_t <= now + 1e-15) rep_event(b, x, T->next_rep_t);
    if ((T->isr & T->dier & 0x10u) && !b->scs.active[16 + k_irq[x]] && !b->scs.pending[16 + k_irq[x]])
      b->scs.pending[16 + k_irq[x]] = 1;
  }
}

static bool refuse(board *b, const char *reg, uint32_t v, uint32_t allowed) {
  if (v & ~allowed) {
    board_fault(b, "HRTIM %s 0x%08X: bits 0x%08X are reserved or not modelled", reg, v, v & ~allowed);
    return true;
  }
  return false;
}

static const char *tname(int x) {
  static const char *n[7] = {"TIMA", "TIMB", "TIMC", "TIMD", "TIME", "TIMF", "Master"};
  return n[x];
}

/* Registers at the same offsets in the master and in timers A-F: ISR, ICR, DIER, CNT, PER,
 * REP, CMP1-4. Returns false when the offset is not one of them. */
static bool counter_read(board *b, int x, uint32_t r, uint32_t *v) {
  hrtim_timer *T = &b->hr.t[x];
  switch (r) {
  case 0x04: *v = T->isr; return true;
  case 0x0C: *v = T->dier; return true;
  case 0x10:
    *v = running(b, x) ? (uint32_t)fmod((board_now(b) - T->start_t) / tick_s(b, x), (double)T->per) : 0u;
    return true;
  /* software accesses the preload registers (equal to the active ones without PREEN) */
  case 0x14: *v = T->pre_per; return true;
  case 0x18: *v = T->pre_rep; return true;
  case 0x1C: *v = T->pre_cmp[0]; return true;
  case 0x24: case 0x28: case 0x2C: *v = T->pre_cmp[(r - 0x20) / 4]; return true;
  }
  return false;
}

static bool preload_on(const board *b, int x) { return ((x == MST ? b->hr.mcr : b->hr.t[x].cr) >> 27) & 1u; }

static bool counter_write(board *b, int x, uint32_t r, uint32_t v) {
  hrtim_timer *T = &b->hr.t[x];
  switch (r) {
  case 0x08: T->isr &= ~(v & 0x3FFFu); return true; /* ICR */
  case 0x0C:
    if (v & ~0x10u) { board_fault(b, "HRTIM %s DIER 0x%08X: only REPIE is modelled", tname(x), v); return true; }
    T->dier = v;
    return true;
  case 0x14: case 0x1C: case 0x24: case 0x28: case 0x2C: {
    uint32_t ck = ckpsc(b, x), min = ck <= 5 ? 3u << (5 - ck) : 3u; /* at least 3 fHRTIM periods */
    if (v > 0xFFFFu || (v < min && !(r != 0x14 && v == 0))) {
      board_fault(b, "HRTIM %s %s 0x%X outside 0x%X..0xFFFF for CKPSC=%u (RM0440: at least 3 fHRTIM periods)",
                  tname(x), r == 0x14 ? "PER" : "CMP", v, min, ck);
      return true;
    }
    uint32_t *pre = r == 0x14 ? &T->pre_per : &T->pre_cmp[r == 0x1C ? 0 : (r - 0x20) / 4];
    uint32_t *act = r == 0x14 ? &T->per : &T->cmp[r == 0x1C ? 0 : (r - 0x20) / 4];
    *pre = v;
    if (preload_on(b, x) && running(b, x)) T->preload_pending = true;
    else *act = v;
    return true;
  }
  case 0x18:
    if (v > 0xFFu) { board_fault(b, "HRTIM %s REP 0x%X > 0xFF", tname(x), v); return true; }
    T->pre_rep = v;
    if (preload_on(b, x) && running(b, x)) T->preload_pending = true;
    else T->rep = v;
    return true;
  }
  return false;
}

uint32_t hrtim_read(board *b, uint32_t off) {
  hrtim_state *h = &b->hr;
  uint32_t v;
  if (off < TIM_OFF(0)) {
    if (off == 0x00) return h->mcr;
    if (counter_read(b, MST, off, &v)) return v;
  } else if (off < CMN_OFF) {
    int x = (int)((off - TIM_OFF(0)) / 0x80u);
    hrtim_timer *T = &h->t[x];
    uint32_t r = (off - TIM_OFF(0)) % 0x80u;
    if (counter_read(b, x, r, &v)) return v;
    switch (r) {
    case 0x00: return T->cr;
    case 0x38: return T->dt;
    case 0x3C: return T->set[0];
    case 0x40: return T->rst[0];
    case 0x44: return T->set[1];
    case 0x48: return T->rst[1];
    case 0x64: return T->outr;
    case 0x68: return T->flt;
    }
  } else {
    switch (off - CMN_OFF) {
    case 0x08: return h->isr;
    case 0x14: return h->oen;
    case 0x18: return 0;
    case 0x1C: { uint32_t d = 0; for (int c = 0; c < 12; c++) if (h->faulted[c] && !((h->oen >> c) & 1u)) d |= 1u << c; return d; }
    case 0x4C: return h->dllcr;
    case 0x50: return h->fltinr1;
    case 0x54: return h->fltinr2;
    }
  }
  board_fault(b, "read of HRTIM offset 0x%03X: not modelled", off);
  return 0;
}

static void timer_write(board *b, int x, uint32_t r, uint32_t v) {
  hrtim_timer *T = &b->hr.t[x];
  char name[16];
  if (counter_write(b, x, r, v)) return;
  switch (r) {
  case 0x00: /* TIMxCR: CKPSC, CONT, TxREPU, PREEN */
    snprintf(name, sizeof name, "TIM%cCR", 'A' + x);
    if (refuse(b, name, v, 0x0802000Fu)) return;
    if (!(v & 8u)) { board_fault(b, "HRTIM TIM%cCR.CONT=0: single-shot mode is not modelled", 'A' + x); return; }
    if (running(b, x) && ((v ^ T->cr) & 0xFu)) { board_fault(b, "HRTIM TIM%cCR: CKPSC/CONT changed while the timer runs", 'A' + x); return; }
    T->cr = v;
    return;
  case 0x38:
    snprintf(name, sizeof name, "DT%cR", 'A' + x);
    if (refuse(b, name, v, 0x01FF1DFFu & ~0x200u)) return; /* no negative dead time, no locks */
    T->dt = v;
    return;
  case 0x3C: case 0x40: case 0x44: case 0x48: {
    int o = r >= 0x44, set = r == 0x3C || r == 0x44;
    snprintf(name, sizeof name, "%s%c%dR", set ? "SET" : "RST", 'A' + x, o + 1);
    if (refuse(b, name, v, 0xFFDu)) return; /* SST/SRT, PER, CMP1-4, MSTPER, MSTCMP1-4 */
    if (v & 1u) { T->sw_level[o] = set; T->sw_t[o] = board_now(b); } /* software set/reset */
    if (set) T->set[o] = v & ~1u; else T->rst[o] = v & ~1u;
    return;
  }
  case 0x64:
    snprintf(name, sizeof name, "OUT%cR", 'A' + x);
    if (refuse(b, name, v, 0x003A013Au)) return; /* POL, IDLES, FAULT, DTEN */
    T->outr = v;
    return;
  case 0x68:
    snprintf(name, sizeof name, "FLT%cR", 'A' + x);
    if (refuse(b, name, v, 0x3Fu)) return;
    T->flt = v;
    return;
  }
  board_fault(b, "write 0x%08X to HRTIM timer %c offset 0x%02X: not modelled", v, 'A' + x, r);
}

void hrtim_write(board *b, uint32_t off, uint32_t v) {
  hrtim_state *h = &b->hr;
  if (off < TIM_OFF(0)) {
    if (off == 0x00) {
      /* MCR: CKPSC, CONT, MCEN, TxCEN, PREEN, MREPU */
      if (refuse(b, "MCR", v, 0x287F000Fu)) return;
      if ((v & (1u << 16)) && !(v & 8u)) { board_fault(b, "HRTIM MCR.CONT=0: single-shot master is not modelled"); return; }
      if (running(b, MST) && ((v ^ h->mcr) & 0xFu)) { board_fault(b, "HRTIM MCR: CKPSC/CONT changed while the master runs"); return; }
      double now = board_now(b);
      uint32_t old = h->mcr;
      h->mcr = (h->mcr & 0x007F0000u) | (v & ~0x007F0000u); /* prescaler first: the master's tick */
      for (int x = 0; x < 7; x++) {
        uint32_t bit = 1u << (x == MST ? 16 : 17 + x);
        if ((v & bit) && !(old & bit)) {
          if (ckpsc(b, x) < 5u && !(h->isr & (1u << 16))) {
            board_fault(b, "HRTIM %s started in high resolution (CKPSC<5) before the DLL is calibrated (ISR.DLLRDY)", tname(x));
            h->mcr = old;
            return;
          }
          h->t[x].start_t = now;
          h->t[x].next_rep_t = now + period_s(b, x) * (double)(h->t[x].rep + 1u);
        }
      }
      h->mcr = v;
      return;
    }
    if (counter_write(b, MST, off, v)) return;
    board_fault(b, "write 0x%08X to HRTIM master offset 0x%02X: not modelled", v, off);
    return;
  }
  if (off < CMN_OFF) { timer_write(b, (int)((off - TIM_OFF(0)) / 0x80u), (off - TIM_OFF(0)) % 0x80u, v); return; }
  switch (off - CMN_OFF) {
  case 0x0C: h->isr &= ~(v & 0x3007Fu); return; /* ICR */
  case 0x14: /* OENR: 1 enables; a faulted output stays off until its fault flag is cleared */
    if (refuse(b, "OENR", v, 0xFFFu)) return;
    for (int c = 0; c < 12; c++)
      if ((v >> c) & 1u) {
        int n_fault = 0;
        for (int n = 0; n < 6; n++) n_fault |= (h->t[c / 2].flt >> n) & 1u && (h->isr >> (n == 5 ? 6 : n)) & 1u;
        if (n_fault) continue;
        h->faulted[c] = 0;
        h->oen |= 1u << c;
      }
    return;
  case 0x18: if (refuse(b, "ODISR", v, 0xFFFu)) return; h->oen &= ~v; return;
  case 0x4C: /* DLLCR: CAL starts a calibration */
    if (refuse(b, "DLLCR", v, 0xFu)) return;
    h->dllcr = v & ~1u;
    if (v & 1u) { h->isr &= ~(1u << 16); h->dll_ready_t = board_now(b) + DLL_CAL_S; }
    return;
  case 0x50: if (refuse(b, "FLTINR1", v, 0x03030303u)) return; h->fltinr1 = v; return; /* FLTnE, FLTnP, from pins */
  case 0x54: if (refuse(b, "FLTINR2", v, 0x0303u)) return; h->fltinr2 = v; return;
  }
  board_fault(b, "write 0x%08X to HRTIM common offset 0x%02X: not modelled", v, off - CMN_OFF);
}
