/* State of the ADC model (adc.c), RM0440 §21: the ADC1/ADC2 pair and the ADC3/4/5 group. */
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

/* One ADC group with its common registers: ADC12 (ADC1 master, ADC2 slave) or ADC345 (ADC3;
 * ADC4 and ADC5 are not modelled, every access to them is refused). */
typedef struct {
  adc_unit u[2];
  int first;              /* number of u[0]: 1 (ADC1) or 3 (ADC3) */
  int n_modelled;         /* units with a model: 2 (ADC1, ADC2) or 1 (ADC3) */
  uint32_t ccr;
  /* the injected sequence in progress (dual: both ADCs in lockstep) */
  bool busy;
  int rank, len;
  double t_trig;
  double rank_sample_t, rank_end_t, seq_end_t;
  uint16_t pending_code[2];
} adc_group;

/* Sampling instants of the three phase currents (ia PA0, ib PA1, ic PB1), whatever ADC converts them:
 * per HRTIM trigger, the spread of the three instants (a measurement for the tests). */
typedef struct {
  double trig_t[3], sample_t[3]; /* last conversion of each: its trigger and its sampling instant */
  double counted_trig_t;         /* trigger already summarised */
  uint64_t triples;              /* triggers with all three currents converted */
  double max_skew_s;             /* largest spread of the three instants in one trigger */
  double after_trigger_s[3];     /* last sampling instant - trigger, per current */
} adc_current_instants;

typedef struct {
  adc_group g[2];         /* [0] ADC12 at 0x50000000, [1] ADC345 at 0x50000400 */
  bool in_advance;        /* adc_advance is running (it integrates the plant itself) */
  adc_current_instants cur;
} adc_state;

#endif
