/**
 * @file startup_stm32g474.c
 * @brief Vector table and reset handler for the STM32G474 (Cortex-M4F).
 *
 * The table follows the STM32G474 interrupt layout of RM0440 (positions 0..101).
 * Every handler is a weak alias of Default_Handler, so a driver takes an
 * interrupt just by defining the function with the same name; an interrupt
 * nobody claimed forces the safe state instead of running wild.
 */
#include <stdint.h>

#include "board.h"
#include "stm32g474_regs.h"

/* Symbols from stm32g474.ld. */
extern uint32_t _sidata[], _sdata[], _edata[], _sbss[], _ebss[];
extern uint32_t _estack[];

int main(void);

void Reset_Handler(void);
void Default_Handler(void);

/** Vector number of the last unclaimed exception (for the debugger). */
volatile uint32_t g_unhandled_vector;

/**
 * Any exception or interrupt without a handler, and the CPU faults: gates
 * off, remember which vector it was, and wait for the independent watchdog
 * (if started) to reset the chip. Context: exception.
 */
void Default_Handler(void)
{
    uint32_t ipsr;
    __asm volatile("mrs %0, ipsr" : "=r"(ipsr));
    board_safe_state();
    g_unhandled_vector = ipsr & 0x1FFu;
    for (;;) {
    }
}

#define WEAK_ALIAS __attribute__((weak, alias("Default_Handler")))

/* Cortex-M4 system exceptions */
void NMI_Handler(void) WEAK_ALIAS;
void HardFault_Handler(void) WEAK_ALIAS;
void MemManage_Handler(void) WEAK_ALIAS;
void BusFault_Handler(void) WEAK_ALIAS;
void UsageFault_Handler(void) WEAK_ALIAS;
void SVC_Handler(void) WEAK_ALIAS;
void DebugMon_Handler(void) WEAK_ALIAS;
void PendSV_Handler(void) WEAK_ALIAS;
void SysTick_Handler(void) WEAK_ALIAS;

