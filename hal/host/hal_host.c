/**
 * @file hal_host.c
 * @brief The HAL contract implemented on a simulated board (host SIL).
 *
 * Every hal_* function acts on the board bound with hal_host_bind(). The
 * bound-board pointer is the one piece of file-static state: it models the
 * board's registers, which a real HAL reaches by address. With no board
 * bound the functions are harmless (errors or neutral values).
 *
 * Time: hal_cycles() is real host time, so ISR timing is measured, not
 * simulated: on x86-64 the time-stamp counter (one instruction, no system
 * call: under User-Mode Linux every clock_gettime is a trapped system call of
 * 20-90 us, and the drive reads the counter twice per tick), with its rate
 * calibrated once against CLOCK_MONOTONIC; elsewhere CLOCK_MONOTONIC in ns.
 * hal_millis() is the board's SIMULATED time, so heartbeats and timeouts
 * follow the simulation, not the wall clock.
 */
#define _POSIX_C_SOURCE 200809L

#include "hal_host/hal_host.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#if defined(__x86_64__)
#include <x86intrin.h>
#define HAL_HOST_TSC 1
#endif

static hal_host_board *g_board; /* the board's "registers" */

/* ------------------------------------------------------------ engine side */

void hal_host_board_init(hal_host_board *b)
{
    memset(b, 0, sizeof *b);
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 3; k++)
            b->act_latched.vector[i].leg[k] = HAL_LEG_O;
    b->act_latched.duty0 = 1.0f;
    memset(b->nvm, 0xFF, sizeof b->nvm);
    b->nvm_write_budget = -1;
}

void hal_host_bind(hal_host_board *b)
{
    if (b != NULL)
        (void)hal_cycles_hz(); /* calibrate now, not in the first tick */
    g_board = b;
}

hal_host_board *hal_host_bound(void) { return g_board; }

void hal_host_set_sample(hal_host_board *b, const hal_sample *s)
{
    b->sample = *s;
    b->sample_pending = true;
}

void hal_host_run_tick(hal_host_board *b)
{
    if (!b->tick_running || b->handler == NULL)
        return;
    b->act_written = false;
    b->handler(b->handler_ctx);
}

void hal_host_take_actuation(const hal_host_board *b, hal_actuation *act, bool *gates_on)
{
    *gates_on = b->gates_enabled;
    if (b->gates_enabled) {
        *act = b->act_latched;
        return;
    }
    /* Gates off: the modulator holds the zero vector, so re-enabling never
     * starts from a stale active vector. */
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 3; k++)
            act->vector[i].leg[k] = HAL_LEG_O;
    act->duty0 = 1.0f;
}

int hal_host_nvm_load(hal_host_board *b, const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return errno == ENOENT ? HAL_OK : HAL_EIO; /* missing: stays erased */
    uint8_t img[HAL_HOST_NVM_SIZE];
    size_t n = fread(img, 1, sizeof img, f);
    int extra = fgetc(f);
    int bad = ferror(f);
    fclose(f);
    if (bad || n != sizeof img || extra != EOF)
        return HAL_EIO; /* wrong size or unreadable: keep what we have */
    memcpy(b->nvm, img, sizeof img);
    return HAL_OK;
}

bool hal_host_watchdog_expired(const hal_host_board *b)
{
    if (b->wdg_timeout_ms == 0u)
        return false;
    return (b->t_s - b->wdg_last_kick_s) * 1000.0 > (double)b->wdg_timeout_ms;
}

/* ------------------------------------------------------------ control tick */

int hal_tick_start(hal_tick_handler handler, void *ctx, uint32_t period_us)
{
    hal_host_board *b = g_board;
    if (b == NULL)
        return HAL_EIO;
    if (handler == NULL || period_us < 50u || period_us > 1000u)
        return HAL_EINVAL;
    b->handler = handler;
    b->handler_ctx = ctx;
    b->period_us = period_us;
    b->tick_running = true;
    return HAL_OK;
}

void hal_tick_stop(void)
{
    hal_host_board *b = g_board;
    if (b == NULL)
        return;
    b->gates_enabled = false;
    b->tick_running = false;
}

bool hal_tick_missed(void)
{
    /* The SIL runs each tick to completion between two plant periods: simulated
     * time does not advance inside the handler, so no deadline is missed unless
     * a scenario injects one ([faults] overrun). (Host wall-clock timing of the
     * handler is reported, not judged.) */
    hal_host_board *b = g_board;
    if (b == NULL || !b->tick_missed)
        return false;
    b->tick_missed = false;
    return true;
}

