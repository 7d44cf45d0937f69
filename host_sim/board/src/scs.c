/* The private peripheral bus modelled in the host (Unicorn has no SCS for M-profile):
 * NVIC, SCB, SysTick, FPU control (CPACR, FPCCR), DWT CYCCNT and CoreDebug DEMCR.
 * ARMv7-M ARM B3.2-B3.4, C1.6; Cortex-M4 values from the Cortex-M4 TRM / ST PM0214. */
#include "board_priv.h"
#include <string.h>

#define CPUID_M4F_R0P1 0x410FC241u
#define ST_ENABLE 1u
#define ST_TICKINT 2u
#define ST_CLKSOURCE 4u
#define ST_COUNTFLAG (1u << 16)

static uint32_t uc32(board *b, int r) {
  uint32_t v = 0;
  uc_reg_read(b->uc, r, &v);
  return v;
}

void scs_reset(board *b) {
  scs_state *s = &b->scs;
  memset(s, 0, sizeof *s);
  s->ccr = 1u << 9;                    /* STKALIGN (Cortex-M4 reset value) */
  s->fpccr = 0xC0000000u;              /* ASPEN | LSPEN */
  s->st_next_zero = UINT64_MAX;
}

/* ---- SysTick: counts HCLK (CLKSOURCE=1) or HCLK/8 (CLKSOURCE=0, RM0440 §7.2) ---- */

static uint64_t st_div(const board *b) { return (b->scs.st_csr & ST_CLKSOURCE) ? 1u : 8u; }

static uint32_t st_value(const board *b) {
  const scs_state *s = &b->scs;
  if (!(s->st_csr & ST_ENABLE)) return s->st_val;
  uint64_t ticks = (b->cycles - s->st_base_cycle) / st_div(b);
  if (ticks == 0) return s->st_val;
  if (s->st_val > 0 && ticks <= s->st_val) return s->st_val - (uint32_t)ticks;
  if (s->st_rvr == 0) return 0;
  uint64_t k = ticks - s->st_val, period = (uint64_t)s->st_rvr + 1u; /* 0 -> reload -> ... -> 0 */
  return s->st_rvr - (uint32_t)((k - 1u) % period);
}

/* Freeze the current count as the new base, keeping the fractional prescaler phase. */
static void st_rebase(board *b) {
  scs_state *s = &b->scs;
  if (s->st_csr & ST_ENABLE) {
    uint64_t ticks = (b->cycles - s->st_base_cycle) / st_div(b);
    s->st_val = st_value(b);
    s->st_base_cycle += ticks * st_div(b);
  } else {
    s->st_base_cycle = b->cycles;
  }
}

static void st_schedule(board *b) {
  scs_state *s = &b->scs;
  s->st_next_zero = UINT64_MAX;
  if (!(s->st_csr & ST_ENABLE) || s->st_rvr == 0) return;
  uint64_t first = s->st_val > 0 ? s->st_val : (uint64_t)s->st_rvr + 1u;
  s->st_next_zero = s->st_base_cycle + first * st_div(b);
}

uint64_t scs_next_event(board *b) { return b->scs.st_next_zero; }

void scs_event(board *b) {
  scs_state *s = &b->scs;
  while (s->st_next_zero <= b->cycles) { /* the counter went 1 -> 0 */
    s->st_csr |= ST_COUNTFLAG;
    if (s->st_csr & ST_TICKINT) s->pending[15] = 1;
    s->st_next_zero += ((uint64_t)s->st_rvr + 1u) * st_div(b);
  }
}

/* Pend from a peripheral model: end the slice so the exception is taken promptly. */
void scs_set_pending(board *b, int exc) {
  b->scs.pending[exc] = 1;
  board_end_slice(b);
}

/* ---- DWT CYCCNT (counts while DEMCR.TRCENA and DWT_CTRL.CYCCNTENA) ---- */

static bool cyc_running(const board *b) { return (b->scs.demcr & (1u << 24)) && (b->scs.dwt_ctrl & 1u); }
static uint32_t cyc_value(const board *b) {
  return b->scs.dwt_cyccnt + (cyc_running(b) ? (uint32_t)(b->cycles - b->scs.dwt_base_cycle) : 0u);
}
static void cyc_rebase(board *b) {
  b->scs.dwt_cyccnt = cyc_value(b);
  b->scs.dwt_base_cycle = b->cycles;
}

/* ---- register file ---- */

