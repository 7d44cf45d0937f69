/* PWR, RM0440 §6: voltage scaling range (CR1.VOS) and range 1 boost (CR5.R1MODE=0),
 * which bound HCLK: range 2 26 MHz, range 1 normal 150 MHz, range 1 boost 170 MHz. */
#include "board_priv.h"
#include <string.h>

void pwr_reset(board *b) {
  pwr_state *p = &b->pwr;
  memset(p, 0, sizeof *p);
  p->cr1 = PWR_CR1_VOS_RANGE1; /* reset values */
  p->cr3 = PWR_CR3_EIWUL;
  p->cr5 = PWR_CR5_R1MODE;     /* normal mode, no boost */
}

/* The two pull registers of port x (PUCRx, PDCRx) are the words 2x and 2x + 1 from PUCRA. */
static bool in_pull_regs(uint32_t off) { return off >= PWR_PUCRA_OFS && off <= PWR_PDCRG_OFS; }

int pwr_range(const board *b) { return (b->pwr.cr1 & PWR_CR1_VOS) == PWR_CR1_VOS_RANGE2 ? 2 : 1; }
bool pwr_boost(const board *b) { return pwr_range(b) == 1 && !(b->pwr.cr5 & PWR_CR5_R1MODE); }

uint32_t pwr_read(board *b, uint32_t off) {
  pwr_state *p = &b->pwr;
  switch (off) {
  case PWR_CR1_OFS: return p->cr1;
  case PWR_CR2_OFS: return p->cr2;
  case PWR_CR3_OFS: return p->cr3;
  case PWR_CR4_OFS: return p->cr4;
  case PWR_SR1_OFS: return 0; /* no wake-up events */
  case PWR_SR2_OFS: return 0; /* VOSF=0, the regulator is ready at once */
  case PWR_SCR_OFS: return 0;
  case PWR_CR5_OFS: return p->cr5;
  }
  if (in_pull_regs(off)) return p->pucr[(off - PWR_PUCRA_OFS) / 4];
  board_fault(b, "read of reserved PWR offset 0x%02X", off);
  return 0;
}

void pwr_write(board *b, uint32_t off, uint32_t v) {
  pwr_state *p = &b->pwr;
  switch (off) {
  case PWR_CR1_OFS: {
    uint32_t vos = v & PWR_CR1_VOS;
    if (vos != PWR_CR1_VOS_RANGE1 && vos != PWR_CR1_VOS_RANGE2) {
      board_fault(b, "PWR_CR1.VOS=%u is reserved (RM0440 §6.4.1)", reg_field(vos, PWR_CR1_VOS));
      return;
    }
    if (v & PWR_CR1_LPMS) { board_fault(b, "PWR_CR1.LPMS=%u: low-power modes are not modelled", reg_field(v, PWR_CR1_LPMS)); return; }
    uint32_t old = p->cr1;
    p->cr1 = v & PWR_CR1_WRITABLE;
    rcc_check_clocking(b, rcc_hclk_hz(b), "PWR_CR1.VOS change");
    if (b->fault) p->cr1 = old;
    return;
  }
  case PWR_CR2_OFS: p->cr2 = v; return;
  case PWR_CR3_OFS: p->cr3 = v; return;
  case PWR_CR4_OFS: p->cr4 = v; return;
  case PWR_SCR_OFS: return; /* clear flags */
  case PWR_CR5_OFS: {
    if (v & ~PWR_CR5_R1MODE) { board_fault(b, "PWR_CR5 0x%08X writes reserved bits", v); return; }
    uint32_t old = p->cr5;
    p->cr5 = v;
    rcc_check_clocking(b, rcc_hclk_hz(b), "PWR_CR5.R1MODE change");
    if (b->fault) p->cr5 = old;
    return;
  }
  }
  if (in_pull_regs(off)) { p->pucr[(off - PWR_PUCRA_OFS) / 4] = v; return; }
  board_fault(b, "write 0x%08X to reserved PWR offset 0x%02X", v, off);
}
