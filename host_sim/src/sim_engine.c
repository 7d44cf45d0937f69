/**
 * @file sim_engine.c
 * @brief The SIL loop: plant -> HAL sample -> drive_isr -> background ->
 *        (one period later) actuation -> plant. See sim/sim.h for the order
 *        of one tick and the one-period actuation delay.
 */
#define _POSIX_C_SOURCE 200809L

#include "sim/sim.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "dtc/drive.h"
#include "dtc/ratings.h"
#include "dtc/drive_ident.h"
#include "metrics.h"
#include "open_loop.h"
#include "plant/plant.h"
#include "sim/control_keys.h"
#include "tick_recorder.h"
#include "trace.h"

#define PI 3.14159265358979323846
#define RPM_TO_RAD_S (2.0 * PI / 60.0)
/* Tolerance for "the event's time has come" at a tick boundary, s. */
#define T_EPS 1e-9

typedef struct {
    plant_state ps;
    hal_host_board board;
    drive drv;
    hal_host_can_backend can_sock;
    bool can_sock_open;
    metrics_acc acc;
    bool acc_init;
    sim_trace trace;
    bool trace_open;
    tick_recorder rec;                           /* --record-samples (rec.f NULL: off) */
    scenario_fault faults[SCENARIO_MAX_ENTRIES]; /* sorted by time (stable) */
    int n_faults;
    double factor[SCENARIO_EV_KINDS];            /* parameter factors applied so far */
    bool invalid[SCENARIO_N_CHANNELS];           /* channels the firmware reads as NaN */
    uint32_t warnings_seen;                      /* telemetry warning bits of any tick */
} engine;

void sim_options_default(sim_options *o)
{
    memset(o, 0, sizeof *o);
    o->controller = -1;
}

