/* Nested preemption by priority, tail-chaining, BASEPRI and PRIMASK masking: the order of
 * events is logged as letters. */
#include "tb.h"
static volatile char log_[32];
static volatile uint32_t n, sp0, sp2;
static void logc(char c) { log_[n++] = c; }
static uint32_t sp(void) { uint32_t v; __asm__ volatile("mov %0, sp" : "=r"(v)); return v; }

void IRQ0_Handler(void) { /* low priority */
  logc('A');
  sp0 = sp();
  NVIC_ISPR0 = 1u << 1; /* IRQ1, higher priority: preempts at once */
  tb_dsb();
  NVIC_ISPR0 = 1u << 2; /* IRQ2, lower priority: waits, then tail-chains */
  tb_dsb();
  logc('a');
}
void IRQ1_Handler(void) { logc('B'); }
void IRQ2_Handler(void) { logc('C'); sp2 = sp(); }

int main(void) {
  NVIC_IPR(0) = 0xC0;
  NVIC_IPR(1) = 0x40;
  NVIC_IPR(2) = 0xE0;
  NVIC_ISER0 = 7u;
  NVIC_ISPR0 = 1u;
  tb_dsb();
  logc('M');
  __asm__ volatile("msr basepri, %0" ::"r"(0x80u));
  NVIC_ISPR0 = 1u << 1; /* 0x40 < 0x80: runs */
  tb_dsb();
  NVIC_ISPR0 = 1u << 2; /* 0xE0: masked */
  tb_dsb();
  logc('m');
  __asm__ volatile("msr basepri, %0" ::"r"(0u));
  __asm__ volatile("isb");
  __asm__ volatile("cpsid i");
  NVIC_ISPR0 = 1u << 1;
  tb_dsb();
  logc('p');
  __asm__ volatile("cpsie i");
  __asm__ volatile("isb");
  logc('e');
  for (uint32_t i = 0; i < n; i += 4)
    tb_result[i / 4] = (uint32_t)log_[i] | (uint32_t)log_[i + 1] << 8 | (uint32_t)log_[i + 2] << 16 | (uint32_t)log_[i + 3] << 24;
  tb_result[8] = n;
  tb_result[9] = sp0 == sp2; /* tail-chained IRQ2 ran on the same frame as IRQ0 */
  return 0;
}
