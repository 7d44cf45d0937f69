/**
 * @file pil_bench.c
 * @brief Processor-in-the-loop benchmark: instructions per control tick of
 *        ctl_step() cross-compiled for the Cortex-M4F, counted exactly under
 *        QEMU mps2-an386 with -icount shift=7 (see icount.h).
 *
 * Usage (tools/pil_bench.sh does this): qemu-system-arm -M mps2-an386 ...
 *   -semihosting-config enable=on,target=native,arg=dtc-pil,arg=<ticks>
 *
 * Inputs are synthetic but realistic: the 10 hp motor turning at 500 rpm
 * (16.7 Hz electrical) at no load: about 10.5 A of magnetising current and
 * 1.5 A of torque current, quantised like the board's 12-bit ADC (+-150 A,
 * 0..500 V) with +-1 LSB of pseudo-random noise, and a 155.5 V + 155.5 V DC
 * link with a small third-harmonic neutral-point ripple. The loop is open: the
 * currents do not respond to the vectors chosen, which is enough to run every
 * stage of the control step (observer, speed controller, DTC, protection).
 *
 * Each speed controller (IP, nominal, RBFN) runs from a fresh ctl_init() for
 * the given number of ticks (default 5000 = 1 s). Printed per controller:
 * min / mean / max instructions per ctl_step call, the same split by run
 * state, the fault bits at the end, an estimate of the time at 170 MHz, and a
 * digest of the outputs (to compare runs and, later, with the host build);
 * at the end, the stack high-water mark (painted stack).
 *
 * Exit status: 0 done, 1 the instruction counter failed its self-check
 * (QEMU run without -icount shift=7?), 2 bad command line, 3 exception.
 */
#include <stdint.h>
#include <string.h>

#include "dtc/ctl.h"
#include "dtc/num.h"
#include "icount.h"
#include "semihost.h"

#define PIL_TICKS_DEFAULT 5000u
#define PIL_TICKS_MAX 1000000u
#define PIL_PERIOD_S 2e-4f
#define PIL_SPEED_RAD_S (500.0f * 2.0f * NUM_PI / 60.0f) /* 500 rpm, mechanical */
#define PIL_POLE_PAIRS 2.0f
#define PIL_ID_A 10.5f  /* magnetising current for 0.45 Wb (psi / Ls) */
#define PIL_IQ_A 1.5f   /* torque current for friction at 500 rpm */
#define PIL_VC_V 155.5f /* each capacitor: 311 V / 2 */
#define PIL_NP_RIPPLE_V 0.5f
#define ADC_CODES 4095.0f
#define ADC_I_FS_A 150.0f
#define ADC_V_FS_V 500.0f

enum { EXIT_OK = 0, EXIT_COUNTER = 1, EXIT_USAGE = 2 };

typedef void (*step_fn)(ctl_state *, const ctl_cfg *, const ctl_in *, ctl_out *);

/* Large structs live in .bss, not on the stack. */
static ctl_cfg g_cfg;
static ctl_state g_state;
static ctl_in g_in;
static ctl_out g_out;

/* Both the measured and the calibration call go through this pointer, so the
 * call sequence around them is the same instructions. */
static step_fn volatile g_step;

/* ------------------------------------------------------------ statistics */

typedef struct {
    uint32_t n, min, max;
    uint64_t sum;
} pil_stat;

static void stat_reset(pil_stat *s)
{
    s->n = 0u;
    s->min = UINT32_MAX;
    s->max = 0u;
    s->sum = 0u;
}

static void stat_add(pil_stat *s, uint32_t v)
{
    s->n++;
    s->sum += v;
    if (v < s->min)
        s->min = v;
    if (v > s->max)
        s->max = v;
}

static uint32_t stat_mean_tenths(const pil_stat *s)
{
    return s->n != 0u ? (uint32_t)((s->sum * 10u + s->n / 2u) / s->n) : 0u;
}

static void line_stat(pil_line *l, const pil_stat *s)
{
    line_str(l, "min ");
    line_u32(l, s->n != 0u ? s->min : 0u);
    line_str(l, "  mean ");
    line_tenths(l, stat_mean_tenths(s));
    line_str(l, "  max ");
    line_u32(l, s->max);
}