/* ----------------------------------------------------- sample and actuation */

int hal_sample_read(hal_sample *out)
{
    hal_host_board *b = g_board;
    if (b == NULL || !b->sample_pending)
        return HAL_EAGAIN;
    *out = b->sample;
    b->sample_pending = false;
    return HAL_OK;
}

int hal_actuate(const hal_actuation *act)
{
    hal_host_board *b = g_board;
    if (b == NULL)
        return HAL_EIO;
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 3; k++)
            if (act->vector[i].leg[k] > HAL_LEG_P)
                return HAL_EINVAL;
    /* The negated form also refuses NaN. */
    if (!(act->duty0 >= 0.0f && act->duty0 <= 1.0f))
        return HAL_EINVAL;
    b->act_latched = *act;
    b->act_written = true;
    return HAL_OK;
}

/* ------------------------------------------------------- gates and faults */

void hal_gate_enable(bool enable)
{
    hal_host_board *b = g_board;
    if (b == NULL)
        return;
    /* As in hardware, an active fault input keeps the gates off. */
    b->gates_enabled = enable && !b->fault_input;
}

bool hal_gate_enabled(void) { return g_board != NULL && g_board->gates_enabled; }

bool hal_fault_input_active(void) { return g_board != NULL && g_board->fault_input; }

/* ------------------------------------------------------------ time */

static uint64_t mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

#ifdef HAL_HOST_TSC
/* Counter rate after the shift, Hz (0: not calibrated yet), and the right
 * shift that keeps it below 2^32 so it fits hal_cycles_hz(). Written once. */
static uint32_t g_tsc_hz;
static unsigned g_tsc_shift;

/* One (TSC, CLOCK_MONOTONIC) pair, taken when the two reads are close
 * together: a pair split by a preemption would skew the rate. */
static void tsc_mono_pair(uint64_t *tsc, uint64_t *ns)
{
    uint64_t best = UINT64_MAX;
    for (int i = 0; i < 5; i++) {
        uint64_t a = __rdtsc();
        uint64_t t = mono_ns();
        uint64_t b = __rdtsc();
        if (b - a < best) {
            best = b - a;
            *tsc = a + (b - a) / 2u;
            *ns = t;
        }
    }
}

/* The TSC rate over about 10 ms of CLOCK_MONOTONIC (the TSC of current x86-64
 * CPUs runs at a constant rate whatever the core clock). */
static void tsc_calibrate(void)
{
    uint64_t c0 = 0u, n0 = 0u, c1 = 0u, n1 = 0u;
    tsc_mono_pair(&c0, &n0);
    struct timespec nap = { 0, 10000000L };
    while (nanosleep(&nap, &nap) != 0 && errno == EINTR) {
    }
    tsc_mono_pair(&c1, &n1);
    double hz = n1 > n0 && c1 > c0 ? (double)(c1 - c0) * 1e9 / (double)(n1 - n0) : 0.0;
    if (!(hz >= 1e6)) {
        hz = 1e9; /* a counter that does not count: cannot happen on x86-64; stay sane */
    }
    unsigned shift = 0u;
    while (hz / (double)(1ull << shift) >= 4294967295.0)
        shift++;
    g_tsc_shift = shift;
    g_tsc_hz = (uint32_t)llround(hz / (double)(1ull << shift));
}
#endif

uint32_t hal_cycles(void)
{
#ifdef HAL_HOST_TSC
    if (g_tsc_hz == 0u)
        tsc_calibrate(); /* the shift must be known before the first count */
    return (uint32_t)(__rdtsc() >> g_tsc_shift); /* wraps at 2^32 counts, like a cycle counter */
#else
    return (uint32_t)mono_ns(); /* wraps at 2^32 ns (4.3 s), like a cycle counter */
#endif
}

uint32_t hal_cycles_hz(void)
{
#ifdef HAL_HOST_TSC
    if (g_tsc_hz == 0u)
        tsc_calibrate(); /* once, about 10 ms (also done by hal_host_bind) */
    return g_tsc_hz;
#else
    return 1000000000u;
#endif
}

uint32_t hal_millis(void)
{
    hal_host_board *b = g_board;
    if (b == NULL || !(b->t_s > 0.0))
        return 0u;
    /* The small epsilon keeps k * 1 ms from rounding down to k - 1. */
    double ms = floor(b->t_s * 1000.0 + 1e-6);
    return (uint32_t)(uint64_t)fmod(ms, 4294967296.0);
}

/* ------------------------------------------------------------- CAN */

