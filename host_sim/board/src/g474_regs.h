/* The STM32G474's register offsets and bit fields as the twin's models decode them: every
 * offset is from its peripheral's base (the SVD's addressOffset), every field a mask of all its
 * bits (or a value placed in it). Written from RM0440 like the firmware's header
 * (hal/stm32g4/stm32g474_regs.h) but independently of it: the twin judges the firmware, so it
 * does not take the firmware's numbers. Each define carries a tag that tools/svd/check_regs.py
 * checks against host_sim/board/svd/stm32g474_models_subset.json, the subset of ST's SVD this
 * header uses (ctest board.svd_model_regs):
 *   @svd P.R          the address of register R of peripheral P
 *   @svd P.R.F        the mask of field F (all of its bits)
 *   @svd P.R.F=v      value v placed in field F
 *   @svd-shift P.R.F  the bit offset of field F
 *   @svd-base P       the base address of peripheral P
 *   @svd-offset P.R   the offset of R inside P
 *   @core             Cortex-M4 system register (not in the vendor SVD)
 *   @const            a plain constant (a count, a stride), not a register or field
 * After adding a register or field: tools/svd/gen_svd_subset.py --svd STM32G474.svd
 *   --header host_sim/board/src/g474_regs.h --out host_sim/board/svd/stm32g474_models_subset.json */
#ifndef BOARD_G474_REGS_H
#define BOARD_G474_REGS_H /* @const include guard */
#include <stdint.h>

/* The value of field `mask` in register value `v` (mask: all of the field's bits). */
static inline uint32_t reg_field(uint32_t v, uint32_t mask) { return (v & mask) / (mask & (0u - mask)); }

/* Value `x` placed in field `mask`. */
static inline uint32_t reg_value(uint32_t mask, uint32_t x) { return (x * (mask & (0u - mask))) & mask; }

/* ------------------------------------------------ HRTIM1 (RM0440 §27.5): master, timers A-F, common */
#define HRTIM_MASTER_BASE 0x40016800u          /* @svd-base HRTIM_Master */
#define HRTIM_TIMA_BASE 0x40016880u            /* @svd-base HRTIM_TIMA */
#define HRTIM_TIMF_BASE 0x40016B00u            /* @svd-base HRTIM_TIMF */
#define HRTIM_COMMON_BASE 0x40016B80u          /* @svd-base HRTIM_Common */
#define HRTIM_SIZE 0x800u                      /* @const master, six timers, common: 2 KiB */
#define HRTIM_TIM_STRIDE 0x80u                 /* @const timers A-F: the same layout 0x80 apart */
#define HRTIM_NTIM 6                           /* @const */

#define HRTIM_MCR_OFS 0x00u                    /* @svd-offset HRTIM_Master.MCR */
#define HRTIM_MISR_OFS 0x04u                   /* @svd-offset HRTIM_Master.MISR */
#define HRTIM_MICR_OFS 0x08u                   /* @svd-offset HRTIM_Master.MICR */
#define HRTIM_MDIER_OFS 0x0Cu                  /* @svd-offset HRTIM_Master.MDIER */
#define HRTIM_MCNTR_OFS 0x10u                  /* @svd-offset HRTIM_Master.MCNTR */
#define HRTIM_MPER_OFS 0x14u                   /* @svd-offset HRTIM_Master.MPER */
#define HRTIM_MREP_OFS 0x18u                   /* @svd-offset HRTIM_Master.MREP */
#define HRTIM_MCMP1R_OFS 0x1Cu                 /* @svd-offset HRTIM_Master.MCMP1R */
#define HRTIM_MCMP2R_OFS 0x24u                 /* @svd-offset HRTIM_Master.MCMP2R */
#define HRTIM_MCMP3R_OFS 0x28u                 /* @svd-offset HRTIM_Master.MCMP3R */
#define HRTIM_MCMP4R_OFS 0x2Cu                 /* @svd-offset HRTIM_Master.MCMP4R */
#define HRTIM_MCR_CK_PSC (7u << 0)             /* @svd HRTIM_Master.MCR.CK_PSC */
#define HRTIM_MCR_CONT (1u << 3)               /* @svd HRTIM_Master.MCR.CONT */
#define HRTIM_MCR_MCEN (1u << 16)              /* @svd HRTIM_Master.MCR.MCEN */
#define HRTIM_MCR_TFCEN (1u << 22)             /* @svd HRTIM_Master.MCR.TFCEN */
#define HRTIM_MCR_PREEN (1u << 27)             /* @svd HRTIM_Master.MCR.PREEN */
#define HRTIM_MCR_MREPU (1u << 29)             /* @svd HRTIM_Master.MCR.MREPU */
#define HRTIM_MCR_CEN_ALL (0x7Fu << 16)        /* @const MCEN, TACEN..TFCEN: the seven counter enables */
#define HRTIM_MISR_MCMP1 (1u << 0)             /* @svd HRTIM_Master.MISR.MCMP1 (MCMPk: bit k - 1) */
#define HRTIM_MISR_MREP (1u << 4)              /* @svd HRTIM_Master.MISR.MREP */
#define HRTIM_MISR_MUPD (1u << 6)              /* @svd HRTIM_Master.MISR.MUPD */
#define HRTIM_MISR_ALL 0x7Fu                   /* @const MCMP1..MUPD, the flags MDIER enables */
#define HRTIM_MDIER_IE_ALL 0x7Fu               /* @const MCMP1IE..MUPDIE (bits 16-22: DMA requests) */
#define HRTIM_PER_MAX 0xFFDFu                  /* @const largest period in low resolution (RM0440 §27.5) */
#define HRTIM_PER_MIN 3u                       /* @const smallest period and compare value */
#define HRTIM_CKPSC_LOW_RES 5u                 /* @const CK_PSC from 5: low resolution, no DLL */

