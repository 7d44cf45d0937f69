/**
 * @file stm32g474_regs.h
 * @brief The few STM32G474 / Cortex-M4 registers this binding touches.
 *
 * Written from RM0440 (STM32G4 reference manual) and the ARMv7-M architecture
 * reference manual, because no vendor headers are installed and the binding
 * needs only a handful of registers. Addresses are absolute; bit names follow
 * the manuals so they can be checked against them line by line.
 * Private to hal/stm32g4: the firmware never includes it.
 */
#ifndef HAL_STM32G474_REGS_H
#define HAL_STM32G474_REGS_H

#include <stdint.h>

#define REG32(addr) (*(volatile uint32_t *)(uintptr_t)(addr))
#define REG8(addr) (*(volatile uint8_t *)(uintptr_t)(addr))

/* ------------------------------------------------ Cortex-M4 system control */
#define SCB_VTOR REG32(0xE000ED08u)
#define SCB_AIRCR REG32(0xE000ED0Cu)
#define SCB_CCR REG32(0xE000ED14u)
#define SCB_SHPR3 REG32(0xE000ED20u) /* [31:24] SysTick priority, [23:16] PendSV */
#define SCB_SHCSR REG32(0xE000ED24u)
#define SCB_CPACR REG32(0xE000ED88u)
#define SCB_CCR_DIV_0_TRP (1u << 4)
#define SCB_SHCSR_MEMFAULTENA (1u << 16)
#define SCB_SHCSR_BUSFAULTENA (1u << 17)
#define SCB_SHCSR_USGFAULTENA (1u << 18)
#define SCB_CPACR_CP10_CP11_FULL (0xFu << 20) /* FPU coprocessors: full access */

/* SysTick (ARMv7-M B3.3) */
#define SYST_CSR REG32(0xE000E010u)
#define SYST_RVR REG32(0xE000E014u)
#define SYST_CVR REG32(0xE000E018u)
#define SYST_CSR_ENABLE (1u << 0)
#define SYST_CSR_TICKINT (1u << 1)
#define SYST_CSR_CLKSOURCE (1u << 2) /* 1: processor clock */

/* NVIC: 4 priority bits on the STM32G4, held in the top nibble of each byte. */
#define NVIC_ISER(n) REG32(0xE000E100u + 4u * (n))
#define NVIC_ICER(n) REG32(0xE000E180u + 4u * (n))
#define NVIC_ICPR(n) REG32(0xE000E280u + 4u * (n))
#define NVIC_IPR8(irq) REG8(0xE000E400u + (irq))
#define NVIC_PRIO_SHIFT 4u

/* DWT cycle counter (ARMv7-M C1.8) */
#define DEMCR REG32(0xE000EDFCu)
#define DEMCR_TRCENA (1u << 24)
#define DWT_CTRL REG32(0xE0001000u)
#define DWT_CYCCNT REG32(0xE0001004u)
#define DWT_CTRL_CYCCNTENA (1u << 0)

/* ------------------------------------------------ STM32G474 interrupt numbers */
#define IRQN_FDCAN1_IT0 21u
#define IRQN_TIM6_DAC 54u
#define IRQN_HRTIM1_MASTER 67u
#define IRQN_HRTIM1_FLT 73u
#define IRQN_COUNT 102u /* 0..101 (FMAC is the last) */

/* ------------------------------------------------ RCC (RM0440 7.4) */
#define RCC_BASE 0x40021000u
#define RCC_CR REG32(RCC_BASE + 0x00u)
#define RCC_CFGR REG32(RCC_BASE + 0x08u)
#define RCC_PLLCFGR REG32(RCC_BASE + 0x0Cu)
#define RCC_AHB2ENR REG32(RCC_BASE + 0x4Cu)
#define RCC_APB1ENR1 REG32(RCC_BASE + 0x58u)
#define RCC_APB2ENR REG32(RCC_BASE + 0x60u)
#define RCC_CSR REG32(RCC_BASE + 0x94u)

#define RCC_CR_HSION (1u << 8)
#define RCC_CR_HSIRDY (1u << 10)
#define RCC_CR_PLLON (1u << 24)
#define RCC_CR_PLLRDY (1u << 25)

