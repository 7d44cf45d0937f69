/* ADC1 power-up (DEEPPWD off, ADVREGEN, 20 us, ADCAL, ADEN, ADRDY) and two injected software-
 * triggered conversions on channels 1 and 5 at ADC clock HCLK/2 = 8 MHz; the conversion time is
 * measured with DWT. VARIANT 1 enables without calibrating, VARIANT 2 leaves deep power-down on. */
#include "tb.h"
#ifndef VARIANT
#define VARIANT 0
#endif
#define ADC1(o) REG(0x50000000u + (o))
#define ADC12_CCR REG(0x50000308u)
int main(void) {
  DEMCR |= 1u << 24;
  DWT_CTRL |= 1u;
  RCC_AHB2ENR |= 1u << 13;
  ADC12_CCR = 2u << 16;                  /* CKMODE: HCLK/2 */
  if (VARIANT != 2) ADC1(0x08) = 0;      /* leave deep power-down */
  ADC1(0x08) |= 1u << 28;                /* ADVREGEN */
  uint32_t c0 = DWT_CYCCNT;
  while (DWT_CYCCNT - c0 < 16u * 25u) {} /* > 20 us at 16 MHz */
  if (VARIANT != 1) {
    ADC1(0x08) |= 1u << 31;              /* ADCAL */
    while (ADC1(0x08) & (1u << 31)) {}
  }
  ADC1(0x08) |= 1u;                      /* ADEN */
  while (!(ADC1(0x00) & 1u)) {}
  ADC1(0x14) = 2u << 3;                  /* channel 1: 12.5 cycles sampling */
  ADC1(0x4C) = 1u | (1u << 9) | (5u << 15); /* JL=2 conversions: channels 1, 5; software trigger */
  uint32_t t0 = DWT_CYCCNT;
  ADC1(0x08) |= 1u << 3;                 /* JADSTART */
  while (!(ADC1(0x00) & 0x40u)) {}       /* JEOS */
  tb_result[0] = DWT_CYCCNT - t0;
  tb_result[1] = ADC1(0x80);
  tb_result[2] = ADC1(0x84);
  tb_result[3] = ADC1(0x08) & (1u << 3); /* JADSTART cleared at the end */
  return 0;
}