/* STM32G474 interrupts, RM0440 table "STM32G4 vector table" */
void WWDG_IRQHandler(void) WEAK_ALIAS;
void PVD_PVM_IRQHandler(void) WEAK_ALIAS;
void RTC_TAMP_LSECSS_IRQHandler(void) WEAK_ALIAS;
void RTC_WKUP_IRQHandler(void) WEAK_ALIAS;
void FLASH_IRQHandler(void) WEAK_ALIAS;
void RCC_IRQHandler(void) WEAK_ALIAS;
void EXTI0_IRQHandler(void) WEAK_ALIAS;
void EXTI1_IRQHandler(void) WEAK_ALIAS;
void EXTI2_IRQHandler(void) WEAK_ALIAS;
void EXTI3_IRQHandler(void) WEAK_ALIAS;
void EXTI4_IRQHandler(void) WEAK_ALIAS;
void DMA1_Channel1_IRQHandler(void) WEAK_ALIAS;
void DMA1_Channel2_IRQHandler(void) WEAK_ALIAS;
void DMA1_Channel3_IRQHandler(void) WEAK_ALIAS;
void DMA1_Channel4_IRQHandler(void) WEAK_ALIAS;
void DMA1_Channel5_IRQHandler(void) WEAK_ALIAS;
void DMA1_Channel6_IRQHandler(void) WEAK_ALIAS;
void DMA1_Channel7_IRQHandler(void) WEAK_ALIAS;
void ADC1_2_IRQHandler(void) WEAK_ALIAS;
void USB_HP_IRQHandler(void) WEAK_ALIAS;
void USB_LP_IRQHandler(void) WEAK_ALIAS;
void FDCAN1_IT0_IRQHandler(void) WEAK_ALIAS;
void FDCAN1_IT1_IRQHandler(void) WEAK_ALIAS;
void EXTI9_5_IRQHandler(void) WEAK_ALIAS;
void TIM1_BRK_TIM15_IRQHandler(void) WEAK_ALIAS;
void TIM1_UP_TIM16_IRQHandler(void) WEAK_ALIAS;
void TIM1_TRG_COM_TIM17_IRQHandler(void) WEAK_ALIAS;
void TIM1_CC_IRQHandler(void) WEAK_ALIAS;
void TIM2_IRQHandler(void) WEAK_ALIAS;
void TIM3_IRQHandler(void) WEAK_ALIAS;
void TIM4_IRQHandler(void) WEAK_ALIAS;
void I2C1_EV_IRQHandler(void) WEAK_ALIAS;
void I2C1_ER_IRQHandler(void) WEAK_ALIAS;
void I2C2_EV_IRQHandler(void) WEAK_ALIAS;
void I2C2_ER_IRQHandler(void) WEAK_ALIAS;
void SPI1_IRQHandler(void) WEAK_ALIAS;
void SPI2_IRQHandler(void) WEAK_ALIAS;
void USART1_IRQHandler(void) WEAK_ALIAS;
void USART2_IRQHandler(void) WEAK_ALIAS;
void USART3_IRQHandler(void) WEAK_ALIAS;
void EXTI15_10_IRQHandler(void) WEAK_ALIAS;
void RTC_Alarm_IRQHandler(void) WEAK_ALIAS;
void USBWakeUp_IRQHandler(void) WEAK_ALIAS;
void TIM8_BRK_IRQHandler(void) WEAK_ALIAS;
void TIM8_UP_IRQHandler(void) WEAK_ALIAS;
void TIM8_TRG_COM_IRQHandler(void) WEAK_ALIAS;
void TIM8_CC_IRQHandler(void) WEAK_ALIAS;
void ADC3_IRQHandler(void) WEAK_ALIAS;
void FMC_IRQHandler(void) WEAK_ALIAS;
void LPTIM1_IRQHandler(void) WEAK_ALIAS;
void TIM5_IRQHandler(void) WEAK_ALIAS;
void SPI3_IRQHandler(void) WEAK_ALIAS;
void UART4_IRQHandler(void) WEAK_ALIAS;
void UART5_IRQHandler(void) WEAK_ALIAS;
void TIM6_DAC_IRQHandler(void) WEAK_ALIAS;
void TIM7_DAC_IRQHandler(void) WEAK_ALIAS;
void DMA2_Channel1_IRQHandler(void) WEAK_ALIAS;
void DMA2_Channel2_IRQHandler(void) WEAK_ALIAS;
void DMA2_Channel3_IRQHandler(void) WEAK_ALIAS;
void DMA2_Channel4_IRQHandler(void) WEAK_ALIAS;
void DMA2_Channel5_IRQHandler(void) WEAK_ALIAS;
void ADC4_IRQHandler(void) WEAK_ALIAS;
void ADC5_IRQHandler(void) WEAK_ALIAS;
void UCPD1_IRQHandler(void) WEAK_ALIAS;
void COMP1_2_3_IRQHandler(void) WEAK_ALIAS;
void COMP4_5_6_IRQHandler(void) WEAK_ALIAS;
void COMP7_IRQHandler(void) WEAK_ALIAS;
void HRTIM1_Master_IRQHandler(void) WEAK_ALIAS;
void HRTIM1_TIMA_IRQHandler(void) WEAK_ALIAS;
void HRTIM1_TIMB_IRQHandler(void) WEAK_ALIAS;
void HRTIM1_TIMC_IRQHandler(void) WEAK_ALIAS;
void HRTIM1_TIMD_IRQHandler(void) WEAK_ALIAS;
void HRTIM1_TIME_IRQHandler(void) WEAK_ALIAS;
void HRTIM1_FLT_IRQHandler(void) WEAK_ALIAS;
void HRTIM1_TIMF_IRQHandler(void) WEAK_ALIAS;
void CRS_IRQHandler(void) WEAK_ALIAS;
void SAI1_IRQHandler(void) WEAK_ALIAS;
void TIM20_BRK_IRQHandler(void) WEAK_ALIAS;
void TIM20_UP_IRQHandler(void) WEAK_ALIAS;
void TIM20_TRG_COM_IRQHandler(void) WEAK_ALIAS;
void TIM20_CC_IRQHandler(void) WEAK_ALIAS;
void FPU_IRQHandler(void) WEAK_ALIAS;
void I2C4_EV_IRQHandler(void) WEAK_ALIAS;
void I2C4_ER_IRQHandler(void) WEAK_ALIAS;
void SPI4_IRQHandler(void) WEAK_ALIAS;
void FDCAN2_IT0_IRQHandler(void) WEAK_ALIAS;
void FDCAN2_IT1_IRQHandler(void) WEAK_ALIAS;
void FDCAN3_IT0_IRQHandler(void) WEAK_ALIAS;
void FDCAN3_IT1_IRQHandler(void) WEAK_ALIAS;
void RNG_IRQHandler(void) WEAK_ALIAS;
void LPUART1_IRQHandler(void) WEAK_ALIAS;
void I2C3_EV_IRQHandler(void) WEAK_ALIAS;
void I2C3_ER_IRQHandler(void) WEAK_ALIAS;
void DMAMUX_OVR_IRQHandler(void) WEAK_ALIAS;
void QUADSPI_IRQHandler(void) WEAK_ALIAS;
void DMA1_Channel8_IRQHandler(void) WEAK_ALIAS;
void DMA2_Channel6_IRQHandler(void) WEAK_ALIAS;
void DMA2_Channel7_IRQHandler(void) WEAK_ALIAS;
void DMA2_Channel8_IRQHandler(void) WEAK_ALIAS;
void CORDIC_IRQHandler(void) WEAK_ALIAS;
void FMAC_IRQHandler(void) WEAK_ALIAS;