static uint32_t icsr(board *b) {
  scs_state *s = &b->scs;
  uint32_t ipsr = uc32(b, UC_ARM_REG_IPSR) & 0x1FFu, v = ipsr;
  int nact = 0, pend = 0, bp = 1 << 30;
  for (int e = 1; e < NUM_EXC; e++) {
    nact += s->active[e];
    if (s->pending[e] && exc_priority(b, e) < bp) { bp = exc_priority(b, e); pend = e; }
  }
  if (nact <= 1) v |= 1u << 11;                 /* RETTOBASE */
  v |= (uint32_t)pend << 12;                    /* VECTPENDING */
  for (int e = 16; e < NUM_EXC; e++)
    if (s->pending[e]) v |= 1u << 22;           /* ISRPENDING */
  if (s->pending[15]) v |= 1u << 26;
  if (s->pending[14]) v |= 1u << 28;
  if (s->pending[2]) v |= 1u << 31;
  return v;
}

static uint32_t nvic_bits(const uint8_t *arr, uint32_t word) {
  uint32_t v = 0;
  for (uint32_t i = 0; i < 32; i++) {
    uint32_t irq = word * 32u + i;
    if (irq < NUM_IRQ && arr[16 + irq]) v |= 1u << i;
  }
  return v;
}

static uint32_t read_word(board *b, uint32_t a, bool *ok) {
  scs_state *s = &b->scs;
  *ok = true;
  if (a >= 0xE000E100u && a < 0xE000E120u) return nvic_bits(s->enabled, (a - 0xE000E100u) / 4);
  if (a >= 0xE000E180u && a < 0xE000E1A0u) return nvic_bits(s->enabled, (a - 0xE000E180u) / 4);
  if (a >= 0xE000E200u && a < 0xE000E220u) return nvic_bits(s->pending, (a - 0xE000E200u) / 4);
  if (a >= 0xE000E280u && a < 0xE000E2A0u) return nvic_bits(s->pending, (a - 0xE000E280u) / 4);
  if (a >= 0xE000E300u && a < 0xE000E320u) return nvic_bits(s->active, (a - 0xE000E300u) / 4);
  if (a >= 0xE000E400u && a < 0xE000E400u + NUM_IRQ + 2) { /* IPR: 4 bytes per word */
    uint32_t v = 0;
    for (uint32_t i = 0; i < 4; i++) {
      uint32_t irq = a - 0xE000E400u + i;
      if (irq < NUM_IRQ) v |= (uint32_t)s->prio[16 + irq] << (8 * i);
    }
    return v;
  }
  if (a >= 0xE000ED18u && a < 0xE000ED24u) { /* SHPR1-3: exceptions 4..15 */
    uint32_t v = 0;
    for (uint32_t i = 0; i < 4; i++) v |= (uint32_t)s->prio[4 + (a - 0xE000ED18u) + i] << (8 * i);
    return v;
  }
  switch (a) {
  case 0xE000E004u: return (NUM_IRQ + 31) / 32 - 1; /* ICTR */
  case 0xE000E008u: return 0;                       /* ACTLR */
  case 0xE000E010u: { uint32_t v = s->st_csr; s->st_csr &= ~ST_COUNTFLAG; return v; }
  case 0xE000E014u: return s->st_rvr;
  case 0xE000E018u: return st_value(b);
  case 0xE000E01Cu: return 0x40000000u | 21250u; /* CALIB: NOREF=0... TENMS not verified against RM0440 */
  case 0xE000ED00u: return CPUID_M4F_R0P1;
  case 0xE000ED04u: return icsr(b);
  case 0xE000ED08u: return s->vtor;
  case 0xE000ED0Cu: return 0xFA050000u | (s->aircr_prigroup << 8);
  case 0xE000ED10u: return s->scr;
  case 0xE000ED14u: return s->ccr;
  case 0xE000ED24u: {
    uint32_t v = s->shcsr & 0x70000u;
    v |= s->active[4] ? 1u : 0u; v |= s->active[5] ? 2u : 0u; v |= s->active[6] ? 8u : 0u;
    v |= s->active[11] ? 0x80u : 0u; v |= s->active[14] ? 0x400u : 0u; v |= s->active[15] ? 0x800u : 0u;
    return v;
  }
  case 0xE000ED28u: return s->cfsr;
  case 0xE000ED2Cu: return s->hfsr;
  case 0xE000ED30u: case 0xE000ED34u: case 0xE000ED38u: case 0xE000ED3Cu: return 0;
  case 0xE000ED88u: return s->cpacr;
  case 0xE000ED90u: return 0x00000800u; /* MPU_TYPE: 8 regions */
  case 0xE000ED94u: return 0;           /* MPU_CTRL */
  case 0xE000EDF0u: return 0;           /* DHCSR: no debugger */
  case 0xE000EDFCu: return s->demcr;
  case 0xE000EF34u: return s->fpccr;
  case 0xE000EF38u: return s->fpcar;
  case 0xE000EF3Cu: return s->fpdscr;
  case 0xE0001000u: return 0x40000000u | (s->dwt_ctrl & 1u); /* NUMCOMP=4 */
  case 0xE0001004u: return cyc_value(b);
  default: *ok = false; return 0;
  }
}

