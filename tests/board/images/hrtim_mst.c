/* HRTIM master timer and preload at 16 MHz (CKPSC=5): the master (PER 320 = 20 us, CMP1 80)
 * sets TB1 on MSTPER and resets it on MSTCMP1 (25 %); timer A (PER 160, PREEN, TAREPU) starts
 * at CMP1 40 and its handler preloads CMP1 120 after 5 repetitions (75 % afterwards). */
#include "tb.h"
#define HR 0x40016800u
#define MST(o) REG(HR + (o))
#define TA(o) REG(HR + 0x80u + (o))
#define TB(o) REG(HR + 0x100u + (o))
#define CMN(o) REG(HR + 0x380u + (o))
#define RCC_APB2ENR REG(0x40021060u)
static volatile uint32_t reps, mreps, cmp_seen;
void HRTIM_TIMA_Handler(void) {
  if (++reps == 5) { TA(0x1C) = 120u; cmp_seen = TA(0x1C); } /* preloaded: active at the next REP */
  TA(0x08) = 0x10u;
}
void HRTIM_Master_Handler(void) { mreps++; MST(0x08) = 0x10u; }
int main(void) {
  RCC_APB2ENR |= 1u << 26;
  MST(0x00) = 8u | 5u;                         /* CONT, CKPSC=5 */
  MST(0x14) = 320u;
  MST(0x1C) = 80u;
  MST(0x0C) = 0x10u;                           /* MREPIE */
  TB(0x00) = 8u | 5u;
  TB(0x14) = 320u;
  TB(0x3C) = 1u << 7;                          /* SETB1R: MSTPER */
  TB(0x40) = 1u << 8;                          /* RSTB1R: MSTCMP1 */
  TA(0x00) = 8u | 5u | (1u << 27) | (1u << 17); /* PREEN, TAREPU */
  TA(0x14) = 160u;
  TA(0x1C) = 40u;
  TA(0x3C) = 1u << 2;
  TA(0x40) = 1u << 3;
  TA(0x0C) = 0x10u;
  REG(0xE000E100u + 8u) = (1u << (67u - 64u)) | (1u << (68u - 64u));
  CMN(0x14) = 1u | 4u;                         /* TA1OEN, TB1OEN */
  MST(0x00) = 8u | 5u | (1u << 16) | (1u << 17) | (1u << 18); /* MCEN, TACEN, TBCEN */
  while (reps < 12) __asm__ volatile("wfi");
  tb_result[0] = reps;
  tb_result[1] = mreps;
  tb_result[2] = cmp_seen;
  return 0;
}
