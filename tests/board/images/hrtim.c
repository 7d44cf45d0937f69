/* HRTIM timer A at 16 MHz HCLK: CKPSC=5 (counter at fHRTIM), PER=160 (10 us), set on PER,
 * reset on CMP1=40 (25 %), complementary output with 1 us dead time on both edges, REP
 * interrupt every period; FLT1 drives both outputs inactive; both outputs enabled and left running for the host to sample. */
#include "tb.h"
#define HR 0x40016800u
#define TA(o) REG(HR + 0x80u + (o))
#define CMN(o) REG(HR + 0x380u + (o))
#define RCC_APB2ENR REG(0x40021060u)
static volatile uint32_t reps;
void HRTIM_TIMA_Handler(void) {
  reps++;
  TA(0x08) = 0x10u; /* clear REP */
}
int main(void) {
  RCC_APB2ENR |= 1u << 26;
  CMN(0x4C) = 1u;                     /* DLL calibration */
  while (!(CMN(0x08) & (1u << 16))) {}
  TA(0x00) = 8u | 5u;                 /* CONT, CKPSC=5 */
  TA(0x14) = 160u;
  TA(0x1C) = 40u;
  TA(0x3C) = 1u << 2;                 /* SETA1R: PER */
  TA(0x40) = 1u << 3;                 /* RSTA1R: CMP1 */
  TA(0x38) = (3u << 10) | 16u | (16u << 16); /* DTPRSC=3: tDTG = tHRTIM; 16 -> 1 us */
  TA(0x64) = (1u << 8) | (2u << 4) | (2u << 20); /* DTEN; on a fault both outputs inactive */
  CMN(0x50) = 1u;                     /* FLTINR1: FLT1 enabled */
  TA(0x68) = 1u;                      /* FLTAR: timer A reacts to FLT1 */
  TA(0x0C) = 0x10u;                   /* REPIE */
  REG(0xE000E100u + 4u * (68u / 32u)) = 1u << (68u % 32u);
  CMN(0x14) = 3u;                     /* TA1OEN, TA2OEN */
  tb_result[0] = CMN(0x14);
  REG(HR) = 1u << 17;                 /* MCR.TACEN */
  while (reps < 20) __asm__ volatile("wfi");
  tb_result[1] = reps;
  return 0;
}
