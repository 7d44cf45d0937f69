/* A small pin configuration for the docs/board.md check: PA8 AF13, PA9 output, PC13 input
 * with pull-up (read back through IDR); PB0 left analog (its reset state). */
#include "tb.h"
#ifndef VARIANT
#define VARIANT 0
#endif
#define GPIOA 0x48000000u
#define GPIOC 0x48000800u
int main(void) {
  RCC_AHB2ENR |= 1u | 4u;
  REG(GPIOA + 0x24) = (REG(GPIOA + 0x24) & ~0xFu) | 13u;              /* AFRH: PA8 AF13 */
  REG(GPIOA + 0x00) = (REG(GPIOA + 0x00) & ~(0xFu << 16)) | (2u << 16) | (1u << 18); /* PA8 AF, PA9 out */
  REG(GPIOA + 0x18) = 1u << 9;                                         /* BSRR: PA9 high */
  REG(GPIOC + 0x0C) = 1u << 26;                                        /* PC13 pull-up */
  REG(GPIOC + 0x00) &= ~(3u << 26);                                    /* PC13 input */
  tb_result[0] = (REG(GPIOA + 0x10) >> 9) & 1u;
  tb_result[1] = (REG(GPIOC + 0x10) >> 13) & 1u;
  /* lock PA8: LCKK=1+pin, LCKK=0+pin, LCKK=1+pin, read (RM0440 §9.4.8) */
  REG(GPIOA + 0x1C) = (1u << 16) | (1u << 8);
  REG(GPIOA + 0x1C) = 1u << 8;
  REG(GPIOA + 0x1C) = (1u << 16) | (1u << 8);
  (void)REG(GPIOA + 0x1C);
  tb_result[2] = REG(GPIOA + 0x1C);
  REG(GPIOA + 0x00) = REG(GPIOA + 0x00) | (1u << 20); /* PA10: not locked */
#if VARIANT == 1
  REG(GPIOA + 0x00) &= ~(3u << 16);                   /* PA8 is locked: refused */
#elif VARIANT == 2
  SCB_AIRCR = 0x00000004u;                            /* SYSRESETREQ without VECTKEY */
#endif
  return 0;
}
