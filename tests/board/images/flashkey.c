/* FLASH_KEYR: the right sequence unlocks; a wrong key is a bus error (HardFault here) and
 * locks FLASH_CR until the next reset, even against the right sequence (RM0440 §5.3.5). */
#include "tb.h"
static volatile uint32_t faults;
void HardFault_Handler(void) { faults++; }
int main(void) {
  FLASH_KEYR = 0x45670123u;
  FLASH_KEYR = 0xCDEF89ABu;
  tb_result[0] = FLASH_CR >> 31;       /* 0: unlocked */
  FLASH_CR = 1u << 31;                 /* lock again */
  tb_result[1] = FLASH_CR >> 31;       /* 1 */
  FLASH_KEYR = 0x12345678u;            /* wrong key */
  tb_dsb();
  tb_result[2] = faults;               /* 1 */
  tb_result[3] = SCB_HFSR;             /* FORCED */
  tb_result[4] = SCB_CFSR;             /* IMPRECISERR */
  FLASH_KEYR = 0x45670123u;            /* the right sequence no longer works */
  tb_dsb();
  FLASH_KEYR = 0xCDEF89ABu;
  tb_dsb();
  tb_result[5] = faults;               /* 3 */
  tb_result[6] = FLASH_CR >> 31;       /* still 1 */
  return 0;
}
