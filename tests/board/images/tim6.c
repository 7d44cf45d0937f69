/* TIM6 at 16 MHz: PSC 15, ARR 999 -> one update per 16000 core clocks; UG with URS=1 sets
 * no UIF, with URS=0 it does; a handler that leaves UIF set is entered again (level). */
#include "tb.h"
#define TIM6 0x40001000u
#define T(o) REG(TIM6 + (o))
static volatile uint32_t n, c_first, c_last, again;
void TIM6_Handler(void) {
  uint32_t c = DWT_CYCCNT;
  if (n == 0) c_first = c;
  c_last = c;
  n++;
  if (n == 3 && !again) { again = 1; return; } /* leave UIF set once */
  T(0x10) = ~1u;
}
int main(void) {
  DEMCR |= 1u << 24;
  DWT_CTRL |= 1u;
  RCC_APB1ENR1 |= 1u << 4;
  T(0x00) = 4u;            /* URS */
  T(0x28) = 15u;
  T(0x2C) = 999u;
  T(0x14) = 1u;            /* UG: load PSC; URS=1 so no UIF */
  tb_result[0] = T(0x10);
  T(0x00) = 0u;
  T(0x14) = 1u;            /* URS=0: UG sets UIF */
  tb_result[1] = T(0x10);
  T(0x10) = 0u;
  T(0x0C) = 1u;            /* UIE */
  REG(0xE000E100u + 4u * (54u / 32u)) = 1u << (54u % 32u);
  T(0x00) = 1u;            /* CEN */
  while (n < 12) __asm__ volatile("wfi");
  T(0x00) = 0u;
  tb_result[2] = n;
  tb_result[3] = c_last - c_first;
  tb_result[4] = again;
  return 0;
}
