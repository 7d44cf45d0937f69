/* Accesses the twin must refuse, one per variant. */
#include "tb.h"
__attribute__((noinline)) uint32_t tb_bad_read(void) { return REG(0x30000000u); }
__attribute__((noinline)) uint32_t tb_usart_read(void) { return REG(0x40013800u); } /* USART1: not modelled */
__attribute__((noinline)) uint32_t tb_gpio_unclocked(void) { return REG(0x48000000u); }
int main(void) {
#if VARIANT == 1
  return (int)tb_bad_read();
#elif VARIANT == 2
  return (int)tb_usart_read();
#else
  return (int)tb_gpio_unclocked();
#endif
}
