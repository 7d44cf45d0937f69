/**
 * @file stm32g474_regs.h
 * @brief The STM32G474 / Cortex-M4 registers and bit fields this binding touches.
 *
 * Written from RM0440 rev 8 (STM32G4 reference manual) and the ARMv7-M
 * architecture reference manual; no vendor header is used. Addresses are
 * absolute; bit names follow the manuals.
 *
 * Every STM32 register and field carries a machine-readable tag in its
 * comment, checked by tools/svd/check_regs.py (ctest "svd_regs") against
 * hal/stm32g4/svd/stm32g474_subset.json, the subset of ST's STM32G474.svd
 * this header uses:
 *   @svd P.R          the macro is the address of register R of peripheral P
 *   @svd P.R.F        the macro is the mask of field F (all of its bits)
 *   @svd P.R.F=v      the macro is value v placed in field F (v fits its width)
 *   @svd-shift P.R.F  the macro is the bit offset of field F
 *   @svd-base P       the macro is the base address of peripheral P
 *   @svd-offset P.R   the macro is the offset of R inside P (for P-indexed macros)
 *   @core             Cortex-M4 system register (not in the vendor SVD;
 *                     checked by hand against the ARMv7-M ARM)
 *   @const            a plain constant (key, count), not a register or field
 * The checker refuses an untagged define, so nothing slips past it.
 * Private to hal/stm32g4: the firmware never includes it.
 */
#ifndef HAL_STM32G474_REGS_H
#define HAL_STM32G474_REGS_H

#include <stdint.h>

#define REG32(addr) (*(volatile uint32_t *)(uintptr_t)(addr))
#define REG8(addr) (*(volatile uint8_t *)(uintptr_t)(addr))

/* ------------------------------------------------ Cortex-M4 system control */
#define SCB_VTOR REG32(0xE000ED08u)   /* @core */
#define SCB_AIRCR REG32(0xE000ED0Cu)  /* @core */
#define SCB_CCR REG32(0xE000ED14u)    /* @core */
#define SCB_SHPR3 REG32(0xE000ED20u)  /* @core [31:24] SysTick priority, [23:16] PendSV */
#define SCB_SHCSR REG32(0xE000ED24u)  /* @core */
#define SCB_CPACR REG32(0xE000ED88u)  /* @core */
#define SCB_CCR_DIV_0_TRP (1u << 4)       /* @core */
#define SCB_SHCSR_MEMFAULTENA (1u << 16)  /* @core */
#define SCB_SHCSR_BUSFAULTENA (1u << 17)  /* @core */
#define SCB_SHCSR_USGFAULTENA (1u << 18)  /* @core */
#define SCB_CPACR_CP10_CP11_FULL (0xFu << 20) /* @core FPU coprocessors: full access */
#define SCB_AIRCR_VECTKEY (0x05FAu << 16) /* @core */
#define SCB_AIRCR_PRIGROUP_4_0 (3u << 8)  /* @core 4 bits group priority, no sub-priority */

/* SysTick (ARMv7-M B3.3) */
#define SYST_CSR REG32(0xE000E010u) /* @core */
#define SYST_RVR REG32(0xE000E014u) /* @core */
#define SYST_CVR REG32(0xE000E018u) /* @core */
#define SYST_CSR_ENABLE (1u << 0)    /* @core */
#define SYST_CSR_TICKINT (1u << 1)   /* @core */
#define SYST_CSR_CLKSOURCE (1u << 2) /* @core 1: processor clock */

/* NVIC: 4 priority bits on the STM32G4, held in the top nibble of each byte. */
#define NVIC_ISER(n) REG32(0xE000E100u + 4u * (n)) /* @core */
#define NVIC_ICER(n) REG32(0xE000E180u + 4u * (n)) /* @core */
#define NVIC_ICPR(n) REG32(0xE000E280u + 4u * (n)) /* @core */
#define NVIC_IPR8(irq) REG8(0xE000E400u + (irq))   /* @core */
#define NVIC_PRIO_SHIFT 4u                         /* @core */

/* DWT cycle counter (ARMv7-M C1.8) */
#define DEMCR REG32(0xE000EDFCu)        /* @core */
#define DEMCR_TRCENA (1u << 24)         /* @core */
#define DWT_CTRL REG32(0xE0001000u)     /* @core */
#define DWT_CYCCNT REG32(0xE0001004u)   /* @core */
#define DWT_CTRL_CYCCNTENA (1u << 0)    /* @core */

/* ------------------------------------------------ STM32G474 interrupt numbers (RM0440 table 97) */
#define IRQN_ADC1_2 18u       /* @const */
#define IRQN_FDCAN1_IT0 21u   /* @const */
#define IRQN_HRTIM1_MASTER 67u /* @const */
#define IRQN_HRTIM1_FLT 73u   /* @const */
#define IRQN_COUNT 102u       /* @const 0..101 (FMAC is the last) */

/* ------------------------------------------------ RCC (RM0440 7.4) */
#define RCC_BASE 0x40021000u                 /* @svd-base RCC */
#define RCC_CR REG32(RCC_BASE + 0x00u)       /* @svd RCC.RCC_CR */
#define RCC_CFGR REG32(RCC_BASE + 0x08u)     /* @svd RCC.RCC_CFGR */
#define RCC_PLLCFGR REG32(RCC_BASE + 0x0Cu)  /* @svd RCC.RCC_PLLCFGR */
#define RCC_CIFR REG32(RCC_BASE + 0x1Cu)     /* @svd RCC.RCC_CIFR */
#define RCC_CICR REG32(RCC_BASE + 0x20u)     /* @svd RCC.RCC_CICR */
#define RCC_AHB1ENR REG32(RCC_BASE + 0x48u)  /* @svd RCC.RCC_AHB1ENR */
#define RCC_AHB2ENR REG32(RCC_BASE + 0x4Cu)  /* @svd RCC.RCC_AHB2ENR */
#define RCC_APB1ENR1 REG32(RCC_BASE + 0x58u) /* @svd RCC.RCC_APB1ENR1 */
#define RCC_APB2ENR REG32(RCC_BASE + 0x60u)  /* @svd RCC.RCC_APB2ENR */
#define RCC_CCIPR REG32(RCC_BASE + 0x88u)    /* @svd RCC.RCC_CCIPR */
#define RCC_CSR REG32(RCC_BASE + 0x94u)      /* @svd RCC.RCC_CSR */