typedef void (*vector_fn)(void);

/* Entry 0 is the initial main stack pointer, the rest are handler addresses. */
__attribute__((section(".isr_vector"), used)) const vector_fn g_vectors[16u + IRQN_COUNT] = {
    (vector_fn)(uintptr_t)_estack,
    Reset_Handler,
    NMI_Handler,
    HardFault_Handler,
    MemManage_Handler,
    BusFault_Handler,
    UsageFault_Handler,
    0, 0, 0, 0, /* reserved */
    SVC_Handler,
    DebugMon_Handler,
    0, /* reserved */
    PendSV_Handler,
    SysTick_Handler,
    /* 0 */ WWDG_IRQHandler,
    /* 1 */ PVD_PVM_IRQHandler,
    /* 2 */ RTC_TAMP_LSECSS_IRQHandler,
    /* 3 */ RTC_WKUP_IRQHandler,
    /* 4 */ FLASH_IRQHandler,
    /* 5 */ RCC_IRQHandler,
    /* 6 */ EXTI0_IRQHandler,
    /* 7 */ EXTI1_IRQHandler,
    /* 8 */ EXTI2_IRQHandler,
    /* 9 */ EXTI3_IRQHandler,
    /* 10 */ EXTI4_IRQHandler,
    /* 11 */ DMA1_Channel1_IRQHandler,
    /* 12 */ DMA1_Channel2_IRQHandler,
    /* 13 */ DMA1_Channel3_IRQHandler,
    /* 14 */ DMA1_Channel4_IRQHandler,
    /* 15 */ DMA1_Channel5_IRQHandler,
    /* 16 */ DMA1_Channel6_IRQHandler,
    /* 17 */ DMA1_Channel7_IRQHandler,
    /* 18 */ ADC1_2_IRQHandler,
    /* 19 */ USB_HP_IRQHandler,
    /* 20 */ USB_LP_IRQHandler,
    /* 21 */ FDCAN1_IT0_IRQHandler,
    /* 22 */ FDCAN1_IT1_IRQHandler,
    /* 23 */ EXTI9_5_IRQHandler,
    /* 24 */ TIM1_BRK_TIM15_IRQHandler,
    /* 25 */ TIM1_UP_TIM16_IRQHandler,
    /* 26 */ TIM1_TRG_COM_TIM17_IRQHandler,
    /* 27 */ TIM1_CC_IRQHandler,
    /* 28 */ TIM2_IRQHandler,
    /* 29 */ TIM3_IRQHandler,
    /* 30 */ TIM4_IRQHandler,
    /* 31 */ I2C1_EV_IRQHandler,
    /* 32 */ I2C1_ER_IRQHandler,
    /* 33 */ I2C2_EV_IRQHandler,
    /* 34 */ I2C2_ER_IRQHandler,
    /* 35 */ SPI1_IRQHandler,
    /* 36 */ SPI2_IRQHandler,
    /* 37 */ USART1_IRQHandler,
    /* 38 */ USART2_IRQHandler,
    /* 39 */ USART3_IRQHandler,
    /* 40 */ EXTI15_10_IRQHandler,
    /* 41 */ RTC_Alarm_IRQHandler,
    /* 42 */ USBWakeUp_IRQHandler,
    /* 43 */ TIM8_BRK_IRQHandler,
    /* 44 */ TIM8_UP_IRQHandler,
    /* 45 */ TIM8_TRG_COM_IRQHandler,
    /* 46 */ TIM8_CC_IRQHandler,
    /* 47 */ ADC3_IRQHandler,
    /* 48 */ FMC_IRQHandler,
    /* 49 */ LPTIM1_IRQHandler,
    /* 50 */ TIM5_IRQHandler,
    /* 51 */ SPI3_IRQHandler,
    /* 52 */ UART4_IRQHandler,
    /* 53 */ UART5_IRQHandler,
    /* 54 */ TIM6_DAC_IRQHandler,
    /* 55 */ TIM7_DAC_IRQHandler,
    /* 56 */ DMA2_Channel1_IRQHandler,
    /* 57 */ DMA2_Channel2_IRQHandler,
    /* 58 */ DMA2_Channel3_IRQHandler,
    /* 59 */ DMA2_Channel4_IRQHandler,
    /* 60 */ DMA2_Channel5_IRQHandler,
    /* 61 */ ADC4_IRQHandler,
    /* 62 */ ADC5_IRQHandler,
    /* 63 */ UCPD1_IRQHandler,
    /* 64 */ COMP1_2_3_IRQHandler,
    /* 65 */ COMP4_5_6_IRQHandler,
    /* 66 */ COMP7_IRQHandler,
    /* 67 */ HRTIM1_Master_IRQHandler,
    /* 68 */ HRTIM1_TIMA_IRQHandler,
    /* 69 */ HRTIM1_TIMB_IRQHandler,
    /* 70 */ HRTIM1_TIMC_IRQHandler,
    /* 71 */ HRTIM1_TIMD_IRQHandler,
    /* 72 */ HRTIM1_TIME_IRQHandler,
    /* 73 */ HRTIM1_FLT_IRQHandler,
    /* 74 */ HRTIM1_TIMF_IRQHandler,
    /* 75 */ CRS_IRQHandler,
    /* 76 */ SAI1_IRQHandler,
    /* 77 */ TIM20_BRK_IRQHandler,
    /* 78 */ TIM20_UP_IRQHandler,
    /* 79 */ TIM20_TRG_COM_IRQHandler,
    /* 80 */ TIM20_CC_IRQHandler,
    /* 81 */ FPU_IRQHandler,
    /* 82 */ I2C4_EV_IRQHandler,
    /* 83 */ I2C4_ER_IRQHandler,
    /* 84 */ SPI4_IRQHandler,
    /* 85 */ 0, /* reserved (AES on other parts) */
    /* 86 */ FDCAN2_IT0_IRQHandler,
    /* 87 */ FDCAN2_IT1_IRQHandler,
    /* 88 */ FDCAN3_IT0_IRQHandler,
    /* 89 */ FDCAN3_IT1_IRQHandler,
    /* 90 */ RNG_IRQHandler,
    /* 91 */ LPUART1_IRQHandler,
    /* 92 */ I2C3_EV_IRQHandler,
    /* 93 */ I2C3_ER_IRQHandler,
    /* 94 */ DMAMUX_OVR_IRQHandler,
    /* 95 */ QUADSPI_IRQHandler,
    /* 96 */ DMA1_Channel8_IRQHandler,
    /* 97 */ DMA2_Channel6_IRQHandler,
    /* 98 */ DMA2_Channel7_IRQHandler,
    /* 99 */ DMA2_Channel8_IRQHandler,
    /* 100 */ CORDIC_IRQHandler,
    /* 101 */ FMAC_IRQHandler,
};

/**
 * Reset: enable the FPU before anything can emit a float instruction, set up
 * .data and .bss, bring up clocks (board_init), run main. Written so that it
 * touches no initialised data and no floats before they exist.
 */
__attribute__((noreturn)) void Reset_Handler(void)
{
    /* CP10/CP11 full access; the barriers make the change visible before the
     * next instruction (ARMv7-M B3.2.20). */
    SCB_CPACR |= SCB_CPACR_CP10_CP11_FULL;
    __asm volatile("dsb\n\tisb" ::: "memory");

    for (uint32_t *src = _sidata, *dst = _sdata; dst < _edata;)
        *dst++ = *src++;
    for (uint32_t *dst = _sbss; dst < _ebss;)
        *dst++ = 0u;

    board_init();
    (void)main();

    /* main never returns in the product; if it does, stay safe. */
    board_safe_state();
    for (;;) {
    }
}