static int set_error(sim_result *res, int status, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int set_error(sim_result *res, int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(res->error, sizeof res->error, fmt, ap);
    va_end(ap);
    res->status = status;
    return status;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Push the scenario's motor, DC link, period, controller and [control] keys
 * into the firmware configuration, the way the background would. */
/* What ctl_cfg_check's codes mean (firmware/control/include/dtc/ctl.h). */
static const char *cfg_check_text(int rc)
{
    switch (rc) {
    case CTL_CFG_E_MOTOR: return "a motor parameter not > 0, or Ls, Lr not > Lm";
    case CTL_CFG_E_PERIOD: return "period_s outside 20e-6..2e-3 or vdc_nom_V not > 0";
    case CTL_CFG_E_DTC: return "DTC settings inconsistent (psi_ref, bands, levels or duty_min)";
    case CTL_CFG_E_OBSERVER: return "observer settings inconsistent (k_gain < 1, a gain < 0 or speed_lpf_hz < 0)";
    case CTL_CFG_E_PROTECTION: return "protection inconsistent (a trip level not > 0, or vdc_min_V >= vdc_max_V)";
    case CTL_CFG_E_SPEED: return "speed-controller settings inconsistent";
    default: return "inconsistent";
    }
}

/*
 * The scenario's configuration for the firmware, refused as a CAN write would
 * be (0x06040043, parameter incompatibility): the [control] key that makes
 * the configuration inconsistent (ctl_cfg_check) is named with its line.
 * @return SIM_OK or SIM_EINPUT with res->error set.
 */
static int configure_firmware(engine *e, const scenario *sc, int controller, sim_result *res)
{
    drive *d = &e->drv;
    drive_init(d);
    ctl_cfg *cfg = drive_cfg_edit(d);
    /* Without [ratings] the configuration is absolute, as given: the 10 hp
     * defaults with the plant's model and link; nothing derived again. */
    cfg->from_plate = false;
    const plant_motor_params *m = &sc->plant.motor;
    cfg->motor.Rs_ohm = (real_t)m->Rs_ohm;
    cfg->motor.Rr_ohm = (real_t)m->Rr_ohm;
    cfg->motor.Ls_H = (real_t)(m->Lls_H + m->Lm_H);
    cfg->motor.Lr_H = (real_t)(m->Llr_H + m->Lm_H);
    cfg->motor.Lm_H = (real_t)m->Lm_H;
    cfg->motor.pole_pairs = (real_t)m->pole_pairs;
    cfg->motor.J_kgm2 = (real_t)m->J_kgm2;
    cfg->motor.B_Nms = (real_t)m->B_Nms;
    /* The power stage's dead time is commissioning data like the motor's:
     * the board port's default is its own HRTIM dead time (docs/board.md). */
    cfg->dead_time_comp_s = (real_t)sc->plant.inverter.dead_time_s;
    cfg->period_s = (real_t)sc->period_s;
    cfg->vdc_nom_V = (real_t)sc->plant.dc.vdc_V;
    cfg->speed.mode = (speed_mode)controller;
    if (sc->has_ratings) {
        /* The plate and the label, derived like a commissioning over CAN:
         * with model = exact the plant's model is set (as an identification
         * would give it), with model = plate it is the plate's estimate. The
         * link's nominal voltage is the plate's. */
        cfg->from_plate = true;
        scenario_ratings_to_plate(sc, &cfg->plate);
        memset(&cfg->set, 0, sizeof cfg->set);
        if (sc->model == SCENARIO_MODEL_EXACT)
            for (int id = RATINGS_ID_MOTOR_RS; id <= RATINGS_ID_MOTOR_B; id++)
                ratings_mask_set(&cfg->set, (ratings_id)id);
        ratings plate = cfg->plate;
        ratings_mask set = cfg->set;
        ratings_error re = ratings_derive_cfg(cfg, &plate, &set);
        if (re.reason != RATINGS_OK) {
            const char *field = ratings_field_name(re.field);
            return set_error(res, SIM_EINPUT, "%s:%d: [ratings] %s: %s (refused as a CAN write: 0x%08X)", sc->source,
                             scenario_key_line(sc, "ratings", field), field, ratings_reason_text(re.reason),
                             (unsigned)ratings_abort_code(re.reason));
        }
        if (sc->model == SCENARIO_MODEL_EXACT && cfg->motor.pole_pairs != (real_t)m->pole_pairs)
            return set_error(res, SIM_EINPUT, "%s:%d: [ratings] n_rpm: gives %g pole pairs, the [motor] has %d",
                             sc->source, scenario_key_line(sc, "ratings", "n_rpm"), (double)cfg->motor.pole_pairs,
                             m->pole_pairs);
    }
    int rc = ctl_cfg_check(cfg);
    if (rc != CTL_CFG_OK)
        return set_error(res, SIM_EINPUT, "%s: the firmware refuses the motor and drive values: %s", sc->source,
                         cfg_check_text(rc));
    for (int i = 0; i < sc->n_control; i++) {
        const scenario_control *k = &sc->control[i];
        sim_control_key_apply(k->key, cfg, k->value);
        if (cfg->from_plate) {
            /* the user's value, kept; what is derived from it follows */
            size_t n_keys;
            ratings_id id = ratings_id_at(sim_control_keys(&n_keys)[k->key].offset);
            if (id != RATINGS_ID_COUNT)
                ratings_mask_set(&cfg->set, id);
            (void)ctl_cfg_rederive(cfg);
        }
        rc = ctl_cfg_check(cfg);
        if (rc != CTL_CFG_OK) {
            size_t n_keys;
            const char *name = sim_control_keys(&n_keys)[k->key].name;
            if (k->line == SCENARIO_LINE_SET)
                return set_error(res, SIM_EINPUT, "--set control.%s: refused by the firmware (as a CAN write: "
                                 "0x06040043): %s", name, cfg_check_text(rc));
            return set_error(res, SIM_EINPUT, "%s:%d: [control] %s = %g refused by the firmware (as a CAN write: "
                             "0x06040043): %s", sc->source, k->line, name, k->value, cfg_check_text(rc));
        }
    }
    drive_cfg_commit(d);
    /* Re-initialise the control state from the final configuration (no tick has run yet). */
    ctl_init(&d->ctl, drive_cfg(d));
    return SIM_OK;
}

static void sort_faults(engine *e, const scenario *sc)
{
    e->n_faults = sc->n_faults;
    memcpy(e->faults, sc->faults, (size_t)sc->n_faults * sizeof sc->faults[0]);
    for (int i = 1; i < e->n_faults; i++) { /* stable insertion sort (--set may append out of order) */
        scenario_fault x = e->faults[i];
        int j = i - 1;
        while (j >= 0 && e->faults[j].t_s > x.t_s) {
            e->faults[j + 1] = e->faults[j];
            j--;
        }
        e->faults[j + 1] = x;
    }
}

/* Parameter steps and ramps: the factor of each kind at t, pushed into the
 * plant when it changed (every tick during a ramp: a staircase of one tick). */
static void apply_params(engine *e, const scenario *sc, double t)
{
    const plant_motor_params *m0 = &sc->plant.motor; /* events scale the ORIGINAL values */
    for (int k = 0; k < SCENARIO_EV_KINDS; k++) {
        double f = scenario_param_factor(sc, (scenario_event_kind)k, t);
        if (f == e->factor[k])
            continue;
        e->factor[k] = f;
        switch ((scenario_event_kind)k) {
        case SCENARIO_EV_J:
            plant_set_inertia(&e->ps, m0->J_kgm2 * f);
            break;
        case SCENARIO_EV_B:
            plant_set_friction(&e->ps, m0->B_Nms * f);
            break;
        case SCENARIO_EV_RS:
            plant_set_rs(&e->ps, m0->Rs_ohm * f);
            break;
        case SCENARIO_EV_RR:
            plant_set_rr(&e->ps, m0->Rr_ohm * f);
            break;
        case SCENARIO_EV_LM:
            plant_set_lm(&e->ps, m0->Lm_H * f);
            break;
        case SCENARIO_EV_KINDS:
            break;
        }
    }
}

/* One [faults] entry. Plant-side faults go to the plant's sensor chain and
 * supply; the rest act on what the board hands the firmware. */
static void apply_fault(engine *e, const scenario *sc, const scenario_fault *f)
{
    const plant_sensor_params *s0 = &sc->plant.sensor;
    const int ch = f->channel;
    switch (f->kind) {
    case SCENARIO_FAULT_GAIN:
        plant_set_sensor_gain(&e->ps, ch, f->value);
        break;
    case SCENARIO_FAULT_OFFSET:
        plant_set_sensor_offset(&e->ps, ch, f->value);
        break;
    case SCENARIO_FAULT_STUCK:
        plant_set_sensor_fault(&e->ps, ch, PLANT_SENSOR_STUCK);
        break;
    case SCENARIO_FAULT_LOST:
        plant_set_sensor_fault(&e->ps, ch, PLANT_SENSOR_LOST);
        break;
    case SCENARIO_FAULT_INVALID:
        e->invalid[ch] = true;
        break;
    case SCENARIO_FAULT_RESTORE:
        plant_set_sensor_fault(&e->ps, ch, PLANT_SENSOR_OK);
        plant_set_sensor_gain(&e->ps, ch, ch < 3 ? s0->i_gain[ch] : s0->v_gain[ch - 3]);
        plant_set_sensor_offset(&e->ps, ch, ch < 3 ? s0->i_offset_A[ch] : s0->v_offset_V[ch - 3]);
        e->invalid[ch] = false;
        break;
    case SCENARIO_FAULT_VDC:
        plant_set_vdc(&e->ps, f->value);
        break;
    case SCENARIO_FAULT_HW:
        e->board.fault_input = f->value != 0.0;
        break;
    case SCENARIO_FAULT_OPEN_PHASE:
        plant_set_phase_open(&e->ps, ch, 1);
        break;
    case SCENARIO_FAULT_OVERRUN: /* this tick ends late: the firmware latches OVERRUN next tick */
        e->board.tick_missed = true;
        break;
    case SCENARIO_FAULT_STALE: /* handled at the sample (one tick only) */
    case SCENARIO_FAULT_KINDS:
        break;
    }
}

/* Eq. 5 uncertainty: eps = (-B'/J' + B/J) w + (1/J' - 1/J) Te - T_L/J',
 * primes = the plant's present values, plain = nominal (scenario start). */
static double eps_true(const engine *e, const scenario *sc, double omega, double te)
{
    double J = sc->plant.motor.J_kgm2, B = sc->plant.motor.B_Nms;
    double Jp = e->ps.cfg.motor.J_kgm2, Bp = e->ps.cfg.motor.B_Nms;
    return (-Bp / Jp + B / J) * omega + (1.0 / Jp - 1.0 / J) * te - plant_load_torque(&e->ps, omega) / Jp;
}

static int check_writable(const char *path, sim_result *res)
{
    size_t n = strlen(path);
    char *p = malloc(n + 9u);
    if (p == NULL)
        return set_error(res, SIM_ERUNTIME, "out of memory");
    memcpy(p, path, n);
    memcpy(p + n, ".partial", 9u);
    /* O_EXCL: a file that is there already is never truncated or removed. */
    int fd = open(p, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    int rc = SIM_OK;
    if (fd < 0 && errno == EEXIST)
        rc = set_error(res, SIM_EINPUT, "%s: exists already (a file this run did not create is never replaced)", p);
    else if (fd < 0)
        rc = set_error(res, SIM_EINPUT, "%s: cannot create: %s", p, strerror(errno));
    else {
        close(fd);
        remove(p);
    }
    free(p);
    return rc;
}

static int open_can(engine *e, const sim_options *o, sim_result *res)
{
    if (o->can_iface != NULL) {
        int rc = hal_host_socketcan_open(o->can_iface, &e->can_sock);
        if (rc == -EAFNOSUPPORT)
            return set_error(res, SIM_EINPUT,
                             "SocketCAN is not available in this kernel (errno %d); use a kernel with vcan "
                             "or the UML test runner", EAFNOSUPPORT);
        if (rc == -ENODEV)
            return set_error(res, SIM_EINPUT, "--can %s: no such CAN interface", o->can_iface);
        if (rc != 0)
            return set_error(res, SIM_EINPUT, "--can %s: %s (errno %d)", o->can_iface, strerror(-rc), -rc);
        e->can_sock_open = true;
        e->board.can = e->can_sock;
    } else if (o->can != NULL) {
        e->board.can = *o->can;
    }
    return SIM_OK;
}

/* Realtime pacing step, s: the loop runs this many seconds of ticks, then
 * waits for the wall clock. Each step costs a clock read and a sleep, which
 * under User-Mode Linux (the CAN tests) are system calls of 20-90 us each, so
 * the step is longer than the 200 us tick; it also bounds the time a CAN frame
 * waits before the drive reads it. */
#define PACE_STEP_S 0.5e-3

static void sleep_until(const struct timespec *deadline, const volatile sig_atomic_t *stop)
{
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, deadline, NULL) == EINTR)
        if (stop != NULL && *stop)
            return;
}

/* Advance the absolute deadline *next by step_ns and wait for it. With a CAN
 * backend that can wait (SocketCAN), wait on its receive queue instead of
 * sleeping blind: that notes whether a frame arrived, so the per-tick
 * hal_can_recv makes no system call on an idle bus. A frame that arrives is
 * read by the first tick after the deadline (within one step of its arrival);
 * the ticks keep following the wall clock. When late, the queue is still
 * looked at once (zero timeout), so frames are served at every step. */
static void pace(struct timespec *next, long step_ns, const hal_host_can_backend *can,
                 const volatile sig_atomic_t *stop)
{
    next->tv_nsec += step_ns;
    while (next->tv_nsec >= 1000000000L) {
        next->tv_nsec -= 1000000000L;
        next->tv_sec++;
    }
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    double late = (double)(now.tv_sec - next->tv_sec) + 1e-9 * (double)(now.tv_nsec - next->tv_nsec);
    if (late > 0.1)
        *next = now; /* far behind (suspended, overloaded): resynchronise, no burst */
    if (can == NULL || can->wait_rx == NULL) {
        if (late < 0.0)
            sleep_until(next, stop);
        return;
    }
    for (;;) {
        struct timespec left = { next->tv_sec - now.tv_sec, next->tv_nsec - now.tv_nsec };
        if (left.tv_nsec < 0) {
            left.tv_nsec += 1000000000L;
            left.tv_sec--;
        }
        if (left.tv_sec < 0)
            left.tv_sec = left.tv_nsec = 0; /* late: only look whether a frame came */
        int rc = can->wait_rx(can->ctx, &left);
        if (rc == 0)
            return; /* the deadline came with no frame */
        if (rc != HAL_EAGAIN) {
            if (late < 0.0)
                sleep_until(next, stop); /* a frame is waiting (or the wait failed): the rest blind */
            return;
        }
        if (stop != NULL && *stop)
            return; /* a signal: stop when asked, else wait out the rest */
        clock_gettime(CLOCK_MONOTONIC, &now);
    }
}

/* ---------------------------------------------- [commission] identify */

/* The identification run's longest drive time the commissioning waits for, s
 * (the standstill part takes at most 30 s, docs/commissioning.md). */
#define COMMISSION_MAX_S 60.0

static const char *ident_abort_text(ident_abort a)
{
    switch (a) {
    case IDENT_ABORT_STOPPED: return "the run command dropped";
    case IDENT_ABORT_FAULT: return "the drive latched a fault";
    case IDENT_ABORT_OVERCURRENT: return "a phase current above the run's bound";
    case IDENT_ABORT_TURNING: return "the rotor turns";
    case IDENT_ABORT_LINK: return "the DC link sagged";
    case IDENT_ABORT_TIMEOUT: return "a stage timed out";
    case IDENT_ABORT_NONE:
    default: return "unknown";
    }
}

/*
 * [commission] identify: the drive's identification run on the plant before
 * the profile starts (no metrics, no trace, no events; the board's clock
 * stands at 0 for the CAN services meanwhile), started as over CAN
 * (0x2800:1) with the plate the drive holds; its ok results are written to
 * the configuration the profile then runs on. A refused or aborted run ends
 * the simulation (SIM_ERUNTIME); `full` is refused with the key's line
 * (SIM_EINPUT: the drive runs the standstill part only).
 */
static int commission(engine *e, const scenario *sc, sim_result *res)
{
    if (sc->identify == SCENARIO_IDENTIFY_NONE)
        return SIM_OK;
    if (sc->identify == SCENARIO_IDENTIFY_FULL) {
        if (sc->identify_line == SCENARIO_LINE_SET)
            return set_error(res, SIM_EINPUT, "--set commission.identify = full: the drive carries out the "
                             "standstill part only (use standstill)");
        return set_error(res, SIM_EINPUT, "%s:%d: [commission] identify = full: the drive carries out the "
                         "standstill part only (use standstill)", sc->source, sc->identify_line);
    }
    drive *d = &e->drv;
    const double T = sc->period_s;
    const uint8_t legs_off[3] = { 3, 3, 3 };
    hal_actuation prev, act;
    bool gates_on = false;
    hal_host_take_actuation(&e->board, &prev, &gates_on);
    const uint64_t n_max = (uint64_t)llround(COMMISSION_MAX_S / T);
    bool started = false;
    for (uint64_t k = 0; k < n_max; k++) {
        plant_adc adc;
        plant_sample(&e->ps, &adc);
        double i_A[3], v_V[2];
        plant_adc_to_units(&e->ps.cfg, &adc, i_A, v_V);
        hal_sample s = { (float)i_A[0], (float)i_A[1], (float)i_A[2], (float)v_V[0], (float)v_V[1],
                         (float)adc.omega_m_rad_s, true, (uint32_t)(k + 1u) };
        hal_host_set_sample(&e->board, &s);
        e->board.t_s = -COMMISSION_MAX_S - 1.0 + (double)k * T; /* before the profile's t = 0 */
        hal_host_run_tick(&e->board);
        drive_background(d);
        if (!started && k >= 10u) { /* a few ticks first: the snapshot has the link's voltage */
            int rc = drive_ident_start(d, NULL, false);
            if (rc != 0)
                return set_error(res, SIM_ERUNTIME, "%s: [commission] identify = standstill: the drive refused "
                                 "the identification run (ident_error %d)", sc->source, rc);
            started = true;
        } else if (started && !drive_ident_running(d)) {
            if (d->ident_outcome != (uint8_t)DRIVE_IDENT_DONE)
                return set_error(res, SIM_ERUNTIME, "%s: [commission] identify: the identification run ended "
                                 "without results (outcome %u: %s)", sc->source, (unsigned)d->ident_outcome,
                                 d->ident_outcome == (uint8_t)DRIVE_IDENT_ABORTED
                                     ? ident_abort_text(d->ident.abort_reason) : "rejected");
            break;
        }
        hal_host_take_actuation(&e->board, &act, &gates_on);
        if (!gates_on)
            plant_advance(&e->ps, legs_off, legs_off, 1.0, T);
        else
            plant_advance(&e->ps, prev.vector[0].leg, prev.vector[1].leg, (double)prev.duty0, T);
        prev = act;
    }
    if (drive_ident_running(d))
        return set_error(res, SIM_ERUNTIME, "%s: [commission] identify: the run did not end in %.0f s", sc->source,
                         COMMISSION_MAX_S);
    e->board.t_s = 0.0;
    return SIM_OK;
}

/* The tick loop. Returns SIM_OK or an error status (res->error set). */
static int run_loop(engine *e, const scenario *sc, const sim_options *o, sim_result *res, bool firmware)
{
    const double T = sc->period_s;
    const long period_ns = (long)llround(T * 1e9);
    /* Realtime pacing every PACE_STEP_S (a few ticks), not every tick: per-tick pacing
     * under User-Mode Linux left the SIL at 0.5x real time with 1 kHz telemetry. */
    const uint64_t pace_every = llround(PACE_STEP_S / T) > 1 ? (uint64_t)llround(PACE_STEP_S / T) : 1u;
    const uint64_t n_ticks = (uint64_t)llround(sc->duration_s / T);
    const bool forever = o->realtime && o->run_forever;
    const uint64_t trace_every =
        (uint64_t)llround(sc->trace_interval_s / T) > 0 ? (uint64_t)llround(sc->trace_interval_s / T) : 1u;
    const uint8_t legs_off[3] = { 3, 3, 3 };

    hal_actuation prev; /* latched on the previous tick: applied in this period */
    hal_host_take_actuation(&e->board, &prev, &(bool){ false });
    int fault_i = 0;
    double load_nm = 0.0; /* the plant starts without load */
    for (int k = 0; k < SCENARIO_EV_KINDS; k++)
        e->factor[k] = 1.0;
    double last_ref_rpm = NAN;
    float last_set_rad_s = 0.0f; /* what the drive made of the profile's last value (its limits applied) */
    /* Until the bus takes it the drive's reference is the profile's last value
     * as the drive limited it (the engine writes every change, the first tick's included); found
     * different at a tick, the drive's bus (SDO, RPDO, a CiA 402 halt) changed
     * it, and from then on the master owns the reference for the rest of the
     * run: the profile no longer overrides a set point a tuner has just written
     * (the README's session starts during CASE1's ramp). A halt counts too: the
     * master that stopped the motor also gives the next reference. */
    bool ref_from_bus = false;
    bool started = false;
    drive_snapshot snap;
    memset(&snap, 0, sizeof snap);

    struct timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);

    for (uint64_t k = 0;; k++) {
        const double t = (double)k * T;
        if (o->stop != NULL && *o->stop) {
            if (!o->realtime)
                return set_error(res, SIM_ERUNTIME, "interrupted at t = %.4f s", t);
            break; /* realtime: a clean stop */
        }

        /* 1. sample at the period start; faults due now act on this sample */
        bool stale = false;
        while (fault_i < e->n_faults && e->faults[fault_i].t_s <= t + T_EPS) {
            stale = stale || e->faults[fault_i].kind == SCENARIO_FAULT_STALE;
            apply_fault(e, sc, &e->faults[fault_i++]);
        }
        plant_adc adc;
        plant_sample(&e->ps, &adc);
        double i_A[3], v_V[2];
        plant_adc_to_units(&e->ps.cfg, &adc, i_A, v_V);
        hal_sample s = { (float)i_A[0], (float)i_A[1], (float)i_A[2], (float)v_V[0], (float)v_V[1],
                         (float)adc.omega_m_rad_s, true, (uint32_t)(k + 1u) };
        float *chan[SCENARIO_N_CHANNELS] = { &s.ia_A, &s.ib_A, &s.ic_A, &s.vc1_V, &s.vc2_V };
        for (int c = 0; c < SCENARIO_N_CHANNELS; c++)
            if (e->invalid[c])
                *chan[c] = NAN;
        if (!stale) /* a stale tick: the ADC did not convert, hal_sample_read finds nothing new */
            hal_host_set_sample(&e->board, &s);
        e->board.t_s = t;

        /* 2. events whose time has come */
        if (firmware && !ref_from_bus && !isnan(last_ref_rpm) && e->drv.speed_ref_rad_s != last_set_rad_s)
            ref_from_bus = true;
        apply_params(e, sc, t + T_EPS);
        double tl = scenario_load_nm(sc, t + T_EPS);
        if (tl != load_nm)
            plant_set_load(&e->ps, tl);
        load_nm = tl;
        if (o->on_plant != NULL)
            o->on_plant(o->user, t, &e->ps);
        double ref_rpm = scenario_ref_rpm(sc, t + T_EPS);
        if (firmware && !ref_from_bus && ref_rpm != last_ref_rpm) {
            drive_set_speed_ref(&e->drv, (float)(ref_rpm * RPM_TO_RAD_S));
            last_set_rad_s = e->drv.speed_ref_rad_s;
        }
        last_ref_rpm = ref_rpm;
        if (firmware && !started && t + T_EPS >= o->start_delay_s) {
            drive_set_run(&e->drv, true); /* the run command (--start-delay) */
            started = true;
        }

        /* 3. the interrupt, then one background pass */
        hal_actuation act = prev;
        bool gates_on = false;
        if (firmware) {
            if (e->rec.f != NULL)
                tick_recorder_inputs(&e->rec, k, &e->board, &e->drv);
            hal_host_run_tick(&e->board);
            if (e->rec.f != NULL)
                tick_recorder_outputs(&e->rec, &e->drv);
            drive_background(&e->drv);
        }
        if (o->on_tick != NULL)
            o->on_tick(o->user, t, firmware ? &e->drv : NULL);
        if (firmware) {
            if (hal_host_watchdog_expired(&e->board))
                return set_error(res, SIM_ERUNTIME, "watchdog expired at t = %.4f s", t);
            hal_host_take_actuation(&e->board, &act, &gates_on);
            drive_read_snapshot(&e->drv, &snap);
            e->warnings_seen |= snap.tel.warnings;
        } else if (o->open_loop_hz > 0.0) {
            open_loop_actuation(t, o->open_loop_hz, k, &act);
            gates_on = true;
        }

        /* 5. metrics and trace at the sample instant */
        plant_truth tr;
        plant_get_truth(&e->ps, &tr);
        if (!isfinite(tr.omega_m_rad_s) || !isfinite(tr.ia_A) || !isfinite(tr.vc1_V))
            return set_error(res, SIM_ERUNTIME, "the plant diverged at t = %.4f s", t);
        double eps = eps_true(e, sc, tr.omega_m_rad_s, tr.te_Nm);
        metrics_sample ms = {
            .t_s = t,
            .speed_rpm = tr.omega_m_rad_s / RPM_TO_RAD_S,
            .ref_rpm = ref_rpm,
            .est_rpm = firmware ? (double)snap.tel.omega_est_rad_s / RPM_TO_RAD_S : 0.0,
            .te_nm = tr.te_Nm,
            .is_sq = tr.ia_A * tr.ia_A + tr.ib_A * tr.ib_A + tr.ic_A * tr.ic_A,
            .eps_hat = firmware ? (double)snap.tel.eps_hat : 0.0,
            .eps_true = eps,
            .np_dev_v = fabs(tr.vc1_V - tr.vc2_V),
            .w_norm = firmware ? (double)snap.tel.w_norm : 0.0,
            .switch_count = e->ps.switch_count,
        };
        metrics_acc_add(&e->acc, &ms);
        if (e->trace_open && k % trace_every == 0u) {
            sim_trace_row row = { t, tr.omega_m_rad_s, tr.te_Nm, tr.ia_A, tr.ib_A, tr.ic_A, tr.vc1_V, tr.vc2_V,
                                  ref_rpm, plant_load_torque(&e->ps, tr.omega_m_rad_s), eps,
                                  firmware ? &snap : NULL };
            trace_write(&e->trace, &row);
        }
        res->ticks = k + 1u;
        if (!forever && k >= n_ticks)
            break;

        /* 4. integrate the period with the actuation latched one tick ago */
        if (e->ps.cfg.supply == PLANT_SUPPLY_SINE)
            plant_advance(&e->ps, legs_off, legs_off, 1.0, T);
        else if (!gates_on)
            plant_advance(&e->ps, legs_off, legs_off, 1.0, T);
        else
            plant_advance(&e->ps, prev.vector[0].leg, prev.vector[1].leg, (double)prev.duty0, T);
        prev = act; /* the zero vector when the gates are off (see hal_host_take_actuation) */

        if (o->realtime && (k + 1u) % pace_every == 0u)
            pace(&next, (long)pace_every * period_ns, &e->board.can, o->stop);
    }
    return SIM_OK;
}

