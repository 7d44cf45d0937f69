/* State of the ADC1/ADC2 model (adc.c), RM0440 §21. */
#ifndef BOARD_ADC_H
#define BOARD_ADC_H
#include <stdbool.h>
#include <stdint.h>

typedef struct {
  uint32_t isr, ier, cr, cfgr, cfgr2, smpr[2], jsqr, ofr[4], difsel, calfact;
  uint32_t jdr[4];
  double advregen_t;      /* when ADVREGEN was set, <0: off */
  double cal_done_t;      /* ADCAL clears then, <0: none running */
  double cal_end_t;       /* last calibration end (ADEN needs 4 ADC clocks after it) */
  double rdy_t;           /* ADRDY rises then, <0: none pending */
  double dis_t;           /* ADDIS completes then, <0: none */
  bool calibrated;
  bool ready;             /* ADEN took effect (ADRDY rose; the flag itself may be cleared) */
} adc_unit;

typedef struct {
  adc_unit u[2];
  uint32_t ccr;
  /* the injected sequence in progress (dual: both ADCs in lockstep) */
  bool busy;
  int rank, len;
  double t_trig;
  double rank_sample_t, rank_end_t, seq_end_t;
  bool in_advance;        /* adc_advance is running (it integrates the plant itself) */
  uint16_t pending_code[2];
} adc_state;

#endif
