/* The twin's outside world: the plant wired to the HRTIM outputs and the ADC pins, the
 * gate-driver fault line, and what a logic analyser on the 12 gate signals would measure. */
#ifndef BOARD_TWIN_TWIN_H
#define BOARD_TWIN_TWIN_H
#include <stdbool.h>
#include <stdint.h>
#include "board_twin/board.h"
#include "plant/plant.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Wire a plant (copied from cfg and initialised) to the board: from now on the HRTIM outputs
 * drive it and the ADC converts its sensors. 0, or PLANT_EINVAL. */
int board_attach_plant(board *b, const plant_config *cfg);
/* The attached plant, synchronised to the board's present time; NULL without one. */
plant_state *board_plant(board *b);

/* Drive a pin from outside (level 0/1) or release it (-1). */
void board_drive_pin(board *b, char port, int pin, int level);
/* The gate drivers' common fault line (active low; -1 releases it to the pull-ups). The interface
 * board ties it to two pins (docs/board.md): PB10 = HRTIM_FLT3 and PB5 = HRTIM_EEV6. */
void board_drive_fault_line(board *b, int level);

/* Logic analyser on the 12 gate signals, in switch order: index 4 x leg + 0 S1, 1 S3, 2 S2, 3 S4
 * (the interface board wires TA2, TA1, TB1, TB2 = leg a S1, S3, S2, S4; C/D leg b, E/F leg c). */
typedef struct {
  uint64_t on_edges[12], off_edges[12];
  double on_time_s[12];          /* total time on */
  double first_on_s[12], last_off_s[12]; /* -1: never */
  double min_on_s[12], min_off_s[12];    /* shortest complete on / off pulse; INFINITY: none */
  double min_dead_time_s;        /* shortest off->on gap between the two switches of a pair; INFINITY: none */
  double max_dead_time_s;
  uint64_t dead_time_events;
  uint64_t overlaps;             /* segments with S1+S3 or S2+S4 on together */
  uint64_t pn_steps;             /* leg P<->N without passing through O */
  uint64_t bad_combinations;     /* other switch combinations outside P/O/N/off/dead time */
  double t_s;                    /* analysed up to */
  double mark_s;                 /* board_la_mark time, -1: none */
  uint32_t on_at_mark;           /* outputs on at the mark */
  double off_after_mark_s[12];   /* first on->off edge at or after the mark, -1: none yet */
} board_la_stats;
/* Gate levels now, in switch order (bit 4 x leg + 0 S1, 1 S3, 2 S2, 3 S4). */
uint32_t board_gate_levels(board *b);
/* Remember which outputs are on now and time their next turn-off (the fault test). */
void board_la_mark(board *b);
void board_la_get(board *b, board_la_stats *out);

/* When the ADCs sampled the three phase currents (ia PA0, ib PA1, ic PB1), whichever ADC converts
 * each: over every HRTIM trigger that converted all three, the largest spread of their sampling
 * instants, and for the last one each instant after the trigger. */
typedef struct {
  uint64_t triples;           /* triggers with all three currents converted */
  double max_skew_s;          /* largest (latest - earliest) sampling instant within one trigger */
  double after_trigger_s[3];  /* ia, ib, ic: sampling instant - trigger instant, last trigger */
} board_current_sampling;
void board_current_sampling_get(board *b, board_current_sampling *out);

/* Executed instructions per exception number (16 + IRQ), exact, excluding nested exceptions. */
typedef struct {
  uint64_t count;
  uint64_t total, worst, best;
} board_irq_stat;
void board_irq_get(board *b, int exc, board_irq_stat *out);

#ifdef __cplusplus
}
#endif

#endif
