/* State of the HRTIM model (hrtim.c), RM0440 §27 (High-resolution timer). */
#ifndef BOARD_HRTIM_H
#define BOARD_HRTIM_H
#include <stdbool.h>
#include <stdint.h>

#define HRTIM_NOUT 12      /* TA1, TA2, TB1, ... TF2 (bit order of OENR/ODISR/ODSR) */
#define HRTIM_MAX_EDGES 32

typedef struct {
  double t;
  uint8_t level;
} hrtim_edge;

/* Waveform of one output before gating (dead-time unit output), as future edges. */
typedef struct {
  uint8_t level;                   /* level before the first queued edge */
  int n;
  hrtim_edge e[HRTIM_MAX_EDGES];
} hrtim_wave;

typedef struct {
  /* active registers, and their preload copies (RM0440 §27.3.8 registers preload and update) */
  uint32_t cr, per, rep, cmp[4], set[2], rst[2];
  uint32_t p_per, p_rep, p_cmp[4], p_set[2], p_rst[2];
  uint32_t dtr, outr, fltr, dier, isr;
  uint8_t ref[2];                  /* crossbar output (before dead time) at the end of the emitted period */
  /* the period's crossbar programme: set/reset events in time order, and the reference at its start */
  hrtim_edge plan[2][8];           /* PER, CMP1-4, and software sets (SST) */
  int n_plan[2];
  uint8_t ref_start[2];
  hrtim_edge last_tr[2];           /* last reference transition before this period (t < 0: none) */
} hrtim_timer;

#define HRTIM_EEV_HIST 16

typedef struct {
  uint32_t mcr, mper, mrep, mcmp[4], p_mper, p_mrep, p_mcmp[4], misr, mdier;
  hrtim_timer tim[6];
  uint32_t cr1, isr, ier, oen, fault_state, adcr[4], fltinr1, fltinr2;
  bool running;
  double t_period;                 /* start of the current period, s */
  double t_count;                  /* seconds per counter tick */
  double next_period_t, next_mcmp_t[4];
  bool mcmp_done[4];
  hrtim_wave wave[HRTIM_NOUT];
  bool flt3_line_low;              /* FLT3 input as the HRTIM sees it (after the pin mux) */
  double flt3_apply_t;             /* the synchronised input takes effect then, <0: nothing pending */
  /* external events (EECR1-3) and external event 6 (PB5, the fault line's second input) */
  uint32_t eecr[3];
  bool eev6_pin_low;               /* EEV6 input as the HRTIM sees it (after the pin mux) */
  bool eev6_raw;                   /* after the polarity: active */
  bool eev6_on;                    /* after the digital filter and the resynchronisation */
  double eev6_apply_t;             /* eev6_on takes eev6_raw's value then, <0: nothing pending */
  bool eev6_on_at_t0;              /* eev6_on at the start of the present period, and its changes since */
  int n_eev6_hist;
  hrtim_edge eev6_hist[HRTIM_EEV_HIST];
  uint64_t periods;
} hrtim_state;

#endif
