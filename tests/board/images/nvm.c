/* Boot records in flash page 127 of bank 2 (0x0807F800): each boot programs one double
 * word and resets through AIRCR.SYSRESETREQ until three records were added in this run;
 * the seventh boot record erases the page first. Programming errors are probed once. */
#include "tb.h"
#define PAGE_ADDR 0x0807F800u
#define FL_PG 1u
#define FL_PER 2u
#define FL_BKER (1u << 11)
#define FL_STRT (1u << 16)
#define SR_ERRS 0x3FAu

static void wait_bsy(void) { while (FLASH_SR & (1u << 16)) {} }
static void program(uint32_t addr, uint32_t w0, uint32_t w1) {
  FLASH_CR = FL_PG;
  REG(addr) = w0;
  REG(addr + 4) = w1;
  wait_bsy();
  FLASH_CR = 0;
}

int main(void) {
  uint32_t k = 0;
  while (k < 256 && (REG(PAGE_ADDR + 8 * k) != 0xFFFFFFFFu || REG(PAGE_ADDR + 8 * k + 4) != 0xFFFFFFFFu)) k++;
  FLASH_KEYR = 0x45670123u;
  FLASH_KEYR = 0xCDEF89ABu;
  if (k == 6) {
    FLASH_CR = FL_PER | FL_BKER | (127u << 3);
    FLASH_CR = FL_PER | FL_BKER | (127u << 3) | FL_STRT | (1u << 24);
    wait_bsy();
    tb_result[6] = FLASH_SR & 1u; /* EOP (EOPIE set) */
    FLASH_SR = 1u;
    FLASH_CR = 0;
    k = 0;
  }
  program(PAGE_ADDR + 8 * k, 0xB0070000u | k, ~(0xB0070000u | k));
  tb_result[0] = k;
  tb_result[1] = RCC_CSR;
  tb_result[2] = REG(PAGE_ADDR + 8 * k);
  if (k % 3 != 2) {
    SCB_AIRCR = 0x05FA0004u;
    for (;;) {}
  }
  /* error probes, each cleared afterwards */
  program(PAGE_ADDR, 0x1234u, 0x5678u);            /* onto a programmed double word */
  tb_result[3] = FLASH_SR & SR_ERRS;               /* PROGERR */
  FLASH_SR = SR_ERRS;
  FLASH_CR = FL_PG;
  REG(PAGE_ADDR + 8 * 200 + 4) = 0;                /* not 64-bit aligned */
  tb_result[4] = FLASH_SR & SR_ERRS;               /* PGAERR */
  FLASH_SR = SR_ERRS;
  FLASH_CR = 0;
  REG(PAGE_ADDR + 8 * 201) = 0;                    /* PG not set */
  tb_result[5] = FLASH_SR & SR_ERRS;               /* PGSERR */
  FLASH_SR = SR_ERRS;
  tb_result[7] = REG(PAGE_ADDR + 8 * 201);         /* still erased */
  return 0;
}
