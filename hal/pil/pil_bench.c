/**
 * @file pil_bench.c
 * @brief Processor-in-the-loop benchmark and equivalence check of the WHOLE
 *        control interrupt on the Cortex-M4F (QEMU mps2-an386, exact
 *        instruction counts with -icount shift=7, see icount.h).
 *
 * Usage (tools/pil_bench.sh and tests/pil do this):
 *   qemu-system-arm -M mps2-an386 ... -icount shift=7 -kernel dtc-pil.elf
 *     -semihosting-config enable=on,target=native,arg=dtc-pil,arg=REC1,arg=REC2...
 * Each REC is a recorded closed-loop SIL run (`dtc-sim run SCENARIO
 * --record-samples REC`, format in recording/tick_record.h). For every recorded tick the
 * program hands the board the recorded sample, fault input and missed-deadline
 * flag, sets the drive fields the background owns (run, speed reference,
 * clear-faults and quick-stop requests) to their recorded values, and raises
 * the control-tick interrupt in the NVIC. The interrupt is the real path:
 * hal_pil_tick_irq latches the sample and calls drive_isr (sample read through
 * the HAL -> ctl_step -> gates and hal_actuate -> telemetry snapshot -> scope,
 * which is kept armed and capturing four channels every tick).
 *
 * Counted: every instruction from the interrupt's first to its return, i.e.
 * the instructions between two SysTick readings around the pending store,
 * less those of the same site raising the same interrupt with an empty handler
 * (one return instruction, counted back in) in the same vector slot.
 *
 * After each tick the outputs (vectors, duty split, gate enable, run state,
 * faults, torque reference, flux, speed estimate, observer state) are compared
 * bit for bit with what the host build produced in the SIL run; the first
 * difference of each file is printed.
 *
 * Printed: per recording one line (ticks, identical or first difference);
 * then the table of instructions per interrupt, min / mean / max, per
 * controller and per run state over everything run, the worst tick of each
 * controller, estimated cycles and time at 170 MHz, the stack high-water mark
 * of the interrupt.
 *
 * Exit status: 0 done and identical, 1 the instruction counter failed its
 * self-check (run without -icount shift=7?), 2 bad command line or recording,
 * 3 exception, 4 outputs differ from the host build's.
 */
#include <stdint.h>
#include <string.h>

#include "dtc/drive.h"
#include "hal_pil.h"
#include "icount.h"
#include "semihost.h"
#include "recording/tick_record.h"

enum { EXIT_OK = 0, EXIT_COUNTER = 1, EXIT_USAGE = 2, EXIT_MISMATCH = 4 };

#define PIL_MAX_FILES 64u
#define PIL_CMDLINE_BYTES 8192u
#define PIL_CHUNK_RECORDS 128u
#define PIL_CFG_WORDS_MAX 128u
#define PIL_FW_FRAC 0.98f /* running with the flux reference below 98 % of nominal: field weakening */

/* ------------------------------------------------------------ NVIC, vectors */

#define NVIC_ISER0 (*(volatile uint32_t *)0xE000E100u)
#define NVIC_ISPR0 (*(volatile uint32_t *)0xE000E200u)
#define SCB_VTOR (*(volatile uint32_t *)0xE000ED08u)
#define PIL_VECTORS 48u

typedef void (*vector_fn)(void);
extern const vector_fn g_pil_vectors[PIL_VECTORS];

/* The vector table in RAM, so the bench can swap the tick's handler (VTOR
 * needs the table aligned to its size rounded up to a power of two). */
__attribute__((aligned(256))) static vector_fn g_ram_vectors[PIL_VECTORS];

#define TICK_VECTOR (16u + HAL_PIL_TICK_IRQ)

/* One instruction: the calibration handler. */
__attribute__((naked)) static void empty_irq(void) { __asm volatile("bx lr"); }