int hal_can_open(uint32_t bitrate_bps)
{
    hal_host_board *b = g_board;
    if (b == NULL)
        return HAL_EIO;
    if (bitrate_bps != 125000u && bitrate_bps != 250000u && bitrate_bps != 500000u &&
        bitrate_bps != 1000000u)
        return HAL_EINVAL;
    b->can_bitrate = bitrate_bps;
    b->can_open = true;
    return HAL_OK;
}

int hal_can_send(const hal_can_frame *frame)
{
    hal_host_board *b = g_board;
    if (b == NULL || !b->can_open)
        return HAL_EIO;
    if (frame->id > 0x7FFu || frame->dlc > 8u)
        return HAL_EINVAL;
    if (b->can.send == NULL)
        return HAL_OK; /* no bus attached: the frame goes nowhere */
    return b->can.send(b->can.ctx, frame);
}

int hal_can_recv(hal_can_frame *frame)
{
    hal_host_board *b = g_board;
    if (b == NULL || !b->can_open || b->can.recv == NULL)
        return HAL_EAGAIN;
    return b->can.recv(b->can.ctx, frame);
}

void hal_can_get_state(hal_can_state *out)
{
    const hal_host_board *b = g_board;
    out->bus_off = false;
    out->bus_off_count = 0u;
    if (b != NULL && b->can_open && b->can.state != NULL)
        b->can.state(b->can.ctx, out);
}

/* -------------------------------------------------------- non-volatile */

uint32_t hal_nvm_size(void) { return HAL_HOST_NVM_SIZE; }

static bool nvm_range_ok(uint32_t offset, size_t len)
{
    return offset <= HAL_HOST_NVM_SIZE && len <= (size_t)(HAL_HOST_NVM_SIZE - offset);
}

int hal_nvm_read(uint32_t offset, void *buf, size_t len)
{
    hal_host_board *b = g_board;
    if (b == NULL)
        return HAL_EIO;
    if (!nvm_range_ok(offset, len))
        return HAL_ENOSPC;
    if (len > 0u)
        memcpy(buf, &b->nvm[offset], len);
    return HAL_OK;
}

/* Write the whole image to PATH.tmp and rename it over PATH, so the mirror
 * file is always a complete image (old or new), never a torn one. */
static int nvm_mirror(const hal_host_board *b)
{
    size_t plen = strlen(b->nvm_path);
    char *tmp = malloc(plen + 5u);
    if (tmp == NULL)
        return HAL_EIO;
    memcpy(tmp, b->nvm_path, plen);
    memcpy(tmp + plen, ".tmp", 5u);
    int rc = HAL_EIO;
    FILE *f = fopen(tmp, "wb");
    if (f != NULL) {
        size_t n = fwrite(b->nvm, 1, sizeof b->nvm, f);
        int closed = fclose(f);
        if (n == sizeof b->nvm && closed == 0 && rename(tmp, b->nvm_path) == 0)
            rc = HAL_OK;
        else
            remove(tmp);
    }
    free(tmp);
    return rc;
}

int hal_nvm_write(uint32_t offset, const void *buf, size_t len)
{
    hal_host_board *b = g_board;
    if (b == NULL)
        return HAL_EIO;
    if (!nvm_range_ok(offset, len))
        return HAL_ENOSPC;
    size_t n = len;
    bool power_lost = false;
    if (b->nvm_write_budget >= 0 && (unsigned long)b->nvm_write_budget < len) {
        /* Simulated power loss: only a prefix lands. */
        n = (size_t)b->nvm_write_budget;
        power_lost = true;
    }
    if (n > 0u)
        memcpy(&b->nvm[offset], buf, n);
    if (b->nvm_write_budget >= 0)
        b->nvm_write_budget -= (long)n;
    int rc = HAL_OK;
    if (b->nvm_path != NULL && n > 0u)
        rc = nvm_mirror(b);
    return power_lost ? HAL_EIO : rc;
}

/* ------------------------------------------------------------ watchdog */

int hal_watchdog_start(uint32_t timeout_ms)
{
    hal_host_board *b = g_board;
    if (b == NULL)
        return HAL_EIO;
    if (timeout_ms < 1u || timeout_ms > 4000u)
        return HAL_EINVAL;
    b->wdg_timeout_ms = timeout_ms;
    b->wdg_last_kick_s = b->t_s;
    return HAL_OK;
}

/* The host board starts as from power: it has no reset of its own. */
uint32_t hal_reset_cause(void) { return HAL_RESET_POWER_ON; }

void hal_watchdog_kick(void)
{
    hal_host_board *b = g_board;
    if (b != NULL)
        b->wdg_last_kick_s = b->t_s;
}
