/**
 * @file startup_mps2_an386.c
 * @brief Vector table and reset handler for the PIL programs on QEMU mps2-an386.
 *
 * Reset: enable the FPU (CPACR CP10/CP11) before any float instruction, copy
 * .data, zero .bss, run main and end the emulation with main's return value
 * as QEMU's exit status. Any unexpected exception prints its number and ends
 * the emulation with status 3, so a crash is a visible failure, never a hang.
 */
#include <stdint.h>

#include "semihost.h"

extern uint32_t _sidata[], _sdata[], _edata[], _sbss[], _ebss[];
extern uint32_t _estack[];

int main(void);

void Reset_Handler(void);
void Default_Handler(void);

#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)
#define SCB_CPACR_CP10_CP11_FULL (0xFu << 20)
#define SCB_SHCSR (*(volatile uint32_t *)0xE000ED24u)
#define SCB_SHCSR_FAULTS_ENA (7u << 16) /* MemManage, BusFault, UsageFault */

#define PIL_EXIT_EXCEPTION 3

void Default_Handler(void)
{
    uint32_t ipsr;
    __asm volatile("mrs %0, ipsr" : "=r"(ipsr));
    pil_line l = {.len = 0u};
    line_str(&l, "pil: unexpected exception, vector ");
    line_u32(&l, ipsr & 0x1FFu);
    line_flush(&l);
    semihost_exit(PIL_EXIT_EXCEPTION);
}

typedef void (*vector_fn)(void);

#define PIL_IRQ_COUNT 32u

__attribute__((section(".isr_vector"), used)) const vector_fn g_pil_vectors[16u + PIL_IRQ_COUNT] = {
    [0] = (vector_fn)(uintptr_t)_estack,
    [1] = Reset_Handler,
    [2] = Default_Handler,  /* NMI */
    [3] = Default_Handler,  /* HardFault */
    [4] = Default_Handler,  /* MemManage */
    [5] = Default_Handler,  /* BusFault */
    [6] = Default_Handler,  /* UsageFault */
    [11] = Default_Handler, /* SVC */
    [12] = Default_Handler, /* DebugMon */
    [14] = Default_Handler, /* PendSV */
    [15] = Default_Handler, /* SysTick (the counter runs without its interrupt) */
    [16] = Default_Handler, [17] = Default_Handler, [18] = Default_Handler, [19] = Default_Handler,
    [20] = Default_Handler, [21] = Default_Handler, [22] = Default_Handler, [23] = Default_Handler,
    [24] = Default_Handler, [25] = Default_Handler, [26] = Default_Handler, [27] = Default_Handler,
    [28] = Default_Handler, [29] = Default_Handler, [30] = Default_Handler, [31] = Default_Handler,
    [32] = Default_Handler, [33] = Default_Handler, [34] = Default_Handler, [35] = Default_Handler,
    [36] = Default_Handler, [37] = Default_Handler, [38] = Default_Handler, [39] = Default_Handler,
    [40] = Default_Handler, [41] = Default_Handler, [42] = Default_Handler, [43] = Default_Handler,
    [44] = Default_Handler, [45] = Default_Handler, [46] = Default_Handler, [47] = Default_Handler,
};

__attribute__((noreturn)) void Reset_Handler(void)
{
    SCB_CPACR |= SCB_CPACR_CP10_CP11_FULL;
    __asm volatile("dsb\n\tisb" ::: "memory");

    for (uint32_t *src = _sidata, *dst = _sdata; dst < _edata;)
        *dst++ = *src++;
    for (uint32_t *dst = _sbss; dst < _ebss;)
        *dst++ = 0u;

    SCB_SHCSR |= SCB_SHCSR_FAULTS_ENA;
    semihost_exit(main());
}
