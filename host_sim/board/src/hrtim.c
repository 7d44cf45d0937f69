/* HRTIM, a first subset (RM0440, HRTIM chapter; register map and reset values from the SVD):
 * DLL calibration (DLLCR.CAL -> ISR.DLLRDY), timers A-F in continuous up-counting mode with
 * prescaler CKPSC (f = 32 x fHRTIM / 2^CKPSC), period PER (period = PER counter ticks, as in
 * ST's HRTIM cookbook AN4539), compares 1-4, set/reset crossbar from PER and CMP1-4 (reset wins
 * on a tie), software set/reset (SST/SRT), dead time on output pairs (DTEN, DTR/DTF, DTPRSC),
 * polarity, output enable/disable (OENR/ODISR/ODSR) with the idle level, fault inputs 1-6 as a
 * host input (FLTINR1/2 enable, FLTxR per timer, OUTxR.FAULTx state, outputs disabled, ISR.FLTn),
 * repetition counter with REP interrupt (IRQ 68-72, 74). Everything else (master timer
 * counting, half/interleaved/push-pull modes, external events, capture, burst mode, ADC
 * triggers, preload) is refused as not modelled rather than guessed. */
#include "board_priv.h"
#include <math.h>
#include <string.h>

#define MST_OFF 0x000u
#define TIM_OFF(x) (0x080u + 0x80u * (uint32_t)(x))
#define CMN_OFF 0x380u
static const int k_irq[6] = {68, 69, 70, 71, 72, 74};
#define DLL_CAL_S 14e-6 /* calibration time: order of the datasheet's t_DLL */

void hrtim_reset(board *b) {
  memset(&b->hr, 0, sizeof b->hr);
  b->hr.mper = 0xFFFFu;
  for (int x = 0; x < 6; x++) b->hr.t[x].per = 0xFFFFu;
  b->hr.dll_ready_t = -1;
}

static double f_hrtim(board *b) {
  uint32_t ppre2 = (b->rcc.cfgr >> 11) & 7u;
  double hclk = rcc_hclk_hz(b);
  return ppre2 < 4 ? hclk : 2.0 * hclk / (double)(1u << (ppre2 - 3)); /* APB2 timer clock */
}

static double tick_s(board *b, int x) { return (double)(1u << (b->hr.t[x].cr & 7u)) / (32.0 * f_hrtim(b)); }
static double period_s(board *b, int x) { return (double)b->hr.t[x].per * tick_s(b, x); }
static bool running(const board *b, int x) { return (b->hr.mcr >> (17 + x)) & 1u; }

