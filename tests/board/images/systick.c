/* SysTick counting core clocks (CLKSOURCE=1) and HCLK/8 (CLKSOURCE=0), timed with DWT CYCCNT;
 * the idle loop sleeps in WFI. With -DIDLE_SECONDS=n: a 1 kHz tick for n seconds (speed). */
#include "tb.h"
static volatile uint32_t ticks, c_first, c_last;
void SysTick_Handler(void) {
  uint32_t c = DWT_CYCCNT;
  if (ticks == 0) c_first = c;
  c_last = c;
  ticks++;
}

static uint32_t measure(uint32_t rvr, uint32_t csr, uint32_t n) {
  ticks = 0;
  SYST_RVR = rvr;
  SYST_CVR = 0;
  SYST_CSR = csr;
  while (ticks < n + 1) __asm__ volatile("wfi");
  SYST_CSR = 0;
  return c_last - c_first;
}

int main(void) {
  DEMCR |= 1u << 24;
  DWT_CYCCNT = 0;
  DWT_CTRL |= 1u;
#ifdef IDLE_SECONDS
  tb_result[0] = measure(15999, 7, IDLE_SECONDS * 1000);
  return 0;
#else
  tb_result[0] = measure(999, 7, 100);    /* 100 periods of 1000 core clocks */
  tb_result[1] = measure(99, 3, 100);     /* 100 periods of 100 ticks of HCLK/8 */
  SYST_RVR = 49;
  SYST_CVR = 0;
  SYST_CSR = 5; /* no interrupt: poll COUNTFLAG */
  uint32_t spins = 0;
  while (!(SYST_CSR & (1u << 16))) spins++;
  tb_result[2] = SYST_CSR >> 16 & 1u; /* cleared by the previous read */
  tb_result[3] = spins > 0;
  return 0;
#endif
}