/* timer x registers, offsets from the timer's base (HRTIM_TIMA_BASE + t * HRTIM_TIM_STRIDE) */
#define HRTIM_TIMxCR_OFS 0x00u                 /* @svd-offset HRTIM_TIMA.TIMACR */
#define HRTIM_TIMxISR_OFS 0x04u                /* @svd-offset HRTIM_TIMA.TIMAISR */
#define HRTIM_TIMxICR_OFS 0x08u                /* @svd-offset HRTIM_TIMA.TIMAICR */
#define HRTIM_TIMxDIER_OFS 0x0Cu               /* @svd-offset HRTIM_TIMA.TIMADIER */
#define HRTIM_CNTxR_OFS 0x10u                  /* @svd-offset HRTIM_TIMA.CNTAR */
#define HRTIM_PERxR_OFS 0x14u                  /* @svd-offset HRTIM_TIMA.PERAR */
#define HRTIM_REPxR_OFS 0x18u                  /* @svd-offset HRTIM_TIMA.REPAR */
#define HRTIM_CMP1xR_OFS 0x1Cu                 /* @svd-offset HRTIM_TIMA.CMP1AR */
#define HRTIM_CMP2xR_OFS 0x24u                 /* @svd-offset HRTIM_TIMA.CMP2AR */
#define HRTIM_CMP3xR_OFS 0x28u                 /* @svd-offset HRTIM_TIMA.CMP3AR */
#define HRTIM_CMP4xR_OFS 0x2Cu                 /* @svd-offset HRTIM_TIMA.CMP4AR */
#define HRTIM_DTxR_OFS 0x38u                   /* @svd-offset HRTIM_TIMA.DTAR */
#define HRTIM_SETx1R_OFS 0x3Cu                 /* @svd-offset HRTIM_TIMA.SETA1R */
#define HRTIM_RSTx1R_OFS 0x40u                 /* @svd-offset HRTIM_TIMA.RSTA1R */
#define HRTIM_SETx2R_OFS 0x44u                 /* @svd-offset HRTIM_TIMA.SETA2R */
#define HRTIM_RSTx2R_OFS 0x48u                 /* @svd-offset HRTIM_TIMA.RSTA2R */
#define HRTIM_OUTxR_OFS 0x64u                  /* @svd-offset HRTIM_TIMA.OUTAR */
#define HRTIM_FLTxR_OFS 0x68u                  /* @svd-offset HRTIM_TIMA.FLTAR */
#define HRTIM_TIMxCR_CK_PSCx (7u << 0)         /* @svd HRTIM_TIMA.TIMACR.CK_PSCx */
#define HRTIM_TIMxCR_CONT (1u << 3)            /* @svd HRTIM_TIMA.TIMACR.CONT */
#define HRTIM_TIMxCR_TxREPU (1u << 17)         /* @svd HRTIM_TIMA.TIMACR.TxREPU */
#define HRTIM_TIMxCR_PREEN (1u << 27)          /* @svd HRTIM_TIMA.TIMACR.PREEN */
#define HRTIM_TIMxISR_O1STAT (1u << 18)        /* @svd HRTIM_TIMA.TIMAISR.O1STAT */
#define HRTIM_TIMxISR_O2STAT (1u << 19)        /* @svd HRTIM_TIMA.TIMAISR.O2STAT */
#define HRTIM_CMP_VALUE (0xFFFFu << 0)         /* @svd HRTIM_TIMA.CMP1AR.CMP1x every compare: 16 bits */
#define HRTIM_REP_VALUE (0xFFu << 0)           /* @svd HRTIM_TIMA.REPAR.REPx */
#define HRTIM_PER_VALUE (0xFFFFu << 0)         /* @svd HRTIM_TIMA.PERAR.PERx */
#define HRTIM_DTxR_DTRx (0x1FFu << 0)          /* @svd HRTIM_TIMA.DTAR.DTRx rising dead time, tDTG */
#define HRTIM_DTxR_SDTRx (1u << 9)             /* @svd HRTIM_TIMA.DTAR.SDTRx */
#define HRTIM_DTxR_DTPRSC (7u << 10)           /* @svd HRTIM_TIMA.DTAR.DTPRSC */
#define HRTIM_DTxR_DTRSLKx (1u << 14)          /* @svd HRTIM_TIMA.DTAR.DTRSLKx */
#define HRTIM_DTxR_DTRLKx (1u << 15)           /* @svd HRTIM_TIMA.DTAR.DTRLKx */
#define HRTIM_DTxR_DTFx (0x1FFu << 16)         /* @svd HRTIM_TIMA.DTAR.DTFx falling dead time, tDTG */
#define HRTIM_DTxR_SDTFx (1u << 25)            /* @svd HRTIM_TIMA.DTAR.SDTFx */
#define HRTIM_DTxR_DTFSLKx (1u << 30)          /* @svd HRTIM_TIMA.DTAR.DTFSLKx */
#define HRTIM_DTxR_DTFLKx (1u << 31)           /* @svd HRTIM_TIMA.DTAR.DTFLKx */
#define HRTIM_DTxR_RISING_FIELDS 0x7FFFu       /* @const bits 0-14, locked by DTRLKx */
#define HRTIM_DTxR_FALLING_FIELDS 0x7FFF0000u  /* @const bits 16-30, locked by DTFLKx */
#define HRTIM_DTPRSC_MIN_LOW_RES 3u            /* @const tDTG = tHRTIM: coarser needs no DLL */
#define HRTIM_SET_SST (1u << 0)                /* @svd HRTIM_TIMA.SETA1R.SST software set of output 1 */
#define HRTIM_SET_PER (1u << 2)                /* @svd HRTIM_TIMA.SETA1R.PER */
#define HRTIM_SET_CMP1 (1u << 3)               /* @svd HRTIM_TIMA.SETA1R.CMP1 (CMPk: bit k + 2) */
#define HRTIM_SET_CMP4 (1u << 6)               /* @svd HRTIM_TIMA.SETA1R.CMP4 */
#define HRTIM_RST_PER (1u << 2)                /* @svd HRTIM_TIMA.RSTA1R.PER */
#define HRTIM_RST_CMP1 (1u << 3)               /* @svd HRTIM_TIMA.RSTA1R.CMP1 */
#define HRTIM_RST_CMP4 (1u << 6)               /* @svd HRTIM_TIMA.RSTA1R.CMP4 */
#define HRTIM_RST_EXTEVNT6 (1u << 26)          /* @svd HRTIM_TIMA.RSTA1R.EXTEVNT6 */
#define HRTIM_EVENTS_PER_CMP 0x7Cu             /* @const PER and CMP1-4 in SETxyR/RSTxyR: bits 2-6 */
#define HRTIM_OUTxR_POL1 (1u << 1)             /* @svd HRTIM_TIMA.OUTAR.POL1 */
#define HRTIM_OUTxR_IDLES1 (1u << 3)           /* @svd HRTIM_TIMA.OUTAR.IDLES1 */
#define HRTIM_OUTxR_FAULT1 (3u << 4)           /* @svd HRTIM_TIMA.OUTAR.FAULT1 */
#define HRTIM_OUTxR_DTEN (1u << 8)             /* @svd HRTIM_TIMA.OUTAR.DTEN */
#define HRTIM_OUTxR_POL2 (1u << 17)            /* @svd HRTIM_TIMA.OUTAR.POL2 */
#define HRTIM_OUTxR_IDLES2 (1u << 19)          /* @svd HRTIM_TIMA.OUTAR.IDLES2 */
#define HRTIM_OUTxR_FAULT2 (3u << 20)          /* @svd HRTIM_TIMA.OUTAR.FAULT2 */
#define HRTIM_OUTxR_OUT2_SHIFT 16u             /* @const output 2's POL/IDLES/FAULT: output 1's + 16 */
#define HRTIM_OUTxR_FAULT1_NONE (0u << 4)      /* @svd HRTIM_TIMA.OUTAR.FAULT1=0 no action */
#define HRTIM_OUTxR_FAULT1_ACTIVE (1u << 4)    /* @svd HRTIM_TIMA.OUTAR.FAULT1=1 */
#define HRTIM_OUTxR_FAULT1_HIGH_Z (3u << 4)    /* @svd HRTIM_TIMA.OUTAR.FAULT1=3 */
#define HRTIM_FLTxR_FLT1EN (1u << 0)           /* @svd HRTIM_TIMA.FLTAR.FLT1EN (FLTkEN: bit k - 1) */
#define HRTIM_FLTxR_FLT3EN (1u << 2)           /* @svd HRTIM_TIMA.FLTAR.FLT3EN */
#define HRTIM_FLTxR_FLT6EN (1u << 5)           /* @svd HRTIM_TIMA.FLTAR.FLT6EN */
#define HRTIM_FLTxR_FLTEN_ALL 0x3Fu            /* @const FLT1EN..FLT6EN */
#define HRTIM_FLTxR_FLTLCK (1u << 31)          /* @svd HRTIM_TIMA.FLTAR.FLTLCK */

/* common registers, offsets from HRTIM_COMMON_BASE */
#define HRTIM_CR1_OFS 0x00u                    /* @svd-offset HRTIM_Common.CR1 */
#define HRTIM_CR2_OFS 0x04u                    /* @svd-offset HRTIM_Common.CR2 */
#define HRTIM_ISR_OFS 0x08u                    /* @svd-offset HRTIM_Common.ISR */
#define HRTIM_ICR_OFS 0x0Cu                    /* @svd-offset HRTIM_Common.ICR */
#define HRTIM_IER_OFS 0x10u                    /* @svd-offset HRTIM_Common.IER */
#define HRTIM_OENR_OFS 0x14u                   /* @svd-offset HRTIM_Common.OENR */
#define HRTIM_ODISR_OFS 0x18u                  /* @svd-offset HRTIM_Common.ODISR */
#define HRTIM_ODSR_OFS 0x1Cu                   /* @svd-offset HRTIM_Common.ODSR */
#define HRTIM_EECR1_OFS 0x30u                  /* @svd-offset HRTIM_Common.EECR1 */
#define HRTIM_EECR2_OFS 0x34u                  /* @svd-offset HRTIM_Common.EECR2 */
#define HRTIM_EECR3_OFS 0x38u                  /* @svd-offset HRTIM_Common.EECR3 */
#define HRTIM_ADC1R_OFS 0x3Cu                  /* @svd-offset HRTIM_Common.ADC1R */
#define HRTIM_ADC4R_OFS 0x48u                  /* @svd-offset HRTIM_Common.ADC4R */
#define HRTIM_FLTINR1_OFS 0x50u                /* @svd-offset HRTIM_Common.FLTINR1 */
#define HRTIM_FLTINR2_OFS 0x54u                /* @svd-offset HRTIM_Common.FLTINR2 */
#define HRTIM_CR1_MUDIS (1u << 0)              /* @svd HRTIM_Common.CR1.MUDIS (TxUDIS: bit 1 + t) */
#define HRTIM_CR1_TAUDIS (1u << 1)             /* @svd HRTIM_Common.CR1.TAUDIS */
#define HRTIM_CR1_UDIS_ALL 0x7Fu               /* @const MUDIS, TAUDIS..TFUDIS */
#define HRTIM_CR2_MSWU (1u << 0)               /* @svd HRTIM_Common.CR2.MSWU (TxSWU: bit 1 + t) */
#define HRTIM_CR2_TASWU (1u << 1)              /* @svd HRTIM_Common.CR2.TASWU */
#define HRTIM_CR2_SWU_ALL 0x7Fu                /* @const MSWU, TASWU..TFSWU */
#define HRTIM_ISR_FLT3 (1u << 2)               /* @svd HRTIM_Common.ISR.FLT3 */
#define HRTIM_ISR_FAULTS 0x3Fu                 /* @const FLT1-5 and SYSFLT, the flags IER enables (bits 0-5) */
#define HRTIM_IER_FLT3IE (1u << 2)             /* @svd HRTIM_Common.IER.FLT3IE */
#define HRTIM_OUT_ALL 0xFFFu                   /* @const TA1..TF2 in OENR/ODISR/ODSR: output o at bit o */
#define HRTIM_EECR2_EE6SRC (3u << 0)           /* @svd HRTIM_Common.EECR2.EE6SRC (EEk: 6 bits per event, EE6 first) */
#define HRTIM_EECR2_EE6POL (1u << 2)           /* @svd HRTIM_Common.EECR2.EE6POL 1: active low */
#define HRTIM_EECR2_EE6SNS (3u << 3)           /* @svd HRTIM_Common.EECR2.EE6SNS 0: level */
#define HRTIM_EECR2_EE7SRC (3u << 6)           /* @svd HRTIM_Common.EECR2.EE7SRC */
#define HRTIM_EECR2_EVENT_BITS 6u              /* @const the stride of events 6-10 in EECR2 */
#define HRTIM_EECR2_EVENT_RESERVED (1u << 5)   /* @const bit 5 of each event's six: reserved */
#define HRTIM_EECR2_RESERVED (3u << 30)        /* @const */
#define HRTIM_EECR3_EE6F (0xFu << 0)           /* @svd HRTIM_Common.EECR3.EE6F */
#define HRTIM_EECR3_EEVSD (3u << 30)           /* @svd HRTIM_Common.EECR3.EEVSD */
#define HRTIM_ADCxR_MC1 (1u << 0)              /* @svd HRTIM_Common.ADC1R.AD1MC1 (master compare k: bit k - 1) */
#define HRTIM_ADCxR_MPER (1u << 4)             /* @svd HRTIM_Common.ADC1R.AD1MPER */
#define HRTIM_ADCxR_MASTER 0x1Fu               /* @const master CMP1-4 and period, bits 0-4 */
#define HRTIM_FLTINR1_FLT1E (1u << 0)          /* @svd HRTIM_Common.FLTINR1.FLT1E (input k's byte: input 1's << 8 (k - 1)) */
#define HRTIM_FLTINR1_FLT1P (1u << 1)          /* @svd HRTIM_Common.FLTINR1.FLT1P 0: active low */
#define HRTIM_FLTINR1_FLT1SRC (1u << 2)        /* @svd HRTIM_Common.FLTINR1.FLT1SRC */
#define HRTIM_FLTINR1_FLT1F (0xFu << 3)        /* @svd HRTIM_Common.FLTINR1.FLT1F */
#define HRTIM_FLTINR1_FLT1LCK (1u << 7)        /* @svd HRTIM_Common.FLTINR1.FLT1LCK */
#define HRTIM_FLTINR1_FLT3E (1u << 16)         /* @svd HRTIM_Common.FLTINR1.FLT3E */
#define HRTIM_FLTINR1_FLT3P (1u << 17)         /* @svd HRTIM_Common.FLTINR1.FLT3P */
#define HRTIM_FLTINR1_INPUT_BITS 8u            /* @const the stride of inputs 1-4 in FLTINR1 */
#define HRTIM_FLTINR2_FLT5E (1u << 0)          /* @svd HRTIM_Common.FLTINR2.FLT5E */
#define HRTIM_FLTINR2_FLT6E (1u << 8)          /* @svd HRTIM_Common.FLTINR2.FLT6E */
#define HRTIM_FLTINR2_FLTSD (3u << 24)         /* @svd HRTIM_Common.FLTINR2.FLTSD */
#define HRTIM_FLTINR2_MODELLED 0x0101FFFFu     /* @const FLT5/FLT6 byte fields and their SRC_1 bits */