#define RCC_CR_HSION (1u << 8)   /* @svd RCC.RCC_CR.HSION */
#define RCC_CR_HSIRDY (1u << 10) /* @svd RCC.RCC_CR.HSIRDY */
#define RCC_CR_HSEON (1u << 16)  /* @svd RCC.RCC_CR.HSEON */
#define RCC_CR_HSERDY (1u << 17) /* @svd RCC.RCC_CR.HSERDY */
#define RCC_CR_HSEBYP (1u << 18) /* @svd RCC.RCC_CR.HSEBYP */
#define RCC_CR_CSSON (1u << 19)  /* @svd RCC.RCC_CR.CSSON */
#define RCC_CR_PLLON (1u << 24)  /* @svd RCC.RCC_CR.PLLON */
#define RCC_CR_PLLRDY (1u << 25) /* @svd RCC.RCC_CR.PLLRDY */

#define RCC_CFGR_SW_MASK (3u << 0)       /* @svd RCC.RCC_CFGR.SW */
#define RCC_CFGR_SW_HSI16 (1u << 0)      /* @svd RCC.RCC_CFGR.SW=1 */
#define RCC_CFGR_SW_PLL (3u << 0)        /* @svd RCC.RCC_CFGR.SW=3 */
#define RCC_CFGR_SWS_MASK (3u << 2)      /* @svd RCC.RCC_CFGR.SWS */
#define RCC_CFGR_SWS_HSI16 (1u << 2)     /* @svd RCC.RCC_CFGR.SWS=1 */
#define RCC_CFGR_SWS_PLL (3u << 2)       /* @svd RCC.RCC_CFGR.SWS=3 */
#define RCC_CFGR_HPRE_MASK (0xFu << 4)   /* @svd RCC.RCC_CFGR.HPRE */
#define RCC_CFGR_HPRE_DIV2 (0x8u << 4)   /* @svd RCC.RCC_CFGR.HPRE=8 */
#define RCC_CFGR_PPRE1_MASK (7u << 8)    /* @svd RCC.RCC_CFGR.PPRE1 */
#define RCC_CFGR_PPRE2_MASK (7u << 11)   /* @svd RCC.RCC_CFGR.PPRE2 */

#define RCC_PLLCFGR_PLLSRC_MASK (3u << 0)  /* @svd RCC.RCC_PLLCFGR.PLLSRC */
#define RCC_PLLCFGR_PLLSRC_HSI16 (2u << 0) /* @svd RCC.RCC_PLLCFGR.PLLSRC=2 */
#define RCC_PLLCFGR_PLLSRC_HSE (3u << 0)   /* @svd RCC.RCC_PLLCFGR.PLLSRC=3 */
#define RCC_PLLCFGR_PLLM_SHIFT 4u          /* @svd-shift RCC.RCC_PLLCFGR.PLLM field = M - 1 */
#define RCC_PLLCFGR_PLLN_SHIFT 8u          /* @svd-shift RCC.RCC_PLLCFGR.PLLN field = N */
#define RCC_PLLCFGR_PLLREN (1u << 24)      /* @svd RCC.RCC_PLLCFGR.PLLREN */
#define RCC_PLLCFGR_PLLR_SHIFT 25u         /* @svd-shift RCC.RCC_PLLCFGR.PLLR 0: /2, 1: /4, 2: /6, 3: /8 */

#define RCC_CIFR_CSSF (1u << 8)    /* @svd RCC.RCC_CIFR.CSSF */
#define RCC_CICR_CSSC (1u << 8)    /* @svd RCC.RCC_CICR.CSSC */

#define RCC_AHB1ENR_FLASHEN (1u << 8)   /* @svd RCC.RCC_AHB1ENR.FLASHEN */
#define RCC_AHB2ENR_GPIOAEN (1u << 0)   /* @svd RCC.RCC_AHB2ENR.GPIOAEN */
#define RCC_AHB2ENR_GPIOBEN (1u << 1)   /* @svd RCC.RCC_AHB2ENR.GPIOBEN */
#define RCC_AHB2ENR_GPIOCEN (1u << 2)   /* @svd RCC.RCC_AHB2ENR.GPIOCEN */
#define RCC_AHB2ENR_ADC12EN (1u << 13)  /* @svd RCC.RCC_AHB2ENR.ADC12EN */
#define RCC_AHB2ENR_ADC345EN (1u << 14) /* @svd RCC.RCC_AHB2ENR.ADC345EN */
#define RCC_APB1ENR1_FDCANEN (1u << 25) /* @svd RCC.RCC_APB1ENR1.FDCANEN */
#define RCC_APB1ENR1_PWREN (1u << 28)   /* @svd RCC.RCC_APB1ENR1.PWREN */
#define RCC_APB2ENR_SYSCFGEN (1u << 0)  /* @svd RCC.RCC_APB2ENR.SYSCFGEN */
#define RCC_APB2ENR_HRTIM1EN (1u << 26) /* @svd RCC.RCC_APB2ENR.HRTIM1EN */
#define RCC_CCIPR_FDCANSEL_MASK (3u << 24)  /* @svd RCC.RCC_CCIPR.FDCANSEL */
#define RCC_CCIPR_FDCANSEL_PCLK1 (2u << 24) /* @svd RCC.RCC_CCIPR.FDCANSEL=2 */
#define RCC_CCIPR_ADC12SEL_MASK (3u << 28)  /* @svd RCC.RCC_CCIPR.ADC12SEL */
#define RCC_CCIPR_ADC12SEL_SYSCLK (2u << 28) /* @svd RCC.RCC_CCIPR.ADC12SEL=2 */
#define RCC_CCIPR_ADC345SEL_MASK (3u << 30)  /* @svd RCC.RCC_CCIPR.ADC345SEL */
#define RCC_CCIPR_ADC345SEL_SYSCLK (2u << 30) /* @svd RCC.RCC_CCIPR.ADC345SEL=2 */
#define RCC_CSR_LSION (1u << 0)    /* @svd RCC.RCC_CSR.LSION */
#define RCC_CSR_RMVF (1u << 23)     /* @svd RCC.RCC_CSR.RMVF */
#define RCC_CSR_OBLRSTF (1u << 25)  /* @svd RCC.RCC_CSR.OBLRSTF */
#define RCC_CSR_PINRSTF (1u << 26)  /* @svd RCC.RCC_CSR.PINRSTF */
#define RCC_CSR_BORRSTF (1u << 27)  /* @svd RCC.RCC_CSR.BORRSTF */
#define RCC_CSR_SFTRSTF (1u << 28)  /* @svd RCC.RCC_CSR.SFTRSTF */
#define RCC_CSR_IWDGRSTF (1u << 29) /* @svd RCC.RCC_CSR.IWDGRSTF */
#define RCC_CSR_WWDGRSTF (1u << 30) /* @svd RCC.RCC_CSR.WWDGRSTF */
#define RCC_CSR_LPWRRSTF (1u << 31) /* @svd RCC.RCC_CSR.LPWRRSTF */

