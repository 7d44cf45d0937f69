/* Minimal start-up for the test images: vector table, .data/.bss, FPU on, main, exit. */
#include "tb.h"

extern uint32_t _sidata[], _sdata[], _edata[], _sbss[], _ebss[], _estack[];
int main(void);
volatile uint32_t tb_result[32];
uint32_t tb_initial_sp;

static uint32_t semihost(uint32_t op, const void *arg) {
  register uint32_t r0 __asm__("r0") = op;
  register const void *r1 __asm__("r1") = arg;
  __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}
void tb_puts(const char *s) { semihost(0x04, s); }
void tb_exit(int code) {
  uint32_t blk[2] = {0x20026u, (uint32_t)code};
  semihost(0x20, blk);
  for (;;) {}
}

/* naked, so the SP it reports is the one the core loaded from vector 0 */
__attribute__((naked)) void Reset_Handler(void) { __asm__ volatile("mov r0, sp\n b tb_start"); }

__attribute__((used, noreturn)) void tb_start(uint32_t sp) {
  for (uint32_t *s = _sidata, *d = _sdata; d < _edata;) *d++ = *s++;
  for (uint32_t *d = _sbss; d < _ebss;) *d++ = 0;
  tb_initial_sp = sp;
  SCB_CPACR |= 0xFu << 20; /* CP10, CP11 full access */
  tb_dsb();
  tb_exit(main());
}

void Default_Handler(void) {
  tb_puts("unexpected exception\n");
  tb_exit(99);
}
#define WEAK __attribute__((weak, alias("Default_Handler")))
void NMI_Handler(void) WEAK;
void HardFault_Handler(void) WEAK;
void PendSV_Handler(void) WEAK;
void SysTick_Handler(void) WEAK;
void IRQ0_Handler(void) WEAK;
void IRQ1_Handler(void) WEAK;
void IRQ2_Handler(void) WEAK;
void TIM6_Handler(void) WEAK;
void HRTIM_TIMA_Handler(void) WEAK;
void HRTIM_Master_Handler(void) WEAK;

__attribute__((section(".isr_vector"), used)) void (*const tb_vectors[16 + 102])(void) = {
  (void (*)(void))_estack, Reset_Handler, NMI_Handler, HardFault_Handler,
  [4 ... 13] = Default_Handler, [14] = PendSV_Handler, [15] = SysTick_Handler,
  [16] = IRQ0_Handler, [17] = IRQ1_Handler, [18] = IRQ2_Handler, [19 ... 69] = Default_Handler, [16 + 54] = TIM6_Handler, [71 ... 82] = Default_Handler, [16 + 67] = HRTIM_Master_Handler, [16 + 68] = HRTIM_TIMA_Handler,
  [85 ... 117] = Default_Handler,
};
