/* HSE 24 MHz -> PLL -> 170 MHz with boost and 4 wait states (VARIANT 0) and the mistakes
 * the twin must refuse: 1 no boost, 2 too few wait states, 3 VCO above 344 MHz,
 * 4 PLLR above 170 MHz, 5 switching before PLLRDY. */
#include "tb.h"
#ifndef VARIANT
#define VARIANT 0
#endif
int main(void) {
  RCC_APB1ENR1 |= 1u << 28;            /* PWREN */
  (void)RCC_APB1ENR1;
  if (VARIANT != 1) PWR_CR5 = 0;       /* R1MODE=0: range 1 boost */
  FLASH_ACR = (FLASH_ACR & ~0xFu) | (VARIANT == 2 ? 3u : 4u);
  RCC_CR |= 1u << 16;                  /* HSEON */
  while (!(RCC_CR & (1u << 17))) {}
  uint32_t n = VARIANT == 3 ? 90u : VARIANT == 4 ? 86u : 85u;
  /* PLLSRC=HSE, PLLM=/6 (4 MHz), PLLN, PLLR=/2, PLLREN */
  RCC_PLLCFGR = 3u | (5u << 4) | (n << 8) | (1u << 24);
  RCC_CR |= 1u << 24;                  /* PLLON */
  if (VARIANT != 5) while (!(RCC_CR & (1u << 25))) {}
  RCC_CFGR = (RCC_CFGR & ~3u) | 3u;    /* SW=PLL */
  while (((RCC_CFGR >> 2) & 3u) != 3u) {}
  tb_result[0] = (RCC_CFGR >> 2) & 3u;
  tb_result[1] = RCC_CR;
  return 0;
}
