/* An interrupt whose handler overwrites s0-s15 and FPSCR while the interrupted code holds
 * FP values in them: the interrupted code must find its registers intact. */
#include "tb.h"
static volatile float in[16], out[16], junk[16];
static volatile uint32_t irqs, exc_return;

void IRQ0_Handler(void) {
  uint32_t lr;
  __asm__ volatile("mov %0, lr" : "=r"(lr));
  exc_return = lr;
  __asm__ volatile("vldmia %0, {s0-s15}\n vmsr fpscr, %1\n vadd.f32 s0, s1, s2" ::"r"(junk), "r"(0u)
                   : "s0", "s1", "s2", "s3", "s4", "s5", "s6", "s7", "s8", "s9", "s10", "s11", "s12", "s13",
                     "s14", "s15", "memory");
  irqs++;
}

int main(void) {
  NVIC_ISER0 = 1u;
  uint32_t bad = 0, bad_fpscr = 0;
  for (int k = 0; k < 16; k++) junk[k] = -1000.0f - (float)k;
  for (int i = 0; i < 1000; i++) {
    for (int k = 0; k < 16; k++) in[k] = (float)(i * 16 + k) + 0.25f;
    uint32_t fpscr_out;
    __asm__ volatile("vldmia %[in], {s0-s15}\n"
                     "vmsr fpscr, %[fs]\n"
                     "str %[one], [%[ispr]]\n" /* pend IRQ0: taken right after this store */
                     "nop\n nop\n"
                     "vstmia %[out], {s0-s15}\n"
                     "vmrs %[fo], fpscr\n"
                     : [fo] "=&r"(fpscr_out)
                     : [in] "r"(in), [out] "r"(out), [fs] "r"(0x00C00000u), [one] "r"(1u), [ispr] "r"(0xE000E200u)
                     : "s0", "s1", "s2", "s3", "s4", "s5", "s6", "s7", "s8", "s9", "s10", "s11", "s12", "s13", "s14",
                       "s15", "memory");
    for (int k = 0; k < 16; k++) bad += out[k] != in[k];
    bad_fpscr += fpscr_out != 0x00C00000u;
  }
  tb_result[0] = bad;
  tb_result[1] = irqs;
  tb_result[2] = bad_fpscr;
  tb_result[3] = exc_return;
  return 0;
}
