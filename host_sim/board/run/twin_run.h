/* `dtc-board run`: a dtc-sim scenario on the emulated board (twin_run.c). */
#ifndef BOARD_TWIN_RUN_H
#define BOARD_TWIN_RUN_H
#include <stddef.h>
#include <stdint.h>
#include "board_twin/board.h"
#include "sim/sim.h"

/* argv[1] is "run". Exit status as dtc-sim: 0 ok, 1 runtime failure, 2 bad input. */
int twin_run_main(int argc, char **argv);
/* Add the board's measurements (logic analyser, interrupt instruction counts, fault test) to the
 * metrics JSON written by sim_write_metrics_json. 0 or 1 with err. */
int twin_metrics_extend(board *b, const char *path, const sim_metrics *m, double fault_t, uint32_t faults_after,
                        char *err, size_t n);
#endif
