/* Exception entry and return in the host (Unicorn does not emulate them for M-profile),
 * after the ARMv7-M ARM B1.5: priorities and preemption with PRIGROUP, PRIMASK and
 * BASEPRI; push/pop of the basic frame and of the extended FP frame; EXC_RETURN; IPSR;
 * tail-chaining.
 *
 * FP context: the core (QEMU) sets CONTROL.FPCA when an FP instruction executes
 * (FPCCR.ASPEN=1 at reset). Entry with FPCA=1 pushes the extended frame (s0-s15, FPSCR)
 * *eagerly*: lazy stacking (FPCCR.LSPEN) only defers the same stores to the handler's
 * first FP instruction, so software sees identical values; only FPCCR.LSPACT/FPCAR and
 * the timing differ. Only the main stack is supported (CONTROL.SPSEL=1 stops the run). */
#include "board_priv.h"

static uint32_t reg32(board *b, int r) {
  uint32_t v = 0;
  uc_reg_read(b->uc, r, &v);
  return v;
}
static void wreg(board *b, int r, uint32_t v) { uc_reg_write(b->uc, r, &v); }

static int group(const board *b, int prio) {
  if (prio < 0) return prio;
  uint32_t mask = (0xFFu << (b->scs.aircr_prigroup + 1)) & 0xFFu; /* B1.5.4 */
  return (int)((uint32_t)prio & mask);
}

int exc_priority(const board *b, int exc) {
  if (exc == 1) return -3;
  if (exc == 2) return -2;
  if (exc == 3) return -1;
  return b->scs.prio[exc];
}

static bool exc_enabled(const board *b, int exc) {
  if (exc >= 16) return b->scs.enabled[exc];
  switch (exc) {
  case 2: case 3: case 11: case 12: case 14: case 15: return true;
  case 4: return b->scs.shcsr & (1u << 16);
  case 5: return b->scs.shcsr & (1u << 17);
  case 6: return b->scs.shcsr & (1u << 18);
  default: return false;
  }
}

static int execution_priority(board *b, int ignore_exc) {
  int ep = 256;
  for (int e = 1; e < NUM_EXC; e++)
    if (b->scs.active[e] && e != ignore_exc && group(b, exc_priority(b, e)) < ep) ep = group(b, exc_priority(b, e));
  uint32_t basepri = reg32(b, UC_ARM_REG_BASEPRI) & 0xF0u;
  if (basepri && group(b, (int)basepri) < ep) ep = group(b, (int)basepri);
  if (reg32(b, UC_ARM_REG_PRIMASK) & 1u && ep > 0) ep = 0;
  return ep;
}

/* Highest-priority pending, enabled exception (lowest priority value, then lowest number). */
static int best_pending(const board *b) {
  int best = 0, bp = 1 << 30;
  for (int e = 1; e < NUM_EXC; e++) {
    if (!b->scs.pending[e] || !exc_enabled(b, e)) continue;
    int p = exc_priority(b, e);
    if (p < bp) { bp = p; best = e; }
  }
  return best;
}

bool exc_any_pending_enabled(const board *b) { return best_pending(b) != 0; }

static int take_against(board *b, int ignore_exc) {
  int e = best_pending(b);
  if (e && group(b, exc_priority(b, e)) < execution_priority(b, ignore_exc)) return e;
  return 0;
}

int exc_pending_to_take(board *b) { return take_against(b, 0); }

static int vector_jump(board *b, int exc) {
  uint32_t vec = 0;
  if (uc_mem_read(b->uc, b->scs.vtor + 4u * (uint32_t)exc, &vec, 4) != UC_ERR_OK) {
    board_fault(b, "vector table read for exception %d failed (VTOR 0x%08X)", exc, b->scs.vtor);
    return -1;
  }
  if (!(vec & 1u)) {
    board_fault(b, "vector of exception %d is 0x%08X (no Thumb bit): the core would lock up", exc, vec);
    return -1;
  }
  wreg(b, UC_ARM_REG_PC, vec & ~1u);
  b->scs.pending[exc] = 0;
  b->scs.active[exc] = 1;
  return 0;
}

int exc_enter(board *b, int exc) {
  uint32_t control = reg32(b, UC_ARM_REG_CONTROL);
  uint32_t ipsr = reg32(b, UC_ARM_REG_IPSR) & 0x1FFu;
  if (ipsr == 0 && (control & 2u)) {
    board_fault(b, "exception %d taken while thread mode uses the process stack: not modelled", exc);
    return -1;
  }
  bool fp = control & 4u;                       /* CONTROL.FPCA */
  uint32_t frame = fp ? 0x68u : 0x20u;
  uint32_t sp = reg32(b, UC_ARM_REG_SP);
  uint32_t xpsr = reg32(b, UC_ARM_REG_XPSR) | (1u << 24);
  uint32_t align = (b->scs.ccr & (1u << 9)) && (sp & 4u) ? 1u : 0u; /* CCR.STKALIGN, B1.5.7 */
  uint32_t fptr = (sp - frame) & ~(align << 2);
  uint32_t w[26] = {reg32(b, UC_ARM_REG_R0), reg32(b, UC_ARM_REG_R1), reg32(b, UC_ARM_REG_R2),
                    reg32(b, UC_ARM_REG_R3), reg32(b, UC_ARM_REG_R12), reg32(b, UC_ARM_REG_LR),
                    reg32(b, UC_ARM_REG_PC), (xpsr & ~(1u << 9)) | (align << 9)};
  if (fp) {
    for (int i = 0; i < 16; i++) w[8 + i] = reg32(b, UC_ARM_REG_S0 + i);
    w[24] = reg32(b, UC_ARM_REG_FPSCR);
    w[25] = 0;
  }
  if (uc_mem_write(b->uc, fptr, w, frame) != UC_ERR_OK) {
    board_fault(b, "stacking the exception frame for exception %d at 0x%08X failed (stack overflow?)", exc, fptr);
    return -1;
  }
  wreg(b, UC_ARM_REG_SP, fptr);
  /* EXC_RETURN (B1.5.8): bit4 = basic frame, bit3 = return to thread, bit2 = PSP */
  wreg(b, UC_ARM_REG_LR, 0xFFFFFFE1u | (fp ? 0u : 0x10u) | (ipsr == 0 ? 0x8u : 0u));
  wreg(b, UC_ARM_REG_CONTROL, control & ~4u);
  wreg(b, UC_ARM_REG_XPSR, (1u << 24) | (uint32_t)exc);
  irqstat_enter(b, exc);
  return vector_jump(b, exc);
}