/* ------------------------------------------------ the other peripherals the twin models: bases */
#define TIM6_BASE 0x40001000u                  /* @svd-base TIM6 */
#define IWDG_BASE 0x40003000u                  /* @svd-base IWDG */
#define FDCAN1_BASE 0x40006400u                /* @svd-base FDCAN1 */
#define PWR_BASE 0x40007000u                   /* @svd-base PWR */
#define SRAMCAN_BASE 0x4000A400u               /* @svd-base FDCAN the message RAM of FDCAN1-3 */
#define RCC_BASE 0x40021000u                   /* @svd-base RCC */
#define FLASH_R_BASE 0x40022000u               /* @svd-base FLASH the flash interface's registers */
#define GPIOA_BASE 0x48000000u                 /* @svd-base GPIOA */
#define GPIOG_BASE 0x48001800u                 /* @svd-base GPIOG */
#define GPIO_PORT_STRIDE 0x400u                /* @const ports A-G, one 1 KiB block each */
#define ADC1_BASE 0x50000000u                  /* @svd-base ADC1 ADC1, ADC2, their common registers */
#define ADC3_BASE 0x50000400u                  /* @svd-base ADC3 ADC3, ADC4, ADC5, their common registers */
#define APB_AHB_BLOCK 0x400u                   /* @const one peripheral's address block */

/* ------------------------------------------------ FLASH interface (RM0440 §5.7) */
#define FLASH_ACR_OFS 0x00u                    /* @svd-offset FLASH.FLASH_ACR */
#define FLASH_PDKEYR_OFS 0x04u                 /* @svd-offset FLASH.FLASH_PDKEYR */
#define FLASH_KEYR_OFS 0x08u                   /* @svd-offset FLASH.FLASH_KEYR */
#define FLASH_OPTKEYR_OFS 0x0Cu                /* @svd-offset FLASH.FLASH_OPTKEYR */
#define FLASH_SR_OFS 0x10u                     /* @svd-offset FLASH.FLASH_SR */
#define FLASH_CR_OFS 0x14u                     /* @svd-offset FLASH.FLASH_CR */
#define FLASH_ECCR_OFS 0x18u                   /* @svd-offset FLASH.FLASH_ECCR */
#define FLASH_OPTR_OFS 0x20u                   /* @svd-offset FLASH.FLASH_OPTR */
#define FLASH_PCROP1SR_OFS 0x24u               /* @svd-offset FLASH.FLASH_PCROP1SR */
#define FLASH_PCROP1ER_OFS 0x28u               /* @svd-offset FLASH.FLASH_PCROP1ER */
#define FLASH_WRP1AR_OFS 0x2Cu                 /* @svd-offset FLASH.FLASH_WRP1AR */
#define FLASH_WRP1BR_OFS 0x30u                 /* @svd-offset FLASH.FLASH_WRP1BR */
#define FLASH_PCROP2SR_OFS 0x44u               /* @svd-offset FLASH.FLASH_PCROP2SR */
#define FLASH_PCROP2ER_OFS 0x48u               /* @svd-offset FLASH.FLASH_PCROP2ER */
#define FLASH_WRP2AR_OFS 0x4Cu                 /* @svd-offset FLASH.FLASH_WRP2AR */
#define FLASH_WRP2BR_OFS 0x50u                 /* @svd-offset FLASH.FLASH_WRP2BR */
#define FLASH_SEC1R_OFS 0x70u                  /* @svd-offset FLASH.FLASH_SEC1R */
#define FLASH_SEC2R_OFS 0x74u                  /* @svd-offset FLASH.FLASH_SEC2R */
#define FLASH_ACR_LATENCY (0xFu << 0)          /* @svd FLASH.FLASH_ACR.LATENCY */
#define FLASH_ACR_ICRST (1u << 11)             /* @svd FLASH.FLASH_ACR.ICRST */
#define FLASH_ACR_DCRST (1u << 12)             /* @svd FLASH.FLASH_ACR.DCRST */
#define FLASH_ACR_WRITABLE 0x00047F0Fu         /* @const LATENCY, PRFTEN..SLEEP_PD, DBG_SWEN */
#define FLASH_KEY1 0x45670123u                 /* @const RM0440 §5.3.5 unlock sequence */
#define FLASH_KEY2 0xCDEF89ABu                 /* @const */
#define FLASH_SR_EOP (1u << 0)                 /* @svd FLASH.FLASH_SR.EOP */
#define FLASH_SR_OPERR (1u << 1)               /* @svd FLASH.FLASH_SR.OPERR */
#define FLASH_SR_PROGERR (1u << 3)             /* @svd FLASH.FLASH_SR.PROGERR */
#define FLASH_SR_WRPERR (1u << 4)              /* @svd FLASH.FLASH_SR.WRPERR */
#define FLASH_SR_PGAERR (1u << 5)              /* @svd FLASH.FLASH_SR.PGAERR */
#define FLASH_SR_SIZERR (1u << 6)              /* @svd FLASH.FLASH_SR.SIZERR */
#define FLASH_SR_PGSERR (1u << 7)              /* @svd FLASH.FLASH_SR.PGSERR */
#define FLASH_SR_MISSERR (1u << 8)             /* @svd FLASH.FLASH_SR.MISSERR */
#define FLASH_SR_FASTERR (1u << 9)             /* @svd FLASH.FLASH_SR.FASTERR */
#define FLASH_SR_RDERR (1u << 14)              /* @svd FLASH.FLASH_SR.RDERR */
#define FLASH_SR_OPTVERR (1u << 15)            /* @svd FLASH.FLASH_SR.OPTVERR */
#define FLASH_SR_BSY (1u << 16)                /* @svd FLASH.FLASH_SR.BSY */
#define FLASH_CR_PG (1u << 0)                  /* @svd FLASH.FLASH_CR.PG */
#define FLASH_CR_PER (1u << 1)                 /* @svd FLASH.FLASH_CR.PER */
#define FLASH_CR_MER1 (1u << 2)                /* @svd FLASH.FLASH_CR.MER1 */
#define FLASH_CR_PNB (0x7Fu << 3)              /* @svd FLASH.FLASH_CR.PNB */
#define FLASH_CR_BKER (1u << 11)               /* @svd FLASH.FLASH_CR.BKER */
#define FLASH_CR_MER2 (1u << 15)               /* @svd FLASH.FLASH_CR.MER2 */
#define FLASH_CR_STRT (1u << 16)               /* @svd FLASH.FLASH_CR.START */
#define FLASH_CR_OPTSTRT (1u << 17)            /* @svd FLASH.FLASH_CR.OPTSTRT */
#define FLASH_CR_FSTPG (1u << 18)              /* @svd FLASH.FLASH_CR.FSTPG */
#define FLASH_CR_EOPIE (1u << 24)              /* @svd FLASH.FLASH_CR.EOPIE */
#define FLASH_CR_OPTLOCK (1u << 30)            /* @svd FLASH.FLASH_CR.OPTLOCK */
#define FLASH_CR_LOCK (1u << 31)               /* @svd FLASH.FLASH_CR.LOCK */
#define FLASH_CR_SOFTWARE 0x3F07BFFFu          /* @const the bits software writes; LOCK, OPTLOCK aside */
#define FLASH_ECCR_ADDR_ECC (0x7FFFFu << 0)    /* @svd FLASH.FLASH_ECCR.ADDR_ECC */
#define FLASH_ECCR_BK_ECC (1u << 21)           /* @svd FLASH.FLASH_ECCR.BK_ECC */
#define FLASH_ECCR_ECCCIE (1u << 24)           /* @svd FLASH.FLASH_ECCR.ECCCIE */
#define FLASH_ECCR_ECCC (1u << 30)             /* @svd FLASH.FLASH_ECCR.ECCC */
#define FLASH_ECCR_ECCD (1u << 31)             /* @svd FLASH.FLASH_ECCR.ECCD */

