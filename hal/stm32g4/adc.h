/**
 * @file adc.h
 * @brief The five analog inputs: ADC1 + ADC2 in dual injected simultaneous
 *        mode (ia, vc1 / ib, vc2) and ADC3 (ic), all triggered by HRTIM ADC
 *        trigger 2 at a fixed instant of the PWM period; ADC1's end of
 *        sequence is the control tick. Private to hal/stm32g4.
 *
 * Scaling (docs/board.md, "Analog inputs"): currents code 0 = -150 A,
 * 4095 = +150 A about the start-up offset; capacitor voltages code 0 = 0 V,
 * 4095 = 500 V.
 */
#ifndef HAL_STM32G4_ADC_H
#define HAL_STM32G4_ADC_H

#include <stdbool.h>

#include "hal/hal_types.h"
#include "stm32g474_regs.h"

/**
 * Clock, power up, calibrate (single-ended) and enable ADC1..3, program the
 * injected sequences on the HRTIM trigger and arm them (JADSTART); the
 * sample is not calibrated until adc_calibrate_offsets(). Context: BG.
 * @return HAL_OK, HAL_EIO when a regulator, calibration or enable timed out
 * (BOARD_FAULT_ADC_CAL recorded; call adc_stop()).
 */
int adc_init(void);

/** Stop the injected conversions and disable ADC1..3, so adc_init() may run again. Context: BG. */
void adc_stop(void);

/**
 * The current sensors' zero, with the gates off: the mean of 64 periods'
 * codes (the HRTIM must run). Samples are delivered only after this
 * succeeded. Context: BG.
 * @return HAL_OK, HAL_EIO when no conversion came, ADC3 missed one, or an
 * offset is more than +-5 % of full scale from mid-scale
 * (BOARD_FAULT_ADC_OFFSET recorded: every sample is refused).
 */
int adc_calibrate_offsets(void);

/** @return true once adc_calibrate_offsets() succeeded (since adc_init()). Context: ANY. */
bool adc_calibrated(void);

/** Clear ADC1's sequence flags and enable its end-of-sequence interrupt (the tick). Context: BG. */
void adc_tick_irq_enable(void);

/** @return true when ADC1's injected sequence has ended (a tick is due). Context: ISR. */
static inline bool adc_tick_pending(void) { return (ADC_REG(ADC1_BASE, ADC_ISR_OFS) & ADC_ISR_JEOS) != 0u; }

/**
 * Latch this tick's five codes and clear the flags. The sample becomes
 * readable once (adc_sample_read()) when it is calibrated, no current is at
 * a rail (BOARD_FAULT_ADC_RANGE otherwise) and ADC3 converted with ADC1/2
 * (BOARD_FAULT_ADC_SYNC otherwise). Context: ISR (the control tick).
 */
void adc_latch(void);

/**
 * The one allowed read of this tick's sample, converted to A and V into
 * @p out (speed_meas_valid false: no speed sensor). Context: ISR.
 * @return HAL_OK, HAL_EINVAL for a NULL @p out, HAL_EAGAIN when the sample
 * was read already or refused.
 */
int adc_sample_read(hal_sample *out);

#endif /* HAL_STM32G4_ADC_H */