/* ------------------------------------------------ PWR (RM0440 6.4) */
#define PWR_BASE 0x40007000u                /* @svd-base PWR */
#define PWR_CR1 REG32(PWR_BASE + 0x00u)     /* @svd PWR.PWR_CR1 */
#define PWR_SR2 REG32(PWR_BASE + 0x14u)     /* @svd PWR.PWR_SR2 */
#define PWR_CR5 REG32(PWR_BASE + 0x80u)     /* @svd PWR.PWR_CR5 */
#define PWR_CR1_VOS_MASK (3u << 9)          /* @svd PWR.PWR_CR1.VOS */
#define PWR_CR1_VOS_RANGE1 (1u << 9)        /* @svd PWR.PWR_CR1.VOS=1 */
#define PWR_SR2_VOSF (1u << 10)             /* @svd PWR.PWR_SR2.VOSF */
#define PWR_CR5_R1MODE (1u << 8)            /* @svd PWR.PWR_CR5.R1MODE 0: range 1 boost mode */

/* ------------------------------------------------ FLASH (RM0440 5.7) */
#define FLASH_BASE_R 0x40022000u                /* @svd-base FLASH */
#define FLASH_ACR REG32(FLASH_BASE_R + 0x00u)   /* @svd FLASH.FLASH_ACR */
#define FLASH_KEYR REG32(FLASH_BASE_R + 0x08u)  /* @svd FLASH.FLASH_KEYR */
#define FLASH_SR REG32(FLASH_BASE_R + 0x10u)    /* @svd FLASH.FLASH_SR */
#define FLASH_CR REG32(FLASH_BASE_R + 0x14u)    /* @svd FLASH.FLASH_CR */
#define FLASH_ECCR REG32(FLASH_BASE_R + 0x18u)  /* @svd FLASH.FLASH_ECCR */
#define FLASH_OPTR REG32(FLASH_BASE_R + 0x20u)  /* @svd FLASH.FLASH_OPTR */
#define FLASH_ECCR_ECCCIE (1u << 24)            /* @svd FLASH.FLASH_ECCR.ECCCIE */
#define FLASH_ECCR_ECCD (1u << 31)              /* @svd FLASH.FLASH_ECCR.ECCD */
#define FLASH_ACR_LATENCY_MASK (0xFu << 0)      /* @svd FLASH.FLASH_ACR.LATENCY */
#define FLASH_ACR_LATENCY_4WS (4u << 0)         /* @svd FLASH.FLASH_ACR.LATENCY=4 */
#define FLASH_ACR_PRFTEN (1u << 8)              /* @svd FLASH.FLASH_ACR.PRFTEN */
#define FLASH_ACR_ICEN (1u << 9)                /* @svd FLASH.FLASH_ACR.ICEN */
#define FLASH_ACR_DCEN (1u << 10)               /* @svd FLASH.FLASH_ACR.DCEN */
#define FLASH_ACR_DCRST (1u << 12)              /* @svd FLASH.FLASH_ACR.DCRST */
#define FLASH_KEY1 0x45670123u                  /* @const RM0440 5.3.5 unlock sequence */
#define FLASH_KEY2 0xCDEF89ABu                  /* @const */
#define FLASH_SR_EOP (1u << 0)                  /* @svd FLASH.FLASH_SR.EOP */
#define FLASH_SR_OPERR (1u << 1)                /* @svd FLASH.FLASH_SR.OPERR */
#define FLASH_SR_PROGERR (1u << 3)              /* @svd FLASH.FLASH_SR.PROGERR */
#define FLASH_SR_WRPERR (1u << 4)               /* @svd FLASH.FLASH_SR.WRPERR */
#define FLASH_SR_PGAERR (1u << 5)               /* @svd FLASH.FLASH_SR.PGAERR */
#define FLASH_SR_SIZERR (1u << 6)               /* @svd FLASH.FLASH_SR.SIZERR */
#define FLASH_SR_PGSERR (1u << 7)               /* @svd FLASH.FLASH_SR.PGSERR */
#define FLASH_SR_MISSERR (1u << 8)              /* @svd FLASH.FLASH_SR.MISSERR */
#define FLASH_SR_FASTERR (1u << 9)              /* @svd FLASH.FLASH_SR.FASTERR */
#define FLASH_SR_RDERR (1u << 14)               /* @svd FLASH.FLASH_SR.RDERR */
#define FLASH_SR_OPTVERR (1u << 15)             /* @svd FLASH.FLASH_SR.OPTVERR */
#define FLASH_SR_BSY (1u << 16)                 /* @svd FLASH.FLASH_SR.BSY */
#define FLASH_CR_PG (1u << 0)                   /* @svd FLASH.FLASH_CR.PG */
#define FLASH_CR_PER (1u << 1)                  /* @svd FLASH.FLASH_CR.PER */
#define FLASH_CR_PNB_SHIFT 3u                   /* @svd-shift FLASH.FLASH_CR.PNB */
#define FLASH_CR_PNB_MASK (0x7Fu << 3)          /* @svd FLASH.FLASH_CR.PNB */
#define FLASH_CR_BKER (1u << 11)                /* @svd FLASH.FLASH_CR.BKER */
#define FLASH_CR_STRT (1u << 16)                /* @svd FLASH.FLASH_CR.START */
#define FLASH_CR_LOCK (1u << 31)                /* @svd FLASH.FLASH_CR.LOCK */
#define FLASH_OPTR_DBANK (1u << 22)             /* @svd FLASH.FLASH_OPTR.DBANK */
#define FLASH_OPTR_NSWBOOT0 (1u << 26)          /* @svd FLASH.FLASH_OPTR.nSWBOOT0 */
#define FLASH_OPTR_NBOOT0 (1u << 27)            /* @svd FLASH.FLASH_OPTR.nBOOT0 */

/* ------------------------------------------------ IWDG (RM0440 41.4) */
#define IWDG_BASE 0x40003000u               /* @svd-base IWDG */
#define IWDG_KR REG32(IWDG_BASE + 0x00u)    /* @svd IWDG.KR */
#define IWDG_PR REG32(IWDG_BASE + 0x04u)    /* @svd IWDG.PR */
#define IWDG_RLR REG32(IWDG_BASE + 0x08u)   /* @svd IWDG.RLR */
#define IWDG_SR REG32(IWDG_BASE + 0x0Cu)    /* @svd IWDG.SR */
#define IWDG_KEY_START 0xCCCCu              /* @svd IWDG.KR.KEY=0xCCCC */
#define IWDG_KEY_UNLOCK 0x5555u             /* @svd IWDG.KR.KEY=0x5555 */
#define IWDG_KEY_REFRESH 0xAAAAu            /* @svd IWDG.KR.KEY=0xAAAA */
#define IWDG_PR_DIV32 3u                    /* @svd IWDG.PR.PR=3 LSI 32 kHz / 32 = 1 kHz */
#define IWDG_RLR_MAX 0xFFFu                 /* @svd IWDG.RLR.RL */
#define IWDG_SR_PVU (1u << 0)               /* @svd IWDG.SR.PVU */
#define IWDG_SR_RVU (1u << 1)               /* @svd IWDG.SR.RVU */
#define IWDG_SR_WVU (1u << 2)               /* @svd IWDG.SR.WVU */
#define IWDG_SR_BUSY_MASK (IWDG_SR_PVU | IWDG_SR_RVU | IWDG_SR_WVU) /* @const */

