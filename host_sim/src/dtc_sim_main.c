/**
 * @file dtc_sim_main.c
 * @brief The `dtc-sim` command line: run a scenario, or benchmark the engine.
 *
 * Exit status: 0 success, 1 runtime failure, 2 bad input (usage, scenario,
 * --set, output path, CAN interface, NVM file). Every bad-input message is
 * ONE line on stderr: "FILE:LINE: problem", "--set section.key: problem" or
 * "dtc-sim: problem".
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sim/decimal.h"
#include "sim/file_safety.h"
#include "sim/sim.h"

#ifndef DTC_SOURCE_DIR
#define DTC_SOURCE_DIR "."
#endif

#define MAX_SETS 64

static volatile sig_atomic_t g_stop; /* set by SIGINT/SIGTERM */

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

static const char usage[] =
    "usage:\n"
    "  dtc-sim run FILE [options]   run a scenario (INI, see docs/scenarios.md)\n"
    "  dtc-sim bench [FILE]         run FILE three times and print the best speed\n"
    "  dtc-sim --help               this text\n"
    "\n"
    "run options:\n"
    "  --controller NAME     ip | nominal | rbfn (overrides [controller] name)\n"
    "  --csv OUT.csv         write the trace (one row per [sim] trace_interval_s)\n"
    "  --metrics OUT.json    write the metrics\n"
    "  --start-delay SECONDS keep the drive stopped (no run command) for SECONDS (0..600)\n"
    "  --record-samples OUT.rec\n"
    "                        record every control tick's interrupt inputs and outputs\n"
    "                        (binary, docs/pil.md) for the PIL replay (tools/pil_bench.sh)\n"
    "  --set SECTION.KEY=VALUE\n"
    "                        override a scenario key (repeatable); for a repeated key\n"
    "                        (reference.step, load.step, events.J_scale, metrics.window, ...)\n"
    "                        the whole list is replaced by this one entry\n"
    "  --duration SECONDS    override [sim] duration_s; with --realtime, 'inf' or 0 runs\n"
    "                        until SIGINT/SIGTERM (then the outputs are written, exit 0)\n"
    "  --realtime            pace the ticks to the wall clock (absolute deadlines)\n"
    "  --can IFACE           bind the drive's CAN to SocketCAN interface IFACE\n"
    "                        (only with --realtime; without it nothing touches CAN)\n"
    "  --nvm FILE            mirror the drive's non-volatile memory to FILE (a 4096-byte\n"
    "                        image; created on the first write; survives restarts)\n"
    "  --quiet               no summary on stdout\n"
    "\n"
    "Numbers are decimal (500, -0.25, .5, 2e-3): no hexadecimal, no inf or nan\n"
    "(except --duration inf). A value that does not fit (a --duration of more than\n"
    "48 characters, a --set key of more than 127, a value of more than 255) is\n"
    "refused, never cut short.\n"
    "\n"
    "Outputs are written as OUT.partial (the NVM image as FILE.tmp) and renamed when\n"
    "the run succeeds; a failed run leaves no output behind. dtc-sim never removes or\n"
    "truncates a file it did not create: an output that is the scenario, another\n"
    "output or another's temporary, or whose temporary exists already, is refused\n"
    "(exit 2) before anything is written. Ctrl-C ends a --realtime run cleanly; it\n"
    "abandons a batch run (exit 1, no outputs).\n"
    "\n"
    "bench: FILE defaults to host_sim/scenarios/case2.ini in the source tree when it\n"
    "exists, else a built-in 5 s inverter-fed run at the 200 us tick with a rotating\n"
    "open-loop vector sequence (plant and engine only). The last line reads\n"
    "  'S s simulated in W s wall: Nx real time'.\n"
    "\n"
    "exit status: 0 success, 1 runtime failure, 2 bad input.\n";