/* ------------------------------------------------ RCC (RM0440 §7.4) */
#define RCC_CR_OFS 0x00u                       /* @svd-offset RCC.RCC_CR */
#define RCC_ICSCR_OFS 0x04u                    /* @svd-offset RCC.RCC_ICSCR */
#define RCC_CFGR_OFS 0x08u                     /* @svd-offset RCC.RCC_CFGR */
#define RCC_PLLCFGR_OFS 0x0Cu                  /* @svd-offset RCC.RCC_PLLCFGR */
#define RCC_CIER_OFS 0x18u                     /* @svd-offset RCC.RCC_CIER */
#define RCC_CIFR_OFS 0x1Cu                     /* @svd-offset RCC.RCC_CIFR */
#define RCC_CICR_OFS 0x20u                     /* @svd-offset RCC.RCC_CICR */
#define RCC_AHB1RSTR_OFS 0x28u                 /* @svd-offset RCC.RCC_AHB1RSTR first of the seven reset registers */
#define RCC_APB2RSTR_OFS 0x40u                 /* @svd-offset RCC.RCC_APB2RSTR last */
#define RCC_AHB1ENR_OFS 0x48u                  /* @svd-offset RCC.RCC_AHB1ENR first of the seven enable registers */
#define RCC_AHB2ENR_OFS 0x4Cu                  /* @svd-offset RCC.RCC_AHB2ENR */
#define RCC_AHB3ENR_OFS 0x50u                  /* @svd-offset RCC.RCC_AHB3ENR */
#define RCC_APB1ENR1_OFS 0x58u                 /* @svd-offset RCC.RCC_APB1ENR1 */
#define RCC_APB2ENR_OFS 0x60u                  /* @svd-offset RCC.RCC_APB2ENR last */
#define RCC_AHB1SMENR_OFS 0x68u                /* @svd-offset RCC.RCC_AHB1SMENR first of the seven sleep enables */
#define RCC_AHB3SMENR_OFS 0x70u                /* @svd-offset RCC.RCC_AHB3SMENR */
#define RCC_APB2SMENR_OFS 0x80u                /* @svd-offset RCC.RCC_APB2SMENR last */
#define RCC_CCIPR_OFS 0x88u                    /* @svd-offset RCC.RCC_CCIPR */
#define RCC_BDCR_OFS 0x90u                     /* @svd-offset RCC.RCC_BDCR */
#define RCC_CSR_OFS 0x94u                      /* @svd-offset RCC.RCC_CSR */
#define RCC_CRRCR_OFS 0x98u                    /* @svd-offset RCC.RCC_CRRCR */
#define RCC_CCIPR2_OFS 0x9Cu                   /* @svd-offset RCC.RCC_CCIPR2 */
#define RCC_BUS_REG_STRIDE 4u                  /* @const AHB1, AHB2, AHB3, (reserved), APB1 1, APB1 2, APB2 */
#define RCC_ICSCR_HSICAL (0xFFu << 16)         /* @svd RCC.RCC_ICSCR.HSICAL */
#define RCC_ICSCR_HSITRIM (0x7Fu << 24)        /* @svd RCC.RCC_ICSCR.HSITRIM */
#define RCC_CR_HSION (1u << 8)                 /* @svd RCC.RCC_CR.HSION */
#define RCC_CR_HSIRDY (1u << 10)               /* @svd RCC.RCC_CR.HSIRDY */
#define RCC_CR_HSEON (1u << 16)                /* @svd RCC.RCC_CR.HSEON */
#define RCC_CR_HSERDY (1u << 17)               /* @svd RCC.RCC_CR.HSERDY */
#define RCC_CR_HSEBYP (1u << 18)               /* @svd RCC.RCC_CR.HSEBYP */
#define RCC_CR_PLLON (1u << 24)                /* @svd RCC.RCC_CR.PLLON */
#define RCC_CR_PLLRDY (1u << 25)               /* @svd RCC.RCC_CR.PLLRDY */
#define RCC_CR_WRITABLE 0x030F0700u            /* @const HSION..PLLRDY without the reserved bits */
#define RCC_CFGR_SW (3u << 0)                  /* @svd RCC.RCC_CFGR.SW */
#define RCC_CFGR_SWS (3u << 2)                 /* @svd RCC.RCC_CFGR.SWS */
#define RCC_CFGR_HPRE (0xFu << 4)              /* @svd RCC.RCC_CFGR.HPRE */
#define RCC_CFGR_PPRE1 (7u << 8)               /* @svd RCC.RCC_CFGR.PPRE1 */
#define RCC_CFGR_RESERVED 0x80FFC000u          /* @const bits 14-23 and 31 */
#define RCC_SW_HSI16 1u                        /* @svd RCC.RCC_CFGR.SW=1 */
#define RCC_SW_HSE 2u                          /* @svd RCC.RCC_CFGR.SW=2 */
#define RCC_SW_PLL 3u                          /* @svd RCC.RCC_CFGR.SW=3 */
#define RCC_PLLCFGR_PLLSRC (3u << 0)           /* @svd RCC.RCC_PLLCFGR.PLLSRC */
#define RCC_PLLSRC_HSI16 2u                    /* @svd RCC.RCC_PLLCFGR.PLLSRC=2 */
#define RCC_PLLSRC_HSE 3u                      /* @svd RCC.RCC_PLLCFGR.PLLSRC=3 */
#define RCC_PLLCFGR_PLLM (0xFu << 4)           /* @svd RCC.RCC_PLLCFGR.PLLM field = M - 1 */
#define RCC_PLLCFGR_PLLN (0x7Fu << 8)          /* @svd RCC.RCC_PLLCFGR.PLLN */
#define RCC_PLLCFGR_PLLQEN (1u << 20)          /* @svd RCC.RCC_PLLCFGR.PLLQEN */
#define RCC_PLLCFGR_PLLQ (3u << 21)            /* @svd RCC.RCC_PLLCFGR.PLLQ 0: /2 .. 3: /8 */
#define RCC_PLLCFGR_PLLREN (1u << 24)          /* @svd RCC.RCC_PLLCFGR.PLLREN */
#define RCC_PLLCFGR_PLLR (3u << 25)            /* @svd RCC.RCC_PLLCFGR.PLLR 0: /2 .. 3: /8 */
#define RCC_PLLCFGR_RESERVED 0x0088800Cu       /* @const bits 2-3, 15, 19, 23 */
#define RCC_AHB1ENR_FLASHEN (1u << 8)          /* @svd RCC.RCC_AHB1ENR.FLASHEN */
#define RCC_AHB2ENR_GPIOAEN (1u << 0)          /* @svd RCC.RCC_AHB2ENR.GPIOAEN (GPIOxEN: bit x) */
#define RCC_AHB2ENR_ADC12EN (1u << 13)         /* @svd RCC.RCC_AHB2ENR.ADC12EN */
#define RCC_AHB2ENR_ADC345EN (1u << 14)        /* @svd RCC.RCC_AHB2ENR.ADC345EN */
#define RCC_APB1ENR1_TIM6EN (1u << 4)          /* @svd RCC.RCC_APB1ENR1.TIM6EN */
#define RCC_APB1ENR1_RTCAPBEN (1u << 10)       /* @svd RCC.RCC_APB1ENR1.RTCAPBEN */
#define RCC_APB1ENR1_FDCANEN (1u << 25)        /* @svd RCC.RCC_APB1ENR1.FDCANEN */
#define RCC_APB1ENR1_PWREN (1u << 28)          /* @svd RCC.RCC_APB1ENR1.PWREN */
#define RCC_APB2ENR_HRTIM1EN (1u << 26)        /* @svd RCC.RCC_APB2ENR.HRTIM1EN */
#define RCC_CCIPR_FDCANSEL (3u << 24)          /* @svd RCC.RCC_CCIPR.FDCANSEL */
#define RCC_CSR_LSION (1u << 0)                /* @svd RCC.RCC_CSR.LSION */
#define RCC_CSR_LSIRDY (1u << 1)               /* @svd RCC.RCC_CSR.LSIRDY */
#define RCC_CSR_RMVF (1u << 23)                /* @svd RCC.RCC_CSR.RMVF */
#define RCC_CSR_PINRSTF (1u << 26)             /* @svd RCC.RCC_CSR.PINRSTF */
#define RCC_CSR_BORRSTF (1u << 27)             /* @svd RCC.RCC_CSR.BORRSTF */
#define RCC_CSR_RESET_FLAGS 0xFE000000u        /* @const OBLRSTF..LPWRRSTF, bits 25-31 */
#define RCC_CRRCR_HSI48ON (1u << 0)            /* @svd RCC.RCC_CRRCR.HSI48ON */

/* ------------------------------------------------ ADC1-5 (RM0440 §21.7): each group (ADC1/2, ADC3/4/5) in one
 * 1 KiB block, its ADCs 0x100 apart, its common registers in the fourth 0x100 */