/* ------------------------------------------------ DBGMCU (RM0440 47.16) */
#define DBGMCU_APB1L_FZ REG32(0xE0042008u)   /* @svd DBGMCU.APB1L_FZ */
#define DBGMCU_APB2_FZ REG32(0xE0042010u)    /* @svd DBGMCU.APB2_FZ */
#define DBGMCU_APB1L_FZ_IWDG (1u << 12)      /* @svd DBGMCU.APB1L_FZ.DBG_IWDG_STOP */

/* ------------------------------------------------ GPIO (RM0440 9.4) */
#define GPIOA_BASE 0x48000000u        /* @svd-base GPIOA */
#define GPIOB_BASE 0x48000400u        /* @svd-base GPIOB */
#define GPIOC_BASE 0x48000800u        /* @svd-base GPIOC */
#define GPIO_MODER_OFS 0x00u          /* @svd-offset GPIOA.MODER */
#define GPIO_OTYPER_OFS 0x04u         /* @svd-offset GPIOA.OTYPER */
#define GPIO_OSPEEDR_OFS 0x08u        /* @svd-offset GPIOA.OSPEEDR */
#define GPIO_PUPDR_OFS 0x0Cu          /* @svd-offset GPIOA.PUPDR */
#define GPIO_IDR_OFS 0x10u            /* @svd-offset GPIOA.IDR */
#define GPIO_BSRR_OFS 0x18u           /* @svd-offset GPIOA.BSRR */
#define GPIO_AFRL_OFS 0x20u           /* @svd-offset GPIOA.AFRL */
#define GPIO_AFRH_OFS 0x24u           /* @svd-offset GPIOA.AFRH */
#define GPIO_MODER_MASK0 (3u << 0)    /* @svd GPIOA.MODER.MODER0 2 bits per pin */
#define GPIO_AFR_MASK0 (0xFu << 0)    /* @svd GPIOA.AFRL.AFRL0 4 bits per pin */
#define GPIO_MODE_INPUT 0u            /* @svd GPIOA.MODER.MODER0=0 */
#define GPIO_MODE_OUTPUT 1u           /* @svd GPIOA.MODER.MODER0=1 */
#define GPIO_MODE_AF 2u               /* @svd GPIOA.MODER.MODER0=2 */
#define GPIO_MODE_ANALOG 3u           /* @svd GPIOA.MODER.MODER0=3 */
#define GPIO_REG(base, ofs) REG32((base) + (ofs)) /* @const */

/* ------------------------------------------------ HRTIM1 (RM0440 27.5) */
#define HRTIM_MASTER_BASE 0x40016800u               /* @svd-base HRTIM_Master */
#define HRTIM_MCR REG32(HRTIM_MASTER_BASE + 0x00u)   /* @svd HRTIM_Master.MCR */
#define HRTIM_MISR REG32(HRTIM_MASTER_BASE + 0x04u)  /* @svd HRTIM_Master.MISR */
#define HRTIM_MICR REG32(HRTIM_MASTER_BASE + 0x08u)  /* @svd HRTIM_Master.MICR */
#define HRTIM_MCNTR REG32(HRTIM_MASTER_BASE + 0x10u) /* @svd HRTIM_Master.MCNTR */
#define HRTIM_MPER REG32(HRTIM_MASTER_BASE + 0x14u)  /* @svd HRTIM_Master.MPER */
#define HRTIM_MREP REG32(HRTIM_MASTER_BASE + 0x18u)  /* @svd HRTIM_Master.MREP */
#define HRTIM_MCMP1R REG32(HRTIM_MASTER_BASE + 0x1Cu) /* @svd HRTIM_Master.MCMP1R */
#define HRTIM_MCR_CK_PSC_SHIFT 0u     /* @svd-shift HRTIM_Master.MCR.CK_PSC */
#define HRTIM_MCR_CONT (1u << 3)      /* @svd HRTIM_Master.MCR.CONT */
#define HRTIM_MCR_MCEN (1u << 16)     /* @svd HRTIM_Master.MCR.MCEN */
#define HRTIM_MCR_TACEN (1u << 17)    /* @svd HRTIM_Master.MCR.TACEN */
#define HRTIM_MCR_TBCEN (1u << 18)    /* @svd HRTIM_Master.MCR.TBCEN */
#define HRTIM_MCR_TCCEN (1u << 19)    /* @svd HRTIM_Master.MCR.TCCEN */
#define HRTIM_MCR_TDCEN (1u << 20)    /* @svd HRTIM_Master.MCR.TDCEN */
#define HRTIM_MCR_TECEN (1u << 21)    /* @svd HRTIM_Master.MCR.TECEN */
#define HRTIM_MCR_TFCEN (1u << 22)    /* @svd HRTIM_Master.MCR.TFCEN */
#define HRTIM_MCR_PREEN (1u << 27)    /* @svd HRTIM_Master.MCR.PREEN */
#define HRTIM_MCR_MREPU (1u << 29)    /* @svd HRTIM_Master.MCR.MREPU */
#define HRTIM_MISR_MCMP1 (1u << 0)    /* @svd HRTIM_Master.MISR.MCMP1 */
#define HRTIM_MICR_MCMP1C (1u << 0)   /* @svd HRTIM_Master.MICR.MCMP1C */

