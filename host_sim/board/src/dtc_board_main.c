/* dtc-board: the flashable image on the emulated STM32G474.
 *   dtc-board exec --elf FILE [--nvm FILE] [--seconds S] [--pins BOARD_MD] [--stats] [--peek SYM[+OFF]]...
 * runs the image until it exits through semihosting, a strictness stop, or S seconds of
 * virtual time. Exit status: the image's exit code; 1 for a strictness stop (the message
 * names the address, the PC and the function); 2 for bad usage.
 *   dtc-board run SCENARIO --elf FILE ...  (the plant binding: not yet, see README) */
#define _POSIX_C_SOURCE 200809L
#include "board_twin/board.h"
#include "board_twin/pinmap.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int usage(void) {
  fprintf(stderr, "usage: dtc-board exec --elf FILE [--nvm FILE] [--seconds S] [--pins BOARD_MD] [--stats] [--peek SYM[+OFF]]...\n"
                  "       dtc-board run SCENARIO --elf FILE [...]   (not implemented yet)\n");
  return 2;
}

static double wall(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv) {
  if (argc < 2) return usage();
  if (strcmp(argv[1], "run") == 0) {
    fprintf(stderr, "dtc-board run: the plant binding (HRTIM, ADC and FDCAN models) is not implemented yet\n");
    return 2;
  }
  if (strcmp(argv[1], "exec") != 0) return usage();
  board_config cfg;
  board_config_default(&cfg);
  double seconds = 10.0;
  const char *pins = NULL;
  int stats = 0;
  const char *peek[16];
  int npeek = 0;
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    if (strcmp(a, "--stats") == 0) { stats = 1; continue; }
    if (i + 1 >= argc) return usage();
    if (strcmp(a, "--elf") == 0) cfg.elf_path = argv[++i];
    else if (strcmp(a, "--nvm") == 0) cfg.nvm_path = argv[++i];
    else if (strcmp(a, "--seconds") == 0) seconds = atof(argv[++i]);
    else if (strcmp(a, "--pins") == 0) pins = argv[++i];
    else if (strcmp(a, "--peek") == 0 && npeek < 16) peek[npeek++] = argv[++i];
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
  for (int i = 0; i < npeek; i++) { /* a 32-bit word at a symbol after the run */
    char name[128];
    snprintf(name, sizeof name, "%s", peek[i]);
    char *plus = strchr(name, '+');
    uint32_t off = 0, v = 0;
    if (plus) { *plus = 0; off = (uint32_t)strtoul(plus + 1, NULL, 0); }
    if (board_read_symbol(b, name, off, &v) == 0) printf("%s = 0x%08X (%u)\n", peek[i], v, v);
    else { fprintf(stderr, "dtc-board: no symbol %s\n", name); rc = rc ? rc : 2; }
  }
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