#define ADC_UNIT_STRIDE 0x100u                 /* @const */
#define ADC_COMMON_OFS 0x300u                  /* @const ADC12_Common - ADC1, ADC345_Common - ADC3 */
#define ADC12_COMMON_BASE 0x50000300u          /* @svd-base ADC12_Common */
#define ADC345_COMMON_BASE 0x50000700u         /* @svd-base ADC345_Common */
#define ADC_ISR_OFS 0x00u                      /* @svd-offset ADC1.ISR */
#define ADC_IER_OFS 0x04u                      /* @svd-offset ADC1.IER */
#define ADC_CR_OFS 0x08u                       /* @svd-offset ADC1.CR */
#define ADC_CFGR_OFS 0x0Cu                     /* @svd-offset ADC1.CFGR */
#define ADC_CFGR2_OFS 0x10u                    /* @svd-offset ADC1.CFGR2 */
#define ADC_SMPR1_OFS 0x14u                    /* @svd-offset ADC1.SMPR1 */
#define ADC_SMPR2_OFS 0x18u                    /* @svd-offset ADC1.SMPR2 */
#define ADC_JSQR_OFS 0x4Cu                     /* @svd-offset ADC1.JSQR */
#define ADC_OFR1_OFS 0x60u                     /* @svd-offset ADC1.OFR1 */
#define ADC_OFR4_OFS 0x6Cu                     /* @svd-offset ADC1.OFR4 */
#define ADC_JDR1_OFS 0x80u                     /* @svd-offset ADC1.JDR1 */
#define ADC_JDR4_OFS 0x8Cu                     /* @svd-offset ADC1.JDR4 */
#define ADC_DIFSEL_OFS 0xB0u                   /* @svd-offset ADC1.DIFSEL */
#define ADC_CALFACT_OFS 0xB4u                  /* @svd-offset ADC1.CALFACT */
#define ADC_CSR_OFS 0x00u                      /* @svd-offset ADC12_Common.CSR */
#define ADC_CCR_OFS 0x08u                      /* @svd-offset ADC12_Common.CCR */
#define ADC_ISR_ADRDY (1u << 0)                /* @svd ADC1.ISR.ADRDY */
#define ADC_ISR_JEOC (1u << 5)                 /* @svd ADC1.ISR.JEOC */
#define ADC_ISR_JEOS (1u << 6)                 /* @svd ADC1.ISR.JEOS */
#define ADC_ISR_ALL 0x7FFu                     /* @const ADRDY..JQOVF, bits 0-10 */
#define ADC_IER_ADRDYIE (1u << 0)              /* @svd ADC1.IER.ADRDYIE */
#define ADC_IER_JEOCIE (1u << 5)               /* @svd ADC1.IER.JEOCIE */
#define ADC_IER_JEOSIE (1u << 6)               /* @svd ADC1.IER.JEOSIE */
#define ADC_CR_ADEN (1u << 0)                  /* @svd ADC1.CR.ADEN */
#define ADC_CR_ADDIS (1u << 1)                 /* @svd ADC1.CR.ADDIS */
#define ADC_CR_ADSTART (1u << 2)               /* @svd ADC1.CR.ADSTART */
#define ADC_CR_JADSTART (1u << 3)              /* @svd ADC1.CR.JADSTART */
#define ADC_CR_JADSTP (1u << 5)                /* @svd ADC1.CR.JADSTP */
#define ADC_CR_ADVREGEN (1u << 28)             /* @svd ADC1.CR.ADVREGEN */
#define ADC_CR_DEEPPWD (1u << 29)              /* @svd ADC1.CR.DEEPPWD */
#define ADC_CR_ADCALDIF (1u << 30)             /* @svd ADC1.CR.ADCALDIF */
#define ADC_CR_ADCAL (1u << 31)                /* @svd ADC1.CR.ADCAL */
#define ADC_CR_START_STOP 0x3Fu                /* @const ADEN..JADSTP, bits 0-5 */
#define ADC_CFGR_JQDIS (1u << 31)              /* @svd ADC1.CFGR.JQDIS */
#define ADC_SMPR1_SMP0 (7u << 0)               /* @svd ADC1.SMPR1.SMP0 (channel ch: 3 bits at 3 (ch % 10), SMPR1 for 0-9) */
#define ADC_SMPR1_SMPPLUS (1u << 31)           /* @svd ADC1.SMPR1.SMPPLUS */
#define ADC_SMPR_BITS 3u                       /* @const */
#define ADC_SMPR_CHANNELS 10u                  /* @const channels per SMPR register */
#define ADC_JSQR_JL (3u << 0)                  /* @svd ADC1.JSQR.JL field = length - 1 */
#define ADC_JSQR_JEXTSEL (0x1Fu << 2)          /* @svd ADC1.JSQR.JEXTSEL */
#define ADC_JSQR_JEXTEN (3u << 7)              /* @svd ADC1.JSQR.JEXTEN */
#define ADC_JSQR_JEXTEN_RISING (1u << 7)       /* @svd ADC1.JSQR.JEXTEN=1 rising edge; 0: software trigger */
#define ADC_JSQR_JSQ1 (0x1Fu << 9)             /* @svd ADC1.JSQR.JSQ1 (rank r: 5 bits at 9 + 6 r) */
#define ADC_JSQR_JSQ2 (0x1Fu << 15)            /* @svd ADC1.JSQR.JSQ2 */
#define ADC_JSQ_STRIDE 6u                      /* @const */
#define ADC_OFR_OFFSET (0xFFFu << 0)           /* @svd ADC1.OFR1.OFFSET1 */
#define ADC_OFR_OFFSETPOS (1u << 24)           /* @svd ADC1.OFR1.OFFSETPOS */
#define ADC_OFR_SATEN (1u << 25)               /* @svd ADC1.OFR1.SATEN */
#define ADC_OFR_CH (0x1Fu << 26)               /* @svd ADC1.OFR1.OFFSET1_CH */
#define ADC_OFR_EN (1u << 31)                  /* @svd ADC1.OFR1.OFFSET1_EN */
#define ADC_JDR_JDATA (0xFFFFu << 0)           /* @svd ADC1.JDR1.JDATA1 */
#define ADC_CCR_DUAL (0x1Fu << 0)              /* @svd ADC12_Common.CCR.DUAL */
#define ADC_DUAL_INDEPENDENT 0u                /* @svd ADC12_Common.CCR.DUAL=0 */
#define ADC_DUAL_INJ_SIMULT 5u                 /* @svd ADC12_Common.CCR.DUAL=5 injected simultaneous only */
#define ADC_CCR_DELAY (0xFu << 8)              /* @svd ADC12_Common.CCR.DELAY */
#define ADC_CCR_CKMODE (3u << 16)              /* @svd ADC12_Common.CCR.CKMODE */
#define ADC_CCR_CKMODE_ASYNC (0u << 16)        /* @svd ADC12_Common.CCR.CKMODE=0 */
#define ADC_CCR_CKMODE_HCLK (1u << 16)         /* @svd ADC12_Common.CCR.CKMODE=1 */
#define ADC_CCR_CKMODE_HCLK_DIV2 (2u << 16)    /* @svd ADC12_Common.CCR.CKMODE=2 */
#define ADC_CCR_CKMODE_HCLK_DIV4 (3u << 16)    /* @svd ADC12_Common.CCR.CKMODE=3 */
#define ADC_CSR_SLV_SHIFT 16u                  /* @svd-shift ADC12_Common.CSR.ADRDY_SLV the slave's flags: the master's + 16 */

/* ------------------------------------------------ GPIO ports A-G (RM0440 §9.4): one layout */
#define GPIO_MODER_OFS 0x00u                   /* @svd-offset GPIOA.MODER */
#define GPIO_OTYPER_OFS 0x04u                  /* @svd-offset GPIOA.OTYPER */
#define GPIO_OSPEEDR_OFS 0x08u                 /* @svd-offset GPIOA.OSPEEDR */
#define GPIO_PUPDR_OFS 0x0Cu                   /* @svd-offset GPIOA.PUPDR */
#define GPIO_IDR_OFS 0x10u                     /* @svd-offset GPIOA.IDR */
#define GPIO_ODR_OFS 0x14u                     /* @svd-offset GPIOA.ODR */
#define GPIO_BSRR_OFS 0x18u                    /* @svd-offset GPIOA.BSRR */
#define GPIO_LCKR_OFS 0x1Cu                    /* @svd-offset GPIOA.LCKR */
#define GPIO_AFRL_OFS 0x20u                    /* @svd-offset GPIOA.AFRL */
#define GPIO_AFRH_OFS 0x24u                    /* @svd-offset GPIOA.AFRH */
#define GPIO_BRR_OFS 0x28u                     /* @svd-offset GPIOA.BRR */
#define GPIO_MODER_MODE0 (3u << 0)             /* @svd GPIOA.MODER.MODER0 pin p: 2 bits at 2 p */
#define GPIO_MODE_INPUT 0u                     /* @svd GPIOA.MODER.MODER0=0 */
#define GPIO_MODE_OUTPUT 1u                    /* @svd GPIOA.MODER.MODER0=1 */
#define GPIO_MODE_AF 2u                        /* @svd GPIOA.MODER.MODER0=2 */
#define GPIO_MODE_ANALOG 3u                    /* @svd GPIOA.MODER.MODER0=3 */
#define GPIO_PUPDR_PUPD0 (3u << 0)             /* @svd GPIOA.PUPDR.PUPDR0 */
#define GPIO_PULL_UP 1u                        /* @svd GPIOA.PUPDR.PUPDR0=1 */
#define GPIO_PULL_RESERVED 3u                  /* @svd GPIOA.PUPDR.PUPDR0=3 */
#define GPIO_AFRL_AF0 (0xFu << 0)              /* @svd GPIOA.AFRL.AFRL0 pin p: 4 bits at 4 (p % 8) */
#define GPIO_LCKR_LCKK (1u << 16)              /* @svd GPIOA.LCKR.LCKK */
#define GPIO_PINS 0xFFFFu                      /* @const the 16 pins' bits of IDR, ODR, BRR, LCKR, BSRR's set half */

