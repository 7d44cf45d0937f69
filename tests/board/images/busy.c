/* A busy loop for the emulation speed (instructions per wall second). */
#include "tb.h"
int main(void) {
  volatile uint32_t acc = 0;
  for (uint32_t i = 0; i < 10000000u; i++) acc += i ^ (acc >> 3);
  tb_result[0] = acc;
  return 0;
}