/* Timing units A..F: identical layouts 0x80 apart (RM0440 27.5.21..). */
#define HRTIM_TIMA_BASE 0x40016880u   /* @svd-base HRTIM_TIMA */
#define HRTIM_TIMB_BASE 0x40016900u   /* @svd-base HRTIM_TIMB */
#define HRTIM_TIMC_BASE 0x40016980u   /* @svd-base HRTIM_TIMC */
#define HRTIM_TIMD_BASE 0x40016A00u   /* @svd-base HRTIM_TIMD */
#define HRTIM_TIME_BASE 0x40016A80u   /* @svd-base HRTIM_TIME */
#define HRTIM_TIMF_BASE 0x40016B00u   /* @svd-base HRTIM_TIMF */
#define HRTIM_TIM_STRIDE 0x80u        /* @const */
#define HRTIM_TIMxCR_OFS 0x00u        /* @svd-offset HRTIM_TIMA.TIMACR */
#define HRTIM_TIMxISR_OFS 0x04u       /* @svd-offset HRTIM_TIMA.TIMAISR */
#define HRTIM_TIMxICR_OFS 0x08u       /* @svd-offset HRTIM_TIMA.TIMAICR */
#define HRTIM_CNTxR_OFS 0x10u         /* @svd-offset HRTIM_TIMA.CNTAR */
#define HRTIM_PERxR_OFS 0x14u         /* @svd-offset HRTIM_TIMA.PERAR */
#define HRTIM_REPxR_OFS 0x18u         /* @svd-offset HRTIM_TIMA.REPAR */
#define HRTIM_CMP1xR_OFS 0x1Cu        /* @svd-offset HRTIM_TIMA.CMP1AR */
#define HRTIM_CMP2xR_OFS 0x24u        /* @svd-offset HRTIM_TIMA.CMP2AR */
#define HRTIM_DTxR_OFS 0x38u          /* @svd-offset HRTIM_TIMA.DTAR */
#define HRTIM_SETx1R_OFS 0x3Cu        /* @svd-offset HRTIM_TIMA.SETA1R */
#define HRTIM_RSTx1R_OFS 0x40u        /* @svd-offset HRTIM_TIMA.RSTA1R */
#define HRTIM_SETx2R_OFS 0x44u        /* @svd-offset HRTIM_TIMA.SETA2R */
#define HRTIM_RSTx2R_OFS 0x48u        /* @svd-offset HRTIM_TIMA.RSTA2R */
#define HRTIM_OUTxR_OFS 0x64u         /* @svd-offset HRTIM_TIMA.OUTAR */
#define HRTIM_FLTxR_OFS 0x68u         /* @svd-offset HRTIM_TIMA.FLTAR */
#define HRTIM_TIM_REG(t, ofs) REG32(HRTIM_TIMA_BASE + HRTIM_TIM_STRIDE * (t) + (ofs)) /* @const t = 0..5: A..F */

#define HRTIM_TIMxCR_CK_PSC_SHIFT 0u  /* @svd-shift HRTIM_TIMA.TIMACR.CK_PSCx */
#define HRTIM_TIMxCR_CONT (1u << 3)   /* @svd HRTIM_TIMA.TIMACR.CONT */
#define HRTIM_TIMxCR_TREPU (1u << 17) /* @svd HRTIM_TIMA.TIMACR.TxREPU */
#define HRTIM_TIMxCR_PREEN (1u << 27) /* @svd HRTIM_TIMA.TIMACR.PREEN */
#define HRTIM_DTxR_DTR_SHIFT 0u       /* @svd-shift HRTIM_TIMA.DTAR.DTRx */
#define HRTIM_DTxR_DTR_MASK (0x1FFu << 0) /* @svd HRTIM_TIMA.DTAR.DTRx */
#define HRTIM_DTxR_DTPRSC_SHIFT 10u   /* @svd-shift HRTIM_TIMA.DTAR.DTPRSC */
#define HRTIM_DTxR_DTF_SHIFT 16u      /* @svd-shift HRTIM_TIMA.DTAR.DTFx */
#define HRTIM_DTxR_DTF_MASK (0x1FFu << 16) /* @svd HRTIM_TIMA.DTAR.DTFx */
#define HRTIM_DTxR_DTRLK (1u << 15)   /* @svd HRTIM_TIMA.DTAR.DTRLKx */
#define HRTIM_DTxR_DTFLK (1u << 31)   /* @svd HRTIM_TIMA.DTAR.DTFLKx */
#define HRTIM_SET_SST (1u << 0)       /* @svd HRTIM_TIMA.SETA1R.SST software set, not preloaded */
#define HRTIM_SET_PER (1u << 2)       /* @svd HRTIM_TIMA.SETA1R.PER */
#define HRTIM_SET_CMP1 (1u << 3)      /* @svd HRTIM_TIMA.SETA1R.CMP1 */
#define HRTIM_SET_CMP2 (1u << 4)      /* @svd HRTIM_TIMA.SETA1R.CMP2 */
#define HRTIM_RST_PER (1u << 2)       /* @svd HRTIM_TIMA.RSTA1R.PER */
#define HRTIM_RST_CMP1 (1u << 3)      /* @svd HRTIM_TIMA.RSTA1R.CMP1 */
#define HRTIM_RST_CMP2 (1u << 4)      /* @svd HRTIM_TIMA.RSTA1R.CMP2 */
#define HRTIM_RST_EXTEVNT6 (1u << 26) /* @svd HRTIM_TIMA.RSTA1R.EXTEVNT6 */
#define HRTIM_OUTxR_POL1 (1u << 1)    /* @svd HRTIM_TIMA.OUTAR.POL1 */
#define HRTIM_OUTxR_IDLES1 (1u << 3)  /* @svd HRTIM_TIMA.OUTAR.IDLES1 */
#define HRTIM_OUTxR_FAULT1_MASK (3u << 4)     /* @svd HRTIM_TIMA.OUTAR.FAULT1 */
#define HRTIM_OUTxR_FAULT1_NONE (0u << 4)     /* @svd HRTIM_TIMA.OUTAR.FAULT1=0 */
#define HRTIM_OUTxR_FAULT1_INACTIVE (2u << 4) /* @svd HRTIM_TIMA.OUTAR.FAULT1=2 */
#define HRTIM_OUTxR_DTEN (1u << 8)    /* @svd HRTIM_TIMA.OUTAR.DTEN */
#define HRTIM_OUTxR_POL2 (1u << 17)   /* @svd HRTIM_TIMA.OUTAR.POL2 */
#define HRTIM_OUTxR_IDLES2 (1u << 19) /* @svd HRTIM_TIMA.OUTAR.IDLES2 */
#define HRTIM_OUTxR_FAULT2_MASK (3u << 20)     /* @svd HRTIM_TIMA.OUTAR.FAULT2 */
#define HRTIM_OUTxR_FAULT2_NONE (0u << 20)     /* @svd HRTIM_TIMA.OUTAR.FAULT2=0 */
#define HRTIM_OUTxR_FAULT2_INACTIVE (2u << 20) /* @svd HRTIM_TIMA.OUTAR.FAULT2=2 */
#define HRTIM_FLTxR_FLT3EN (1u << 2)  /* @svd HRTIM_TIMA.FLTAR.FLT3EN */
#define HRTIM_FLTxR_FLTLCK (1u << 31) /* @svd HRTIM_TIMA.FLTAR.FLTLCK */

