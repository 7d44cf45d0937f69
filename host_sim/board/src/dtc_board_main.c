/* dtc-board: the flashable image on the emulated STM32G474.
 *   dtc-board exec --elf FILE [--nvm FILE] [--seconds S] [--pins BOARD_MD] [--stats] [--peek SYM[+OFF]]...
 *                  [--can IFACE [--can-bitrate BPS]] [--realtime]
 * runs the image until it exits through semihosting, a strictness stop, or S seconds of
 * virtual time. --can bridges FDCAN1 to a SocketCAN interface (frames out at the emulated
 * time their transmission ends, frames in through the image's filters); --can-bitrate is the
 * bus's rate (a node joining at another rate stops the run); --realtime holds virtual time
 * back to wall-clock time (a tool on the bus sees the image at its real pace); SIGINT or SIGTERM
 * then ends the run like a power-off (the --nvm file is written, exit status 0). Exit status: the image's exit code; 1 for a strictness stop (the message
 * names the address, the PC and the function); 2 for bad usage.
 *   dtc-board run SCENARIO --elf FILE [--controller NAME] [--csv OUT] [--metrics OUT] [--set k=v]
 *                 [--nvm FILE] [--fault-line T_S [--fault-irq-off]]
 * runs a dtc-sim scenario with the image driving the plant through the HRTIM and ADC models. */
#define _POSIX_C_SOURCE 200809L
#include "board_twin/board.h"
#include "board_twin/can.h"
#include "board_twin/pinmap.h"
#include "board_twin/twin.h"
#include "twin_run.h"
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* SIGINT/SIGTERM end a --realtime run between slices: a clean power-off, the NVM file written. */
static volatile sig_atomic_t g_stop;
static void on_signal(int sig) { (void)sig; g_stop = 1; }

static int usage(void) {
  fprintf(stderr, "usage: dtc-board exec --elf FILE [--nvm FILE] [--seconds S] [--pins BOARD_MD] [--stats] [--peek SYM[+OFF]]...\n"
                  "                      [--can IFACE [--can-bitrate BPS]] [--realtime]\n"
                  "       dtc-board run SCENARIO --elf FILE [--controller NAME] [--csv OUT] [--metrics OUT]\n"
                  "                 [--set SECTION.KEY=VALUE]... [--nvm FILE] [--fault-line T_S [--fault-irq-off]] [--quiet]\n");
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
  int stats = 0, realtime = 0;
  const char *peek[16];
  int npeek = 0;
  const char *can_iface = NULL;
  long can_bitrate = 0;
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    if (strcmp(a, "--stats") == 0) { stats = 1; continue; }
    if (strcmp(a, "--realtime") == 0) { realtime = 1; continue; }
    if (i + 1 >= argc) return usage();
    if (strcmp(a, "--elf") == 0) cfg.elf_path = argv[++i];
    else if (strcmp(a, "--nvm") == 0) cfg.nvm_path = argv[++i];
    else if (strcmp(a, "--seconds") == 0) seconds = atof(argv[++i]);
    else if (strcmp(a, "--pins") == 0) pins = argv[++i];
    else if (strcmp(a, "--peek") == 0 && npeek < 16) peek[npeek++] = argv[++i];
    else if (strcmp(a, "--can") == 0) can_iface = argv[++i];
    else if (strcmp(a, "--can-bitrate") == 0) can_bitrate = atol(argv[++i]);
    else return usage();
  }
  if (!cfg.elf_path) return usage();
  char err[512];
  board *b = board_open(&cfg, err, sizeof err);
  if (!b) { fprintf(stderr, "dtc-board: %s\n", err); return 2; }
  hal_host_can_backend can = {0};
  if (can_iface) {
    int e = hal_host_socketcan_open(can_iface, &can);
    if (e != 0) {
      fprintf(stderr, "dtc-board: --can %s: %s%s\n", can_iface, strerror(-e),
              e == -97 ? " (this kernel has no CAN: run under User-Mode Linux, tests/can/uml/run_in_uml.sh)" : "");
      board_close(b);
      return 2;
    }
    board_can_attach(b, &can, can_bitrate > 0 ? (uint32_t)can_bitrate : 0u);
  }
  double w0 = wall();
  board_status st;
  if (realtime) { /* 1 ms of virtual time at a time, never ahead of the wall clock */
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    st = BOARD_TIME_UP;
    double t0 = board_time_s(b);
    while (st == BOARD_TIME_UP && !g_stop && board_time_s(b) - t0 < seconds - 1e-12) {
      double left = seconds - (board_time_s(b) - t0);
      st = board_run(b, left < 1e-3 ? left : 1e-3);
      double ahead = (board_time_s(b) - t0) - (wall() - w0);
      struct timespec ts = {0, 0};
      if (ahead > 0) ts = (struct timespec){(time_t)ahead, (long)((ahead - (double)(time_t)ahead) * 1e9)};
      if (can.wait_rx) /* in the socket: the bus model's polls of an idle socket then cost no system call */
        (void)can.wait_rx(can.ctx, &ts);
      else if (ahead > 0)
        nanosleep(&ts, NULL);
    }
  } else {
    st = board_run(b, seconds);
  }
  double w = wall() - w0;
  int rc = 0;
  if (st == BOARD_FAULT) { fprintf(stderr, "dtc-board: %s\n", board_message(b)); rc = 1; }
  else if (st == BOARD_EXITED) rc = board_exit_code(b);
  if (stats)
    fprintf(stderr, "dtc-board: %.6f s simulated in %.3f s wall (%.2f sim s per wall s), %llu instructions (%.1f M/s), "
            "HCLK %.3f MHz, %u resets\n", board_time_s(b), w, board_time_s(b) / (w > 0 ? w : 1e-9),
            (unsigned long long)board_instructions(b), (double)board_instructions(b) / (w > 0 ? w : 1e-9) / 1e6,
            board_core_hz(b) / 1e6, board_resets(b));
  if (stats) {
    board_irq_stat tick;
    board_irq_get(b, 16 + 18, &tick); /* ADC1_2: the image's control tick */
    fprintf(stderr, "dtc-board: control tick (ADC1_2): %llu interrupts, %.0f instructions mean, %llu worst\n",
            (unsigned long long)tick.count, tick.count ? (double)tick.total / (double)tick.count : 0.0,
            (unsigned long long)tick.worst);
  }
  if (stats) {
    board_can_status cs;
    board_can_get_status(b, &cs);
    if (cs.on_bus || cs.tx_frames || cs.tx_errors || cs.bus_offs)
      fprintf(stderr, "dtc-board: FDCAN1 %.0f bit/s (kernel %.3f MHz %s / %u / NBRP %u, %u tq), sample point %.1f %%;"
              " %llu frames out, %llu in, %llu filtered, %llu lost, %llu transmit errors, %llu bus-off\n",
              cs.timing.bitrate, cs.timing.kernel_hz / 1e6, cs.timing.kernel_src, cs.timing.ckdiv, cs.timing.prescaler,
              cs.timing.ntq, 100.0 * cs.timing.sample_point, (unsigned long long)cs.tx_frames,
              (unsigned long long)cs.rx_frames, (unsigned long long)cs.rx_rejected, (unsigned long long)cs.rx_lost,
              (unsigned long long)cs.tx_errors, (unsigned long long)cs.bus_offs);
  }
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
  if (can_iface) hal_host_socketcan_close(&can);
  return rc;
}
