/* Power cut and flash ECC: every boot first reads double word 5 of page 127 of bank 2
 * (0x0807F828) and records the NMIs that read raised and FLASH_ECCR; then, if the double word
 * reads erased, programs it (the host cuts the power during that program, torn); if not, erases
 * the page and reads the double word again. The host runs it: boot 1 (program, cut), power-on,
 * boot 2 (read: ECC double error; erase; read again: clean). */
#include "tb.h"
#define PAGE_ADDR 0x0807F800u
#define DW (PAGE_ADDR + 8u * 5u)
#define FLASH_ECCR REG(0x40022018u)
#define FL_PG 1u
#define FL_PER 2u
#define FL_BKER (1u << 11)
#define FL_STRT (1u << 16)

static volatile uint32_t nmis, eccr_in_nmi;

void NMI_Handler(void) {
  nmis++;
  eccr_in_nmi = FLASH_ECCR;
  FLASH_ECCR = 1u << 31; /* ECCD: rc_w1 */
}

static void wait_bsy(void) { while (FLASH_SR & (1u << 16)) {} }

int main(void) {
  uint32_t w0 = REG(DW), w1 = REG(DW + 4);
  __asm__ volatile("dsb\n isb" ::: "memory");
  tb_result[0] = nmis;
  tb_result[1] = eccr_in_nmi;
  tb_result[2] = w0;
  tb_result[3] = w1;
  tb_result[4] = FLASH_ECCR; /* cleared by the handler */
  FLASH_KEYR = 0x45670123u;
  FLASH_KEYR = 0xCDEF89ABu;
  if (w0 == 0xFFFFFFFFu && w1 == 0xFFFFFFFFu && nmis == 0) {
    FLASH_CR = FL_PG;
    REG(DW) = 0x12345678u;
    REG(DW + 4) = 0x9ABCDEF0u; /* the host cuts the power here */
    wait_bsy();
    FLASH_CR = 0;
    tb_result[5] = REG(DW);
    return 0;
  }
  FLASH_CR = FL_PER | FL_BKER | (127u << 3);
  FLASH_CR = FL_PER | FL_BKER | (127u << 3) | FL_STRT;
  wait_bsy();
  FLASH_CR = 0;
  uint32_t before = nmis;
  tb_result[6] = REG(DW) & REG(DW + 4);
  __asm__ volatile("dsb\n isb" ::: "memory");
  tb_result[7] = nmis - before; /* 0: the erase repaired the ECC */
  return 0;
}