/* Common registers (RM0440 27.5.52..). */
#define HRTIM_COMMON_BASE 0x40016B80u                  /* @svd-base HRTIM_Common */
#define HRTIM_CR1 REG32(HRTIM_COMMON_BASE + 0x00u)     /* @svd HRTIM_Common.CR1 */
#define HRTIM_CR2 REG32(HRTIM_COMMON_BASE + 0x04u)     /* @svd HRTIM_Common.CR2 */
#define HRTIM_ISR REG32(HRTIM_COMMON_BASE + 0x08u)     /* @svd HRTIM_Common.ISR */
#define HRTIM_ICR REG32(HRTIM_COMMON_BASE + 0x0Cu)     /* @svd HRTIM_Common.ICR */
#define HRTIM_IER REG32(HRTIM_COMMON_BASE + 0x10u)     /* @svd HRTIM_Common.IER */
#define HRTIM_OENR REG32(HRTIM_COMMON_BASE + 0x14u)    /* @svd HRTIM_Common.OENR */
#define HRTIM_ODISR REG32(HRTIM_COMMON_BASE + 0x18u)   /* @svd HRTIM_Common.ODISR */
#define HRTIM_ODSR REG32(HRTIM_COMMON_BASE + 0x1Cu)    /* @svd HRTIM_Common.ODSR */
#define HRTIM_ADC2R REG32(HRTIM_COMMON_BASE + 0x40u)   /* @svd HRTIM_Common.ADC2R */
#define HRTIM_EECR2 REG32(HRTIM_COMMON_BASE + 0x34u)   /* @svd HRTIM_Common.EECR2 */
#define HRTIM_EECR3 REG32(HRTIM_COMMON_BASE + 0x38u)   /* @svd HRTIM_Common.EECR3 */
#define HRTIM_FLTINR1 REG32(HRTIM_COMMON_BASE + 0x50u) /* @svd HRTIM_Common.FLTINR1 */
#define HRTIM_FLTINR2 REG32(HRTIM_COMMON_BASE + 0x54u) /* @svd HRTIM_Common.FLTINR2 */
#define HRTIM_CR1_UDIS_ALL (0x7Fu << 0)  /* @const MUDIS|TAUDIS..TFUDIS, bits 0..6 */
#define HRTIM_CR1_MUDIS (1u << 0)        /* @svd HRTIM_Common.CR1.MUDIS */
#define HRTIM_CR1_TFUDIS (1u << 6)       /* @svd HRTIM_Common.CR1.TFUDIS */
#define HRTIM_CR2_MSWU (1u << 0)         /* @svd HRTIM_Common.CR2.MSWU */
#define HRTIM_CR2_TFSWU (1u << 6)        /* @svd HRTIM_Common.CR2.TFSWU */
#define HRTIM_CR2_SWU_ALL (0x7Fu << 0)   /* @const MSWU|TASWU..TFSWU, bits 0..6 */
#define HRTIM_ISR_FLT3 (1u << 2)         /* @svd HRTIM_Common.ISR.FLT3 */
#define HRTIM_ICR_FLT3C (1u << 2)        /* @svd HRTIM_Common.ICR.FLT3C */
#define HRTIM_IER_FLT3IE (1u << 2)       /* @svd HRTIM_Common.IER.FLT3IE */
#define HRTIM_OUT_ALL 0xFFFu             /* @const TA1..TF2: bits 0..11 of OENR/ODISR/ODSR */
#define HRTIM_OENR_TA1OEN (1u << 0)      /* @svd HRTIM_Common.OENR.TA1OEN */
#define HRTIM_OENR_TF2OEN (1u << 11)     /* @svd HRTIM_Common.OENR.TF2OEN */
#define HRTIM_ODISR_TA1ODIS (1u << 0)    /* @svd HRTIM_Common.ODISR.TA1ODIS */
#define HRTIM_ODISR_TF2ODIS (1u << 11)   /* @svd HRTIM_Common.ODISR.TF2ODIS */
#define HRTIM_ADC2R_AD2MC1 (1u << 0)     /* @svd HRTIM_Common.ADC2R.AD2MC1 */
#define HRTIM_EECR2_EE6SRC_PIN (0u << 0) /* @svd HRTIM_Common.EECR2.EE6SRC=0 source 1: the HRTIM_EEV6 pin */
#define HRTIM_EECR2_EE6POL_LOW (1u << 2) /* @svd HRTIM_Common.EECR2.EE6POL 1: active low */
#define HRTIM_EECR2_EE6SNS_LEVEL (0u << 3) /* @svd HRTIM_Common.EECR2.EE6SNS=0 active level, not an edge */
#define HRTIM_EECR2_EE6_MASK (0x1Fu << 0) /* @const EE6SRC | EE6POL | EE6SNS, bits 0..4 */
#define HRTIM_EECR3_EE6F_SHIFT 0u        /* @svd-shift HRTIM_Common.EECR3.EE6F */
#define HRTIM_EECR3_EE6F_MASK (0xFu << 0) /* @svd HRTIM_Common.EECR3.EE6F */
#define HRTIM_EECR3_EEVSD_MASK (3u << 30) /* @svd HRTIM_Common.EECR3.EEVSD */
#define HRTIM_EECR3_EEVSD_DIV1 (0u << 30) /* @svd HRTIM_Common.EECR3.EEVSD=0 fEEVS = fHRTIM */
#define HRTIM_EEF_DIV16_N8 12u           /* @const EExF 1100: fSAMPLING = fEEVS / 16, N = 8 (RM0440, HRTIM_EECR3) */
#define HRTIM_FLTINR1_FLT3E (1u << 16)   /* @svd HRTIM_Common.FLTINR1.FLT3E */
#define HRTIM_FLTINR1_FLT3P (1u << 17)   /* @svd HRTIM_Common.FLTINR1.FLT3P 0: active low */
#define HRTIM_FLTINR1_FLT3SRC (1u << 18) /* @svd HRTIM_Common.FLTINR1.FLT3SRC 0: FLT3 pin */
#define HRTIM_FLTINR1_FLT3F_SHIFT 19u    /* @svd-shift HRTIM_Common.FLTINR1.FLT3F */
#define HRTIM_FLTINR1_FLT3LCK (1u << 23) /* @svd HRTIM_Common.FLTINR1.FLT3LCK */