/* Level of output o (0/1) of timer x from the crossbar, before dead time and polarity. */
static int crossbar(board *b, int x, int o, double t) {
  hrtim_timer *T = &b->hr.t[x];
  if (!running(b, x) || t < T->start_t) return T->sw_level[o];
  double tk = tick_s(b, x);
  double pos = fmod((t - T->start_t) / tk, (double)T->per); /* counter value */
  /* events of a period: position and action (+1 set, -1 reset); reset wins on a tie */
  double best = -1.0;
  int level = -2;
  double last_pos = -1.0;
  int last_level = T->sw_level[o];
  for (int src = 0; src < 5; src++) {
    uint32_t bit = 1u << (2 + src); /* PER, CMP1..CMP4 */
    double p = src == 0 ? 0.0 : (double)T->cmp[src - 1];
    if (src > 0 && T->cmp[src - 1] >= T->per) continue; /* never matched */
    for (int act = 0; act < 2; act++) {
      uint32_t reg = act == 0 ? T->set[o] : T->rst[o];
      if (!(reg & bit)) continue;
      int lv = act == 0 ? 1 : 0;
      if (p <= pos && (p > best || (p == best && lv == 0))) { best = p; level = lv; }
      if (p > last_pos || (p == last_pos && lv == 0)) { last_pos = p; last_level = lv; }
    }
  }
  if (level != -2) return level;
  /* nothing yet in this period: the last event of the previous one, if there was one */
  return (t - T->start_t) >= (double)T->per * tk ? last_level : T->sw_level[o];
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

double hrtim_next_event(board *b) {
  double t = b->hr.dll_ready_t >= 0 ? b->hr.dll_ready_t : INFINITY;
  for (int x = 0; x < 6; x++)
    if (running(b, x) && (b->hr.t[x].dier & 0x10u) && b->hr.t[x].next_rep_t < t) t = b->hr.t[x].next_rep_t;
  return t;
}

void hrtim_event(board *b) {
  double now = board_now(b);
  if (b->hr.dll_ready_t >= 0 && now >= b->hr.dll_ready_t) { b->hr.isr |= 1u << 16; b->hr.dll_ready_t = -1; }
  for (int x = 0; x < 6; x++) {
    hrtim_timer *T = &b->hr.t[x];
    if (!running(b, x) || !(T->dier & 0x10u)) continue;
    while (T->next_rep_t <= now + 1e-15) {
      T->isr |= 0x10u; /* REP */
      T->next_rep_t += period_s(b, x) * (double)(T->rep + 1u);
    }
    if ((T->isr & 0x10u) && !b->scs.active[16 + k_irq[x]] && !b->scs.pending[16 + k_irq[x]])
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

uint32_t hrtim_read(board *b, uint32_t off) {
  hrtim_state *h = &b->hr;
  if (off < TIM_OFF(0)) {
    switch (off) {
    case 0x00: return h->mcr;
    case 0x14: return h->mper;
    }
  } else if (off < CMN_OFF) {
    int x = (int)((off - TIM_OFF(0)) / 0x80u);
    hrtim_timer *T = &h->t[x];
    switch ((off - TIM_OFF(0)) % 0x80u) {
    case 0x00: return T->cr;
    case 0x04: return T->isr;
    case 0x0C: return T->dier;
    case 0x10: return running(b, x) ? (uint32_t)fmod((board_now(b) - T->start_t) / tick_s(b, x), (double)T->per) : 0u;
    case 0x14: return T->per;
    case 0x18: return T->rep;
    case 0x1C: return T->cmp[0];
    case 0x24: return T->cmp[1];
    case 0x28: return T->cmp[2];
    case 0x2C: return T->cmp[3];
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
    case 0x1C: { uint32_t v = 0; for (int c = 0; c < 12; c++) if (h->faulted[c] && !((h->oen >> c) & 1u)) v |= 1u << c; return v; }
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
  switch (r) {
  case 0x00: /* TIMxCR: CKPSC and CONT only */
    snprintf(name, sizeof name, "TIM%cCR", 'A' + x);
    if (refuse(b, name, v, 0xFu)) return;
    if (!(v & 8u)) { board_fault(b, "HRTIM TIM%cCR.CONT=0: single-shot mode is not modelled", 'A' + x); return; }
    if (running(b, x)) { board_fault(b, "HRTIM TIM%cCR written while the timer runs", 'A' + x); return; }
    T->cr = v;
    return;
  case 0x08: T->isr &= ~(v & 0x3FFFu); return; /* ICR */
  case 0x0C:
    snprintf(name, sizeof name, "TIM%cDIER", 'A' + x);
    if (refuse(b, name, v, 0x10u)) return; /* REPIE only */
    T->dier = v;
    return;
  case 0x14: case 0x1C: case 0x24: case 0x28: case 0x2C: {
    uint32_t ck = T->cr & 7u, min = ck <= 5 ? 3u << (5 - ck) : 3u; /* at least 3 fHRTIM periods */
    if (v > 0xFFFFu || (v < min && !(r != 0x14 && v == 0))) {
      board_fault(b, "HRTIM TIM%c %s 0x%X outside 0x%X..0xFFFF for CKPSC=%u (RM0440: at least 3 fHRTIM periods)",
                  'A' + x, r == 0x14 ? "PER" : "CMP", v, min, ck);
      return;
    }
    if (r == 0x14) T->per = v;
    else T->cmp[r == 0x1C ? 0 : (r - 0x20) / 4] = v;
    return;
  }
  case 0x18: if (v > 0xFFu) { board_fault(b, "HRTIM REP%cR 0x%X > 0xFF", 'A' + x, v); return; } T->rep = v; return;
  case 0x38:
    snprintf(name, sizeof name, "DT%cR", 'A' + x);
    if (refuse(b, name, v, 0x01FF1DFFu & ~0x200u)) return; /* no negative dead time, no locks */
    T->dt = v;
    return;
  case 0x3C: case 0x40: case 0x44: case 0x48: {
    int o = r >= 0x44, set = r == 0x3C || r == 0x44;
    snprintf(name, sizeof name, "%s%c%dR", set ? "SET" : "RST", 'A' + x, o + 1);
    if (refuse(b, name, v, 0x7Du)) return; /* SST/SRT, PER, CMP1-4 */
    if (v & 1u) T->sw_level[o] = set; /* software set/reset */
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
      if (refuse(b, "MCR", v, 0x007E0000u)) return; /* timer enables only: the master timer is not modelled */
      double now = board_now(b);
      for (int x = 0; x < 6; x++) {
        bool on = (v >> (17 + x)) & 1u;
        if (on && !running(b, x)) {
          if ((h->t[x].cr & 7u) < 5u && !(h->isr & (1u << 16))) {
            board_fault(b, "HRTIM timer %c started in high resolution (CKPSC<5) before the DLL is calibrated (ISR.DLLRDY)", 'A' + x);
            return;
          }
          h->t[x].start_t = now;
          h->t[x].next_rep_t = now + period_s(b, x) * (double)(h->t[x].rep + 1u);
        }
      }
      h->mcr = v;
      return;
    }
    board_fault(b, "write to HRTIM master timer offset 0x%02X: the master timer is not modelled", off);
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