/* ------------------------------------------------ FDCAN1 (RM0440 §44.4) */
#define FDCAN_CREL_OFS 0x000u                  /* @svd-offset FDCAN1.FDCAN_CREL */
#define FDCAN_ENDN_OFS 0x004u                  /* @svd-offset FDCAN1.FDCAN_ENDN */
#define FDCAN_DBTP_OFS 0x00Cu                  /* @svd-offset FDCAN1.FDCAN_DBTP */
#define FDCAN_TEST_OFS 0x010u                  /* @svd-offset FDCAN1.FDCAN_TEST */
#define FDCAN_RWD_OFS 0x014u                   /* @svd-offset FDCAN1.FDCAN_RWD */
#define FDCAN_CCCR_OFS 0x018u                  /* @svd-offset FDCAN1.FDCAN_CCCR */
#define FDCAN_NBTP_OFS 0x01Cu                  /* @svd-offset FDCAN1.FDCAN_NBTP */
#define FDCAN_TSCC_OFS 0x020u                  /* @svd-offset FDCAN1.FDCAN_TSCC */
#define FDCAN_TSCV_OFS 0x024u                  /* @svd-offset FDCAN1.FDCAN_TSCV */
#define FDCAN_TOCC_OFS 0x028u                  /* @svd-offset FDCAN1.FDCAN_TOCC */
#define FDCAN_TOCV_OFS 0x02Cu                  /* @svd-offset FDCAN1.FDCAN_TOCV */
#define FDCAN_ECR_OFS 0x040u                   /* @svd-offset FDCAN1.FDCAN_ECR */
#define FDCAN_PSR_OFS 0x044u                   /* @svd-offset FDCAN1.FDCAN_PSR */
#define FDCAN_TDCR_OFS 0x048u                  /* @svd-offset FDCAN1.FDCAN_TDCR */
#define FDCAN_IR_OFS 0x050u                    /* @svd-offset FDCAN1.FDCAN_IR */
#define FDCAN_IE_OFS 0x054u                    /* @svd-offset FDCAN1.FDCAN_IE */
#define FDCAN_ILS_OFS 0x058u                   /* @svd-offset FDCAN1.FDCAN_ILS */
#define FDCAN_ILE_OFS 0x05Cu                   /* @svd-offset FDCAN1.FDCAN_ILE */
#define FDCAN_RXGFC_OFS 0x080u                 /* @svd-offset FDCAN1.FDCAN_RXGFC */
#define FDCAN_XIDAM_OFS 0x084u                 /* @svd-offset FDCAN1.FDCAN_XIDAM */
#define FDCAN_HPMS_OFS 0x088u                  /* @svd-offset FDCAN1.FDCAN_HPMS */
#define FDCAN_RXF0S_OFS 0x090u                 /* @svd-offset FDCAN1.FDCAN_RXF0S */
#define FDCAN_RXF0A_OFS 0x094u                 /* @svd-offset FDCAN1.FDCAN_RXF0A */
#define FDCAN_RXF1S_OFS 0x098u                 /* @svd-offset FDCAN1.FDCAN_RXF1S */
#define FDCAN_RXF1A_OFS 0x09Cu                 /* @svd-offset FDCAN1.FDCAN_RXF1A */
#define FDCAN_TXBC_OFS 0x0C0u                  /* @svd-offset FDCAN1.FDCAN_TXBC */
#define FDCAN_TXFQS_OFS 0x0C4u                 /* @svd-offset FDCAN1.FDCAN_TXFQS */
#define FDCAN_TXBRP_OFS 0x0C8u                 /* @svd-offset FDCAN1.FDCAN_TXBRP */
#define FDCAN_TXBAR_OFS 0x0CCu                 /* @svd-offset FDCAN1.FDCAN_TXBAR */
#define FDCAN_TXBCR_OFS 0x0D0u                 /* @svd-offset FDCAN1.FDCAN_TXBCR */
#define FDCAN_TXBTO_OFS 0x0D4u                 /* @svd-offset FDCAN1.FDCAN_TXBTO */
#define FDCAN_TXBCF_OFS 0x0D8u                 /* @svd-offset FDCAN1.FDCAN_TXBCF */
#define FDCAN_TXBTIE_OFS 0x0DCu                /* @svd-offset FDCAN1.FDCAN_TXBTIE */
#define FDCAN_TXBCIE_OFS 0x0E0u                /* @svd-offset FDCAN1.FDCAN_TXBCIE */
#define FDCAN_TXEFS_OFS 0x0E4u                 /* @svd-offset FDCAN1.FDCAN_TXEFS */
#define FDCAN_TXEFA_OFS 0x0E8u                 /* @svd-offset FDCAN1.FDCAN_TXEFA */
#define FDCAN_CKDIV_OFS 0x100u                 /* @svd-offset FDCAN1.FDCAN_CKDIV */
#define FDCAN_CCCR_INIT (1u << 0)              /* @svd FDCAN1.FDCAN_CCCR.INIT */
#define FDCAN_CCCR_CCE (1u << 1)               /* @svd FDCAN1.FDCAN_CCCR.CCE */
#define FDCAN_CCCR_ASM (1u << 2)               /* @svd FDCAN1.FDCAN_CCCR.ASM */
#define FDCAN_CCCR_CSA (1u << 3)               /* @svd FDCAN1.FDCAN_CCCR.CSA */
#define FDCAN_CCCR_CSR (1u << 4)               /* @svd FDCAN1.FDCAN_CCCR.CSR */
#define FDCAN_CCCR_MON (1u << 5)               /* @svd FDCAN1.FDCAN_CCCR.MON */
#define FDCAN_CCCR_DAR (1u << 6)               /* @svd FDCAN1.FDCAN_CCCR.DAR */
#define FDCAN_CCCR_TEST (1u << 7)              /* @svd FDCAN1.FDCAN_CCCR.TEST */
#define FDCAN_CCCR_FDOE (1u << 8)              /* @svd FDCAN1.FDCAN_CCCR.FDOE */
#define FDCAN_CCCR_BRSE (1u << 9)              /* @svd FDCAN1.FDCAN_CCCR.BRSE */
#define FDCAN_CCCR_PXHD (1u << 12)             /* @svd FDCAN1.FDCAN_CCCR.PXHD */
#define FDCAN_CCCR_EFBI (1u << 13)             /* @svd FDCAN1.FDCAN_CCCR.EFBI */
#define FDCAN_CCCR_TXP (1u << 14)              /* @svd FDCAN1.FDCAN_CCCR.TXP */
#define FDCAN_CCCR_NISO (1u << 15)             /* @svd FDCAN1.FDCAN_CCCR.NISO */
#define FDCAN_DBTP_WRITABLE 0x009F1FFFu        /* @const DSJW, DTSEG2, DTSEG1, DBRP, TDC */
#define FDCAN_TEST_LBCK (1u << 4)              /* @svd FDCAN1.FDCAN_TEST.LBCK */
#define FDCAN_TEST_TX (3u << 5)                /* @svd FDCAN1.FDCAN_TEST.TX */
#define FDCAN_TEST_RX (1u << 7)                /* @svd FDCAN1.FDCAN_TEST.RX */
#define FDCAN_RWD_WDC (0xFFu << 0)             /* @svd FDCAN1.FDCAN_RWD.WDC */
#define FDCAN_RWD_WDV (0xFFu << 8)             /* @svd FDCAN1.FDCAN_RWD.WDV */
#define FDCAN_NBTP_NTSEG2 (0x7Fu << 0)         /* @svd FDCAN1.FDCAN_NBTP.NTSEG2 field = tseg2 - 1 */
#define FDCAN_NBTP_NTSEG1 (0xFFu << 8)         /* @svd FDCAN1.FDCAN_NBTP.NTSEG1 field = tseg1 - 1 */
#define FDCAN_NBTP_NBRP (0x1FFu << 16)         /* @svd FDCAN1.FDCAN_NBTP.NBRP field = prescaler - 1 */
#define FDCAN_NBTP_NSJW (0x7Fu << 25)          /* @svd FDCAN1.FDCAN_NBTP.NSJW field = sjw - 1 */
#define FDCAN_TSCC_TSS (3u << 0)               /* @svd FDCAN1.FDCAN_TSCC.TSS */
#define FDCAN_TSS_INTERNAL 1u                  /* @svd FDCAN1.FDCAN_TSCC.TSS=1 counter in bit times */
#define FDCAN_TSS_EXTERNAL 2u                  /* @svd FDCAN1.FDCAN_TSCC.TSS=2 TIM3 */
#define FDCAN_TSCC_TCP (0xFu << 16)            /* @svd FDCAN1.FDCAN_TSCC.TCP prescaler = value + 1 */
#define FDCAN_TOCC_ETOC (1u << 0)              /* @svd FDCAN1.FDCAN_TOCC.ETOC */
#define FDCAN_TOCC_TOS (3u << 1)               /* @svd FDCAN1.FDCAN_TOCC.TOS */
#define FDCAN_TOCC_TOP (0xFFFFu << 16)         /* @svd FDCAN1.FDCAN_TOCC.TOP */
#define FDCAN_ECR_TEC (0xFFu << 0)             /* @svd FDCAN1.FDCAN_ECR.TEC */
#define FDCAN_ECR_REC (0x7Fu << 8)             /* @svd FDCAN1.FDCAN_ECR.REC */
#define FDCAN_ECR_RP (1u << 15)                /* @svd FDCAN1.FDCAN_ECR.RP */
#define FDCAN_ECR_CEL (0xFFu << 16)            /* @svd FDCAN1.FDCAN_ECR.CEL */
#define FDCAN_PSR_LEC (7u << 0)                /* @svd FDCAN1.FDCAN_PSR.LEC */
#define FDCAN_PSR_ACT (3u << 3)                /* @svd FDCAN1.FDCAN_PSR.ACT */
#define FDCAN_PSR_EP (1u << 5)                 /* @svd FDCAN1.FDCAN_PSR.EP */
#define FDCAN_PSR_EW (1u << 6)                 /* @svd FDCAN1.FDCAN_PSR.EW */
#define FDCAN_PSR_BO (1u << 7)                 /* @svd FDCAN1.FDCAN_PSR.BO */
#define FDCAN_PSR_DLEC (7u << 8)               /* @svd FDCAN1.FDCAN_PSR.DLEC */
#define FDCAN_LEC_BIT0 5u                      /* @svd FDCAN1.FDCAN_PSR.LEC=5 Bit0Error */
#define FDCAN_LEC_NO_CHANGE 7u                 /* @svd FDCAN1.FDCAN_PSR.LEC=7 */
#define FDCAN_TDCR_TDCF (0x7Fu << 0)           /* @svd FDCAN1.FDCAN_TDCR.TDCF */
#define FDCAN_TDCR_TDCO (0x7Fu << 8)           /* @svd FDCAN1.FDCAN_TDCR.TDCO */
#define FDCAN_IR_RF0L (1u << 2)                /* @svd FDCAN1.FDCAN_IR.RF0L */
#define FDCAN_IR_RF1L (1u << 5)                /* @svd FDCAN1.FDCAN_IR.RF1L */
#define FDCAN_IR_TEFL (1u << 12)               /* @svd FDCAN1.FDCAN_IR.TEFL */
#define FDCAN_IR_ALL 0x00FFFFFFu               /* @const RF0N..ARA, bits 0-23 */
#define FDCAN_ILS_ALL 0x7Fu                    /* @const the seven interrupt groups */
#define FDCAN_ILE_EINT0 (1u << 0)              /* @svd FDCAN1.FDCAN_ILE.EINT0 */
#define FDCAN_ILE_EINT1 (1u << 1)              /* @svd FDCAN1.FDCAN_ILE.EINT1 */
#define FDCAN_RXGFC_WRITABLE 0x0F1F033Fu       /* @const RRFE, RRFS, ANFE, ANFS, F1OM, F0OM, LSS, LSE */
#define FDCAN_RXGFC_LSS (0x1Fu << 16)          /* @svd FDCAN1.FDCAN_RXGFC.LSS */
#define FDCAN_RXGFC_LSE (0xFu << 24)           /* @svd FDCAN1.FDCAN_RXGFC.LSE */
#define FDCAN_XIDAM_EIDM (0x1FFFFFFFu << 0)    /* @svd FDCAN1.FDCAN_XIDAM.EIDM */
#define FDCAN_RXFS_FFL (0xFu << 0)             /* @svd FDCAN1.FDCAN_RXF0S.F0FL (Rx FIFO 1 alike) */
#define FDCAN_RXFS_FGI (3u << 8)               /* @svd FDCAN1.FDCAN_RXF0S.F0GI */
#define FDCAN_RXFS_FPI (3u << 16)              /* @svd FDCAN1.FDCAN_RXF0S.F0PI */
#define FDCAN_RXFS_FF (1u << 24)               /* @svd FDCAN1.FDCAN_RXF0S.F0F */
#define FDCAN_RXFS_RFL (1u << 25)              /* @svd FDCAN1.FDCAN_RXF0S.RF0L */
#define FDCAN_RXFA_FAI (7u << 0)               /* @svd FDCAN1.FDCAN_RXF0A.F0AI */
#define FDCAN_TXBC_TFQM (1u << 24)             /* @svd FDCAN1.FDCAN_TXBC.TFQM 1: Tx queue, 0: FIFO */
#define FDCAN_TXFQS_TFFL (7u << 0)             /* @svd FDCAN1.FDCAN_TXFQS.TFFL */
#define FDCAN_TXFQS_TFGI (3u << 8)             /* @svd FDCAN1.FDCAN_TXFQS.TFGI */
#define FDCAN_TXFQS_TFQPI (3u << 16)           /* @svd FDCAN1.FDCAN_TXFQS.TFQPI */
#define FDCAN_TXFQS_TFQF (1u << 21)            /* @svd FDCAN1.FDCAN_TXFQS.TFQF */
#define FDCAN_TXB_ALL (7u << 0)                /* @svd FDCAN1.FDCAN_TXBAR.AR the three Tx buffers (TXBRP, TXBCR, ... alike) */
#define FDCAN_TXEFS_EFFL (7u << 0)             /* @svd FDCAN1.FDCAN_TXEFS.EFFL */
#define FDCAN_TXEFS_EFGI (3u << 8)             /* @svd FDCAN1.FDCAN_TXEFS.EFGI */
#define FDCAN_TXEFS_EFPI (3u << 16)            /* @svd FDCAN1.FDCAN_TXEFS.EFPI */
#define FDCAN_TXEFS_EFF (1u << 24)             /* @svd FDCAN1.FDCAN_TXEFS.EFF */
#define FDCAN_TXEFS_TEFL (1u << 25)            /* @svd FDCAN1.FDCAN_TXEFS.TEFL */
#define FDCAN_TXEFA_EFAI (3u << 0)             /* @svd FDCAN1.FDCAN_TXEFA.EFAI */
#define FDCAN_CKDIV_PDIV (0xFu << 0)           /* @svd FDCAN1.FDCAN_CKDIV.PDIV 0: /1, n: /2n */
#define FDCAN_CREL_VALUE 0x32141218u           /* @const release 3.2.1, 2018-12-14 (RM0440 FDCAN_CREL) */
#define FDCAN_ENDN_VALUE 0x87654321u           /* @const the endianness test value */