int exc_return(board *b, uint32_t v) {
  int exc = (int)(reg32(b, UC_ARM_REG_IPSR) & 0x1FFu);
  if (exc == 0 || !b->scs.active[exc]) {
    board_fault(b, "exception return 0x%08X from exception %d which is not active (INVPC)", v, exc);
    return -1;
  }
  if ((v & 0xFFFFFFE3u) != 0xFFFFFFE1u || (v & 0xCu) == 0x4u) {
    board_fault(b, "reserved EXC_RETURN value 0x%08X (INVPC)", v);
    return -1;
  }
  if (v & 0x4u) { board_fault(b, "EXC_RETURN 0x%08X returns to the process stack: not modelled", v); return -1; }
  b->scs.active[exc] = 0;
  irqstat_exit(b, exc);
  b->pc = v;
  /* Tail-chaining (B1.5.12): a pending exception that would preempt the context we return
   * to is entered with the frame left on the stack and the same EXC_RETURN. */
  int next = take_against(b, 0);
  if (next) {
    wreg(b, UC_ARM_REG_XPSR, (1u << 24) | (uint32_t)next);
    wreg(b, UC_ARM_REG_LR, v);
    wreg(b, UC_ARM_REG_CONTROL, reg32(b, UC_ARM_REG_CONTROL) & ~4u);
    irqstat_enter(b, next);
    return vector_jump(b, next);
  }
  bool fp = !(v & 0x10u);
  uint32_t frame = fp ? 0x68u : 0x20u;
  uint32_t sp = reg32(b, UC_ARM_REG_SP), w[26];
  if (uc_mem_read(b->uc, sp, w, frame) != UC_ERR_OK) {
    board_fault(b, "unstacking the exception frame at 0x%08X failed", sp);
    return -1;
  }
  static const int regs[] = {UC_ARM_REG_R0, UC_ARM_REG_R1, UC_ARM_REG_R2, UC_ARM_REG_R3, UC_ARM_REG_R12, UC_ARM_REG_LR};
  for (int i = 0; i < 6; i++) wreg(b, regs[i], w[i]);
  if (fp) {
    for (int i = 0; i < 16; i++) wreg(b, UC_ARM_REG_S0 + i, w[8 + i]);
    wreg(b, UC_ARM_REG_FPSCR, w[24]);
  }
  uint32_t xpsr = w[7];
  sp += frame + ((xpsr >> 9) & 1u) * 4u;
  uint32_t ret_ipsr = xpsr & 0x1FFu;
  bool to_thread = v & 0x8u;
  if (to_thread != (ret_ipsr == 0)) {
    board_fault(b, "EXC_RETURN 0x%08X does not match the stacked IPSR %u (INVPC)", v, ret_ipsr);
    return -1;
  }
  if (to_thread)
    for (int e = 1; e < NUM_EXC; e++)
      if (b->scs.active[e]) {
        board_fault(b, "return to thread mode with exception %d still active (INVPC, CCR.NONBASETHRDENA=0)", e);
        return -1;
      }
  if (!(xpsr & (1u << 24))) { board_fault(b, "stacked xPSR 0x%08X has T=0 (INVSTATE)", xpsr); return -1; }
  wreg(b, UC_ARM_REG_SP, sp);
  uint32_t control = reg32(b, UC_ARM_REG_CONTROL);
  wreg(b, UC_ARM_REG_CONTROL, fp ? control | 4u : control & ~4u);
  wreg(b, UC_ARM_REG_XPSR, xpsr & ~(1u << 9));
  wreg(b, UC_ARM_REG_PC, w[6] & ~1u);
  b->pc = w[6] & ~1u;
  return 0;
}

/* While an enabled exception is pending but masked by PRIMASK/BASEPRI, the code hook checks
 * the masks before each instruction, so the exception is taken right after the CPSIE/MSR
 * that unmasks it (as on the core), at the cost of two register reads per instruction
 * only in that state. Active exceptions cannot change inside a slice. */
bool exc_prepare_poll(board *b) {
  int e = best_pending(b);
  b->poll = false;
  if (!e) return false;
  int ep = 256;
  for (int k = 1; k < NUM_EXC; k++)
    if (b->scs.active[k] && group(b, exc_priority(b, k)) < ep) ep = group(b, exc_priority(b, k));
  b->poll_prio = group(b, exc_priority(b, e));
  b->poll_active_ep = ep;
  b->poll = b->poll_prio < ep; /* otherwise only a return can unmask it, which ends the slice */
  return b->poll;
}

bool exc_poll_unmasked(board *b) {
  int ep = b->poll_active_ep;
  uint32_t basepri = reg32(b, UC_ARM_REG_BASEPRI) & 0xF0u;
  if (basepri && group(b, (int)basepri) < ep) ep = group(b, (int)basepri);
  if ((reg32(b, UC_ARM_REG_PRIMASK) & 1u) && ep > 0) ep = 0;
  return b->poll_prio < ep;
}