/* ------------------------------------------------ ADC1/ADC2 (RM0440 21.7) */
#define ADC1_BASE 0x50000000u          /* @svd-base ADC1 */
#define ADC2_BASE 0x50000100u          /* @svd-base ADC2 */
#define ADC12_COMMON_BASE 0x50000300u  /* @svd-base ADC12_Common */
#define ADC3_BASE 0x50000400u          /* @svd-base ADC3 */
#define ADC345_COMMON_BASE 0x50000700u /* @svd-base ADC345_Common */
#define ADC_ISR_OFS 0x00u              /* @svd-offset ADC1.ISR */
#define ADC_IER_OFS 0x04u              /* @svd-offset ADC1.IER */
#define ADC_CR_OFS 0x08u               /* @svd-offset ADC1.CR */
#define ADC_CFGR_OFS 0x0Cu             /* @svd-offset ADC1.CFGR */
#define ADC_SMPR1_OFS 0x14u            /* @svd-offset ADC1.SMPR1 */
#define ADC_SMPR2_OFS 0x18u            /* @svd-offset ADC1.SMPR2 */
#define ADC_JSQR_OFS 0x4Cu             /* @svd-offset ADC1.JSQR */
#define ADC_JDR1_OFS 0x80u             /* @svd-offset ADC1.JDR1 */
#define ADC_DIFSEL_OFS 0xB0u           /* @svd-offset ADC1.DIFSEL */
#define ADC_REG(base, ofs) REG32((base) + (ofs)) /* @const */
#define ADC_JDR(base, k) REG32((base) + ADC_JDR1_OFS + 4u * (k)) /* @const k = 0..3: JDR1..JDR4 */
#define ADC12_CCR REG32(ADC12_COMMON_BASE + 0x08u) /* @svd ADC12_Common.CCR */
#define ADC345_CCR REG32(ADC345_COMMON_BASE + 0x08u) /* @svd ADC345_Common.CCR */
/* ADC3 has ADC1's register layout (ADC_*_OFS above); the two the tick reads, checked on their own: */
#define ADC3_ISR REG32(ADC3_BASE + 0x00u)  /* @svd ADC3.ISR */
#define ADC3_JDR1 REG32(ADC3_BASE + 0x80u) /* @svd ADC3.JDR1 */
#define ADC3_JSQR REG32(ADC3_BASE + 0x4Cu) /* @svd ADC3.JSQR */

#define ADC_ISR_ADRDY (1u << 0)     /* @svd ADC1.ISR.ADRDY */
#define ADC_ISR_JEOC (1u << 5)      /* @svd ADC1.ISR.JEOC */
#define ADC_ISR_JEOS (1u << 6)      /* @svd ADC1.ISR.JEOS */
#define ADC_ISR_JQOVF (1u << 10)    /* @svd ADC1.ISR.JQOVF */
#define ADC_IER_JEOSIE (1u << 6)    /* @svd ADC1.IER.JEOSIE */
#define ADC_CR_ADEN (1u << 0)       /* @svd ADC1.CR.ADEN */
#define ADC_CR_ADDIS (1u << 1)      /* @svd ADC1.CR.ADDIS */
#define ADC_CR_JADSTART (1u << 3)   /* @svd ADC1.CR.JADSTART */
#define ADC_CR_JADSTP (1u << 5)     /* @svd ADC1.CR.JADSTP */
#define ADC_CR_ADVREGEN (1u << 28)  /* @svd ADC1.CR.ADVREGEN */
#define ADC_CR_DEEPPWD (1u << 29)   /* @svd ADC1.CR.DEEPPWD */
#define ADC_CR_ADCALDIF (1u << 30)  /* @svd ADC1.CR.ADCALDIF */
#define ADC_CR_ADCAL (1u << 31)     /* @svd ADC1.CR.ADCAL */
#define ADC_CFGR_JQDIS (1u << 31)   /* @svd ADC1.CFGR.JQDIS */
#define ADC_SMPR_BITS 3u            /* @const 3 bits per channel in SMPR1/SMPR2 */
#define ADC_SMP_24C5 3u             /* @svd ADC1.SMPR1.SMP0=3 24.5 ADC clock cycles */
#define ADC_JSQR_JL_SHIFT 0u        /* @svd-shift ADC1.JSQR.JL field = length - 1 */
#define ADC_JSQR_JEXTSEL_SHIFT 2u   /* @svd-shift ADC1.JSQR.JEXTSEL */
#define ADC_JSQR_JEXTEN_RISING (1u << 7) /* @svd ADC1.JSQR.JEXTEN=1 */
#define ADC_JSQR_JSQ1_SHIFT 9u      /* @svd-shift ADC1.JSQR.JSQ1 */
#define ADC_JSQR_JSQ2_SHIFT 15u     /* @svd-shift ADC1.JSQR.JSQ2 */
#define ADC_JSQR_JSQ3_SHIFT 21u     /* @svd-shift ADC1.JSQR.JSQ3 */
#define ADC_JEXTSEL_HRTIM_TRG2 19u  /* @const RM0440 table 164: adc_jext_trg19 = hrtim_adc_trg2 (ADC1/2) */
#define ADC345_JEXTSEL_HRTIM_TRG2 19u /* @const RM0440 ADC3/4/5 injected trigger table: adc_jext_trg19 = hrtim_adc_trg2 too */
#define ADC12_CCR_DUAL_MASK (0x1Fu << 0)   /* @svd ADC12_Common.CCR.DUAL */
#define ADC12_CCR_DUAL_INJ_SIMULT (5u << 0) /* @svd ADC12_Common.CCR.DUAL=5 injected simultaneous only */
#define ADC12_CCR_CKMODE_MASK (3u << 16)   /* @svd ADC12_Common.CCR.CKMODE */
#define ADC12_CCR_CKMODE_HCLK_DIV4 (3u << 16) /* @svd ADC12_Common.CCR.CKMODE=3 */
#define ADC345_CCR_DUAL_MASK (0x1Fu << 0)     /* @svd ADC345_Common.CCR.DUAL */
#define ADC345_CCR_CKMODE_MASK (3u << 16)     /* @svd ADC345_Common.CCR.CKMODE */
#define ADC345_CCR_CKMODE_HCLK_DIV4 (3u << 16) /* @svd ADC345_Common.CCR.CKMODE=3 */