/* An empty tick handler (for the PIL board's own share). */
__attribute__((noinline)) static void empty_handler(void *ctx) { (void)ctx; }

/* SP at the measuring site, where the interrupt's frame is pushed. */
static volatile uintptr_t g_site_sp;

static uintptr_t stack_pointer(void)
{
    uintptr_t sp;
    __asm volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

/* The measuring site: raise the tick interrupt and count until it returned. */
__attribute__((noinline)) static uint32_t measure_irq(void)
{
    g_site_sp = stack_pointer();
    uint32_t t0 = icount_now();
    NVIC_ISPR0 = 1u << HAL_PIL_TICK_IRQ;
    __asm volatile("dsb\n\tisb" ::: "memory");
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

enum { CLS_STOPPED, CLS_MAGNETISING, CLS_RUNNING, CLS_FAULTED, CLS_FIELD_WEAKENING, CLS_ALL, CLS_N };

static const char *const k_class_name[CLS_N] = {"stopped",  "magnetising",      "running",
                                                "faulted",  "field weakening",  "all states"};
static const char *const k_mode_name[3] = {"ip", "nominal", "rbfn"};

typedef struct {
    pil_stat cls[CLS_N];
    pil_stat slot[CTL_SLOW_SLOTS]; /* running and field-weakening ticks by the slow tasks' slot (ctl.h) */
    uint32_t worst_tick;
    uint8_t worst_state;
    char worst_file[TICK_REC_NAME_LEN + 1u];
} mode_stats;

/* ------------------------------------------------------------ the drive */

/* Large structs live in .bss. */
static drive g_drive;
static uint8_t g_chunk[PIL_CHUNK_RECORDS * TICK_REC_RECORD_BYTES];
static uint32_t g_cfg_words[PIL_CFG_WORDS_MAX];
static mode_stats g_stats[3];

/* The scope kept capturing every tick, re-armed whenever a record is complete,
 * in its most expensive configuration: the interrupt copies every channel's
 * word alike (scope.h), and these four are the snapshot fields it works out
 * only for a scope that reads them (drive_scope_arm; about 28 a tick more than
 * four plain fields). */
static void scope_keep_armed(drive *d)
{
    if (d->scope.state == SCOPE_ARMED || d->scope.state == SCOPE_TRIGGERED)
        return;
    const scope_src src[SCOPE_CHANNELS] = {
        {(uint16_t)offsetof(drive_snapshot, speed_err_rad_s), SCOPE_SRC_F32},
        {(uint16_t)offsetof(drive_snapshot, vdc_V), SCOPE_SRC_F32},
        {(uint16_t)offsetof(drive_snapshot, i_peak_A), SCOPE_SRC_F32},
        {(uint16_t)offsetof(drive_snapshot, vdc_diff_V), SCOPE_SRC_F32},
    };
    for (unsigned ch = 0u; ch < SCOPE_CHANNELS; ch++)
        d->scope.cfg.channel[ch] = (uint8_t)(ch + 1u);
    d->scope.cfg.trigger = SCOPE_TRIG_REF;
    d->scope.cfg.pretrigger = SCOPE_SAMPLES / 2u;
    d->scope.cfg.decimation = 1u;
    drive_scope_arm(d, src, SCOPE_CHANNELS);
}

static void print_err(const char *file, const char *what)
{
    pil_line l = {.len = 0u};
    line_str(&l, "pil_bench: ");
    line_str(&l, file);
    line_str(&l, ": ");
    line_str(&l, what);
    line_flush(&l);
}

static const char *base_name(const char *path)
{
    const char *b = path;
    for (const char *p = path; *p != '\0'; p++)
        if (*p == '/')
            b = p + 1;
    return b;
}

static void copy_name(char *dst, const char *path)
{
    const char *b = base_name(path);
    size_t i = 0u;
    for (; i < TICK_REC_NAME_LEN && b[i] != '\0'; i++)
        dst[i] = b[i];
    dst[i] = '\0';
}

static int32_t read_exact(int h, void *buf, uint32_t len)
{
    uint32_t got = 0u;
    while (got < len) {
        int32_t n = semihost_read(h, (uint8_t *)buf + got, len - got);
        if (n <= 0)
            break;
        got += (uint32_t)n;
    }
    return (int32_t)got;
}

/* ------------------------------------------------------------ stack */

/* Paint the stack below the caller's frame, run, then find the deepest word
 * overwritten: the high-water mark of everything run meanwhile, interrupt
 * frames included (thread and handler mode share the main stack here). */
#define STACK_PAINT_BYTES 16384u
#define STACK_PAINT_MARGIN 64u
#define STACK_PAINT_WORD 0xA5A5A5A5u

__attribute__((noinline)) static uintptr_t stack_paint(void)
{
    uintptr_t top = (stack_pointer() - STACK_PAINT_MARGIN) & ~(uintptr_t)3u;
    for (volatile uint32_t *p = (volatile uint32_t *)(top - STACK_PAINT_BYTES); p < (volatile uint32_t *)top; p++)
        *p = STACK_PAINT_WORD;
    return top;
}

static uintptr_t stack_low_water(uintptr_t top)
{
    const volatile uint32_t *p = (const volatile uint32_t *)(top - STACK_PAINT_BYTES);
    while (p < (const volatile uint32_t *)top && *p == STACK_PAINT_WORD)
        p++;
    return (uintptr_t)p;
}

/* Deepest interrupt stack seen: bytes below the measuring site's SP. */
static uint32_t g_isr_stack_bytes;

/*
 * Replay one recording. @return 0 identical, EXIT_MISMATCH, or EXIT_USAGE
 * (unreadable or inconsistent file).
 */
static int replay(const char *path, uint32_t site_overhead)
{
    int h = semihost_open_read(path);
    if (h < 0) {
        print_err(path, "cannot open");
        return EXIT_USAGE;
    }
    int32_t flen = semihost_flen(h);
    uint8_t hdr[TICK_REC_HEADER_BYTES];
    tick_rec_header head;
    const char *why = "short header";
    if (flen < (int32_t)TICK_REC_HEADER_BYTES || read_exact(h, hdr, sizeof hdr) != (int32_t)sizeof hdr ||
        tick_rec_decode_header(hdr, &head, &why) != 0) {
        print_err(path, why);
        semihost_close(h);
        return EXIT_USAGE;
    }
    uint32_t cfg_bytes = head.cfg_words * 4u;
    if (head.cfg_words > PIL_CFG_WORDS_MAX || read_exact(h, g_chunk, cfg_bytes) != (int32_t)cfg_bytes) {
        print_err(path, "configuration missing or too long");
        semihost_close(h);
        return EXIT_USAGE;
    }
    for (uint32_t i = 0u; i < head.cfg_words; i++)
        g_cfg_words[i] = (uint32_t)g_chunk[4u * i] | ((uint32_t)g_chunk[4u * i + 1u] << 8) |
                         ((uint32_t)g_chunk[4u * i + 2u] << 16) | ((uint32_t)g_chunk[4u * i + 3u] << 24);
    uint32_t body = (uint32_t)flen - TICK_REC_HEADER_BYTES - cfg_bytes;
    if (body % TICK_REC_RECORD_BYTES != 0u || body == 0u) {
        print_err(path, "the tick records are truncated (size not a whole number of records)");
        semihost_close(h);
        return EXIT_USAGE;
    }
    uint32_t n_ticks = body / TICK_REC_RECORD_BYTES;

    /* The drive as dtc-sim's configure_firmware leaves it: defaults (erased
     * NVM), the recorded settings, derived here by this build. */
    hal_pil_board_reset();
    drive *d = &g_drive;
    drive_init(d);
    ctl_cfg *c = drive_cfg_edit(d);
    tick_rec_cfg_apply(c, g_cfg_words);
    drive_cfg_commit(d);
    ctl_init(&d->ctl, drive_cfg(d));
    if (hal_tick_start(drive_isr, d, head.period_us) != HAL_OK) {
        print_err(path, "hal_tick_start refused the period");
        semihost_close(h);
        return EXIT_USAGE;
    }
    const real_t psi_nom = drive_cfg(d)->dtc.psi_ref_Wb;
    mode_stats *ms = &g_stats[head.speed_mode];

    uint32_t first_diff_tick = UINT32_MAX;
    const char *first_diff = NULL;
    uint32_t done = 0u;
    uintptr_t painted = stack_paint();
    pil_stat file_stat;
    stat_reset(&file_stat);
    while (done < n_ticks) {
        uint32_t n = n_ticks - done < PIL_CHUNK_RECORDS ? n_ticks - done : PIL_CHUNK_RECORDS;
        if (read_exact(h, g_chunk, n * TICK_REC_RECORD_BYTES) != (int32_t)(n * TICK_REC_RECORD_BYTES)) {
            print_err(path, "read failed");
            semihost_close(h);
            return EXIT_USAGE;
        }
        for (uint32_t i = 0u; i < n; i++) {
            tick_rec want, got;
            tick_rec_decode(&g_chunk[i * TICK_REC_RECORD_BYTES], &want);
            /* What the background left for this tick, then the board's inputs. */
            d->run = (want.flags & TICK_REC_RUN) != 0u;
            d->speed_ref_rad_s = want.speed_ref_rad_s;
            d->clear_faults_req = (want.flags & TICK_REC_CLEAR_REQ) != 0u;
            d->quick_stop_req = (want.flags & TICK_REC_QSTOP_REQ) != 0u;
            d->qs.decel_rad_s2 = want.qs_decel_rad_s2;
            hal_pil_set_inputs(&want.sample, (want.flags & TICK_REC_SAMPLE_NEW) != 0u,
                               (want.flags & TICK_REC_FAULT_INPUT) != 0u, (want.flags & TICK_REC_TICK_MISSED) != 0u);
            scope_keep_armed(d);

            uint32_t raw = measure_irq();
            uint32_t cnt = raw > site_overhead ? raw - site_overhead : 0u;

            memset(&got, 0, sizeof got);
            tick_rec_set_outputs(&got, &d->out, &d->ctl.obs);
            const char *diff = tick_rec_diff(&got, &want);
            if (diff != NULL && first_diff == NULL) {
                first_diff = diff;
                first_diff_tick = want.tick;
            }
            uint8_t st = d->out.tel.state;
            unsigned cls = st <= (uint8_t)CTL_FAULTED ? st : (unsigned)CLS_FAULTED;
            if (st == (uint8_t)CTL_RUNNING && d->out.tel.psi_ref_Wb < PIL_FW_FRAC * psi_nom)
                cls = CLS_FIELD_WEAKENING;
            stat_add(&ms->cls[cls], cnt);
            if (st == (uint8_t)CTL_RUNNING) /* the tick's slot: detect_faults advanced it first */
                stat_add(&ms->slot[d->ctl.slow_slot & (CTL_SLOW_SLOTS - 1u)], cnt);
            if (cnt > ms->cls[CLS_ALL].max) {
                ms->worst_tick = want.tick;
                ms->worst_state = (uint8_t)cls;
                copy_name(ms->worst_file, path);
            }
            stat_add(&ms->cls[CLS_ALL], cnt);
            stat_add(&file_stat, cnt);
        }
        done += n;
    }
    semihost_close(h);
    hal_tick_stop();
    uint32_t isr_stack = (uint32_t)(g_site_sp - stack_low_water(painted));
    if (isr_stack > g_isr_stack_bytes)
        g_isr_stack_bytes = isr_stack;

    pil_line l = {.len = 0u};
    line_str(&l, "  ");
    line_str(&l, base_name(path));
    line_str(&l, " = ");
    line_str(&l, base_name(head.name));
    line_str(&l, " (");
    line_str(&l, k_mode_name[head.speed_mode]);
    line_str(&l, "): ");
    line_u32(&l, n_ticks);
    line_str(&l, " ticks, min ");
    line_u32(&l, file_stat.min);
    line_str(&l, ", mean ");
    line_tenths(&l, stat_mean_tenths(&file_stat));
    line_str(&l, ", max ");
    line_u32(&l, file_stat.max);
    line_str(&l, first_diff == NULL ? "; bit-identical to the host build" : "; DIFFERS from the host build");
    line_flush(&l);
    if (first_diff != NULL) {
        line_str(&l, "    first difference at tick ");
        line_u32(&l, first_diff_tick);
        line_str(&l, ": ");
        line_str(&l, first_diff);
        line_flush(&l);
        return EXIT_MISMATCH;
    }
    return EXIT_OK;
}

/* ------------------------------------------------------------ output */

/* Cycles and microseconds at 170 MHz for @p instr at @p cpi_tenths / 10 cycles per instruction. */
static void line_cycles(pil_line *l, uint32_t instr, uint32_t cpi_tenths)
{
    uint32_t cycles = (uint32_t)(((uint64_t)instr * cpi_tenths + 5u) / 10u);
    line_u32(l, cycles);
    line_str(l, " cyc = ");
    line_tenths(l, (uint32_t)(((uint64_t)cycles * 10u + 85u) / 170u));
    line_str(l, " us");
}

static void pad_to(pil_line *l, size_t col)
{
    while (l->len < col && l->len + 1u < sizeof l->buf)
        l->buf[l->len++] = ' ';
}

static void print_table(void)
{
    pil_line l = {.len = 0u};
    line_str(&l, "whole control interrupt, instructions per tick (worst over every recording run):");
    line_flush(&l);
    line_str(&l, "| controller | run state | ticks | min | mean | max |");
    line_flush(&l);
    line_str(&l, "|---|---|---:|---:|---:|---:|");
    line_flush(&l);
    for (unsigned m = 0u; m < 3u; m++) {
        for (unsigned c = 0u; c < CLS_N; c++) {
            unsigned cls = c == 0u ? (unsigned)CLS_ALL : c - 1u; /* "all" first */
            const pil_stat *s = &g_stats[m].cls[cls];
            if (s->n == 0u)
                continue;
            line_str(&l, "| ");
            line_str(&l, k_mode_name[m]);
            line_str(&l, " | ");
            line_str(&l, k_class_name[cls]);
            line_str(&l, " | ");
            line_u32(&l, s->n);
            line_str(&l, " | ");
            line_u32(&l, s->min);
            line_str(&l, " | ");
            line_tenths(&l, stat_mean_tenths(s));
            line_str(&l, " | ");
            line_u32(&l, s->max);
            line_str(&l, " |");
            line_flush(&l);
        }
    }
    /* Where the slow tasks' turns (ctl.h) put the load: the worst tick is the
     * DTC's worst path in the heaviest slot it meets. */
    line_str(&l, "running ticks (field weakening included) by slow-task slot, mean / max:");
    line_flush(&l);
    line_str(&l, "| controller |");
    for (unsigned k = 0u; k < CTL_SLOW_SLOTS; k++) {
        line_str(&l, " slot ");
        line_u32(&l, k);
        line_str(&l, " |");
    }
    line_flush(&l);
    line_str(&l, "|---|");
    for (unsigned k = 0u; k < CTL_SLOW_SLOTS; k++)
        line_str(&l, "---:|");
    line_flush(&l);
    for (unsigned m = 0u; m < 3u; m++) {
        if (g_stats[m].cls[CLS_ALL].n == 0u)
            continue;
        line_str(&l, "| ");
        line_str(&l, k_mode_name[m]);
        line_str(&l, " |");
        for (unsigned k = 0u; k < CTL_SLOW_SLOTS; k++) {
            const pil_stat *s = &g_stats[m].slot[k];
            line_str(&l, " ");
            line_tenths(&l, stat_mean_tenths(s));
            line_str(&l, " / ");
            line_u32(&l, s->n != 0u ? s->max : 0u);
            line_str(&l, " |");
        }
        line_flush(&l);
    }
    line_str(&l, "worst ticks:");
    line_flush(&l);
    for (unsigned m = 0u; m < 3u; m++) {
        const mode_stats *s = &g_stats[m];
        if (s->cls[CLS_ALL].n == 0u)
            continue;
        line_str(&l, "  ");
        line_str(&l, k_mode_name[m]);
        line_str(&l, ": ");
        line_u32(&l, s->cls[CLS_ALL].max);
        line_str(&l, " at tick ");
        line_u32(&l, s->worst_tick);
        line_str(&l, " (");
        line_str(&l, k_class_name[s->worst_state]);
        line_str(&l, ") of ");
        line_str(&l, s->worst_file);
        line_flush(&l);
    }
    /* QEMU has no timing model. Cortex-M4 TRM (r0p1, ch. 3 and 7): ALU and
     * most FP 1 cycle, loads/VLDR 2 (1 when pipelined), taken branches 1 + P
     * (P 1..3), VDIV/VSQRT 14, VFMA 3: mixed control code runs at about 1.5
     * cycles per instruction from zero-wait memory (bracket 1.2 .. 2.0). */
    line_str(&l, "estimated at 170 MHz, 1.5 cycles/instruction (bracket 1.2 .. 2.0, Cortex-M4 TRM timings):");
    line_flush(&l);
    for (unsigned m = 0u; m < 3u; m++) {
        const pil_stat *s = &g_stats[m].cls[CLS_ALL];
        if (s->n == 0u)
            continue;
        line_str(&l, "  ");
        line_str(&l, k_mode_name[m]);
        pad_to(&l, 10u);
        line_str(&l, "max ");
        line_cycles(&l, s->max, 15u);
        line_str(&l, " (");
        line_tenths(&l, (uint32_t)(((uint64_t)s->max * 12u + 85u) / 170u));
        line_str(&l, " .. ");
        line_tenths(&l, (uint32_t)(((uint64_t)s->max * 20u + 85u) / 170u));
        line_str(&l, " us); mean ");
        line_cycles(&l, (uint32_t)((s->sum + s->n / 2u) / s->n), 15u);
        line_str(&l, "; of the 200 us period");
        line_flush(&l);
    }
}

/* ------------------------------------------------------------ command line */

static char g_cmd[PIL_CMDLINE_BYTES];

/* Split the command line in place: program name, then the recordings. */
static int parse_files(const char *files[PIL_MAX_FILES], uint32_t *n)
{
    *n = 0u;
    if (semihost_cmdline(g_cmd, sizeof g_cmd) != 0)
        return -1;
    char *p = g_cmd;
    bool first = true;
    while (*p != '\0') {
        while (*p == ' ')
            *p++ = '\0';
        if (*p == '\0')
            break;
        if (!first) {
            if (*n >= PIL_MAX_FILES)
                return -1;
            files[(*n)++] = p;
        }
        first = false;
        while (*p != '\0' && *p != ' ')
            p++;
    }
    return *n > 0u ? 0 : -1;
}

int main(void)
{
    pil_line l = {.len = 0u};
    const char *files[PIL_MAX_FILES];
    uint32_t n_files;
    if (parse_files(files, &n_files) != 0) {
        line_str(&l, "pil_bench: usage: dtc-pil REC [REC...] (recordings of dtc-sim run --record-samples; at most 64)");
        line_flush(&l);
        return EXIT_USAGE;
    }

    /* The vector table to RAM, the tick interrupt enabled. */
    for (unsigned i = 0u; i < PIL_VECTORS; i++)
        g_ram_vectors[i] = g_pil_vectors[i];
    SCB_VTOR = (uint32_t)(uintptr_t)g_ram_vectors;
    __asm volatile("dsb\n\tisb" ::: "memory");
    NVIC_ISER0 = 1u << HAL_PIL_TICK_IRQ;

    icount_start();
    /* Warm-up: the first readings after SysTick starts (and the first run of
     * each measuring site) can be off by one; they are discarded. */
    (void)measure_nothing();
    (void)measure_nops();
    (void)measure_nothing();
    uint32_t base = measure_nothing();
    uint32_t nops = measure_nops();
    uint32_t nops2 = measure_nops();
    /* The site against itself: the same pending store, the same vector slot,
     * an empty handler (one instruction, its return). */
    g_ram_vectors[TICK_VECTOR] = empty_irq;
    (void)measure_irq();
    uint32_t empty = measure_irq();
    uint32_t empty2 = measure_irq();
    /* The PIL board's own share: the tick handler with an empty drive handler. */
    g_ram_vectors[TICK_VECTOR] = hal_pil_tick_irq;
    hal_pil_board_reset();
    (void)hal_tick_start(empty_handler, NULL, 200u);
    hal_sample s0;
    memset(&s0, 0, sizeof s0);
    hal_pil_set_inputs(&s0, true, false, false);
    (void)measure_irq();
    hal_pil_set_inputs(&s0, true, false, false);
    uint32_t board_raw = measure_irq();
    hal_tick_stop();
    bool ok = nops == base + 100u && nops2 == nops && empty == empty2 && empty > base;

    line_str(&l, "pil_bench: whole control interrupt on Cortex-M4F (QEMU mps2-an386, -icount shift=7)");
    line_flush(&l);
    line_str(&l, "counter self-check: 100 nops -> ");
    line_u32(&l, nops - base);
    line_str(&l, " instructions; empty interrupt at the measuring site -> ");
    line_u32(&l, empty);
    line_str(&l, ok ? " -> ok" : " -> FAILED (run QEMU with -icount shift=7)");
    line_flush(&l);
    if (!ok)
        return EXIT_COUNTER;
    /* Counted back in: the empty handler's one instruction (its return), which
     * the real handler has too. */
    uint32_t site_overhead = empty - 1u;
    line_str(&l, "PIL board's tick handler with an empty drive handler (sample latch + dispatch): ");
    line_u32(&l, board_raw - site_overhead);
    line_str(&l, " instructions");
    line_flush(&l);

    line_str(&l, "recordings:");
    line_flush(&l);
    for (unsigned m = 0u; m < 3u; m++) {
        for (unsigned c = 0u; c < CLS_N; c++)
            stat_reset(&g_stats[m].cls[c]);
        for (unsigned k = 0u; k < CTL_SLOW_SLOTS; k++)
            stat_reset(&g_stats[m].slot[k]);
        g_stats[m].worst_tick = 0u;
        g_stats[m].worst_file[0] = '\0';
    }
    int status = EXIT_OK;
    for (uint32_t i = 0u; i < n_files; i++) {
        int rc = replay(files[i], site_overhead);
        if (rc == EXIT_USAGE)
            return EXIT_USAGE;
        if (rc != EXIT_OK)
            status = rc;
    }
    print_table();
    line_str(&l, "interrupt stack high-water (exception frame with FP context + handler), measured: ");
    line_u32(&l, g_isr_stack_bytes);
    line_str(&l, " bytes below the measuring site's SP");
    line_flush(&l);
    line_str(&l, status == EXIT_OK ? "every recording: outputs bit-identical to the host build's at every tick"
                                   : "OUTPUTS DIFFER from the host build (see above)");
    line_flush(&l);
    return status;
}