#define RCC_CFGR_SW_MASK (3u << 0)
#define RCC_CFGR_SW_PLL (3u << 0)
#define RCC_CFGR_SWS_MASK (3u << 2)
#define RCC_CFGR_SWS_PLL (3u << 2)
#define RCC_CFGR_HPRE_MASK (0xFu << 4)
#define RCC_CFGR_HPRE_DIV2 (0x8u << 4)
#define RCC_CFGR_PPRE1_MASK (7u << 8)
#define RCC_CFGR_PPRE2_MASK (7u << 11)

#define RCC_PLLCFGR_PLLSRC_HSI16 (2u << 0)
#define RCC_PLLCFGR_PLLM_SHIFT 4u  /* field = M - 1 */
#define RCC_PLLCFGR_PLLN_SHIFT 8u  /* field = N */
#define RCC_PLLCFGR_PLLREN (1u << 24)
#define RCC_PLLCFGR_PLLR_SHIFT 25u /* 0: /2, 1: /4, 2: /6, 3: /8 */

#define RCC_AHB2ENR_ADC12EN (1u << 13)
#define RCC_APB1ENR1_TIM6EN (1u << 4)
#define RCC_APB1ENR1_FDCANEN (1u << 25)
#define RCC_APB1ENR1_PWREN (1u << 28)
#define RCC_APB2ENR_HRTIM1EN (1u << 26)
#define RCC_CSR_LSION (1u << 0)

/* ------------------------------------------------ PWR (RM0440 6.4) */
#define PWR_BASE 0x40007000u
#define PWR_CR5 REG32(PWR_BASE + 0x80u)
#define PWR_CR5_R1MODE (1u << 8) /* 0: range 1 boost mode, required above 150 MHz */

/* ------------------------------------------------ FLASH (RM0440 5.7) */
#define FLASH_BASE_R 0x40022000u
#define FLASH_ACR REG32(FLASH_BASE_R + 0x00u)
#define FLASH_ACR_LATENCY_MASK (0xFu << 0)
#define FLASH_ACR_PRFTEN (1u << 8)
#define FLASH_ACR_ICEN (1u << 9)
#define FLASH_ACR_DCEN (1u << 10)

/* ------------------------------------------------ TIM6 basic timer (RM0440 29.4) */
#define TIM6_BASE 0x40001000u
#define TIM6_CR1 REG32(TIM6_BASE + 0x00u)
#define TIM6_DIER REG32(TIM6_BASE + 0x0Cu)
#define TIM6_SR REG32(TIM6_BASE + 0x10u)
#define TIM6_EGR REG32(TIM6_BASE + 0x14u)
#define TIM6_CNT REG32(TIM6_BASE + 0x24u)
#define TIM6_PSC REG32(TIM6_BASE + 0x28u)
#define TIM6_ARR REG32(TIM6_BASE + 0x2Cu)
#define TIM_CR1_CEN (1u << 0)
#define TIM_CR1_URS (1u << 2) /* only an overflow raises the update interrupt */
#define TIM_CR1_ARPE (1u << 7)
#define TIM_DIER_UIE (1u << 0)
#define TIM_SR_UIF (1u << 0)
#define TIM_EGR_UG (1u << 0)

/* ------------------------------------------------ IWDG (RM0440 42.4) */
#define IWDG_BASE 0x40003000u
#define IWDG_KR REG32(IWDG_BASE + 0x00u)
#define IWDG_PR REG32(IWDG_BASE + 0x04u)
#define IWDG_RLR REG32(IWDG_BASE + 0x08u)
#define IWDG_SR REG32(IWDG_BASE + 0x0Cu)
#define IWDG_KEY_START 0xCCCCu
#define IWDG_KEY_UNLOCK 0x5555u
#define IWDG_KEY_REFRESH 0xAAAAu
#define IWDG_PR_DIV32 3u /* LSI 32 kHz / 32 = 1 kHz: one reload count per ms */
#define IWDG_SR_BUSY_MASK 0x7u /* PVU | RVU | WVU */

/* ------------------------------------------------ ADC1/ADC2 injected data (RM0440 21.7) */
#define ADC1_BASE 0x50000000u
#define ADC2_BASE 0x50000100u
#define ADC_JDR(base, k) REG32((base) + 0x80u + 4u * (k)) /* k = 0..3: JDR1..JDR4 */

/* ------------------------------------------------ HRTIM1 (RM0440 27.5), for the later port */
#define HRTIM1_BASE 0x40016800u

#endif /* HAL_STM32G474_REGS_H */