/* ------------------------------------------------ IWDG (RM0440 §41.4) */
#define IWDG_KR_OFS 0x00u                      /* @svd-offset IWDG.KR */
#define IWDG_PR_OFS 0x04u                      /* @svd-offset IWDG.PR */
#define IWDG_RLR_OFS 0x08u                     /* @svd-offset IWDG.RLR */
#define IWDG_SR_OFS 0x0Cu                      /* @svd-offset IWDG.SR */
#define IWDG_WINR_OFS 0x10u                    /* @svd-offset IWDG.WINR */
#define IWDG_KR_KEY (0xFFFFu << 0)             /* @svd IWDG.KR.KEY */
#define IWDG_KEY_START 0xCCCCu                 /* @svd IWDG.KR.KEY=0xCCCC */
#define IWDG_KEY_UNLOCK 0x5555u                /* @svd IWDG.KR.KEY=0x5555 */
#define IWDG_KEY_REFRESH 0xAAAAu               /* @svd IWDG.KR.KEY=0xAAAA */
#define IWDG_PR_PR (7u << 0)                   /* @svd IWDG.PR.PR LSI / (4 << PR), PR 6 and 7 alike */
#define IWDG_RLR_RL (0xFFFu << 0)              /* @svd IWDG.RLR.RL */
#define IWDG_WINR_WIN (0xFFFu << 0)            /* @svd IWDG.WINR.WIN */
#define IWDG_SR_PVU (1u << 0)                  /* @svd IWDG.SR.PVU */
#define IWDG_SR_RVU (1u << 1)                  /* @svd IWDG.SR.RVU */
#define IWDG_SR_WVU (1u << 2)                  /* @svd IWDG.SR.WVU */
#define RCC_CSR_IWDGRSTF (1u << 29)            /* @svd RCC.RCC_CSR.IWDGRSTF */

/* ------------------------------------------------ PWR (RM0440 §6.4) */
#define PWR_CR1_OFS 0x00u                      /* @svd-offset PWR.PWR_CR1 */
#define PWR_CR2_OFS 0x04u                      /* @svd-offset PWR.PWR_CR2 */
#define PWR_CR3_OFS 0x08u                      /* @svd-offset PWR.PWR_CR3 */
#define PWR_CR4_OFS 0x0Cu                      /* @svd-offset PWR.PWR_CR4 */
#define PWR_SR1_OFS 0x10u                      /* @svd-offset PWR.PWR_SR1 */
#define PWR_SR2_OFS 0x14u                      /* @svd-offset PWR.PWR_SR2 */
#define PWR_SCR_OFS 0x18u                      /* @svd-offset PWR.PWR_SCR */
#define PWR_PUCRA_OFS 0x20u                    /* @svd-offset PWR.PWR_PUCRA first of the fourteen pull registers */
#define PWR_PDCRG_OFS 0x54u                    /* @svd-offset PWR.PWR_PDCRG last */
#define PWR_CR5_OFS 0x80u                      /* @svd-offset PWR.PWR_CR5 */
#define PWR_CR1_LPMS (7u << 0)                 /* @svd PWR.PWR_CR1.LPMS */
#define PWR_CR1_VOS (3u << 9)                  /* @svd PWR.PWR_CR1.VOS */
#define PWR_CR1_VOS_RANGE1 (1u << 9)           /* @svd PWR.PWR_CR1.VOS=1 */
#define PWR_CR1_VOS_RANGE2 (2u << 9)           /* @svd PWR.PWR_CR1.VOS=2 */
#define PWR_CR1_WRITABLE 0x0000471Fu           /* @const LPMS, FPD_STOP, DBP, VOS, LPR */
#define PWR_CR3_EIWUL (1u << 15)               /* @svd PWR.PWR_CR3.EIWUL */
#define PWR_CR5_R1MODE (1u << 8)               /* @svd PWR.PWR_CR5.R1MODE 1: range 1 normal mode, 0: boost */

