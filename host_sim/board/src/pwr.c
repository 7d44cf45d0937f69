/* PWR, RM0440 §6: voltage scaling range (CR1.VOS) and range 1 boost (CR5.R1MODE=0),
 * which bound HCLK: range 2 26 MHz, range 1 normal 150 MHz, range 1 boost 170 MHz. */
#include "board_priv.h"
#include <string.h>

void pwr_reset(board *b) {
  pwr_state *p = &b->pwr;
  memset(p, 0, sizeof *p);
  p->cr1 = 0x00000200u; /* VOS=01: range 1 */
  p->cr3 = 0x00008000u; /* EIWUL */
  p->cr5 = 0x00000100u; /* R1MODE=1: normal mode, no boost */
}

int pwr_range(const board *b) { return ((b->pwr.cr1 >> 9) & 3u) == 2u ? 2 : 1; }
bool pwr_boost(const board *b) { return pwr_range(b) == 1 && !(b->pwr.cr5 & (1u << 8)); }

uint32_t pwr_read(board *b, uint32_t off) {
  pwr_state *p = &b->pwr;
  switch (off) {
  case 0x00: return p->cr1;
  case 0x04: return p->cr2;
  case 0x08: return p->cr3;
  case 0x0C: return p->cr4;
  case 0x10: return 0;  /* SR1: no wake-up events */
  case 0x14: return 0;  /* SR2: VOSF=0, the regulator is ready at once */
  case 0x18: return 0;
  case 0x80: return p->cr5;
  }
  if (off >= 0x20 && off <= 0x54) return p->pucr[(off - 0x20) / 4];
  board_fault(b, "read of reserved PWR offset 0x%02X", off);
  return 0;
}

void pwr_write(board *b, uint32_t off, uint32_t v) {
  pwr_state *p = &b->pwr;
  switch (off) {
  case 0x00: {
    uint32_t vos = (v >> 9) & 3u;
    if (vos == 0 || vos == 3) { board_fault(b, "PWR_CR1.VOS=%u is reserved (RM0440 §6.4.1)", vos); return; }
    if (v & 7u) { board_fault(b, "PWR_CR1.LPMS=%u: low-power modes are not modelled", v & 7u); return; }
    uint32_t old = p->cr1;
    p->cr1 = v & 0x0000471Fu;
    rcc_check_clocking(b, rcc_hclk_hz(b), "PWR_CR1.VOS change");
    if (b->fault) p->cr1 = old;
    return;
  }
  case 0x04: p->cr2 = v; return;
  case 0x08: p->cr3 = v; return;
  case 0x0C: p->cr4 = v; return;
  case 0x18: return; /* SCR: clear flags */
  case 0x80: {
    if (v & ~0x100u) { board_fault(b, "PWR_CR5 0x%08X writes reserved bits", v); return; }
    uint32_t old = p->cr5;
    p->cr5 = v;
    rcc_check_clocking(b, rcc_hclk_hz(b), "PWR_CR5.R1MODE change");
    if (b->fault) p->cr5 = old;
    return;
  }
  }
  if (off >= 0x20 && off <= 0x54) { p->pucr[(off - 0x20) / 4] = v; return; }
  board_fault(b, "write 0x%08X to reserved PWR offset 0x%02X", v, off);
}
