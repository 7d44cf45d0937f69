/* The private peripheral bus modelled in the host (Unicorn has no SCS for M-profile):
 * NVIC, SCB, SysTick, FPU control (CPACR, FPCCR), DWT CYCCNT and CoreDebug DEMCR.
 * ARMv7-M ARM B3.2-B3.4, C1.6; Cortex-M4 values from the Cortex-M4 TRM / ST PM0214. */
#include "board_priv.h"
#include <string.h>

#define ST_ENABLE SYST_CSR_ENABLE
#define ST_TICKINT SYST_CSR_TICKINT
#define ST_CLKSOURCE SYST_CSR_CLKSOURCE
#define ST_COUNTFLAG SYST_CSR_COUNTFLAG

/* A word of the bank of 8 NVIC words starting at `base` (ISER, ICER, ISPR, ICPR, IABR). */
static bool in_bank(uint32_t a, uint32_t base) { return a >= base && a < base + NVIC_BANK_BYTES; }

/* The byte-wide priority registers: NVIC_IPR (one byte per interrupt) and SHPR1-3. */
static bool in_ipr(uint32_t a) { return a >= NVIC_IPR0 && a < NVIC_IPR0 + NUM_IRQ + 2; }
static bool in_shpr(uint32_t a) { return a >= SCB_SHPR1 && a < SCB_SHPR_END; }

static uint32_t uc32(board *b, int r) {
  uint32_t v = 0;
  uc_reg_read(b->uc, r, &v);
  return v;
}