/* ------------------------------------------------ TIM6 (RM0440, basic timers) */
#define TIM6_CR1_OFS 0x00u                     /* @svd-offset TIM6.TIM6_CR1 */
#define TIM6_CR2_OFS 0x04u                     /* @svd-offset TIM6.TIM6_CR2 */
#define TIM6_DIER_OFS 0x0Cu                    /* @svd-offset TIM6.TIM6_DIER */
#define TIM6_SR_OFS 0x10u                      /* @svd-offset TIM6.TIM6_SR */
#define TIM6_EGR_OFS 0x14u                     /* @svd-offset TIM6.TIM6_EGR */
#define TIM6_CNT_OFS 0x24u                     /* @svd-offset TIM6.TIM6_CNT */
#define TIM6_PSC_OFS 0x28u                     /* @svd-offset TIM6.TIM6_PSC */
#define TIM6_ARR_OFS 0x2Cu                     /* @svd-offset TIM6.TIM6_ARR */
#define TIM6_CR1_CEN (1u << 0)                 /* @svd TIM6.TIM6_CR1.CEN */
#define TIM6_CR1_UDIS (1u << 1)                /* @svd TIM6.TIM6_CR1.UDIS */
#define TIM6_CR1_URS (1u << 2)                 /* @svd TIM6.TIM6_CR1.URS */
#define TIM6_CR1_OPM (1u << 3)                 /* @svd TIM6.TIM6_CR1.OPM */
#define TIM6_CR1_ARPE (1u << 7)                /* @svd TIM6.TIM6_CR1.ARPE */
#define TIM6_CR1_UIFREMAP (1u << 11)           /* @svd TIM6.TIM6_CR1.UIFREMAP */
#define TIM6_CR1_DITHEN (1u << 12)             /* @svd TIM6.TIM6_CR1.DITHEN */
#define TIM6_CR2_MMS (7u << 4)                 /* @svd TIM6.TIM6_CR2.MMS */
#define TIM6_DIER_UIE (1u << 0)                /* @svd TIM6.TIM6_DIER.UIE */
#define TIM6_DIER_UDE (1u << 8)                /* @svd TIM6.TIM6_DIER.UDE */
#define TIM6_SR_UIF (1u << 0)                  /* @svd TIM6.TIM6_SR.UIF */
#define TIM6_EGR_UG (1u << 0)                  /* @svd TIM6.TIM6_EGR.UG */
#define TIM6_CNT_CNT (0xFFFFu << 0)            /* @svd TIM6.TIM6_CNT.CNT */
#define TIM6_CNT_UIFCPY (1u << 31)             /* @svd TIM6.TIM6_CNT.UIFCPY */
#define TIM6_PSC_PSC (0xFFFFu << 0)            /* @svd TIM6.TIM6_PSC.PSC */
#define TIM6_ARR_WHOLE 0xFFFFu                 /* @const ARR without the dithering bits 19:16 */

/* ------------------------------------------------ Cortex-M4 system control space (ARMv7-M ARM B3.2-B3.4,
 * C1.6-C1.8; Cortex-M4 TRM): absolute addresses, not in the vendor SVD */
#define SCS_ICTR 0xE000E004u                   /* @core interrupt controller type */
#define SCS_ACTLR 0xE000E008u                  /* @core */
#define SYST_CSR 0xE000E010u                   /* @core */
#define SYST_RVR 0xE000E014u                   /* @core */
#define SYST_CVR 0xE000E018u                   /* @core */
#define SYST_CALIB 0xE000E01Cu                 /* @core */
#define NVIC_ISER0 0xE000E100u                 /* @core set-enable, 8 words */
#define NVIC_ICER0 0xE000E180u                 /* @core clear-enable */
#define NVIC_ISPR0 0xE000E200u                 /* @core set-pending */
#define NVIC_ICPR0 0xE000E280u                 /* @core clear-pending */
#define NVIC_IABR0 0xE000E300u                 /* @core active bits */
#define NVIC_IPR0 0xE000E400u                  /* @core priorities, one byte per interrupt */
#define NVIC_BANK_BYTES 0x20u                  /* @core the 8 words of each bit bank */
#define SCB_CPUID 0xE000ED00u                  /* @core */
#define SCB_ICSR 0xE000ED04u                   /* @core */
#define SCB_VTOR 0xE000ED08u                   /* @core */
#define SCB_AIRCR 0xE000ED0Cu                  /* @core */
#define SCB_SCR 0xE000ED10u                    /* @core */
#define SCB_CCR 0xE000ED14u                    /* @core */
#define SCB_SHPR1 0xE000ED18u                  /* @core SHPR1-3: exceptions 4-15, one byte each */
#define SCB_SHPR_END 0xE000ED24u               /* @core the byte after SHPR3 */
#define SCB_SHCSR 0xE000ED24u                  /* @core */
#define SCB_CFSR 0xE000ED28u                   /* @core */
#define SCB_HFSR 0xE000ED2Cu                   /* @core */
#define SCB_DFSR 0xE000ED30u                   /* @core */
#define SCB_MMFAR 0xE000ED34u                  /* @core */
#define SCB_BFAR 0xE000ED38u                   /* @core */
#define SCB_AFSR 0xE000ED3Cu                   /* @core */
#define SCB_CPACR 0xE000ED88u                  /* @core */
#define MPU_TYPE 0xE000ED90u                   /* @core */
#define MPU_CTRL 0xE000ED94u                   /* @core */
#define DHCSR 0xE000EDF0u                      /* @core */
#define DEMCR 0xE000EDFCu                      /* @core */
#define NVIC_STIR 0xE000EF00u                  /* @core */
#define FPU_FPCCR 0xE000EF34u                  /* @core */
#define FPU_FPCAR 0xE000EF38u                  /* @core */
#define FPU_FPDSCR 0xE000EF3Cu                 /* @core */
#define DWT_CTRL 0xE0001000u                   /* @core */
#define DWT_CYCCNT 0xE0001004u                 /* @core */
#define SYST_CSR_ENABLE (1u << 0)              /* @core */
#define SYST_CSR_TICKINT (1u << 1)             /* @core */
#define SYST_CSR_CLKSOURCE (1u << 2)           /* @core 1: the processor clock */
#define SYST_CSR_COUNTFLAG (1u << 16)          /* @core */
#define SYST_RVR_RELOAD 0xFFFFFFu              /* @core */
#define SCB_ICSR_VECTACTIVE 0x1FFu             /* @core the IPSR's exception number, also in xPSR */
#define SCB_ICSR_RETTOBASE (1u << 11)          /* @core */
#define SCB_ICSR_VECTPENDING_SHIFT 12u         /* @core */
#define SCB_ICSR_ISRPENDING (1u << 22)         /* @core */
#define SCB_ICSR_PENDSTCLR (1u << 25)          /* @core */
#define SCB_ICSR_PENDSTSET (1u << 26)          /* @core */
#define SCB_ICSR_PENDSVCLR (1u << 27)          /* @core */
#define SCB_ICSR_PENDSVSET (1u << 28)          /* @core */
#define SCB_ICSR_NMIPENDSET (1u << 31)         /* @core */
#define SCB_AIRCR_VECTRESET (1u << 0)          /* @core */
#define SCB_AIRCR_VECTCLRACTIVE (1u << 1)      /* @core */
#define SCB_AIRCR_SYSRESETREQ (1u << 2)        /* @core */
#define SCB_AIRCR_PRIGROUP (7u << 8)           /* @core */
#define SCB_AIRCR_VECTKEY 0x05FAu              /* @core the write key in bits 31:16 */
#define SCB_AIRCR_VECTKEYSTAT 0xFA050000u      /* @core what bits 31:16 read */
#define SCB_SCR_WRITABLE 0x16u                 /* @core SLEEPONEXIT, SLEEPDEEP, SEVONPEND */
#define SCB_CCR_STKALIGN (1u << 9)             /* @core */
#define SCB_CCR_WRITABLE 0x31Bu                /* @core NONBASETHRDENA..STKALIGN without the reserved bits */
#define SCB_SHCSR_MEMFAULTACT (1u << 0)        /* @core */
#define SCB_SHCSR_BUSFAULTACT (1u << 1)        /* @core */
#define SCB_SHCSR_USGFAULTACT (1u << 3)        /* @core */
#define SCB_SHCSR_SVCALLACT (1u << 7)          /* @core */
#define SCB_SHCSR_PENDSVACT (1u << 10)         /* @core */
#define SCB_SHCSR_SYSTICKACT (1u << 11)        /* @core */
#define SCB_SHCSR_MEMFAULTENA (1u << 16)       /* @core */
#define SCB_SHCSR_BUSFAULTENA (1u << 17)       /* @core */
#define SCB_SHCSR_USGFAULTENA (1u << 18)       /* @core */
#define SCB_SHCSR_ENABLES (7u << 16)           /* @core the three fault enables */
#define SCB_CFSR_IMPRECISERR (1u << 10)        /* @core BFSR.IMPRECISERR */
#define SCB_HFSR_FORCED (1u << 30)             /* @core */
#define SCB_CPACR_CP10 (3u << 20)              /* @core */
#define SCB_CPACR_CP11 (3u << 22)              /* @core */
#define MPU_TYPE_8_REGIONS 0x00000800u         /* @core DREGION = 8 */
#define DEMCR_TRCENA (1u << 24)                /* @core */
#define DEMCR_WRITABLE 0x010F07F1u             /* @core */
#define FPU_FPCCR_ASPEN_LSPEN 0xC0000000u      /* @core automatic and lazy state preservation */
#define FPU_FPDSCR_WRITABLE 0x07C00000u        /* @core AHP, DN, FZ, RMode */
#define DWT_CTRL_CYCCNTENA (1u << 0)           /* @core */
#define DWT_CTRL_NUMCOMP_4 0x40000000u         /* @core four comparators */
#define CPUID_M4F_R0P1 0x410FC241u             /* @core Cortex-M4 r0p1 */
#define DBGMCU_IDCODE 0xE0042000u              /* @svd DBGMCU.IDCODE */
#define DBGMCU_APB2FZR 0xE0042010u             /* @svd DBGMCU.APB2_FZ the last of CR and the freeze registers */
#define DBGMCU_IDCODE_G474 0x20016469u         /* @const DEV_ID 0x469, REV_ID 0x2001 */
#define RCC_CSR_SFTRSTF (1u << 28)             /* @svd RCC.RCC_CSR.SFTRSTF */

#endif