static void fill_static_metrics(const engine *e, const scenario *sc, const sim_options *o, bool firmware,
                                int controller, sim_metrics *m)
{
    m->firmware = firmware;
    snprintf(m->controller, sizeof m->controller, "%s",
             firmware ? scenario_controller_name(controller) : "none");
    (void)o;
    m->np_dev_limit_v = 0.02 * sc->plant.dc.vdc_V;
    if (firmware) {
        const ctl_cfg *cfg = drive_cfg(&e->drv);
        m->m_w = (double)cfg->speed.rbfn.m_w;
        drive_snapshot snap;
        drive_read_snapshot(&e->drv, &snap);
        m->faults = snap.tel.faults;
        m->warnings_seen = e->warnings_seen;
        m->isr_max_us = (double)e->drv.timing.max_cycles / (double)hal_cycles_hz() * 1e6;
        m->isr_overruns = e->drv.timing.overruns;
    }
}

int sim_run(const scenario *sc, const sim_options *opt, sim_result *res)
{
    memset(res, 0, sizeof *res);
    sim_options o;
    if (opt != NULL)
        o = *opt;
    else
        sim_options_default(&o);

    const bool sine = sc->plant.supply == PLANT_SUPPLY_SINE;
    if (o.can_iface != NULL && !o.realtime)
        return set_error(res, SIM_EINPUT, "--can requires --realtime");
    if (o.run_forever && !o.realtime)
        return set_error(res, SIM_EINPUT, "an endless run requires --realtime");
    if (o.controller < -1 || o.controller > SCENARIO_CTL_RBFN)
        return set_error(res, SIM_EINPUT, "unknown controller %d", o.controller);
    if (o.open_loop_hz > 0.0 && sine)
        return set_error(res, SIM_EINPUT, "the open-loop sequence needs the inverter supply");
    if (!(sc->period_s >= 50e-6 && sc->period_s <= 1e-3))
        return set_error(res, SIM_EINPUT, "period_s %g is out of range", sc->period_s);
    const bool firmware = !sine && !(o.open_loop_hz > 0.0);
    const int controller = o.controller >= 0 ? o.controller : sc->controller;

    if (o.csv_path != NULL && check_writable(o.csv_path, res) != SIM_OK)
        return res->status;
    if (o.metrics_path != NULL && check_writable(o.metrics_path, res) != SIM_OK)
        return res->status;
    if (!(o.start_delay_s >= 0.0 && o.start_delay_s <= 600.0))
        return set_error(res, SIM_EINPUT, "start delay %g s is outside 0..600", o.start_delay_s);
    if (o.record_path != NULL && !firmware)
        return set_error(res, SIM_EINPUT, "--record-samples needs the firmware (inverter supply, not open loop)");

    engine *e = calloc(1, sizeof *e);
    if (e == NULL)
        return set_error(res, SIM_ERUNTIME, "out of memory");

    int rc = SIM_OK;
    if (plant_init(&e->ps, &sc->plant) != 0) {
        const char *what = "rejected";
        plant_check_config(&sc->plant, &what);
        rc = set_error(res, SIM_EINPUT, "%s: invalid plant configuration: %s", sc->source, what);
        goto out;
    }
    sort_faults(e, sc);

    hal_host_board_init(&e->board);
    if (o.nvm_path != NULL) {
        if (hal_host_nvm_load(&e->board, o.nvm_path) != HAL_OK) {
            rc = set_error(res, SIM_EINPUT, "--nvm %s: not a readable %u-byte NVM image (left untouched)",
                           o.nvm_path, HAL_HOST_NVM_SIZE);
            goto out;
        }
        e->board.nvm_path = o.nvm_path;
    }
    if ((rc = open_can(e, &o, res)) != SIM_OK)
        goto out;
    hal_host_bind(&e->board);

    if (firmware) {
        if ((rc = configure_firmware(e, sc, controller, res)) != SIM_OK)
            goto out;
        uint32_t period_us = (uint32_t)llround(sc->period_s * 1e6);
        if (hal_tick_start(drive_isr, &e->drv, period_us) != HAL_OK) {
            rc = set_error(res, SIM_EINPUT, "hal_tick_start refused a %u us period", (unsigned)period_us);
            goto out;
        }
        if ((rc = commission(e, sc, res)) != SIM_OK)
            goto out;
        if (o.record_path != NULL &&
            tick_recorder_open(&e->rec, o.record_path, sc->source, &e->drv, period_us, res->error,
                               sizeof res->error) != 0) {
            rc = res->status = SIM_EINPUT;
            goto out;
        }
    }

    if (metrics_acc_init(&e->acc, sc, sc->period_s) != 0) {
        rc = set_error(res, SIM_ERUNTIME, "out of memory");
        goto out;
    }
    e->acc_init = true;
    if (o.csv_path != NULL) {
        if (trace_open(&e->trace, o.csv_path, res->error, sizeof res->error) != 0) {
            rc = res->status = SIM_EINPUT;
            goto out;
        }
        e->trace_open = true;
    }

    double w0 = now_s();
    rc = run_loop(e, sc, &o, res, firmware);
    double wall = now_s() - w0;
    if (rc != SIM_OK)
        goto out;

    sim_metrics *m = &res->metrics;
    metrics_acc_finish(&e->acc, m);
    fill_static_metrics(e, sc, &o, firmware, controller, m);
    m->sim_seconds = res->ticks > 0u ? (double)(res->ticks - 1u) * sc->period_s : 0.0;
    m->wall_seconds = wall;

    if (o.metrics_path != NULL) {
        rc = sim_write_metrics_json(m, o.metrics_path, res->error, sizeof res->error);
        if (rc != SIM_OK) {
            res->status = rc;
            goto out;
        }
    }
    if (e->trace_open) {
        e->trace_open = false;
        if (trace_close(&e->trace, true, res->error, sizeof res->error) != 0) {
            if (o.metrics_path != NULL)
                remove(o.metrics_path); /* all outputs or none */
            rc = res->status = SIM_ERUNTIME;
            goto out;
        }
    }

    if (e->rec.f != NULL && tick_recorder_close(&e->rec, true, res->error, sizeof res->error) != 0) {
        rc = res->status = SIM_ERUNTIME;
        goto out;
    }

out:
    if (e->rec.f != NULL)
        tick_recorder_close(&e->rec, false, NULL, 0);
    if (e->trace_open)
        trace_close(&e->trace, false, NULL, 0);
    if (e->acc_init)
        metrics_acc_free(&e->acc);
    if (firmware && hal_host_bound() == &e->board)
        hal_tick_stop();
    if (hal_host_bound() == &e->board)
        hal_host_bind(NULL);
    if (e->can_sock_open)
        hal_host_socketcan_close(&e->can_sock);
    free(e);
    res->status = rc;
    return rc;
}