/* ------------------------------------------------------------- calibration */

/* The body is a single return instruction. */
__attribute__((noinline)) static void empty_step(ctl_state *s, const ctl_cfg *c, const ctl_in *i,
                                                 ctl_out *o)
{
    (void)s;
    (void)c;
    (void)i;
    (void)o;
}

static uint32_t measure_step(void)
{
    step_fn fn = g_step;
    uint32_t t0 = icount_now();
    fn(&g_state, &g_cfg, &g_in, &g_out);
    uint32_t t1 = icount_now();
    return icount_between(t0, t1);
}

static uint32_t measure_nops(void)
{
    uint32_t t0 = icount_now();
    __asm volatile(".rept 100\n\tnop\n\t.endr" ::: "memory");
    uint32_t t1 = icount_now();
    return icount_between(t0, t1);
}

static uint32_t measure_nothing(void)
{
    uint32_t t0 = icount_now();
    uint32_t t1 = icount_now();
    return icount_between(t0, t1);
}

/* ------------------------------------------------------------- stack */

/* Paint the stack below the caller's frame, run, then find the deepest word
 * overwritten: the stack high-water mark of everything called meanwhile. */
#define STACK_PAINT_BYTES 16384u
#define STACK_PAINT_MARGIN 256u /* left untouched below the painter's frame */
#define STACK_PAINT_WORD 0xA5A5A5A5u

