/* The IWDG resets the MCU when not refreshed; the re-booted image sees IWDGRSTF and a
 * cleared SRAM (a marker outside .data/.bss is gone). */
#include "tb.h"
__attribute__((section(".noinit"))) static volatile uint32_t marker; /* kept by start-up code */
int main(void) {
  uint32_t csr = RCC_CSR;
  tb_result[0] = csr;
  if (csr & (1u << 29)) {
    tb_result[2] = marker; /* the reset must have cleared SRAM */
    return 0;
  }
  marker = 0xDEADBEEFu;
  RCC_CSR = 1u << 23;  /* RMVF: clear the power-on flags */
  IWDG_KR = 0xCCCCu;
  IWDG_KR = 0x5555u;
  IWDG_PR = 0;         /* LSI/4: 8 kHz */
  IWDG_RLR = 799;      /* 0.1 s */
  while (IWDG_SR) {}
  IWDG_KR = 0xAAAAu;
  for (;;) {}          /* no refresh */
}