/* ------------------------------------------------ FDCAN1 (RM0440 44.4) */
#define FDCAN1_BASE 0x40006400u                    /* @svd-base FDCAN1 */
#define FDCAN1_CCCR REG32(FDCAN1_BASE + 0x018u)    /* @svd FDCAN1.FDCAN_CCCR */
#define FDCAN1_NBTP REG32(FDCAN1_BASE + 0x01Cu)    /* @svd FDCAN1.FDCAN_NBTP */
#define FDCAN1_ECR REG32(FDCAN1_BASE + 0x040u)     /* @svd FDCAN1.FDCAN_ECR */
#define FDCAN1_PSR REG32(FDCAN1_BASE + 0x044u)     /* @svd FDCAN1.FDCAN_PSR */
#define FDCAN1_IR REG32(FDCAN1_BASE + 0x050u)      /* @svd FDCAN1.FDCAN_IR */
#define FDCAN1_IE REG32(FDCAN1_BASE + 0x054u)      /* @svd FDCAN1.FDCAN_IE */
#define FDCAN1_ILE REG32(FDCAN1_BASE + 0x05Cu)     /* @svd FDCAN1.FDCAN_ILE */
#define FDCAN1_RXGFC REG32(FDCAN1_BASE + 0x080u)   /* @svd FDCAN1.FDCAN_RXGFC */
#define FDCAN1_RXF0S REG32(FDCAN1_BASE + 0x090u)   /* @svd FDCAN1.FDCAN_RXF0S */
#define FDCAN1_RXF0A REG32(FDCAN1_BASE + 0x094u)   /* @svd FDCAN1.FDCAN_RXF0A */
#define FDCAN1_TXBC REG32(FDCAN1_BASE + 0x0C0u)    /* @svd FDCAN1.FDCAN_TXBC */
#define FDCAN1_TXFQS REG32(FDCAN1_BASE + 0x0C4u)   /* @svd FDCAN1.FDCAN_TXFQS */
#define FDCAN1_TXBAR REG32(FDCAN1_BASE + 0x0CCu)   /* @svd FDCAN1.FDCAN_TXBAR */
#define FDCAN1_CKDIV REG32(FDCAN1_BASE + 0x100u)   /* @svd FDCAN1.FDCAN_CKDIV */
#define FDCAN_CCCR_INIT (1u << 0)      /* @svd FDCAN1.FDCAN_CCCR.INIT */
#define FDCAN_CCCR_CCE (1u << 1)       /* @svd FDCAN1.FDCAN_CCCR.CCE */
#define FDCAN_CCCR_DAR (1u << 6)       /* @svd FDCAN1.FDCAN_CCCR.DAR */
#define FDCAN_CCCR_FDOE (1u << 8)      /* @svd FDCAN1.FDCAN_CCCR.FDOE */
#define FDCAN_CCCR_BRSE (1u << 9)      /* @svd FDCAN1.FDCAN_CCCR.BRSE */
#define FDCAN_NBTP_NTSEG2_SHIFT 0u     /* @svd-shift FDCAN1.FDCAN_NBTP.NTSEG2 field = tseg2 - 1 */
#define FDCAN_NBTP_NTSEG1_SHIFT 8u     /* @svd-shift FDCAN1.FDCAN_NBTP.NTSEG1 field = tseg1 - 1 */
#define FDCAN_NBTP_NBRP_SHIFT 16u      /* @svd-shift FDCAN1.FDCAN_NBTP.NBRP field = prescaler - 1 */
#define FDCAN_NBTP_NSJW_SHIFT 25u      /* @svd-shift FDCAN1.FDCAN_NBTP.NSJW field = sjw - 1 */
#define FDCAN_ECR_TEC_MASK (0xFFu << 0) /* @svd FDCAN1.FDCAN_ECR.TEC */
#define FDCAN_PSR_BO (1u << 7)         /* @svd FDCAN1.FDCAN_PSR.BO */
#define FDCAN_PSR_EP (1u << 5)         /* @svd FDCAN1.FDCAN_PSR.EP */
#define FDCAN_IR_RF0N (1u << 0)        /* @svd FDCAN1.FDCAN_IR.RF0N */
#define FDCAN_IR_RF0L (1u << 2)        /* @svd FDCAN1.FDCAN_IR.RF0L */
#define FDCAN_IR_TFE (1u << 9)         /* @svd FDCAN1.FDCAN_IR.TFE */
#define FDCAN_IE_RF0NE (1u << 0)       /* @svd FDCAN1.FDCAN_IE.RF0NE */
#define FDCAN_IE_TFEE (1u << 9)        /* @svd FDCAN1.FDCAN_IE.TFEE */
#define FDCAN_ILE_EINT0 (1u << 0)      /* @svd FDCAN1.FDCAN_ILE.EINT0 */
#define FDCAN_IR_BO (1u << 19)         /* @svd FDCAN1.FDCAN_IR.BO */
#define FDCAN_RXGFC_RRFE (1u << 0)     /* @svd FDCAN1.FDCAN_RXGFC.RRFE */
#define FDCAN_RXGFC_RRFS (1u << 1)     /* @svd FDCAN1.FDCAN_RXGFC.RRFS */
#define FDCAN_RXGFC_ANFE_REJECT (2u << 2) /* @svd FDCAN1.FDCAN_RXGFC.ANFE=2 */
#define FDCAN_RXGFC_ANFS_REJECT (2u << 4) /* @svd FDCAN1.FDCAN_RXGFC.ANFS=2 */
#define FDCAN_RXGFC_LSS_SHIFT 16u      /* @svd-shift FDCAN1.FDCAN_RXGFC.LSS */
#define FDCAN_RXF0S_F0FL_MASK (0xFu << 0) /* @svd FDCAN1.FDCAN_RXF0S.F0FL */
#define FDCAN_RXF0S_F0GI_SHIFT 8u      /* @svd-shift FDCAN1.FDCAN_RXF0S.F0GI */
#define FDCAN_RXF0S_F0GI_MASK (3u << 8) /* @svd FDCAN1.FDCAN_RXF0S.F0GI */
#define FDCAN_TXBC_TFQM (1u << 24)     /* @svd FDCAN1.FDCAN_TXBC.TFQM 0: FIFO */
#define FDCAN_TXFQS_TFQPI_SHIFT 16u    /* @svd-shift FDCAN1.FDCAN_TXFQS.TFQPI */
#define FDCAN_TXFQS_TFQPI_MASK (3u << 16) /* @svd FDCAN1.FDCAN_TXFQS.TFQPI */
#define FDCAN_TXFQS_TFQF (1u << 21)    /* @svd FDCAN1.FDCAN_TXFQS.TFQF */

/* FDCAN message RAM (RM0440 44.3.3): 212 words per FDCAN at a fixed layout,
 * FDCAN1's at 0x4000A400. Byte offsets of each section (fixed in hardware): */
#define SRAMCAN_BASE 0x4000A400u       /* @const */
#define SRAMCAN_FLSSA 0x000u           /* @const 28 standard filters, 1 word each */
#define SRAMCAN_FLESA 0x070u           /* @const 8 extended filters, 2 words each */
#define SRAMCAN_RF0SA 0x0B0u           /* @const Rx FIFO 0: 3 elements, 18 words each */
#define SRAMCAN_RF1SA 0x188u           /* @const Rx FIFO 1: 3 elements */
#define SRAMCAN_TEFSA 0x260u           /* @const Tx event FIFO: 3 elements, 2 words */
#define SRAMCAN_TBSA 0x278u            /* @const Tx buffers: 3 elements, 18 words */
#define SRAMCAN_SIZE 0x350u            /* @const 212 words */
#define SRAMCAN_ELEM_SIZE 72u          /* @const 18 words per Rx/Tx element */
#define SRAMCAN_WORD(ofs) REG32(SRAMCAN_BASE + (ofs)) /* @const */

#endif /* HAL_STM32G474_REGS_H */
