/* dtc-board: the flashable image on the emulated STM32G474.
 *   dtc-board exec --elf FILE [--nvm FILE] [--seconds S] [--pins BOARD_MD] [--stats]
 * runs the image until it exits through semihosting, a strictness stop, or S seconds of
 * virtual time. Exit status: the image's exit code; 1 for a strictness stop (the message
 * names the address, the PC and the function); 2 for bad usage.
 *   dtc-board run SCENARIO --elf FILE [--controller NAME] [--csv OUT] [--metrics OUT] [--set k=v]
 *                 [--nvm FILE] [--fault-line T_S]
 * runs a dtc-sim scenario with the image driving the plant through the HRTIM and ADC models. */
#define _POSIX_C_SOURCE 200809L
#include "board_twin/board.h"
#include "board_twin/pinmap.h"
#include "twin_run.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int usage(void) {
  fprintf(stderr, "usage: dtc-board exec --elf FILE [--nvm FILE] [--seconds S] [--pins BOARD_MD] [--stats]\n"
                  "       dtc-board run SCENARIO --elf FILE [--controller NAME] [--csv OUT] [--metrics OUT]\n"
                  "                 [--set SECTION.KEY=VALUE]... [--nvm FILE] [--fault-line T_S] [--quiet]\n");
  return 2;
}

static double wall(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv) {
  if (argc < 2) return usage();
  if (strcmp(argv[1], "run") == 0) return twin_run_main(argc, argv);
  if (strcmp(argv[1], "exec") != 0) return usage();
  board_config cfg;
  board_config_default(&cfg);
  double seconds = 10.0;
  const char *pins = NULL;
  int stats = 0;
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    if (strcmp(a, "--stats") == 0) { stats = 1; continue; }
    if (i + 1 >= argc) return usage();
    if (strcmp(a, "--elf") == 0) cfg.elf_path = argv[++i];
    else if (strcmp(a, "--nvm") == 0) cfg.nvm_path = argv[++i];
    else if (strcmp(a, "--seconds") == 0) seconds = atof(argv[++i]);
    else if (strcmp(a, "--pins") == 0) pins = argv[++i];
    else return usage();
  }
  if (!cfg.elf_path) return usage();
  char err[512];
  board *b = board_open(&cfg, err, sizeof err);
  if (!b) { fprintf(stderr, "dtc-board: %s\n", err); return 2; }
  double w0 = wall();
  board_status st = board_run(b, seconds);
  double w = wall() - w0;
  int rc = 0;
  if (st == BOARD_FAULT) { fprintf(stderr, "dtc-board: %s\n", board_message(b)); rc = 1; }
  else if (st == BOARD_EXITED) rc = board_exit_code(b);
  if (stats)
    fprintf(stderr, "dtc-board: %.6f s simulated in %.3f s wall (%.2f sim s per wall s), %llu instructions (%.1f M/s), "
            "HCLK %.3f MHz, %u resets\n", board_time_s(b), w, board_time_s(b) / (w > 0 ? w : 1e-9),
            (unsigned long long)board_instructions(b), (double)board_instructions(b) / (w > 0 ? w : 1e-9) / 1e6,
            board_core_hz(b) / 1e6, board_resets(b));
  if (pins && rc == 0) {
    pinmap_row rows[128];
    int n = pinmap_parse(pins, rows, 128, err, sizeof err);
    if (n < 0) { fprintf(stderr, "%s\n", err); rc = 2; }
    else {
      board_pin bp[7 * 16];
      size_t np = board_pins(b, bp, 7 * 16);
      int bad = pinmap_check(rows, (size_t)n, bp, np, stderr);
      if (bad) { fprintf(stderr, "dtc-board: %d pin(s) differ from %s\n", bad, pins); rc = 1; }
    }
  }
  board_close(b);
  return rc;
}
