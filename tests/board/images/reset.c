/* Reset and vector table: .data copied from flash, .bss zero, SP from vector 0, CPUID,
 * VTOR at reset, the boot alias at 0, a PendSV through a relocated table. */
#include "tb.h"
static volatile uint32_t data_word = 0xC0FFEE01u;
static volatile uint32_t bss_word;
static volatile uint32_t pendsv_seen;
void PendSV_Handler(void) { pendsv_seen++; }

int main(void) {
  tb_result[0] = data_word;
  tb_result[1] = bss_word;
  tb_result[2] = SCB_CPUID;
  tb_result[3] = SCB_VTOR;
  tb_result[4] = tb_initial_sp;
  tb_result[5] = REG(0x00000004u) == REG(0x08000004u); /* boot alias */
  tb_result[6] = RCC_CR;
  tb_result[7] = RCC_CFGR;
  SCB_VTOR = 0x08000000u;
  SCB_ICSR = 1u << 28; /* PENDSVSET */
  tb_dsb();
  tb_result[8] = pendsv_seen;
  tb_result[9] = SCB_VTOR;
  return 0;
}
