/* `dtc-board run SCENARIO --elf FILE ...`: a dtc-sim scenario on the twin. The flashable image
 * runs on the emulated board whose HRTIM drives the plant and whose ADC converts its sensors;
 * the scenario's parser, trace and metrics are host_sim's (scenario*.c, trace.c, metrics*.c).
 *
 * Timeline: the image boots (clock, ADC calibration, 64 offset periods) with the plant attached
 * at standstill; once its control tick runs, the run command (controller, run, reference) is
 * given and the scenario's t = 0 is the next PWM period start. Tick k is the period starting at
 * t0 + k T: scenario events act at its start, the plant truth is taken there, the firmware
 * samples 4 us later, and its telemetry is read at mid-period after the tick interrupt, so the
 * telemetry of row k is from the sample of period k as in dtc-sim.
 *
 * Commands to the firmware: FDCAN is a placeholder in this branch (the CAN model is on branch
 * twin-can), so the controller choice, the run flag and the speed reference are written into
 * the firmware's RAM at g_drive's fields, the way a debugger would (TEST-ONLY path). The field
 * offsets are the host compiler's offsetof of the same header; the run refuses to start unless
 * the image's g_drive shows the expected layout (period_s and period_cycles of the defaults at
 * their offsets, and its tick counter advancing). */
#define _POSIX_C_SOURCE 200809L
#include "twin_run.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "board_twin/board.h"
#include "board_twin/can.h"
#include "board_twin/twin.h"
#include "dtc/drive.h"
#include "metrics.h"
#include "sim/scenario.h"
#include "sim/sim.h"
#include "trace.h"
#include "fw_layout.h"
#include "twin_params.h"

#define RPM_TO_RAD_S (3.14159265358979323846 / 30.0)
#define T_EPS 1e-9
#define EXC_ADC1_2 (16 + 18)
#define BOOT_LIMIT_S 0.5
#define MAX_SETS 64