static int bad_usage(const char *fmt, const char *arg)
{
    fprintf(stderr, "dtc-sim: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, " (see dtc-sim --help)\n");
    return SIM_EINPUT;
}

/* Load FILE, apply --set overrides and finish. */
static int load_scenario(scenario *sc, const char *file, char **sets, int n_sets)
{
    char err[2048];
    scenario_default(sc);
    if (file != NULL && scenario_parse_file(sc, file, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return SIM_EINPUT;
    }
    for (int i = 0; i < n_sets; i++)
        if (scenario_set(sc, sets[i], err, sizeof err) != 0) {
            fprintf(stderr, "%s\n", err);
            return SIM_EINPUT;
        }
    if (scenario_finish(sc, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return SIM_EINPUT;
    }
    return SIM_OK;
}

static void print_summary(const char *file, const scenario *sc, const sim_result *r)
{
    const sim_metrics *m = &r->metrics;
    printf("%s: %s supply, controller %s\n", file, sc->plant.supply == PLANT_SUPPLY_SINE ? "sine" : "inverter",
           m->controller);
    printf("  %.3f s simulated in %.3f s wall (%.0fx real time), %llu ticks\n", m->sim_seconds, m->wall_seconds,
           m->wall_seconds > 0.0 ? m->sim_seconds / m->wall_seconds : 0.0, (unsigned long long)r->ticks);
    printf("  final (last 0.1 s): speed %.2f rpm, torque %.2f N m, stator current %.2f A rms\n", m->speed_final_rpm,
           m->te_final_nm, m->is_rms_final_a);
    printf("  true speed at the end %.2f rpm, largest |true speed| %.2f rpm", m->speed_true_end_rpm,
           m->speed_true_max_abs_rpm);
    if (m->firmware)
        printf(" (runaway limit %.0f rpm)%s", m->runaway_limit_rpm, m->runaway ? ": RUNAWAY" : "");
    printf("\n");
    for (int i = 0; i < m->n_windows; i++)
        if (m->windows[i].valid)
            printf("  window %s: speed %.2f rpm, stator current %.2f A rms\n", m->windows[i].name,
                   m->windows[i].speed_rpm, m->windows[i].is_rms_a);
    if (m->firmware)
        printf("  steady error %.2f rpm, speed estimate error %.2f rpm (last 0.5 s)\n", m->steady_error_rpm,
               m->speed_est_error_rpm);
    if (m->has_rise)
        printf("  rise time (10-90 %%) %.4f s\n", m->rise_time_s);
    if (m->has_disturbance && m->firmware)
        printf("  disturbance at %.3f s: max dip %.2f rpm, recovery %.3f s%s\n", m->disturbance_t_s,
               m->max_dip_rpm, m->recovery_time_s, m->recovered ? "" : " (not recovered)");
    if (m->firmware && m->has_steady_window)
        printf("  after %.2f s: NP deviation max %.2f V (limit %.2f V), switching %.0f Hz\n", m->startup_end_s,
               m->np_dev_max_v, m->np_dev_limit_v, m->switching_freq_hz);
    if (m->firmware)
        printf("  eps_hat %.1f, eps_true %.1f rad/s^2, |W| max %.3g (M_w %.3g), faults 0x%02x, ISR max %.1f us\n",
               m->eps_hat_final, m->eps_true, m->w_norm_max, m->m_w, (unsigned)m->faults, m->isr_max_us);
    if (m->firmware && m->warnings_seen != 0u)
        printf("  warnings seen during the run 0x%02x (docs/faults.md)\n", (unsigned)m->warnings_seen);
}

static int cmd_run(int argc, char **argv)
{
    const char *file = NULL;
    char *sets[MAX_SETS];
    int n_sets = 0;
    sim_options o;
    sim_options_default(&o);
    const char *duration = NULL;
    bool quiet = false;

    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        bool has_next = i + 1 < argc;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            fputs(usage, stdout);
            return SIM_OK;
        } else if (strcmp(a, "--realtime") == 0) {
            o.realtime = true;
        } else if (strcmp(a, "--quiet") == 0) {
            quiet = true;
        } else if (strcmp(a, "--controller") == 0 || strcmp(a, "--csv") == 0 || strcmp(a, "--metrics") == 0 ||
                   strcmp(a, "--set") == 0 || strcmp(a, "--can") == 0 || strcmp(a, "--nvm") == 0 ||
                   strcmp(a, "--record-samples") == 0 || strcmp(a, "--start-delay") == 0 ||
                   strcmp(a, "--duration") == 0) {
            if (!has_next)
                return bad_usage("%s needs a value", a);
            const char *v = argv[++i];
            if (strcmp(a, "--controller") == 0) {
                o.controller = scenario_controller_parse(v);
                if (o.controller < 0)
                    return bad_usage("--controller: unknown controller '%s' (expected ip, nominal or rbfn)", v);
            } else if (strcmp(a, "--csv") == 0) {
                o.csv_path = v;
            } else if (strcmp(a, "--metrics") == 0) {
                o.metrics_path = v;
            } else if (strcmp(a, "--can") == 0) {
                o.can_iface = v;
            } else if (strcmp(a, "--nvm") == 0) {
                o.nvm_path = v;
            } else if (strcmp(a, "--record-samples") == 0) {
                o.record_path = v;
            } else if (strcmp(a, "--start-delay") == 0) {
                if (!sim_parse_decimal(v, &o.start_delay_s) || !(o.start_delay_s >= 0.0 && o.start_delay_s <= 600.0))
                    return bad_usage("--start-delay: '%s' is not a time in 0..600 s", v);
            } else if (strcmp(a, "--duration") == 0) {
                duration = v;
            } else {
                if (n_sets >= MAX_SETS)
                    return bad_usage("too many --set options (at most %s)", "64");
                sets[n_sets++] = argv[i];
            }
        } else if (a[0] == '-' && a[1] != '\0') {
            return bad_usage("unknown option '%s'", a);
        } else if (file == NULL) {
            file = a;
        } else {
            return bad_usage("unexpected argument '%s'", a);
        }
    }
    if (file == NULL)
        return bad_usage("run needs a scenario FILE%s", "");
    if (o.can_iface != NULL && !o.realtime)
        return bad_usage("--can %s requires --realtime", o.can_iface);
    /* Outputs and their temporaries (the suffixes of trace.c, metrics_json.c,
     * tick_recorder.c and the host board's NVM mirror): new names or regular
     * files, never the scenario, never each other, never an existing
     * temporary, all checked before anything is opened for writing. */
    const sim_output outputs[] = {
        { "--csv", o.csv_path, ".partial" },
        { "--metrics", o.metrics_path, ".partial" },
        { "--record-samples", o.record_path, ".partial" },
        { "--nvm", o.nvm_path, ".tmp" },
    };
    char why[2400];
    if (!sim_outputs_allowed(file, outputs, sizeof outputs / sizeof outputs[0], why, sizeof why))
        return bad_usage("%s", why);

    char dur_set[64];
    if (duration != NULL) {
        if (strcmp(duration, "inf") == 0 || strcmp(duration, "0") == 0) {
            if (!o.realtime)
                return bad_usage("--duration %s (run until a signal) requires --realtime", duration);
            o.run_forever = true;
        } else {
            if (n_sets >= MAX_SETS)
                return bad_usage("too many --set options (at most %s)", "64");
            int n = snprintf(dur_set, sizeof dur_set, "sim.duration_s=%s", duration);
            if (n < 0 || (size_t)n >= sizeof dur_set)
                return bad_usage("--duration: '%.40s...' is longer than 48 characters", duration);
            double seconds;
            if (!sim_parse_decimal(duration, &seconds))
                return bad_usage("--duration: '%s' is not a decimal number of seconds (or inf)", duration);
            sets[n_sets++] = dur_set;
        }
    }

    scenario *sc = malloc(sizeof *sc);
    if (sc == NULL) {
        fprintf(stderr, "dtc-sim: out of memory\n");
        return SIM_ERUNTIME;
    }
    int rc = load_scenario(sc, file, sets, n_sets);
    if (rc != SIM_OK) {
        free(sc);
        return rc;
    }

    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    o.stop = &g_stop;

    sim_result *res = malloc(sizeof *res);
    if (res == NULL) {
        free(sc);
        fprintf(stderr, "dtc-sim: out of memory\n");
        return SIM_ERUNTIME;
    }
    rc = sim_run(sc, &o, res);
    if (rc != SIM_OK)
        fprintf(stderr, "dtc-sim: %s\n", res->error);
    else if (!quiet)
        print_summary(file, sc, res);
    free(res);
    free(sc);
    return rc;
}

static bool file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

static int cmd_bench(int argc, char **argv)
{
    const char *file = NULL;
    for (int i = 0; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            fputs(usage, stdout);
            return SIM_OK;
        }
        if (argv[i][0] == '-' && argv[i][1] != '\0')
            return bad_usage("bench: unknown option '%s'", argv[i]);
        if (file != NULL)
            return bad_usage("bench: unexpected argument '%s'", argv[i]);
        file = argv[i];
    }
    const char *def = DTC_SOURCE_DIR "/host_sim/scenarios/case2.ini";
    if (file == NULL && file_exists(def))
        file = def;

    scenario *sc = malloc(sizeof *sc);
    sim_result *res = malloc(sizeof *res);
    if (sc == NULL || res == NULL) {
        free(sc);
        free(res);
        fprintf(stderr, "dtc-sim: out of memory\n");
        return SIM_ERUNTIME;
    }
    sim_options o;
    sim_options_default(&o);
    int rc;
    if (file != NULL) {
        rc = load_scenario(sc, file, NULL, 0);
    } else {
        /* Built-in: 5 s inverter-fed, 200 us tick, 30 Hz rotating small vectors. */
        scenario_default(sc);
        snprintf(sc->source, sizeof sc->source, "built-in open-loop run");
        sc->duration_s = 5.0;
        char err[2048];
        rc = scenario_finish(sc, err, sizeof err);
        if (rc != 0)
            fprintf(stderr, "%s\n", err);
        o.open_loop_hz = 30.0;
    }
    double best_wall = 0.0, sim_s = 0.0;
    for (int run = 0; rc == SIM_OK && run < 3; run++) {
        rc = sim_run(sc, &o, res);
        if (rc != SIM_OK) {
            fprintf(stderr, "dtc-sim: %s\n", res->error);
            break;
        }
        printf("run %d: %.2f s simulated in %.3f s wall\n", run + 1, res->metrics.sim_seconds,
               res->metrics.wall_seconds);
        if (run == 0 || res->metrics.wall_seconds < best_wall)
            best_wall = res->metrics.wall_seconds;
        sim_s = res->metrics.sim_seconds;
    }
    if (rc == SIM_OK) {
        printf("bench: %s\n", sc->source);
        printf("%.2f s simulated in %.3f s wall: %.0fx real time\n", sim_s, best_wall,
               best_wall > 0.0 ? sim_s / best_wall : 0.0);
    }
    free(sc);
    free(res);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc < 2)
        return bad_usage("missing command%s", "");
    const char *cmd = argv[1];
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
        fputs(usage, stdout);
        return SIM_OK;
    }
    if (strcmp(cmd, "run") == 0)
        return cmd_run(argc - 2, argv + 2);
    if (strcmp(cmd, "bench") == 0)
        return cmd_bench(argc - 2, argv + 2);
    return bad_usage("unknown command '%s'", cmd);
}