static uintptr_t stack_pointer(void)
{
    uintptr_t sp;
    __asm volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

__attribute__((noinline)) static uintptr_t stack_paint(void)
{
    uintptr_t top = (stack_pointer() - STACK_PAINT_MARGIN) & ~(uintptr_t)3u;
    for (volatile uint32_t *p = (volatile uint32_t *)(top - STACK_PAINT_BYTES); p < (volatile uint32_t *)top; p++)
        *p = STACK_PAINT_WORD;
    return top;
}

/* Bytes of stack used below @p ref since stack_paint() returned @p top. */
static uint32_t stack_used(uintptr_t top, uintptr_t ref)
{
    const volatile uint32_t *p = (const volatile uint32_t *)(top - STACK_PAINT_BYTES);
    while (p < (const volatile uint32_t *)top && *p == STACK_PAINT_WORD)
        p++;
    return (uint32_t)(ref - (uintptr_t)p);
}

/* ------------------------------------------------------------- inputs */

static uint32_t lcg_next(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state;
}

/* -1, 0 or +1 LSB. */
static int32_t adc_noise(uint32_t *rng) { return (int32_t)((lcg_next(rng) >> 16) % 3u) - 1; }

static int32_t adc_clamp(int32_t code) { return code < 0 ? 0 : (code > 4095 ? 4095 : code); }

static float adc_current_A(float i_A, uint32_t *rng)
{
    float code = (i_A / ADC_I_FS_A + 1.0f) * 0.5f * ADC_CODES;
    int32_t c = adc_clamp((int32_t)(code + 0.5f) + adc_noise(rng));
    return ((float)c / ADC_CODES * 2.0f - 1.0f) * ADC_I_FS_A;
}

static float adc_voltage_V(float v_V, uint32_t *rng)
{
    int32_t c = adc_clamp((int32_t)(v_V / ADC_V_FS_V * ADC_CODES + 0.5f) + adc_noise(rng));
    return (float)c / ADC_CODES * ADC_V_FS_V;
}

static void synth_inputs(uint32_t k, uint32_t *rng, ctl_in *in)
{
    const float two_pi_3 = 2.0f * NUM_PI / 3.0f;
    float omega_e = PIL_SPEED_RAD_S * PIL_POLE_PAIRS;
    /* Wrap the angle from the tick count so it never loses precision. */
    uint32_t ticks_per_rev = (uint32_t)(2.0f * NUM_PI / (omega_e * PIL_PERIOD_S) + 0.5f);
    float th = (float)(k % ticks_per_rev) * (2.0f * NUM_PI / (float)ticks_per_rev);

    float ia = PIL_ID_A * cosf(th) - PIL_IQ_A * sinf(th);
    float ib = PIL_ID_A * cosf(th - two_pi_3) - PIL_IQ_A * sinf(th - two_pi_3);
    float ic = -ia - ib;
    float ripple = PIL_NP_RIPPLE_V * sinf(3.0f * th);

    memset(in, 0, sizeof *in);
    in->sample.ia_A = adc_current_A(ia, rng);
    in->sample.ib_A = adc_current_A(ib, rng);
    in->sample.ic_A = adc_current_A(ic, rng);
    in->sample.vc1_V = adc_voltage_V(PIL_VC_V + ripple, rng);
    in->sample.vc2_V = adc_voltage_V(PIL_VC_V - ripple, rng);
    in->sample.speed_meas_rad_s = PIL_SPEED_RAD_S;
    in->sample.speed_meas_valid = true;
    in->sample.seq = k;
    in->sample_fresh = true;
    in->run = true;
    in->speed_ref_rad_s = PIL_SPEED_RAD_S;
    in->fault_input = false;
}

/* ------------------------------------------------------------- digest */

static uint32_t fnv1a(uint32_t h, const void *p, size_t n)
{
    const uint8_t *b = (const uint8_t *)p;
    for (size_t i = 0u; i < n; i++) {
        h ^= b[i];
        h *= 16777619u;
    }
    return h;
}

static uint32_t digest_out(uint32_t h, const ctl_out *o)
{
    h = fnv1a(h, o->act.vector, sizeof o->act.vector);
    h = fnv1a(h, &o->act.duty0, sizeof o->act.duty0);
    h = fnv1a(h, &o->gate_enable, sizeof o->gate_enable);
    h = fnv1a(h, &o->tel.te_ref_Nm, sizeof o->tel.te_ref_Nm);
    h = fnv1a(h, &o->tel.omega_est_rad_s, sizeof o->tel.omega_est_rad_s);
    return h;
}

/* ------------------------------------------------------------- runs */

static const char *const k_state_name[4] = {"stopped", "magnetising", "running", "faulted"};

static void run_mode(speed_mode mode, const char *name, uint32_t ticks, uint32_t call_overhead)
{
    pil_stat all, by_state[4];
    stat_reset(&all);
    for (unsigned i = 0u; i < 4u; i++)
        stat_reset(&by_state[i]);

    ctl_cfg_default(&g_cfg);
    g_cfg.speed.mode = mode;
    ctl_cfg_derive(&g_cfg);
    ctl_init(&g_state, &g_cfg);
    memset(&g_out, 0, sizeof g_out);
    g_step = ctl_step;

    uint32_t rng = 12345u;
    uint32_t digest = 2166136261u;
    for (uint32_t k = 0u; k < ticks; k++) {
        synth_inputs(k, &rng, &g_in);
        uint32_t raw = measure_step();
        /* ctl_step's own instructions, its return included: the measured
         * count less that of an empty function (one return) through the
         * same call sequence. */
        uint32_t n = raw > call_overhead ? raw - call_overhead : 0u;
        stat_add(&all, n);
        uint8_t st = g_out.tel.state;
        if (st < 4u)
            stat_add(&by_state[st], n);
        digest = digest_out(digest, &g_out);
    }

    pil_line l = {.len = 0u};
    line_str(&l, "controller ");
    line_str(&l, name);
    line_str(&l, ": ");
    line_u32(&l, ticks);
    line_str(&l, " ticks, instructions per ctl_step: ");
    line_stat(&l, &all);
    line_flush(&l);
    for (unsigned i = 0u; i < 4u; i++) {
        if (by_state[i].n == 0u)
            continue;
        line_str(&l, "    ");
        line_str(&l, k_state_name[i]);
        line_str(&l, " (");
        line_u32(&l, by_state[i].n);
        line_str(&l, " ticks): ");
        line_stat(&l, &by_state[i]);
        line_flush(&l);
    }
    /* QEMU has no timing model: bracket the time with 1.2 and 2.0 cycles per
     * instruction (Cortex-M4 TRM timings for mixed float control code). */
    line_str(&l, "    worst tick at 170 MHz: ");
    line_tenths(&l, (uint32_t)(((uint64_t)all.max * 12u + 85u) / 170u));
    line_str(&l, " .. ");
    line_tenths(&l, (uint32_t)(((uint64_t)all.max * 20u + 85u) / 170u));
    line_str(&l, " us of the 200 us period (1.2 .. 2.0 cycles/instruction)");
    line_flush(&l);
    line_str(&l, "    final state ");
    line_str(&l, g_out.tel.state < 4u ? k_state_name[g_out.tel.state] : "?");
    line_str(&l, ", faults ");
    line_hex32(&l, g_out.tel.faults);
    line_str(&l, ", omega_est ");
    float w = g_out.tel.omega_est_rad_s;
    line_str(&l, w < 0.0f ? "-" : "");
    line_tenths(&l, (uint32_t)(num_abs(w) * 10.0f + 0.5f));
    line_str(&l, " rad/s, output digest ");
    line_hex32(&l, digest);
    line_flush(&l);
}

static int parse_ticks(uint32_t *ticks)
{
    char cmd[64];
    *ticks = PIL_TICKS_DEFAULT;
    if (semihost_cmdline(cmd, sizeof cmd) != 0)
        return 0; /* no command line: default */
    const char *p = cmd;
    while (*p != '\0' && *p != ' ') /* skip the program name */
        p++;
    while (*p == ' ')
        p++;
    if (*p == '\0')
        return 0;
    uint32_t v = 0u;
    for (; *p >= '0' && *p <= '9'; p++) {
        v = v * 10u + (uint32_t)(*p - '0');
        if (v > PIL_TICKS_MAX)
            return -1;
    }
    if (*p != '\0' || v == 0u)
        return -1;
    *ticks = v;
    return 0;
}

int main(void)
{
    pil_line l = {.len = 0u};
    uint32_t ticks;
    if (parse_ticks(&ticks) != 0) {
        line_str(&l, "pil_bench: usage: dtc-pil [ticks], ticks 1..");
        line_u32(&l, PIL_TICKS_MAX);
        line_flush(&l);
        return EXIT_USAGE;
    }

    icount_start();
    /* Warm-up: the first readings after SysTick starts (and the first run of
     * each measuring site) can be off by one; they are discarded. */
    (void)measure_nothing();
    (void)measure_nops();
    (void)measure_nothing();
    /* Self-check: 100 NOPs must count as exactly 100 instructions, every time. */
    uint32_t base = measure_nothing();
    uint32_t nops = measure_nops();
    uint32_t nops2 = measure_nops();
    g_step = empty_step;
    (void)measure_step();
    uint32_t empty = measure_step();
    uint32_t empty2 = measure_step();
    bool ok = nops == base + 100u && nops2 == nops && empty == empty2 && empty > base;

    line_str(&l, "pil_bench: ctl_step on Cortex-M4F (QEMU mps2-an386, -icount shift=7)");
    line_flush(&l);
    line_str(&l, "counter self-check: 100 nops -> ");
    line_u32(&l, nops - base);
    line_str(&l, " instructions, empty call ");
    line_u32(&l, empty);
    line_str(&l, ok ? " -> ok" : " -> FAILED (run QEMU with -icount shift=7)");
    line_flush(&l);
    if (!ok)
        return EXIT_COUNTER;

    /* The empty function's body is one instruction (its return), which
     * ctl_step also has: count it back in. */
    uint32_t call_overhead = empty - 1u;

    uintptr_t sp_main = stack_pointer();
    uintptr_t painted = stack_paint();
    run_mode(SPEED_MODE_IP, "IP", ticks, call_overhead);
    run_mode(SPEED_MODE_NOMINAL, "nominal", ticks, call_overhead);
    run_mode(SPEED_MODE_RBFN, "RBFN", ticks, call_overhead);

    line_str(&l, "stack high-water below main (bench frames + ctl_step): ");
    line_u32(&l, stack_used(painted, sp_main));
    line_str(&l, " bytes");
    line_flush(&l);
    return EXIT_OK;
}