static double wall(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct {
  board *b;
  uint32_t drv;  /* address of g_drive */
} fw;

static int rd(fw *f, size_t off, void *out, size_t n) { return board_read_mem(f->b, f->drv + (uint32_t)off, out, n); }

static uint32_t rd_u32(fw *f, size_t off) {
  uint32_t v = 0;
  rd(f, off, &v, 4);
  return v;
}

static float rd_f32(fw *f, size_t off) {
  float v = 0;
  rd(f, off, &v, 4);
  return v;
}

static void wr_f32(fw *f, size_t off, float v) {
  uint32_t u;
  memcpy(&u, &v, 4);
  board_write_u32(f->b, f->drv + (uint32_t)off, u);
}

/* Byte write inside a word (bools). */
static void wr_u8(fw *f, size_t off, uint8_t v) {
  uint32_t a = f->drv + (uint32_t)off, w = 0;
  board_read_u32(f->b, a & ~3u, &w);
  unsigned sh = (a & 3u) * 8u;
  w = (w & ~(0xFFu << sh)) | ((uint32_t)v << sh);
  board_write_u32(f->b, a & ~3u, w);
}

static const fw_layout *L;

/* A second node on the twin's CAN bus (hal_host's loopback backend): it acknowledges the image's
 * frames, as a bus with a master does, and keeps the emergency messages (0x081-0x0FF) it sees,
 * so the fault test checks the EMCY from the bus side. */
#define MAX_EMCY 32
typedef struct {
  hal_host_can_loopback q;
  hal_host_can_backend be;
  uint64_t frames;
  int n_emcy;
  struct { double t_s; uint16_t cob_id; uint16_t code; uint8_t reg; uint32_t faults; } emcy[MAX_EMCY];
} can_listener;

static void can_drain(board *b, can_listener *c, double t0) {
  hal_can_frame fr;
  while (hal_host_can_loopback_take(&c->q, &fr) == HAL_OK) {
    c->frames++;
    if (fr.id >= 0x081u && fr.id <= 0x0FFu && fr.dlc == 8u && c->n_emcy < MAX_EMCY) {
      int i = c->n_emcy++;
      c->emcy[i].t_s = board_time_s(b) - t0; /* seen by the listener at the latest now */
      c->emcy[i].cob_id = fr.id;
      c->emcy[i].code = (uint16_t)(fr.data[0] | (fr.data[1] << 8));
      c->emcy[i].reg = fr.data[2];
      c->emcy[i].faults = (uint32_t)fr.data[3] | ((uint32_t)fr.data[4] << 8) | ((uint32_t)fr.data[5] << 16) |
                          ((uint32_t)fr.data[6] << 24);
    }
  }
}

static can_listener g_can;

/* SIGINT/SIGTERM end a --realtime run after the tick in progress; the outputs are written. */
static volatile sig_atomic_t g_stop;
static void on_signal(int sig) { (void)sig; g_stop = 1; }

/* --realtime: hold the emulated clock (0 at wall time w0) to the wall clock. The twin runs faster
 * than real time, so it waits here; a run that fell behind (a busy machine) catches up at full
 * speed, so over any longer window the bus's timers keep their true periods. It looks at the
 * clock once per PACE_S of emulated time, and with a SocketCAN bus it waits in the socket's
 * wait_rx: from then on the bus model's polls of an idle socket cost no system call (in User-Mode
 * Linux a system call per frame slot and per tick held the twin to 0.6 x real time). A frame
 * that arrives ends the wait early: the twin is then at most PACE_S ahead of the wall clock. */
#define PACE_S 1e-3
typedef struct {
  double w0;                       /* wall time of emulated time 0 */
  double next_s;                   /* emulated time of the next look at the clock */
  const hal_host_can_backend *can; /* the SocketCAN bus, or NULL */
} pacer;

static void pace(board *b, pacer *p) {
  double t = board_time_s(b);
  if (t < p->next_s) return;
  p->next_s = t + PACE_S;
  double ahead = t - (wall() - p->w0);
  struct timespec sl = {0, 0};
  if (ahead > 0) sl = (struct timespec){(time_t)ahead, (long)((ahead - (double)(time_t)ahead) * 1e9)};
  if (p->can && p->can->wait_rx) {
    (void)p->can->wait_rx(p->can->ctx, &sl); /* a frame, the deadline or a signal ends it */
    return;
  }
  if (ahead > 0) nanosleep(&sl, NULL);
}

static void read_snapshot(fw *f, drive_snapshot *s) {
  /* seq + ctl_telemetry + floats: no enums, the same layout on both sides (checked by size) */
  for (int tries = 0; tries < 4; tries++) {
    rd(f, L->snap, s, sizeof *s);
    if (!(s->seq & 1u)) return;
  }
}

static int fail(char *err, size_t n, const char *fmt, const char *a) {
  snprintf(err, n, fmt, a);
  return 2;
}

static const char usage_text[] =
    "usage: dtc-board run SCENARIO --elf FILE [--controller ip|nominal|rbfn] [--csv OUT] [--metrics OUT]\n"
    "                  [--set SECTION.KEY=VALUE]... [--nvm FILE] [--fault-line T_S [--fault-irq-off]\n"
    "                  [--fault-pins both|eev6] [--fault-release T_S]] [--quiet] [--can IFACE --realtime]\n"
    "  --can IFACE        the image's FDCAN1 on SocketCAN interface IFACE (only with --realtime): tune\n"
    "                     the running drive with dtctune; without it a listening node on a private bus\n"
    "                     acknowledges the frames and records the EMCYs\n"
    "  --realtime         hold emulated time to the wall clock (the twin runs faster than real time\n"
    "                     and waits; the bus's heartbeats and inhibit times are then in true time);\n"
    "                     SIGINT/SIGTERM end the run cleanly\n"
    "  --fault-line T_S   test hook: the gate drivers' fault line (PB10 = HRTIM FLT3 and PB5 = HRTIM\n"
    "                     EEV6, tied on the interface board) is pulled low at scenario time T_S and\n"
    "                     held; the metrics gain a \"fault\" section\n"
    "  --fault-irq-off    with --fault-line: the HRTIM1_FLT interrupt's NVIC enable is cleared (as by a\n"
    "                     debugger) just before the line falls, so only the hardware acts on the gates\n"
    "  --fault-pins eev6  with --fault-line: only PB5 (EEV6) goes low, PB10 (FLT3) stays high: a broken\n"
    "                     link between the two pins or a stuck PB5 (default both: the line)\n"
    "  --fault-release T_S  with --fault-line: the line goes high again at scenario time T_S and 2 ms\n"
    "                     later the faults are cleared as the background would on a CAN request: the\n"
    "                     drive restarts (gate re-enable after a trip)\n";

int twin_run_main(int argc, char **argv) {
  const char *path = NULL, *elf = NULL, *csv = NULL, *metrics_path = NULL, *nvm = NULL, *ctl_name = NULL;
  const char *can_iface = NULL;
  int realtime = 0;
  const char *sets[MAX_SETS];
  L = fw_layout_get();
  if (L->snap_size != sizeof(drive_snapshot)) { fprintf(stderr, "dtc-board: drive_snapshot layout differs\n"); return 1; }
  int n_sets = 0, quiet = 0, fault_irq_off = 0, fault_eev6_only = 0;
  double fault_t = -1, release_t = -1;
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    if (strcmp(a, "--quiet") == 0) { quiet = 1; continue; }
    if (strcmp(a, "--realtime") == 0) { realtime = 1; continue; }
    if (strcmp(a, "--fault-irq-off") == 0) { fault_irq_off = 1; continue; }
    if (a[0] != '-' && !path) { path = a; continue; }
    if (i + 1 >= argc) { fputs(usage_text, stderr); return 2; }
    const char *v = argv[++i];
    if (strcmp(a, "--elf") == 0) elf = v;
    else if (strcmp(a, "--csv") == 0) csv = v;
    else if (strcmp(a, "--metrics") == 0) metrics_path = v;
    else if (strcmp(a, "--nvm") == 0) nvm = v;
    else if (strcmp(a, "--controller") == 0) ctl_name = v;
    else if (strcmp(a, "--can") == 0) can_iface = v;
    else if (strcmp(a, "--fault-line") == 0) fault_t = atof(v);
    else if (strcmp(a, "--fault-release") == 0) release_t = atof(v);
    else if (strcmp(a, "--fault-pins") == 0) {
      if (strcmp(v, "both") == 0) fault_eev6_only = 0;
      else if (strcmp(v, "eev6") == 0) fault_eev6_only = 1;
      else { fprintf(stderr, "dtc-board: --fault-pins: 'both' or 'eev6', got '%s'\n", v); return 2; }
    }
    else if (strcmp(a, "--set") == 0) {
      if (n_sets >= MAX_SETS) { fprintf(stderr, "dtc-board: too many --set options\n"); return 2; }
      sets[n_sets++] = v;
    } else { fputs(usage_text, stderr); return 2; }
  }
  if (!path || !elf) { fputs(usage_text, stderr); return 2; }
  if (release_t >= 0 && !(fault_t >= 0 && release_t > fault_t)) {
    fprintf(stderr, "dtc-board: --fault-release needs --fault-line before it\n");
    return 2;
  }
  if (can_iface && !realtime) { fprintf(stderr, "dtc-board: --can needs --realtime (a bus has a clock)\n"); return 2; }

  static scenario sc;
  char err[1536];
  scenario_default(&sc);
  if (scenario_parse_file(&sc, path, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 2; }
  for (int i = 0; i < n_sets; i++)
    if (scenario_set(&sc, sets[i], err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 2; }
  if (scenario_finish(&sc, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 2; }
  int controller = sc.controller;
  if (ctl_name) {
    controller = scenario_controller_parse(ctl_name);
    if (controller < 0) { fprintf(stderr, "dtc-board: --controller: unknown controller '%s'\n", ctl_name); return 2; }
  }
  if (sc.plant.supply != PLANT_SUPPLY_INVERTER) { fprintf(stderr, "dtc-board: %s: the twin needs the inverter supply\n", path); return 2; }
  if (fabs(sc.period_s - 200e-6) > 1e-9) {
    fprintf(stderr, "dtc-board: %s: period_s %g: the image's tick is fixed at 200 us\n", path, sc.period_s);
    return 2;
  }
  (void)fail;

  board_config cfg;
  board_config_default(&cfg);
  cfg.elf_path = elf;
  cfg.nvm_path = nvm;
  board *b = board_open(&cfg, err, sizeof err);
  if (!b) { fprintf(stderr, "dtc-board: %s\n", err); return 2; }
  int rc = 0;
  /* [control] keys: into the image's parameter store before power-on, as dtctune set + save */
  int prc = twin_apply_control(b, &sc, err, sizeof err);
  if (prc != 0) { fprintf(stderr, "dtc-board: %s\n", err); board_close(b); return prc; }
  if (board_attach_plant(b, &sc.plant) != 0) { fprintf(stderr, "dtc-board: %s: invalid plant configuration\n", path); board_close(b); return 2; }
  memset(&g_can, 0, sizeof g_can);
  hal_host_can_loopback_init(&g_can.q, &g_can.be);
  hal_host_can_backend sock;
  memset(&sock, 0, sizeof sock);
  if (can_iface) {
    int e = hal_host_socketcan_open(can_iface, &sock);
    if (e != 0) {
      fprintf(stderr, "dtc-board: --can %s: %s%s\n", can_iface, strerror(-e),
              e == -EAFNOSUPPORT ? " (this kernel has no CAN: run under User-Mode Linux, tests/can/uml/run_in_uml.sh)" : "");
      board_close(b);
      return 2;
    }
    board_can_attach(b, &sock, 0u);
  } else {
    board_can_attach(b, &g_can.be, 0u);
  }
  if (realtime) {
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
  }
  fw f = {b, 0};
  uint32_t size = 0;
  if (board_symbol(b, "g_drive", &f.drv, &size) != 0) { fprintf(stderr, "dtc-board: %s has no g_drive symbol\n", elf); board_close(b); return 2; }

  double w0 = wall();
  pacer pc = {w0, 0.0, can_iface ? &sock : NULL};
  /* boot until the control tick runs with valid offsets (its tick counter advances) */
  uint32_t tick0 = 0;
  double T = sc.period_s;
  for (;;) {
    board_status st = board_run(b, 1e-3);
    if (realtime) pace(b, &pc);
    if (st == BOARD_FAULT) { fprintf(stderr, "dtc-board: %s\n", board_message(b)); board_close(b); return 1; }
    if (st == BOARD_EXITED) { fprintf(stderr, "dtc-board: the image exited (%d) during boot\n", board_exit_code(b)); board_close(b); return 1; }
    uint32_t tick = rd_u32(&f, L->tick);
    if (tick0 == 0 && tick > 0) tick0 = tick;
    if (tick0 && tick >= tick0 + 5u) break;
    if (board_time_s(b) > BOOT_LIMIT_S) {
      board_irq_stat st;
      board_irq_get(b, EXC_ADC1_2, &st);
      uint32_t bf = 0;
      board_read_symbol(b, "g_board_faults", 0, &bf);
      fprintf(stderr, "dtc-board: the image's control tick did not start within %.1f s (%llu ADC interrupts, board "
              "faults 0x%X, g_drive.tick %u)\n", BOOT_LIMIT_S, (unsigned long long)st.count, bf, tick);
      board_close(b);
      return 1;
    }
  }
  /* layout check of the test-only RAM path */
  float per = rd_f32(&f, L->cfg_period_s);
  uint32_t per_cyc = rd_u32(&f, L->period_cycles);
  if (fabsf(per - 200e-6f) > 1e-9f || per_cyc != 34000u) {
    fprintf(stderr, "dtc-board: g_drive layout differs from the host's dtc/drive.h (period_s %g, period_cycles %u): "
                    "cannot command the image through RAM\n", (double)per, per_cyc);
    board_close(b);
    return 1;
  }
  /* the command, as the background would apply it: controller (both copies), clear faults, run */
  if (L->speed_mode_size != 1) { fprintf(stderr, "dtc-board: unexpected speed_mode size %zu\n", L->speed_mode_size); board_close(b); return 1; }
  for (int c = 0; c < 2; c++) wr_u8(&f, L->cfg_speed_mode + (size_t)c * L->cfg_size, (uint8_t)controller);
  double period = 0;
  double t0 = board_pwm_period_start(b, &period);
  if (t0 < 0 || fabs(period - T) > 1e-9) { fprintf(stderr, "dtc-board: PWM period %g s differs from the scenario's %g s\n", period, T); board_close(b); return 1; }
  while (t0 < board_time_s(b) + 1e-9) t0 += T;
  board_run(b, t0 - 20e-6 - board_time_s(b)); /* just before the period: the command is seen by its tick */
  wr_u8(&f, L->clear_faults_req, 1);
  wr_u8(&f, L->run, 1);

  metrics_acc acc;
  if (metrics_acc_init(&acc, &sc, T) != 0) { fprintf(stderr, "dtc-board: out of memory\n"); board_close(b); return 1; }
  sim_trace trace;
  bool trace_open_ok = false;
  if (csv) {
    if (trace_open(&trace, csv, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); metrics_acc_free(&acc); board_close(b); return 2; }
    trace_open_ok = true;
  }
  const plant_motor_params m0 = sc.plant.motor;
  scenario_event events[SCENARIO_MAX_ENTRIES * 4];
  int n_events = sc.n_events < (int)(sizeof events / sizeof events[0]) ? sc.n_events : (int)(sizeof events / sizeof events[0]);
  memcpy(events, sc.events, (size_t)n_events * sizeof events[0]);
  for (int i = 1; i < n_events; i++)
    for (int j = i; j > 0 && events[j].t_s < events[j - 1].t_s; j--) { scenario_event x = events[j]; events[j] = events[j - 1]; events[j - 1] = x; }
  const uint64_t n_ticks = (uint64_t)llround(sc.duration_s / T);
  const uint64_t trace_every = (uint64_t)llround(sc.trace_interval_s / T) > 0 ? (uint64_t)llround(sc.trace_interval_s / T) : 1u;
  int ev_i = 0, load_i = 0;
  double last_ref = NAN;
  bool fault_done = false;
  int release_step = 0; /* 1: line high again, 2: faults cleared */
  const double release_clear_s = 2e-3; /* the core sees the line high for a tick before the clear */
  double fault_board_t = -1;
  uint32_t faults_after = 0;
  drive_snapshot snap;
  memset(&snap, 0, sizeof snap);
  uint64_t k = 0;
  for (;; k++) {
    double tk = t0 + (double)k * T, ts = (double)k * T;
    board_status st = board_run(b, tk - board_time_s(b));
    if (st != BOARD_TIME_UP) { fprintf(stderr, "dtc-board: at t = %.4f s: %s\n", ts, st == BOARD_FAULT ? board_message(b) : "the image exited"); rc = 1; break; }
    plant_state *ps = board_plant(b);
    plant_truth tr;
    plant_get_truth(ps, &tr);
    while (ev_i < n_events && events[ev_i].t_s <= ts + T_EPS) {
      const scenario_event *ev = &events[ev_i++];
      if (ev->kind == SCENARIO_EV_J) plant_set_inertia(ps, m0.J_kgm2 * ev->factor);
      else if (ev->kind == SCENARIO_EV_B) plant_set_friction(ps, m0.B_Nms * ev->factor);
      else if (ev->kind == SCENARIO_EV_RS) plant_set_rs(ps, m0.Rs_ohm * ev->factor);
      else if (ev->kind == SCENARIO_EV_RR) plant_set_rr(ps, m0.Rr_ohm * ev->factor);
    }
    while (load_i < sc.n_load && sc.load[load_i].t_s <= ts + T_EPS) plant_set_load(ps, sc.load[load_i++].nm);
    double ref = scenario_ref_rpm(&sc, ts + T_EPS);
    if (ref != last_ref) wr_f32(&f, L->speed_ref_rad_s, (float)(ref * RPM_TO_RAD_S));
    last_ref = ref;
    if (fault_t >= 0 && !fault_done && ts + T_EPS >= fault_t) {
      /* at the first instant (2 us steps, from the end of the sampling keep-out) where an outer
       * switch (S1 or S4) conducts, so the trip shows the outer-before-inner order */
      board_run(b, 10e-6);
      for (int n = 0; n < 20000 && !(board_gate_levels(b) & 0x999u); n++) board_run(b, 2e-6);
      board_la_mark(b);
      fault_board_t = board_time_s(b);
      if (fault_irq_off) board_nvic_disable(b, 73); /* HRTIM1_FLT: the software back-up stage cannot run */
      if (fault_eev6_only) board_drive_pin(b, 'B', 5, 0);
      else board_drive_fault_line(b, 0);
      fault_done = true;
      while (tk + 0.75 * T < board_time_s(b)) { tk += T; ts += T; k++; } /* ticks spent searching: not sampled */
      board_run(b, tk + 0.75 * T - board_time_s(b));
    } else {
      if (fault_done && release_step == 0 && ts + T_EPS >= release_t && release_t >= 0) {
        if (fault_eev6_only) board_drive_pin(b, 'B', 5, 1);
        else board_drive_fault_line(b, 1);
        release_step = 1;
      }
      if (release_step == 1 && ts + T_EPS >= release_t + release_clear_s) {
        wr_u8(&f, L->clear_faults_req, 1); /* as drive_co does for a fault reset */
        release_step = 2;
      }
      board_run(b, 0.75 * T); /* after the tick interrupt of this period */
    }
    if (b && board_time_s(b) < tk + 0.75 * T - 1e-9) { fprintf(stderr, "dtc-board: %s\n", board_message(b)); rc = 1; break; }
    read_snapshot(&f, &snap);
    can_drain(b, &g_can, t0);
    if (fault_done && faults_after == 0) faults_after = snap.tel.faults;
    double eps_t = (-ps->cfg.motor.B_Nms / ps->cfg.motor.J_kgm2 + m0.B_Nms / m0.J_kgm2) * tr.omega_m_rad_s +
                   (1.0 / ps->cfg.motor.J_kgm2 - 1.0 / m0.J_kgm2) * tr.te_Nm - ps->t_load_Nm / ps->cfg.motor.J_kgm2;
    if (!isfinite(tr.omega_m_rad_s) || !isfinite(tr.ia_A)) { fprintf(stderr, "dtc-board: the plant diverged at t = %.4f s\n", ts); rc = 1; break; }
    metrics_sample ms = {
        .t_s = ts, .speed_rpm = tr.omega_m_rad_s / RPM_TO_RAD_S, .ref_rpm = ref,
        .est_rpm = (double)snap.tel.omega_est_rad_s / RPM_TO_RAD_S, .te_nm = tr.te_Nm,
        .is_sq = tr.ia_A * tr.ia_A + tr.ib_A * tr.ib_A + tr.ic_A * tr.ic_A, .eps_hat = (double)snap.tel.eps_hat,
        .eps_true = eps_t, .np_dev_v = fabs(tr.vc1_V - tr.vc2_V), .w_norm = (double)snap.tel.w_norm,
        .switch_count = ps->switch_count,
    };
    metrics_acc_add(&acc, &ms);
    if (trace_open_ok && k % trace_every == 0u) {
      sim_trace_row row = {ts, tr.omega_m_rad_s, tr.te_Nm, tr.ia_A, tr.ib_A, tr.ic_A, tr.vc1_V, tr.vc2_V, ref, ps->t_load_Nm, eps_t, &snap};
      trace_write(&trace, &row);
    }
    if (k >= n_ticks || g_stop) break;
    if (realtime) pace(b, &pc);
  }
  double w = wall() - w0;

  if (rc == 0) {
    sim_metrics m;
    memset(&m, 0, sizeof m);
    metrics_acc_finish(&acc, &m);
    m.firmware = true;
    snprintf(m.controller, sizeof m.controller, "%s", scenario_controller_name(controller));
    m.np_dev_limit_v = 0.02 * sc.plant.dc.vdc_V;
    uint32_t active = rd_u32(&f, L->cfg_active) & 1u;
    m.m_w = (double)rd_f32(&f, L->cfg_rbfn_m_w + active * L->cfg_size);
    m.faults = snap.tel.faults;
    board_irq_stat tick;
    board_irq_get(b, EXC_ADC1_2, &tick);
    m.isr_max_us = (double)tick.worst / 170.0; /* one instruction per cycle at 170 MHz */
    m.isr_overruns = rd_u32(&f, L->timing_overruns);
    m.sim_seconds = (double)k * T;
    m.wall_seconds = w;
    if (metrics_path) {
      if (sim_write_metrics_json(&m, metrics_path, err, sizeof err) != SIM_OK) { fprintf(stderr, "%s\n", err); rc = 1; }
      else rc = twin_metrics_extend(b, metrics_path, &m, fault_board_t >= 0 ? fault_board_t - t0 : -1.0, faults_after,
                                    err, sizeof err);
      if (rc) fprintf(stderr, "%s\n", err);
    }
    if (!quiet)
      printf("%s on the twin: %.3f s simulated in %.1f s wall (%.2f x real time%s); final %.1f rpm, recovery %.4f s, "
             "steady error %.3f rpm, estimate error %.3f rpm, switching %.0f Hz, tick %.0f instructions mean / %llu worst\n",
             m.controller, m.sim_seconds, w, m.sim_seconds / (w > 0 ? w : 1e-9), realtime ? ", paced by --realtime" : "",
             m.speed_final_rpm, m.recovery_time_s,
             m.steady_error_rpm, m.speed_est_error_rpm, m.switching_freq_hz,
             tick.count ? (double)tick.total / (double)tick.count : 0.0, (unsigned long long)tick.worst);
  }
  if (trace_open_ok && trace_close(&trace, rc == 0, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); rc = 1; }
  metrics_acc_free(&acc);
  board_close(b);
  if (can_iface) hal_host_socketcan_close(&sock);
  return rc;
}

/* The twin's own measurements, added to dtc-sim's metrics JSON as "board". */
int twin_metrics_extend(board *b, const char *path, const sim_metrics *m, double fault_t, uint32_t faults_after,
                        char *err, size_t n) {
  (void)m;
  FILE *fp = fopen(path, "rb");
  if (!fp) { snprintf(err, n, "%s: cannot reopen", path); return 1; }
  fseek(fp, 0, SEEK_END);
  long len = ftell(fp);
  fseek(fp, 0, SEEK_SET);
  char *text = calloc(1, (size_t)len + 1);
  size_t got = fread(text, 1, (size_t)len, fp);
  fclose(fp);
  text[got] = 0;
  cJSON *root = cJSON_Parse(text);
  free(text);
  if (!root) { snprintf(err, n, "%s: cannot parse the metrics", path); return 1; }
  cJSON *bd = cJSON_AddObjectToObject(root, "board");
  board_la_stats la;
  board_la_get(b, &la);
  static const char *names[12] = {"a_S1", "a_S3", "a_S2", "a_S4", "b_S1", "b_S3", "b_S2", "b_S4", "c_S1", "c_S3", "c_S2", "c_S4"};
  cJSON *sw = cJSON_AddObjectToObject(bd, "switches");
  for (int o = 0; o < 12; o++) {
    cJSON *s = cJSON_AddObjectToObject(sw, names[o]);
    cJSON_AddNumberToObject(s, "on_edges", (double)la.on_edges[o]);
    cJSON_AddNumberToObject(s, "off_edges", (double)la.off_edges[o]);
    cJSON_AddNumberToObject(s, "on_time_s", la.on_time_s[o]);
    cJSON_AddNumberToObject(s, "min_on_s", isfinite(la.min_on_s[o]) ? la.min_on_s[o] : -1.0);
    cJSON_AddNumberToObject(s, "min_off_s", isfinite(la.min_off_s[o]) ? la.min_off_s[o] : -1.0);
  }
  cJSON_AddNumberToObject(bd, "min_dead_time_s", isfinite(la.min_dead_time_s) ? la.min_dead_time_s : -1.0);
  cJSON_AddNumberToObject(bd, "max_dead_time_s", la.max_dead_time_s);
  cJSON_AddNumberToObject(bd, "dead_time_events", (double)la.dead_time_events);
  cJSON *v = cJSON_AddObjectToObject(bd, "violations");
  cJSON_AddNumberToObject(v, "pair_overlap", (double)la.overlaps);
  cJSON_AddNumberToObject(v, "pn_step", (double)la.pn_steps);
  cJSON_AddNumberToObject(v, "bad_combination", (double)la.bad_combinations);
  cJSON_AddNumberToObject(v, "total", (double)(la.overlaps + la.pn_steps + la.bad_combinations));
  board_current_sampling cs;
  board_current_sampling_get(b, &cs);
  cJSON *smp = cJSON_AddObjectToObject(bd, "current_sampling");
  cJSON_AddNumberToObject(smp, "triggers", (double)cs.triples);
  cJSON_AddNumberToObject(smp, "max_skew_s", cs.max_skew_s);
  cJSON_AddNumberToObject(smp, "ia_after_trigger_s", cs.after_trigger_s[0]);
  cJSON_AddNumberToObject(smp, "ib_after_trigger_s", cs.after_trigger_s[1]);
  cJSON_AddNumberToObject(smp, "ic_after_trigger_s", cs.after_trigger_s[2]);
  cJSON *irq = cJSON_AddObjectToObject(bd, "interrupt_instructions");
  for (int e = 1; e < 16 + 102; e++) {
    board_irq_stat st;
    board_irq_get(b, e, &st);
    if (!st.count) continue;
    char key[32];
    if (e == EXC_ADC1_2) snprintf(key, sizeof key, "ADC1_2 (control tick)");
    else if (e == 16 + 73) snprintf(key, sizeof key, "HRTIM1_FLT");
    else if (e == 15) snprintf(key, sizeof key, "SysTick");
    else snprintf(key, sizeof key, "exception %d", e);
    cJSON *s = cJSON_AddObjectToObject(irq, key);
    cJSON_AddNumberToObject(s, "count", (double)st.count);
    cJSON_AddNumberToObject(s, "mean", (double)st.total / (double)st.count);
    cJSON_AddNumberToObject(s, "worst", (double)st.worst);
    cJSON_AddNumberToObject(s, "best", (double)st.best);
  }
  cJSON *can = cJSON_AddObjectToObject(bd, "can");
  cJSON_AddNumberToObject(can, "frames_out", (double)g_can.frames);
  cJSON *em = cJSON_AddArrayToObject(can, "emcy");
  for (int i = 0; i < g_can.n_emcy; i++) {
    cJSON *e = cJSON_CreateObject();
    cJSON_AddNumberToObject(e, "t_s", g_can.emcy[i].t_s);
    cJSON_AddNumberToObject(e, "cob_id", g_can.emcy[i].cob_id);
    cJSON_AddNumberToObject(e, "code", g_can.emcy[i].code);
    cJSON_AddNumberToObject(e, "error_register", g_can.emcy[i].reg);
    cJSON_AddNumberToObject(e, "faults", (double)g_can.emcy[i].faults);
    cJSON_AddItemToArray(em, e);
  }
  cJSON_AddNumberToObject(bd, "sim_seconds_per_wall_second", m->wall_seconds > 0 ? m->sim_seconds / m->wall_seconds : 0.0);
  uint32_t bf = 0;
  board_read_symbol(b, "g_board_faults", 0, &bf); /* the binding's fault word (board.h) */
  if (fault_t >= 0) {
    cJSON *ft = cJSON_AddObjectToObject(bd, "fault");
    cJSON_AddNumberToObject(ft, "line_low_at_s", fault_t);
    double outer = -1, inner = -1;
    int outer_on = 0, inner_on = 0;
    for (int o = 0; o < 12; o++) {
      if (!((la.on_at_mark >> o) & 1u)) continue;
      bool is_outer = ((0x999u >> o) & 1u) != 0; /* S1, S4 (switch order: 4 x leg + 0 / 3) */
      double dt = la.off_after_mark_s[o] >= 0 ? la.off_after_mark_s[o] - la.mark_s : INFINITY;
      if (is_outer) { outer_on++; if (dt > outer) outer = dt; }
      else { inner_on++; if (dt > inner) inner = dt; }
    }
    cJSON_AddNumberToObject(ft, "outer_on_at_fault", outer_on);
    cJSON_AddNumberToObject(ft, "inner_on_at_fault", inner_on);
    cJSON_AddNumberToObject(ft, "outer_off_after_s", isfinite(outer) ? outer : -1.0);
    cJSON_AddNumberToObject(ft, "inner_off_after_s", isfinite(inner) ? inner : -1.0);
    cJSON_AddNumberToObject(ft, "telemetry_faults_after", (double)faults_after);
    cJSON_AddNumberToObject(ft, "board_faults", (double)bf);
  }
  char *out = cJSON_Print(root);
  cJSON_Delete(root);
  fp = fopen(path, "wb");
  if (!fp) { free(out); snprintf(err, n, "%s: cannot rewrite", path); return 1; }
  fputs(out, fp);
  fputc('\n', fp);
  fclose(fp);
  free(out);
  return 0;
}