void scs_reset(board *b) {
  scs_state *s = &b->scs;
  memset(s, 0, sizeof *s);
  s->ccr = SCB_CCR_STKALIGN;           /* Cortex-M4 reset values */
  s->fpccr = FPU_FPCCR_ASPEN_LSPEN;
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

static bool cyc_running(const board *b) { return (b->scs.demcr & DEMCR_TRCENA) && (b->scs.dwt_ctrl & DWT_CTRL_CYCCNTENA); }
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
  uint32_t ipsr = uc32(b, UC_ARM_REG_IPSR) & SCB_ICSR_VECTACTIVE, v = ipsr;
  int nact = 0, pend = 0, bp = 1 << 30;
  for (int e = 1; e < NUM_EXC; e++) {
    nact += s->active[e];
    if (s->pending[e] && exc_priority(b, e) < bp) { bp = exc_priority(b, e); pend = e; }
  }
  if (nact <= 1) v |= SCB_ICSR_RETTOBASE;
  v |= (uint32_t)pend << SCB_ICSR_VECTPENDING_SHIFT;
  for (int e = 16; e < NUM_EXC; e++)
    if (s->pending[e]) v |= SCB_ICSR_ISRPENDING;
  if (s->pending[15]) v |= SCB_ICSR_PENDSTSET;
  if (s->pending[14]) v |= SCB_ICSR_PENDSVSET;
  if (s->pending[2]) v |= SCB_ICSR_NMIPENDSET;
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
  if (in_bank(a, NVIC_ISER0)) return nvic_bits(s->enabled, (a - NVIC_ISER0) / 4);
  if (in_bank(a, NVIC_ICER0)) return nvic_bits(s->enabled, (a - NVIC_ICER0) / 4);
  if (in_bank(a, NVIC_ISPR0)) return nvic_bits(s->pending, (a - NVIC_ISPR0) / 4);
  if (in_bank(a, NVIC_ICPR0)) return nvic_bits(s->pending, (a - NVIC_ICPR0) / 4);
  if (in_bank(a, NVIC_IABR0)) return nvic_bits(s->active, (a - NVIC_IABR0) / 4);
  if (in_ipr(a)) { /* 4 bytes per word */
    uint32_t v = 0;
    for (uint32_t i = 0; i < 4; i++) {
      uint32_t irq = a - NVIC_IPR0 + i;
      if (irq < NUM_IRQ) v |= (uint32_t)s->prio[16 + irq] << (8 * i);
    }
    return v;
  }
  if (in_shpr(a)) { /* exceptions 4..15 */
    uint32_t v = 0;
    for (uint32_t i = 0; i < 4; i++) v |= (uint32_t)s->prio[4 + (a - SCB_SHPR1) + i] << (8 * i);
    return v;
  }
  switch (a) {
  case SCS_ICTR: return (NUM_IRQ + 31) / 32 - 1;
  case SCS_ACTLR: return 0;
  case SYST_CSR: { uint32_t v = s->st_csr; s->st_csr &= ~ST_COUNTFLAG; return v; }
  case SYST_RVR: return s->st_rvr;
  case SYST_CVR: return st_value(b);
  case SYST_CALIB: return 0x40000000u | 21250u; /* NOREF=0... TENMS not verified against RM0440 */
  case SCB_CPUID: return CPUID_M4F_R0P1;
  case SCB_ICSR: return icsr(b);
  case SCB_VTOR: return s->vtor;
  case SCB_AIRCR: return SCB_AIRCR_VECTKEYSTAT | reg_value(SCB_AIRCR_PRIGROUP, s->aircr_prigroup);
  case SCB_SCR: return s->scr;
  case SCB_CCR: return s->ccr;
  case SCB_SHCSR: {
    uint32_t v = s->shcsr & SCB_SHCSR_ENABLES;
    v |= s->active[4] ? SCB_SHCSR_MEMFAULTACT : 0u; v |= s->active[5] ? SCB_SHCSR_BUSFAULTACT : 0u;
    v |= s->active[6] ? SCB_SHCSR_USGFAULTACT : 0u; v |= s->active[11] ? SCB_SHCSR_SVCALLACT : 0u;
    v |= s->active[14] ? SCB_SHCSR_PENDSVACT : 0u; v |= s->active[15] ? SCB_SHCSR_SYSTICKACT : 0u;
    return v;
  }
  case SCB_CFSR: return s->cfsr;
  case SCB_HFSR: return s->hfsr;
  case SCB_DFSR: case SCB_MMFAR: case SCB_BFAR: case SCB_AFSR: return 0;
  case SCB_CPACR: return s->cpacr;
  case MPU_TYPE: return MPU_TYPE_8_REGIONS;
  case MPU_CTRL: return 0;
  case DHCSR: return 0; /* no debugger */
  case DEMCR: return s->demcr;
  case FPU_FPCCR: return s->fpccr;
  case FPU_FPCAR: return s->fpcar;
  case FPU_FPDSCR: return s->fpdscr;
  case DWT_CTRL: return DWT_CTRL_NUMCOMP_4 | (s->dwt_ctrl & DWT_CTRL_CYCCNTENA);
  case DWT_CYCCNT: return cyc_value(b);
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
  if (a < DBGMCU_IDCODE || a > DBGMCU_APB2FZR) return false;
  *reg = a == DBGMCU_IDCODE ? NULL : &b->scs.dbgmcu[(a - DBGMCU_IDCODE - 4u) / 4u];
  return true;
}

void board_nvic_disable(board *b, int irq) {
  scs_write(b, NVIC_ICER0 + 4u * (uint32_t)(irq / 32), 4, 1u << (irq % 32));
}

uint32_t scs_read(board *b, uint32_t addr, unsigned size) {
  bool ok;
  uint32_t *dreg;
  if (dbgmcu_reg(b, addr & ~3u, &dreg)) return dreg ? *dreg : DBGMCU_IDCODE_G474;
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
  if (in_ipr(a) || in_shpr(a)) {
    for (unsigned i = 0; i < size; i++) {
      uint8_t p = (uint8_t)((v >> (8 * i)) & 0xF0u);
      uint32_t byte = a + i;
      if (byte >= SCB_SHPR1) {
        int exc = 4 + (int)(byte - SCB_SHPR1);
        if (exc == 4 || exc == 5 || exc == 6 || exc == 11 || exc == 14 || exc == 15) s->prio[exc] = p;
      } else if (byte - NVIC_IPR0 < NUM_IRQ) {
        s->prio[16 + byte - NVIC_IPR0] = p;
      }
    }
    return;
  }
  if (size != 4 || (a & 3u)) { board_fault(b, "%u-byte write to system register 0x%08X (word access only)", size, a); return; }
  if (in_bank(a, NVIC_ISER0)) { set_bits(b, s->enabled, (a - NVIC_ISER0) / 4, v, 1); return; }
  if (in_bank(a, NVIC_ICER0)) { set_bits(b, s->enabled, (a - NVIC_ICER0) / 4, v, 0); return; }
  if (in_bank(a, NVIC_ISPR0)) { set_bits(b, s->pending, (a - NVIC_ISPR0) / 4, v, 1); return; }
  if (in_bank(a, NVIC_ICPR0)) { set_bits(b, s->pending, (a - NVIC_ICPR0) / 4, v, 0); return; }
  switch (a) {
  case SYST_CSR:
    st_rebase(b);
    s->st_csr = (s->st_csr & ST_COUNTFLAG) | (v & (ST_ENABLE | ST_TICKINT | ST_CLKSOURCE));
    st_schedule(b);
    return;
  case SYST_RVR:
    if (v > SYST_RVR_RELOAD) { board_fault(b, "SYST_RVR 0x%08X: bits 31:24 are reserved", v); return; }
    st_rebase(b);
    s->st_rvr = v;
    st_schedule(b);
    return;
  case SYST_CVR: /* any write clears the counter and COUNTFLAG */
    st_rebase(b);
    s->st_val = 0;
    s->st_base_cycle = b->cycles;
    s->st_csr &= ~ST_COUNTFLAG;
    st_schedule(b);
    return;
  case SCB_ICSR:
    if (v & SCB_ICSR_NMIPENDSET) s->pending[2] = 1;
    if (v & SCB_ICSR_PENDSVSET) s->pending[14] = 1;
    if (v & SCB_ICSR_PENDSVCLR) s->pending[14] = 0;
    if (v & SCB_ICSR_PENDSTSET) s->pending[15] = 1;
    if (v & SCB_ICSR_PENDSTCLR) s->pending[15] = 0;
    return;
  case SCB_VTOR:
    /* 118 vectors round up to 128 words: TBLOFF must be 512-byte aligned (B3.2.5) */
    if (v & 0x1FFu) { board_fault(b, "VTOR 0x%08X is not 512-byte aligned for 118 vectors", v); return; }
    s->vtor = v;
    return;
  case SCB_AIRCR:
    if ((v >> 16) != SCB_AIRCR_VECTKEY) { board_fault(b, "AIRCR write 0x%08X without VECTKEY 0x05FA: ignored by the core", v); return; }
    if (v & (SCB_AIRCR_VECTRESET | SCB_AIRCR_VECTCLRACTIVE)) { board_fault(b, "AIRCR VECTRESET/VECTCLRACTIVE are for debuggers only (B3.2.6)"); return; }
    s->aircr_prigroup = reg_field(v, SCB_AIRCR_PRIGROUP);
    if (v & SCB_AIRCR_SYSRESETREQ) board_request_reset(b, RCC_CSR_SFTRSTF | RCC_CSR_PINRSTF); /* NRST is pulsed too */
    return;
  case SCB_SCR: s->scr = v & SCB_SCR_WRITABLE; return;
  case SCB_CCR: s->ccr = v & SCB_CCR_WRITABLE; return;
  case SCB_SHCSR: s->shcsr = (s->shcsr & ~SCB_SHCSR_ENABLES) | (v & SCB_SHCSR_ENABLES); return;
  case SCB_CFSR: s->cfsr &= ~v; return;   /* write-one-to-clear */
  case SCB_HFSR: s->hfsr &= ~v; return;
  case SCB_CPACR: { /* CP10 and CP11 must agree; 0b10 is reserved (B3.2.20) */
    uint32_t cp10 = reg_field(v, SCB_CPACR_CP10), cp11 = reg_field(v, SCB_CPACR_CP11);
    if ((v & ~(SCB_CPACR_CP10 | SCB_CPACR_CP11)) || cp10 != cp11 || cp10 == 2u) {
      board_fault(b, "CPACR 0x%08X: only CP10=CP11 in {0,1,3} is defined on the Cortex-M4F", v);
      return;
    }
    s->cpacr = v;
    return;
  }
  case MPU_CTRL:
    if (v != 0) board_fault(b, "MPU_CTRL 0x%08X: the MPU is not modelled", v);
    return;
  case DEMCR: cyc_rebase(b); s->demcr = v & DEMCR_WRITABLE; return;
  case NVIC_STIR:
    if (v >= NUM_IRQ) { board_fault(b, "STIR %u: no such interrupt (the STM32G474 has %d)", v, NUM_IRQ); return; }
    s->pending[16 + v] = 1;
    return;
  case FPU_FPCCR: s->fpccr = (s->fpccr & ~FPU_FPCCR_ASPEN_LSPEN) | (v & FPU_FPCCR_ASPEN_LSPEN); return;
  case FPU_FPCAR: s->fpcar = v & ~7u; return;
  case FPU_FPDSCR: s->fpdscr = v & FPU_FPDSCR_WRITABLE; return;
  case DWT_CTRL:
  case DWT_CYCCNT:
    if (!(s->demcr & DEMCR_TRCENA)) { board_fault(b, "DWT write with DEMCR.TRCENA=0: the DWT is disabled (C1.6.5)"); return; }
    cyc_rebase(b);
    if (a == DWT_CTRL) s->dwt_ctrl = v & DWT_CTRL_CYCCNTENA;
    else s->dwt_cyccnt = v;
    return;
  default:
    board_fault(b, "write 0x%08X to unmodelled system register 0x%08X", v, a);
  }
}
