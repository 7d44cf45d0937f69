/* HSE 24 MHz -> PLL -> 170 MHz with boost and 4 wait states (VARIANT 0) and the mistakes
 * the twin must refuse: 1 no boost, 2 too few wait states, 3 VCO above 344 MHz,
 * 4 PLLR above 170 MHz, 5 switching before PLLRDY, 6 straight to 170 MHz without the AHB /2
 * step, 7 the /2 step held for less than 1 us. */
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
  /* SW=PLL with HPRE=/2 first (85 MHz), then /1 after at least 1 us */
  RCC_CFGR = (RCC_CFGR & ~0xF3u) | 3u | (VARIANT == 6 ? 0u : 8u << 4);
  while (((RCC_CFGR >> 2) & 3u) != 3u) {}
  for (volatile int i = 0; i < (VARIANT == 7 ? 1 : 100); i++) {}
  RCC_CFGR &= ~0xF0u;
  tb_result[0] = (RCC_CFGR >> 2) & 3u;
  tb_result[1] = RCC_CR;
  return 0;
}