static void set_bits(board *b, uint8_t *arr, uint32_t word, uint32_t v, uint8_t val) {
  (void)b;
  for (uint32_t i = 0; i < 32; i++)
    if ((v >> i) & 1u) {
      uint32_t irq = word * 32u + i;
      if (irq < NUM_IRQ) arr[16 + irq] = val;
    }
}

/* DBGMCU (RM0440 §47.16): IDCODE (DEV_ID 0x469, REV_ID 0x2001), CR and the freeze registers.
 * No debugger is attached, so the freeze bits have no effect. */
static bool dbgmcu_reg(board *b, uint32_t a, uint32_t **reg) {
  if (a < 0xE0042000u || a > 0xE0042010u) return false;
  *reg = a == 0xE0042000u ? NULL : &b->scs.dbgmcu[(a - 0xE0042004u) / 4u];
  return true;
}

void board_nvic_disable(board *b, int irq) {
  scs_write(b, 0xE000E180u + 4u * (uint32_t)(irq / 32), 4, 1u << (irq % 32));
}

uint32_t scs_read(board *b, uint32_t addr, unsigned size) {
  bool ok;
  uint32_t *dreg;
  if (dbgmcu_reg(b, addr & ~3u, &dreg)) return dreg ? *dreg : 0x20016469u;
  uint32_t v = read_word(b, addr & ~3u, &ok);
  if (!ok) { board_fault(b, "read of unmodelled system register 0x%08X", addr); return 0; }
  if (size >= 4) return v;
  return (v >> ((addr & 3u) * 8u)) & ((1u << (size * 8u)) - 1u);
}

