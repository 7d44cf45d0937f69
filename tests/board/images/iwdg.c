/* The IWDG resets the MCU when not refreshed; the re-booted image sees IWDGRSTF. */
#include "tb.h"
int main(void) {
  uint32_t csr = RCC_CSR;
  tb_result[0] = csr;
  if (csr & (1u << 29)) return 0;
  RCC_CSR = 1u << 23;  /* RMVF: clear the power-on flags */
  IWDG_KR = 0xCCCCu;
  IWDG_KR = 0x5555u;
  IWDG_PR = 0;         /* LSI/4: 8 kHz */
  IWDG_RLR = 799;      /* 0.1 s */
  while (IWDG_SR) {}
  IWDG_KR = 0xAAAAu;
  for (;;) {}          /* no refresh */
}