void scs_write(board *b, uint32_t a, unsigned size, uint32_t v) {
  scs_state *s = &b->scs;
  uint32_t *dreg;
  if (dbgmcu_reg(b, a, &dreg)) {
    if (!dreg || size != 4) { board_fault(b, "write to DBGMCU register 0x%08X (IDCODE, or not a 32-bit write)", a); return; }
    *dreg = v;
    return;
  }
  /* byte-accessible priority registers (B3.4.9, B3.2.10-12): 4 implemented bits */
  if ((a >= 0xE000E400u && a < 0xE000E400u + NUM_IRQ + 2) || (a >= 0xE000ED18u && a < 0xE000ED24u)) {
    for (unsigned i = 0; i < size; i++) {
      uint8_t p = (uint8_t)((v >> (8 * i)) & 0xF0u);
      uint32_t byte = a + i;
      if (byte >= 0xE000ED18u) {
        int exc = 4 + (int)(byte - 0xE000ED18u);
        if (exc == 4 || exc == 5 || exc == 6 || exc == 11 || exc == 14 || exc == 15) s->prio[exc] = p;
      } else if (byte - 0xE000E400u < NUM_IRQ) {
        s->prio[16 + byte - 0xE000E400u] = p;
      }
    }
    return;
  }
  if (size != 4 || (a & 3u)) { board_fault(b, "%u-byte write to system register 0x%08X (word access only)", size, a); return; }
  if (a >= 0xE000E100u && a < 0xE000E120u) { set_bits(b, s->enabled, (a - 0xE000E100u) / 4, v, 1); return; }
  if (a >= 0xE000E180u && a < 0xE000E1A0u) { set_bits(b, s->enabled, (a - 0xE000E180u) / 4, v, 0); return; }
  if (a >= 0xE000E200u && a < 0xE000E220u) { set_bits(b, s->pending, (a - 0xE000E200u) / 4, v, 1); return; }
  if (a >= 0xE000E280u && a < 0xE000E2A0u) { set_bits(b, s->pending, (a - 0xE000E280u) / 4, v, 0); return; }
  switch (a) {
  case 0xE000E010u: /* SYST_CSR */
    st_rebase(b);
    s->st_csr = (s->st_csr & ST_COUNTFLAG) | (v & 7u);
    st_schedule(b);
    return;
  case 0xE000E014u:
    if (v > 0xFFFFFFu) { board_fault(b, "SYST_RVR 0x%08X: bits 31:24 are reserved", v); return; }
    st_rebase(b);
    s->st_rvr = v;
    st_schedule(b);
    return;
  case 0xE000E018u: /* any write clears the counter and COUNTFLAG */
    st_rebase(b);
    s->st_val = 0;
    s->st_base_cycle = b->cycles;
    s->st_csr &= ~ST_COUNTFLAG;
    st_schedule(b);
    return;
  case 0xE000ED04u: /* ICSR */
    if (v & (1u << 31)) s->pending[2] = 1;
    if (v & (1u << 28)) s->pending[14] = 1;
    if (v & (1u << 27)) s->pending[14] = 0;
    if (v & (1u << 26)) s->pending[15] = 1;
    if (v & (1u << 25)) s->pending[15] = 0;
    return;
  case 0xE000ED08u:
    /* 118 vectors round up to 128 words: TBLOFF must be 512-byte aligned (B3.2.5) */
    if (v & 0x1FFu) { board_fault(b, "VTOR 0x%08X is not 512-byte aligned for 118 vectors", v); return; }
    s->vtor = v;
    return;
  case 0xE000ED0Cu: /* AIRCR */
    if ((v >> 16) != 0x05FAu) { board_fault(b, "AIRCR write 0x%08X without VECTKEY 0x05FA: ignored by the core", v); return; }
    if (v & 3u) { board_fault(b, "AIRCR VECTRESET/VECTCLRACTIVE are for debuggers only (B3.2.6)"); return; }
    s->aircr_prigroup = (v >> 8) & 7u;
    if (v & 4u) board_request_reset(b, (1u << 28) | (1u << 26)); /* SFTRSTF, and NRST is pulsed: PINRSTF */
    return;
  case 0xE000ED10u: s->scr = v & 0x16u; return;
  case 0xE000ED14u: s->ccr = v & 0x31Bu; return;
  case 0xE000ED24u: s->shcsr = (s->shcsr & ~0x70000u) | (v & 0x70000u); return;
  case 0xE000ED28u: s->cfsr &= ~v; return;   /* write-one-to-clear */
  case 0xE000ED2Cu: s->hfsr &= ~v; return;
  case 0xE000ED88u: { /* CPACR: CP10 and CP11 must agree; 0b10 is reserved (B3.2.20) */
    uint32_t cp10 = (v >> 20) & 3u, cp11 = (v >> 22) & 3u;
    if ((v & ~0x00F00000u) || cp10 != cp11 || cp10 == 2u) {
      board_fault(b, "CPACR 0x%08X: only CP10=CP11 in {0,1,3} is defined on the Cortex-M4F", v);
      return;
    }
    s->cpacr = v;
    return;
  }
  case 0xE000ED94u:
    if (v != 0) board_fault(b, "MPU_CTRL 0x%08X: the MPU is not modelled", v);
    return;
  case 0xE000EDFCu: cyc_rebase(b); s->demcr = v & 0x010F07F1u; return;
  case 0xE000EF00u: /* STIR */
    if (v >= NUM_IRQ) { board_fault(b, "STIR %u: no such interrupt (the STM32G474 has %d)", v, NUM_IRQ); return; }
    s->pending[16 + v] = 1;
    return;
  case 0xE000EF34u: s->fpccr = (s->fpccr & ~0xC0000000u) | (v & 0xC0000000u); return;
  case 0xE000EF38u: s->fpcar = v & ~7u; return;
  case 0xE000EF3Cu: s->fpdscr = v & 0x07C00000u; return;
  case 0xE0001000u:
  case 0xE0001004u:
    if (!(s->demcr & (1u << 24))) { board_fault(b, "DWT write with DEMCR.TRCENA=0: the DWT is disabled (C1.6.5)"); return; }
    cyc_rebase(b);
    if (a == 0xE0001000u) s->dwt_ctrl = v & 1u;
    else s->dwt_cyccnt = v;
    return;
  default:
    board_fault(b, "write 0x%08X to unmodelled system register 0x%08X", v, a);
  }
}
