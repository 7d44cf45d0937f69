/**
 * @file scenario_parse.c
 * @brief INI scenario parser (libinih), `--set` overrides and the final
 *        cross-checks. Every error is ONE line naming the file and line.
 *
 * inih's handler gets no line number, so the file is fed through a reader
 * that counts lines: when the handler runs, the counter is the line of the
 * key being handled. The reader also refuses over-long lines instead of
 * letting inih split them silently.
 */
#define _POSIX_C_SOURCE 200809L
#include "sim/scenario.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <ini.h>

#include "sim/control_keys.h"
#include "sim/decimal.h"
#include "sim/file_safety.h"
#include "dtc/ratings.h"

/* ------------------------------------------------------------ key table */

typedef enum {
    K_REAL,       /**< double */
    K_INT,        /**< int, whole number */
    K_SEED,       /**< double holding a whole number 0..2^32-1 */
    K_SUPPLY,     /**< "inverter" | "sine" -> int */
    K_CONTROLLER, /**< "ip" | "nominal" | "rbfn" -> int */
    K_MODEL,      /**< "exact" | "plate" -> int */
    K_IDENTIFY,   /**< "none" | "standstill" | "full" -> int (scenario_identify) */
} key_kind;

typedef struct {
    const char *section;
    const char *key;
    key_kind kind;
    size_t offset;      /**< into scenario */
    double min, max;
    bool min_open;      /**< min itself is refused (x > min) */
    double scale;       /**< stored = value * scale (phase_deg -> rad) */
    const char *unit;
    const char *plant_path; /**< field name in plant_check_config messages, or NULL */
    size_t has_offset;  /**< bool "given" flag in scenario, or 0 */
} key_def;

#define OFF(f) offsetof(scenario, f)
#define REALK(sec, k, f, lo, open, hi, unit, ppath) { sec, k, K_REAL, OFF(f), lo, hi, open, 1.0, unit, ppath, 0 }
/* Physical lower bounds (R > 0, J > 0, B >= 0, ...) of plant values are
 * judged by plant_check_config in scenario_finish, and its complaint is mapped
 * back to the key's line; the parser keeps only a sanity ceiling. */
#define PLANTK(sec, k, f, hi, unit, ppath) { sec, k, K_REAL, OFF(f), -1e300, hi, false, 1.0, unit, ppath, 0 }

static const key_def keys[] = {
    { "sim", "duration_s", K_REAL, OFF(duration_s), 0.0, 600.0, true, 1.0, "s", NULL, 0 },
    { "sim", "period_s", K_REAL, OFF(period_s), 50e-6, 1e-3, false, 1.0, "s", NULL, 0 },
    { "sim", "h_max_s", K_REAL, OFF(plant.h_max_s), 1e-7, 1e-4, false, 1.0, "s", "h_max_s", 0 },
    { "sim", "trace_interval_s", K_REAL, OFF(trace_interval_s), 50e-6, 600.0, false, 1.0, "s", NULL, 0 },
    { "sim", "seed", K_SEED, OFF(seed), 0.0, 4294967295.0, false, 1.0, "1", "seed", 0 },

    PLANTK("motor", "Rs_ohm", plant.motor.Rs_ohm, 100.0, "ohm", "Rs_ohm"),
    PLANTK("motor", "Rr_ohm", plant.motor.Rr_ohm, 100.0, "ohm", "Rr_ohm"),
    PLANTK("motor", "Lls_H", plant.motor.Lls_H, 10.0, "H", "Lls_H"),
    PLANTK("motor", "Llr_H", plant.motor.Llr_H, 10.0, "H", "Llr_H"),
    PLANTK("motor", "Lm_H", plant.motor.Lm_H, 10.0, "H", "Lm_H"),
    { "motor", "pole_pairs", K_INT, OFF(plant.motor.pole_pairs), 1.0, 32.0, false, 1.0, "1", "pole_pairs", 0 },
    PLANTK("motor", "J_kgm2", plant.motor.J_kgm2, 1e4, "kg m^2", "J_kgm2"),
    PLANTK("motor", "B_Nms", plant.motor.B_Nms, 1e3, "N m s/rad", "B_Nms"),
    PLANTK("motor", "Lm_sat_psi_Wb", plant.motor.Lm_sat_psi_Wb, 10.0, "Wb", "Lm_sat_psi_Wb"),
    PLANTK("motor", "Lm_sat_exponent", plant.motor.Lm_sat_exponent, 20.0, "1", "Lm_sat_exponent"),

    PLANTK("load", "coulomb_Nm", plant.load.coulomb_Nm, 1e4, "N m", "coulomb_Nm"),
    PLANTK("load", "viscous_Nms", plant.load.viscous_Nms, 1e3, "N m s/rad", "viscous_Nms"),
    PLANTK("load", "fan_Nms2", plant.load.fan_Nms2, 100.0, "N m s^2/rad^2", "fan_Nms2"),

    PLANTK("inverter", "dead_time_s", plant.inverter.dead_time_s, 50e-6, "s", "dead_time_s"),
    PLANTK("inverter", "v_on_V", plant.inverter.v_on_V, 50.0, "V", "v_on_V"),

    PLANTK("drive", "vdc_V", plant.dc.vdc_V, 1e4, "V", "vdc_V"),
    PLANTK("drive", "r_src_ohm", plant.dc.r_src_ohm, 1e3, "ohm", "r_src_ohm"),
    PLANTK("drive", "c1_F", plant.dc.c1_F, 10.0, "F", "c1_F"),
    PLANTK("drive", "c2_F", plant.dc.c2_F, 10.0, "F", "c2_F"),

    { "sensors", "adc_bits", K_INT, OFF(plant.sensor.adc_bits), 1.0, 16.0, false, 1.0, "bit", "adc_bits", 0 },
    PLANTK("sensors", "i_fs_A", plant.sensor.i_fs_A, 1e5, "A", "i_fs_A"),
    PLANTK("sensors", "v_fs_V", plant.sensor.v_fs_V, 1e5, "V", "v_fs_V"),
    PLANTK("sensors", "i_gain_a", plant.sensor.i_gain[0], 10.0, "1", "i_gain[0]"),
    PLANTK("sensors", "i_gain_b", plant.sensor.i_gain[1], 10.0, "1", "i_gain[1]"),
    PLANTK("sensors", "i_gain_c", plant.sensor.i_gain[2], 10.0, "1", "i_gain[2]"),
    REALK("sensors", "i_offset_a_A", plant.sensor.i_offset_A[0], -1e4, false, 1e4, "A", "i_offset_A[0]"),
    REALK("sensors", "i_offset_b_A", plant.sensor.i_offset_A[1], -1e4, false, 1e4, "A", "i_offset_A[1]"),
    REALK("sensors", "i_offset_c_A", plant.sensor.i_offset_A[2], -1e4, false, 1e4, "A", "i_offset_A[2]"),
    PLANTK("sensors", "v_gain_1", plant.sensor.v_gain[0], 10.0, "1", "v_gain[0]"),
    PLANTK("sensors", "v_gain_2", plant.sensor.v_gain[1], 10.0, "1", "v_gain[1]"),
    REALK("sensors", "v_offset_1_V", plant.sensor.v_offset_V[0], -1e4, false, 1e4, "V", "v_offset_V[0]"),
    REALK("sensors", "v_offset_2_V", plant.sensor.v_offset_V[1], -1e4, false, 1e4, "V", "v_offset_V[1]"),
    PLANTK("sensors", "i_noise_A", plant.sensor.i_noise_A, 1e4, "A", "i_noise_A"),
    PLANTK("sensors", "v_noise_V", plant.sensor.v_noise_V, 1e4, "V", "v_noise_V"),

    { "supply", "mode", K_SUPPLY, OFF(supply_mode), 0.0, 1.0, false, 1.0, "inverter|sine", "supply", 0 },
    PLANTK("supply", "v_ll_rms_V", plant.sine.v_ll_rms_V, 1e5, "V", "v_ll_rms_V"),
    PLANTK("supply", "f_Hz", plant.sine.f_Hz, 1e3, "Hz", "f_Hz"),
    { "supply", "phase_deg", K_REAL, OFF(phase_rad), -360.0, 360.0, false, 3.14159265358979323846 / 180.0,
      "deg", "phase_rad", 0 },

    /* the plate and the inverter's label: judged as a whole by ratings_check in scenario_finish */
#define RATINGK(k, f, unit) { "ratings", k, K_REAL, OFF(ratings.f), -1e300, 1e300, false, 1.0, unit, NULL, OFF(has_ratings) }
    RATINGK("P_W", P_W, "W"),
    RATINGK("V_ll_V", V_ll_V, "V"),
    RATINGK("I_A", I_A, "A"),
    RATINGK("f_Hz", f_Hz, "Hz"),
    RATINGK("n_rpm", n_rpm, "rpm"),
    RATINGK("cos_phi", cos_phi, "1"),
    RATINGK("vdc_nom_V", vdc_nom_V, "V"),
    RATINGK("inv_I_rated_A", inv_I_rated_A, "A"),
    RATINGK("inv_I_peak_A", inv_I_peak_A, "A"),
#undef RATINGK
    { "commission", "model", K_MODEL, OFF(model), 0.0, 1.0, false, 1.0, "exact|plate", NULL, 0 },
    /* the shaft's state when the run starts (a motor coasting before the run command) */
    { "plant", "initial_speed_rpm", K_REAL, OFF(plant.initial_omega_m_rad_s), -19000.0, 19000.0, false,
      2.0 * 3.14159265358979323846 / 60.0, "rpm", "initial_omega_m_rad_s", 0 },
    { "plant", "initial_flux_frac", K_REAL, OFF(plant.initial_flux_frac), 0.0, 1.2, false, 1.0, "1",
      "initial_flux_frac", 0 },

    { "controller", "name", K_CONTROLLER, OFF(controller), 0.0, 2.0, false, 1.0, "ip|nominal|rbfn", NULL, 0 },

    /* [commission]: the identification run before the profile */
    { "commission", "identify", K_IDENTIFY, OFF(identify), 0.0, 2.0, false, 1.0, "none|standstill|full", NULL, 0 },

    { "metrics", "disturbance_t_s", K_REAL, OFF(disturbance_t_s), 0.0, 600.0, false, 1.0, "s", NULL,
      OFF(has_disturbance) },
    { "metrics", "startup_end_s", K_REAL, OFF(startup_end_s), 0.0, 600.0, false, 1.0, "s", NULL,
      OFF(has_startup_end) },
};

#define N_KEYS (sizeof keys / sizeof keys[0])
_Static_assert(sizeof keys / sizeof keys[0] <= SCENARIO_MAX_SCALAR_KEYS, "raise SCENARIO_MAX_SCALAR_KEYS");

/* Repeated keys: section, key, the tokens they take. */
typedef enum { L_REF_STEP, L_REF_RAMP, L_LOAD_STEP, L_LOAD_RAMP, L_EVENT, L_EVENT_RAMP, L_FAULT, L_WINDOW } list_kind;

typedef struct {
    const char *section;
    const char *key;
    list_kind kind;
    int event_kind;     /**< for L_EVENT, L_EVENT_RAMP and L_FAULT (scenario_fault_kind) */
    const char *syntax; /**< for messages and docs */
} list_def;

static const list_def lists[] = {
    { "reference", "step", L_REF_STEP, 0, "T_S RPM" },
    { "reference", "ramp", L_REF_RAMP, 0, "T0_S T1_S RPM" },
    { "load", "step", L_LOAD_STEP, 0, "T_S NM" },
    { "load", "ramp", L_LOAD_RAMP, 0, "T0_S T1_S NM" },
    { "events", "J_scale", L_EVENT, SCENARIO_EV_J, "T_S FACTOR" },
    { "events", "B_scale", L_EVENT, SCENARIO_EV_B, "T_S FACTOR" },
    { "events", "Rs_scale", L_EVENT, SCENARIO_EV_RS, "T_S FACTOR" },
    { "events", "Rr_scale", L_EVENT, SCENARIO_EV_RR, "T_S FACTOR" },
    { "events", "Lm_scale", L_EVENT, SCENARIO_EV_LM, "T_S FACTOR" },
    { "events", "J_ramp", L_EVENT_RAMP, SCENARIO_EV_J, "T0_S T1_S FACTOR" },
    { "events", "B_ramp", L_EVENT_RAMP, SCENARIO_EV_B, "T0_S T1_S FACTOR" },
    { "events", "Rs_ramp", L_EVENT_RAMP, SCENARIO_EV_RS, "T0_S T1_S FACTOR" },
    { "events", "Rr_ramp", L_EVENT_RAMP, SCENARIO_EV_RR, "T0_S T1_S FACTOR" },
    { "events", "Lm_ramp", L_EVENT_RAMP, SCENARIO_EV_LM, "T0_S T1_S FACTOR" },
    { "faults", "gain", L_FAULT, SCENARIO_FAULT_GAIN, "T_S CHANNEL FACTOR" },
    { "faults", "offset", L_FAULT, SCENARIO_FAULT_OFFSET, "T_S CHANNEL VALUE" },
    { "faults", "stuck", L_FAULT, SCENARIO_FAULT_STUCK, "T_S CHANNEL" },
    { "faults", "lost", L_FAULT, SCENARIO_FAULT_LOST, "T_S CHANNEL" },
    { "faults", "invalid", L_FAULT, SCENARIO_FAULT_INVALID, "T_S CHANNEL" },
    { "faults", "restore", L_FAULT, SCENARIO_FAULT_RESTORE, "T_S CHANNEL" },
    { "faults", "vdc", L_FAULT, SCENARIO_FAULT_VDC, "T_S VOLTS" },
    { "faults", "stale", L_FAULT, SCENARIO_FAULT_STALE, "T_S" },
    { "faults", "overrun", L_FAULT, SCENARIO_FAULT_OVERRUN, "T_S" },
    { "faults", "hw", L_FAULT, SCENARIO_FAULT_HW, "T_S ON" },
    { "faults", "open_phase", L_FAULT, SCENARIO_FAULT_OPEN_PHASE, "T_S PHASE" },
    { "metrics", "window", L_WINDOW, 0, "NAME T0_S T1_S" },
};

#define N_LISTS (sizeof lists / sizeof lists[0])

static const char *const sections[] = { "sim", "motor", "load", "drive", "inverter", "sensors", "supply", "plant",
                                        "controller", "control", "reference", "events", "faults", "metrics",
                                        "ratings", "commission" };

bool scenario_key_info_at(size_t i, scenario_key_info *out)
{
    if (i >= N_KEYS)
        return false;
    out->section = keys[i].section;
    out->key = keys[i].key;
    out->unit = keys[i].unit;
    return true;
}

bool scenario_list_key_at(size_t i, scenario_key_info *out)
{
    if (i >= N_LISTS)
        return false;
    out->section = lists[i].section;
    out->key = lists[i].key;
    out->unit = lists[i].syntax;
    return true;
}

/* ------------------------------------------------------------ errors */

typedef struct {
    scenario *sc;
    char *err;
    size_t errlen;
    bool failed;
    int err_line;          /**< line of the first error */
    int line;              /**< line being handled (SCENARIO_LINE_SET for --set) */
    const char *set_name;  /**< "section.key" of the --set being applied */
    bool from_set;
    /* reader state */
    const char *text;     /**< the whole input (a file is read first, see read_scenario_file) */
} parse_ctx;

static void vfail_at(char *err, size_t errlen, const scenario *sc, int line, const char *set_name,
                     const char *fmt, va_list ap)
{
    char msg[384];
    vsnprintf(msg, sizeof msg, fmt, ap);
    if (line == SCENARIO_LINE_SET)
        snprintf(err, errlen, "--set %s: %s", set_name ? set_name : "?", msg);
    else if (line > 0)
        snprintf(err, errlen, "%s:%d: %s", sc->source, line, msg);
    else
        snprintf(err, errlen, "%s: %s", sc->source, msg);
    /* ONE line: echoed names and values must not break it. */
    for (char *p = err; *p != '\0'; p++)
        if ((unsigned char)*p < 0x20u || *p == 0x7f)
            *p = '?';
}

static int fail(parse_ctx *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int fail(parse_ctx *c, const char *fmt, ...)
{
    if (!c->failed) {
        va_list ap;
        va_start(ap, fmt);
        vfail_at(c->err, c->errlen, c->sc, c->line, c->set_name, fmt, ap);
        va_end(ap);
        c->failed = true;
        c->err_line = c->line;
    }
    return 0;
}

static int fail_line(char *err, size_t errlen, const scenario *sc, int line, const char *set_name,
                     const char *fmt, ...) __attribute__((format(printf, 6, 7)));
static int fail_line(char *err, size_t errlen, const scenario *sc, int line, const char *set_name,
                     const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail_at(err, errlen, sc, line, set_name, fmt, ap);
    va_end(ap);
    return SCENARIO_EINPUT;
}

/* ------------------------------------------------------------ values */

/* Longest value of a key, characters (after the comment and blanks are cut). */
#define VALUE_MAX 255

/* Copy @p value without a trailing '#' comment and surrounding blanks into
 * @p out (VALUE_MAX + 1 bytes). @return false when it does not fit: a value is
 * refused, never cut short. */
static bool clean_value(const char *value, char out[VALUE_MAX + 1])
{
    size_t n = 0;
    while (*value != '\0' && isspace((unsigned char)*value))
        value++;
    while (value[n] != '\0' && value[n] != '#')
        n++;
    while (n > 0 && isspace((unsigned char)value[n - 1]))
        n--;
    if (n > VALUE_MAX)
        return false;
    memcpy(out, value, n);
    out[n] = '\0';
    return true;
}

/* A number in the one syntax of sim/decimal.h (decimal only, finite). */
static bool parse_number(const char *tok, double *out) { return sim_parse_decimal(tok, out); }

/* Split @p s (modified) into at most @p max whitespace-separated tokens. */
static int split_tokens(char *s, char **tok, int max)
{
    int n = 0;
    char *p = s;
    for (;;) {
        while (*p != '\0' && (isspace((unsigned char)*p) || *p == ','))
            p++;
        if (*p == '\0')
            return n;
        if (n == max)
            return max + 1; /* too many */
        tok[n++] = p;
        while (*p != '\0' && !isspace((unsigned char)*p) && *p != ',')
            p++;
        if (*p != '\0')
            *p++ = '\0';
    }
}

static bool is_whole(double v) { return v == floor(v); }

static void describe_range(const key_def *k, char *buf, size_t len)
{
    const char *sp = strcmp(k->unit, "1") != 0 ? " " : "";
    const char *unit = strcmp(k->unit, "1") != 0 ? k->unit : "";
    if (k->min <= -1e299)
        snprintf(buf, len, "<= %g%s%s", k->max, sp, unit);
    else
        snprintf(buf, len, "%s %g and <= %g%s%s", k->min_open ? ">" : ">=", k->min, k->max, sp, unit);
}

static int set_scalar(parse_ctx *c, size_t ki, const char *value)
{
    const key_def *k = &keys[ki];
    scenario *sc = c->sc;
    unsigned char *base = (unsigned char *)sc;
    char v[VALUE_MAX + 1];
    if (!clean_value(value, v))
        return fail(c, "[%s] %s: value longer than %d characters", k->section, k->key, VALUE_MAX);
    if (v[0] == '\0')
        return fail(c, "[%s] %s: missing value", k->section, k->key);

    if (!c->from_set && sc->key_line[ki] > 0)
        return fail(c, "[%s] %s is set twice (first on line %d)", k->section, k->key, sc->key_line[ki]);

    if (k->kind == K_SUPPLY) {
        int mode;
        if (strcmp(v, "inverter") == 0)
            mode = PLANT_SUPPLY_INVERTER;
        else if (strcmp(v, "sine") == 0)
            mode = PLANT_SUPPLY_SINE;
        else
            return fail(c, "[supply] mode: unknown mode '%s' (expected inverter or sine)", v);
        memcpy(base + k->offset, &mode, sizeof mode);
    } else if (k->kind == K_MODEL) {
        int model;
        if (strcmp(v, "exact") == 0)
            model = SCENARIO_MODEL_EXACT;
        else if (strcmp(v, "plate") == 0)
            model = SCENARIO_MODEL_PLATE;
        else
            return fail(c, "[commission] model: unknown model '%s' (expected exact or plate)", v);
        memcpy(base + k->offset, &model, sizeof model);
    } else if (k->kind == K_CONTROLLER) {
        int ctl = scenario_controller_parse(v);
        if (ctl < 0)
            return fail(c, "[controller] name: unknown controller '%s' (expected ip, nominal or rbfn)", v);
        memcpy(base + k->offset, &ctl, sizeof ctl);
    } else if (k->kind == K_IDENTIFY) {
        int id;
        if (strcmp(v, "none") == 0)
            id = SCENARIO_IDENTIFY_NONE;
        else if (strcmp(v, "standstill") == 0)
            id = SCENARIO_IDENTIFY_STANDSTILL;
        else if (strcmp(v, "full") == 0)
            id = SCENARIO_IDENTIFY_FULL;
        else
            return fail(c, "[commission] identify: unknown value '%s' (expected none, standstill or full)", v);
        memcpy(base + k->offset, &id, sizeof id);
        sc->identify_line = c->line;
    } else {
        double x;
        if (!parse_number(v, &x))
            return fail(c, "[%s] %s: malformed number '%s'", k->section, k->key, v);
        bool low = k->min_open ? !(x > k->min) : !(x >= k->min);
        if (low || x > k->max) {
            char r[96];
            describe_range(k, r, sizeof r);
            return fail(c, "[%s] %s = %s is out of range (must be %s)", k->section, k->key, v, r);
        }
        if ((k->kind == K_INT || k->kind == K_SEED) && !is_whole(x))
            return fail(c, "[%s] %s = %s must be a whole number", k->section, k->key, v);
        if (k->kind == K_INT) {
            int iv = (int)x;
            memcpy(base + k->offset, &iv, sizeof iv);
        } else {
            double dv = x * k->scale;
            memcpy(base + k->offset, &dv, sizeof dv);
        }
    }
    if (k->has_offset != 0) {
        bool given = true;
        memcpy(base + k->has_offset, &given, sizeof given);
    }
    sc->key_line[ki] = c->line;
    return 1;
}

static int set_control(parse_ctx *c, const char *name, const char *value)
{
    scenario *sc = c->sc;
    int ki = sim_control_key_find(name);
    if (ki < 0)
        return fail(c, "[control] unknown key '%s' (see docs/scenarios.md for the list)", name);
    size_t nk;
    const sim_control_key *k = &sim_control_keys(&nk)[ki];
    char v[VALUE_MAX + 1];
    if (!clean_value(value, v))
        return fail(c, "[control] %s: value longer than %d characters", name, VALUE_MAX);
    if (v[0] == '\0')
        return fail(c, "[control] %s: missing value", name);
    double x;
    if (k->type == SIM_CK_BOOL) {
        if (strcmp(v, "1") == 0 || strcmp(v, "true") == 0 || strcmp(v, "on") == 0 || strcmp(v, "yes") == 0)
            x = 1.0;
        else if (strcmp(v, "0") == 0 || strcmp(v, "false") == 0 || strcmp(v, "off") == 0 || strcmp(v, "no") == 0)
            x = 0.0;
        else
            return fail(c, "[control] %s: expected true or false, got '%s'", name, v);
    } else {
        if (!parse_number(v, &x))
            return fail(c, "[control] %s: malformed number '%s'", name, v);
        if (x < k->min || x > k->max)
            return fail(c, "[control] %s = %s is out of range (must be >= %g and <= %g %s)", name, v,
                        k->min, k->max, k->unit);
        if (k->type == SIM_CK_U32 && !is_whole(x))
            return fail(c, "[control] %s = %s must be a whole number", name, v);
    }
    for (int i = 0; i < sc->n_control; i++) {
        if (sc->control[i].key != ki)
            continue;
        if (!c->from_set)
            return fail(c, "[control] %s is set twice (first on line %d)", name, sc->control[i].line);
        sc->control[i].value = x; /* --set overrides */
        sc->control[i].line = c->line;
        return 1;
    }
    if (sc->n_control >= SCENARIO_MAX_CONTROL)
        return fail(c, "[control] too many keys (at most %d)", SCENARIO_MAX_CONTROL);
    sc->control[sc->n_control++] = (scenario_control){ ki, x, c->line };
    return 1;
}

/* Parse exactly @p n numbers (after @p skip leading non-numeric tokens). */
static int parse_list_numbers(parse_ctx *c, const list_def *l, char **tok, int ntok, int skip, double *x, int n)
{
    if (ntok != skip + n)
        return fail(c, "[%s] %s: expected '%s = %s', got %s%d value%s", l->section, l->key, l->key, l->syntax,
                    ntok > 7 ? "more than " : "", ntok > 7 ? 7 : ntok, ntok == 1 ? "" : "s");
    for (int i = 0; i < n; i++)
        if (!parse_number(tok[skip + i], &x[i]))
            return fail(c, "[%s] %s: malformed number '%s' (expected %s)", l->section, l->key, tok[skip + i],
                        l->syntax);
    return 1;
}

static const char *const channel_names[SCENARIO_N_CHANNELS] = { "a", "b", "c", "vc1", "vc2" };

/* One [faults] entry: T_S, then CHANNEL and/or a value depending on the kind. */
static int add_fault(parse_ctx *c, const list_def *l, char **tok, int ntok)
{
    scenario *sc = c->sc;
    const scenario_fault_kind kind = (scenario_fault_kind)l->event_kind;
    const bool has_ch = kind <= SCENARIO_FAULT_RESTORE || kind == SCENARIO_FAULT_OPEN_PHASE;
    const bool has_val = kind == SCENARIO_FAULT_GAIN || kind == SCENARIO_FAULT_OFFSET ||
                         kind == SCENARIO_FAULT_VDC || kind == SCENARIO_FAULT_HW;
    const int want = 1 + (has_ch ? 1 : 0) + (has_val ? 1 : 0);
    if (ntok != want)
        return fail(c, "[faults] %s: expected '%s = %s', got %s%d value%s", l->key, l->key, l->syntax,
                    ntok > 7 ? "more than " : "", ntok > 7 ? 7 : ntok, ntok == 1 ? "" : "s");
    double t, v = 0.0;
    int ch = -1;
    if (!parse_number(tok[0], &t))
        return fail(c, "[faults] %s: malformed number '%s' (expected %s)", l->key, tok[0], l->syntax);
    if (t < 0.0 || t > 600.0)
        return fail(c, "[faults] %s: time %g s is out of range (0..600 s)", l->key, t);
    if (has_ch) {
        for (int i = 0; i < SCENARIO_N_CHANNELS; i++)
            if (strcmp(tok[1], channel_names[i]) == 0)
                ch = i;
        if (kind == SCENARIO_FAULT_OPEN_PHASE && (ch < 0 || ch > 2))
            return fail(c, "[faults] open_phase: unknown phase '%s' (expected a, b or c)", tok[1]);
        if (ch < 0)
            return fail(c, "[faults] %s: unknown channel '%s' (expected a, b, c, vc1 or vc2)", l->key, tok[1]);
    }
    if (has_val) {
        const char *vt = tok[want - 1];
        if (kind == SCENARIO_FAULT_HW) {
            if (strcmp(vt, "1") == 0 || strcmp(vt, "on") == 0 || strcmp(vt, "true") == 0 || strcmp(vt, "yes") == 0)
                v = 1.0;
            else if (strcmp(vt, "0") == 0 || strcmp(vt, "off") == 0 || strcmp(vt, "false") == 0 ||
                     strcmp(vt, "no") == 0)
                v = 0.0;
            else
                return fail(c, "[faults] hw: expected on or off, got '%s'", vt);
        } else if (!parse_number(vt, &v)) {
            return fail(c, "[faults] %s: malformed number '%s' (expected %s)", l->key, vt, l->syntax);
        } else if (kind == SCENARIO_FAULT_GAIN && !(v > 0.0 && v <= 10.0)) {
            return fail(c, "[faults] gain: factor %g is out of range (must be > 0 and <= 10)", v);
        } else if (kind == SCENARIO_FAULT_OFFSET && fabs(v) > 1e4) {
            return fail(c, "[faults] offset: %g is out of range (|offset| <= 10000 A or V)", v);
        } else if (kind == SCENARIO_FAULT_VDC && !(v > 0.0 && v <= 1e4)) {
            return fail(c, "[faults] vdc: %g V is out of range (must be > 0 and <= 10000 V)", v);
        }
    }
    if (c->from_set) {
        /* Replace the faults of this key only. */
        int n = 0;
        for (int i = 0; i < sc->n_faults; i++)
            if (sc->faults[i].kind != kind)
                sc->faults[n++] = sc->faults[i];
        sc->n_faults = n;
    } else if (sc->n_faults > 0 && t < sc->faults[sc->n_faults - 1].t_s) {
        return fail(c, "[faults] %s at %g s is out of time order (line %d is at %g s)", l->key, t,
                    sc->faults[sc->n_faults - 1].line, sc->faults[sc->n_faults - 1].t_s);
    }
    if (sc->n_faults >= SCENARIO_MAX_ENTRIES)
        return fail(c, "[faults] too many entries (at most %d)", SCENARIO_MAX_ENTRIES);
    sc->faults[sc->n_faults++] = (scenario_fault){ kind, t, ch, v, c->line };
    return 1;
}

static int add_list(parse_ctx *c, const list_def *l, const char *value)
{
    scenario *sc = c->sc;
    char v[VALUE_MAX + 1];
    if (!clean_value(value, v))
        return fail(c, "[%s] %s: value longer than %d characters", l->section, l->key, VALUE_MAX);
    char *tok[8];
    int ntok = split_tokens(v, tok, 7);
    double x[3];

    switch (l->kind) {
    case L_REF_STEP:
    case L_REF_RAMP: {
        bool ramp = l->kind == L_REF_RAMP;
        if (!parse_list_numbers(c, l, tok, ntok, 0, x, ramp ? 3 : 2))
            return 0;
        double t0 = x[0], t1 = ramp ? x[1] : x[0], rpm = ramp ? x[2] : x[1];
        if (t0 < 0.0 || t0 > 600.0)
            return fail(c, "[reference] %s: time %g s is out of range (0..600 s)", l->key, t0);
        if (ramp && !(t1 > t0 && t1 <= 600.0))
            return fail(c, "[reference] ramp: end time %g s must be after the start %g s (and <= 600 s)", t1, t0);
        if (fabs(rpm) > 100000.0)
            return fail(c, "[reference] %s: speed %g rpm is out of range (|rpm| <= 100000)", l->key, rpm);
        if (c->from_set)
            sc->n_ref = 0; /* --set replaces the whole profile */
        if (sc->n_ref > 0) {
            const scenario_ref_entry *p = &sc->ref[sc->n_ref - 1];
            if (t0 < p->t1_s)
                return fail(c, "[reference] %s at %g s is out of time order (the entry on line %d ends at %g s)",
                            l->key, t0, p->line, p->t1_s);
        }
        if (sc->n_ref >= SCENARIO_MAX_ENTRIES)
            return fail(c, "[reference] too many entries (at most %d)", SCENARIO_MAX_ENTRIES);
        sc->ref[sc->n_ref++] = (scenario_ref_entry){ ramp, t0, t1, rpm, c->line };
        return 1;
    }
    case L_LOAD_STEP:
    case L_LOAD_RAMP: {
        bool ramp = l->kind == L_LOAD_RAMP;
        if (!parse_list_numbers(c, l, tok, ntok, 0, x, ramp ? 3 : 2))
            return 0;
        double t0 = x[0], t1 = ramp ? x[1] : x[0], nm = ramp ? x[2] : x[1];
        if (t0 < 0.0 || t0 > 600.0)
            return fail(c, "[load] %s: time %g s is out of range (0..600 s)", l->key, t0);
        if (ramp && !(t1 > t0 && t1 <= 600.0))
            return fail(c, "[load] ramp: end time %g s must be after the start %g s (and <= 600 s)", t1, t0);
        if (fabs(nm) > 10000.0)
            return fail(c, "[load] %s: torque %g N m is out of range (|T| <= 10000 N m)", l->key, nm);
        if (c->from_set)
            sc->n_load = 0; /* --set replaces the whole load profile */
        if (sc->n_load > 0 && t0 < sc->load[sc->n_load - 1].t1_s) {
            const scenario_load_entry *p = &sc->load[sc->n_load - 1];
            if (p->ramp)
                return fail(c, "[load] %s at %g s is out of time order (the ramp on line %d ends at %g s)",
                            l->key, t0, p->line, p->t1_s);
            return fail(c, "[load] %s at %g s is out of time order (line %d is at %g s)", l->key, t0, p->line,
                        p->t_s);
        }
        if (sc->n_load >= SCENARIO_MAX_ENTRIES)
            return fail(c, "[load] too many entries (at most %d)", SCENARIO_MAX_ENTRIES);
        sc->load[sc->n_load++] = (scenario_load_entry){ ramp, t0, t1, nm, c->line };
        return 1;
    }
    case L_EVENT:
    case L_EVENT_RAMP: {
        bool ramp = l->kind == L_EVENT_RAMP;
        if (!parse_list_numbers(c, l, tok, ntok, 0, x, ramp ? 3 : 2))
            return 0;
        double t0 = x[0], t1 = ramp ? x[1] : x[0], factor = ramp ? x[2] : x[1];
        if (t0 < 0.0 || t0 > 600.0)
            return fail(c, "[events] %s: time %g s is out of range (0..600 s)", l->key, t0);
        if (ramp && !(t1 > t0 && t1 <= 600.0))
            return fail(c, "[events] %s: end time %g s must be after the start %g s (and <= 600 s)", l->key, t1,
                        t0);
        if (!(factor > 0.0 && factor <= 1000.0))
            return fail(c, "[events] %s: factor %g is out of range (must be > 0 and <= 1000)", l->key, factor);
        if (c->from_set) {
            /* Replace the events of this parameter only (steps and ramps). */
            int n = 0;
            for (int i = 0; i < sc->n_events; i++)
                if ((int)sc->events[i].kind != l->event_kind)
                    sc->events[n++] = sc->events[i];
            sc->n_events = n;
        } else if (sc->n_events > 0 && t0 < sc->events[sc->n_events - 1].t_s) {
            return fail(c, "[events] %s at %g s is out of time order (line %d is at %g s)", l->key, t0,
                        sc->events[sc->n_events - 1].line, sc->events[sc->n_events - 1].t_s);
        }
        /* A change of one parameter must not start inside a ramp of the same parameter. */
        for (int i = sc->n_events - 1; i >= 0; i--) {
            const scenario_event *p = &sc->events[i];
            if ((int)p->kind != l->event_kind)
                continue;
            if (p->ramp && t0 < p->t1_s)
                return fail(c, "[events] %s at %g s starts inside the ramp on line %d (it ends at %g s)", l->key,
                            t0, p->line, p->t1_s);
            break;
        }
        if (sc->n_events >= SCENARIO_MAX_ENTRIES)
            return fail(c, "[events] too many entries (at most %d)", SCENARIO_MAX_ENTRIES);
        sc->events[sc->n_events++] =
            (scenario_event){ (scenario_event_kind)l->event_kind, ramp, t0, t1, factor, c->line };
        return 1;
    }
    case L_FAULT:
        return add_fault(c, l, tok, ntok);
    case L_WINDOW: {
        if (ntok < 1)
            return fail(c, "[metrics] window: expected '%s'", l->syntax);
        const char *name = tok[0];
        size_t len = strlen(name);
        if (len == 0 || len >= SCENARIO_NAME_LEN)
            return fail(c, "[metrics] window: name must be 1..%d characters", SCENARIO_NAME_LEN - 1);
        for (size_t i = 0; i < len; i++)
            if (!isalnum((unsigned char)name[i]) && name[i] != '_')
                return fail(c, "[metrics] window: name '%s' may only use letters, digits and '_'", name);
        if (!parse_list_numbers(c, l, tok, ntok, 1, x, 2))
            return 0;
        if (x[0] < 0.0 || !(x[1] > x[0]) || x[1] > 600.0)
            return fail(c, "[metrics] window %s: need 0 <= T0_S < T1_S <= 600 s, got %g %g", name, x[0], x[1]);
        if (c->from_set)
            sc->n_windows = 0;
        for (int i = 0; i < sc->n_windows; i++)
            if (strcmp(sc->windows[i].name, name) == 0)
                return fail(c, "[metrics] window %s is defined twice (first on line %d)", name, sc->windows[i].line);
        if (sc->n_windows >= SCENARIO_MAX_WINDOWS)
            return fail(c, "[metrics] too many windows (at most %d)", SCENARIO_MAX_WINDOWS);
        scenario_window *w = &sc->windows[sc->n_windows++];
        memset(w, 0, sizeof *w);
        memcpy(w->name, name, len + 1);
        w->t0_s = x[0];
        w->t1_s = x[1];
        w->line = c->line;
        return 1;
    }
    }
    return fail(c, "internal error: unhandled list key");
}

/* Dispatch one `section.key = value`. */
static int assign(parse_ctx *c, const char *section, const char *name, const char *value)
{
    if (section[0] == '\0')
        return fail(c, "key '%s' outside a section (start the file with a [section])", name);
    bool known = false;
    for (size_t i = 0; i < sizeof sections / sizeof sections[0]; i++)
        if (strcmp(section, sections[i]) == 0)
            known = true;
    if (!known)
        return fail(c, "unknown section [%s] (sections: sim, motor, load, drive, inverter, sensors, supply, "
                       "controller, control, reference, events, faults, metrics, ratings, commission)", section);
    if (strcmp(section, "control") == 0)
        return set_control(c, name, value);
    for (size_t i = 0; i < N_KEYS; i++)
        if (strcmp(keys[i].section, section) == 0 && strcmp(keys[i].key, name) == 0)
            return set_scalar(c, i, value);
    for (size_t i = 0; i < N_LISTS; i++)
        if (strcmp(lists[i].section, section) == 0 && strcmp(lists[i].key, name) == 0)
            return add_list(c, &lists[i], value);
    return fail(c, "unknown key '%s' in section [%s]", name, section);
}

/* ------------------------------------------------------------ inih glue */

static int handler(void *user, const char *section, const char *name, const char *value)
{
    parse_ctx *c = user;
    if (c->failed)
        return 0; /* keep the first error */
    return assign(c, section, name, value);
}

/* fgets-style reader that counts lines and refuses over-long ones. */
static char *reader(char *str, int num, void *stream)
{
    parse_ctx *c = stream;
    if (num < 2)
        return NULL;
    if (*c->text == '\0')
        return NULL;
    int n = 0;
    while (n < num - 1 && c->text[n] != '\0') {
        str[n] = c->text[n];
        if (c->text[n++] == '\n')
            break;
    }
    str[n] = '\0';
    c->text += n;
    c->line++;
    size_t len = strlen(str);
    if (len == (size_t)num - 1 && str[len - 1] != '\n') {
        /* Over-long: swallow the rest so line numbers stay right. */
        bool more = false;
        while (*c->text != '\0' && *c->text != '\n') {
            c->text++;
            more = true;
        }
        if (*c->text == '\n')
            c->text++;
        if (more && !c->failed)
            fail(c, "line too long (at most %d characters)", num - 2);
    }
    return str;
}

static int run_parser(parse_ctx *c)
{
    int rc = ini_parse_stream(reader, c, handler, c);
    if (rc > 0 && (!c->failed || rc < c->err_line)) {
        /* inih's own syntax error came first. */
        c->failed = false;
        c->line = rc;
        fail(c, "syntax error: expected '[section]' or 'key = value'");
    } else if (rc < 0 && !c->failed) {
        c->line = 0;
        fail(c, "out of memory while parsing");
    }
    return c->failed ? SCENARIO_EINPUT : 0;
}

/* The name used in messages; one that does not fit is refused (messages
 * name the whole file, never a cut-off one). */
static int set_source(scenario *sc, const char *name, char *err, size_t errlen)
{
    if (strlen(name) >= sizeof sc->source) {
        snprintf(sc->source, sizeof sc->source, "%.60s...", name);
        return fail_line(err, errlen, sc, 0, NULL, "the file name is longer than %zu characters",
                         sizeof sc->source - 1u);
    }
    snprintf(sc->source, sizeof sc->source, "%s", name);
    return 0;
}

/* The whole scenario file in memory, refused unless it is a regular file of
 * at most SIM_SCENARIO_MAX_BYTES without a NUL byte: a FIFO, /dev/zero or a
 * directory gives a clear error instead of a hang or a partial read.
 * O_NONBLOCK: opening a FIFO without a writer must not block. */
static int read_scenario_file(scenario *sc, const char *path, char **out, char *err, size_t errlen)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return fail_line(err, errlen, sc, 0, NULL, "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return fail_line(err, errlen, sc, 0, NULL, "not a regular file");
    }
    if (st.st_size > SIM_SCENARIO_MAX_BYTES) {
        close(fd);
        return fail_line(err, errlen, sc, 0, NULL, "larger than %ld bytes (%lld)", SIM_SCENARIO_MAX_BYTES,
                         (long long)st.st_size);
    }
    char *text = malloc((size_t)st.st_size + 1u);
    if (text == NULL) {
        close(fd);
        return fail_line(err, errlen, sc, 0, NULL, "out of memory");
    }
    size_t n = 0;
    for (;;) {
        ssize_t r = read(fd, text + n, (size_t)st.st_size - n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0) {
            int e = errno;
            free(text);
            close(fd);
            return fail_line(err, errlen, sc, 0, NULL, "read error: %s", strerror(e));
        }
        if (r == 0 || (n += (size_t)r) == (size_t)st.st_size)
            break;
    }
    close(fd);
    text[n] = '\0';
    const char *nul = memchr(text, '\0', n);
    if (nul != NULL) {
        int line = 1;
        for (const char *p = text; p < nul; p++)
            line += *p == '\n';
        free(text);
        return fail_line(err, errlen, sc, line, NULL, "NUL byte in the file (a scenario is text)");
    }
    *out = text;
    return 0;
}

int scenario_parse_file(scenario *sc, const char *path, char *err, size_t errlen)
{
    if (set_source(sc, path, err, errlen) != 0)
        return SCENARIO_EINPUT;
    parse_ctx c;
    memset(&c, 0, sizeof c);
    c.sc = sc;
    c.err = err;
    c.errlen = errlen;
    char *text = NULL;
    int rc = read_scenario_file(sc, path, &text, err, errlen);
    if (rc != 0)
        return rc;
    c.text = text;
    rc = run_parser(&c);
    free(text);
    return rc;
}

int scenario_parse_string(scenario *sc, const char *name, const char *text, char *err, size_t errlen)
{
    if (set_source(sc, name, err, errlen) != 0)
        return SCENARIO_EINPUT;
    parse_ctx c;
    memset(&c, 0, sizeof c);
    c.sc = sc;
    c.err = err;
    c.errlen = errlen;
    c.text = text;
    return run_parser(&c);
}

int scenario_set(scenario *sc, const char *assignment, char *err, size_t errlen)
{
    parse_ctx c;
    memset(&c, 0, sizeof c);
    c.sc = sc;
    c.err = err;
    c.errlen = errlen;
    c.line = SCENARIO_LINE_SET;
    c.from_set = true;

    char name[128];
    const char *eq = strchr(assignment, '=');
    size_t nlen = eq != NULL ? (size_t)(eq - assignment) : strlen(assignment);
    if (nlen >= sizeof name) {
        char shown[48];
        snprintf(shown, sizeof shown, "%.32s...", assignment);
        c.set_name = shown;
        fail(&c, "the key is longer than %zu characters", sizeof name - 1u);
        return SCENARIO_EINPUT;
    }
    memcpy(name, assignment, nlen);
    name[nlen] = '\0';
    /* trim the name */
    char *n0 = name;
    while (isspace((unsigned char)*n0))
        n0++;
    size_t l = strlen(n0);
    while (l > 0 && isspace((unsigned char)n0[l - 1]))
        n0[--l] = '\0';
    c.set_name = n0;
    if (eq == NULL) {
        fail(&c, "expected section.key=value (no '=')");
        return SCENARIO_EINPUT;
    }
    char *dot = strchr(n0, '.');
    if (dot == NULL || dot == n0 || dot[1] == '\0') {
        fail(&c, "expected section.key=value (no '.' between section and key)");
        return SCENARIO_EINPUT;
    }
    *dot = '\0';
    const char *section = n0, *key = dot + 1;
    char full[128];
    snprintf(full, sizeof full, "%s.%s", section, key);
    c.set_name = full;
    assign(&c, section, key, eq + 1);
    return c.failed ? SCENARIO_EINPUT : 0;
}

/* ------------------------------------------------------------ final checks */

static int key_index(const char *section, const char *key)
{
    for (size_t i = 0; i < N_KEYS; i++)
        if (strcmp(keys[i].section, section) == 0 && strcmp(keys[i].key, key) == 0)
            return (int)i;
    return -1;
}

int scenario_key_line(const scenario *sc, const char *section, const char *key)
{
    int ki = key_index(section, key);
    return ki >= 0 ? sc->key_line[ki] : 0;
}

/* Report a problem with scalar key (section, key) at the line it was set on. */
static int fail_key(scenario *sc, char *err, size_t errlen, const char *section, const char *key,
                    const char *msg)
{
    int ki = key_index(section, key);
    int line = ki >= 0 ? sc->key_line[ki] : 0;
    char set_name[96];
    snprintf(set_name, sizeof set_name, "%s.%s", section, key);
    return fail_line(err, errlen, sc, line, set_name, "[%s] %s: %s", section, key, msg);
}

/* Map a plant_check_config message to the key whose value it names. */
static int map_plant_error(scenario *sc, const char *what, char *err, size_t errlen)
{
    int best = -1;
    size_t best_len = 0;
    for (size_t i = 0; i < N_KEYS; i++) {
        const char *p = keys[i].plant_path;
        if (p == NULL)
            continue;
        const char *hit = strstr(what, p);
        size_t plen = strlen(p);
        /* A whole-word match: "Rs_ohm" must not match inside "xRs_ohm". */
        while (hit != NULL) {
            bool left = hit == what || !(isalnum((unsigned char)hit[-1]) || hit[-1] == '_');
            bool right = !(isalnum((unsigned char)hit[plen]) || hit[plen] == '_');
            if (left && right)
                break;
            hit = strstr(hit + 1, p);
        }
        if (hit != NULL && plen > best_len) {
            best = (int)i;
            best_len = plen;
        }
    }
    if (best < 0)
        return fail_line(err, errlen, sc, 0, NULL, "invalid plant configuration: %s", what);
    char set_name[96];
    snprintf(set_name, sizeof set_name, "%s.%s", keys[best].section, keys[best].key);
    /* "motor.J_kgm2 must be > 0" -> "[motor] J_kgm2 must be > 0" */
    const char *rest = strstr(what, keys[best].plant_path);
    rest = rest != NULL ? rest + strlen(keys[best].plant_path) : "";
    if (*rest == ' ')
        rest++;
    return fail_line(err, errlen, sc, sc->key_line[best], set_name, "[%s] %s %s", keys[best].section,
                     keys[best].key, *rest != '\0' ? rest : "is rejected by the plant");
}

void scenario_ratings_to_plate(const scenario *sc, ratings *r)
{
    const scenario_ratings *s = &sc->ratings;
    r->P_W = (real_t)s->P_W;
    r->V_ll_V = (real_t)s->V_ll_V;
    r->I_A = (real_t)s->I_A;
    r->f_Hz = (real_t)s->f_Hz;
    r->n_rpm = (real_t)s->n_rpm;
    r->cos_phi = (real_t)s->cos_phi;
    r->vdc_nom_V = (real_t)s->vdc_nom_V;
    r->inv_I_rated_A = (real_t)s->inv_I_rated_A;
    r->inv_I_peak_A = (real_t)s->inv_I_peak_A;
}

/* The plate as the drive judges it (ratings_check: the first offending
 * field, named at its line), every field but cos_phi given, and
 * model = plate only with a plate. */
static int check_ratings(scenario *sc, char *err, size_t errlen)
{
    if (!sc->has_ratings) {
        if (sc->model == SCENARIO_MODEL_PLATE)
            return fail_key(sc, err, errlen, "commission", "model",
                            "plate needs a [ratings] section (the motor's plate and the inverter's label)");
        return 0;
    }
    static const char *const required[] = { "P_W", "V_ll_V", "I_A", "f_Hz", "n_rpm", "vdc_nom_V",
                                            "inv_I_rated_A", "inv_I_peak_A" };
    for (size_t i = 0; i < sizeof required / sizeof required[0]; i++) {
        if (sc->key_line[key_index("ratings", required[i])] == 0) {
            /* named at the section's first key */
            int line = 0;
            for (size_t k = 0; k < N_KEYS; k++)
                if (strcmp(keys[k].section, "ratings") == 0 && sc->key_line[k] > 0 &&
                    (line == 0 || sc->key_line[k] < line))
                    line = sc->key_line[k];
            char set_name[96];
            snprintf(set_name, sizeof set_name, "ratings.%s", required[i]);
            return fail_line(err, errlen, sc, line, set_name, "[ratings] %s: missing (a plate needs P_W, V_ll_V, "
                             "I_A, f_Hz, n_rpm, vdc_nom_V, inv_I_rated_A and inv_I_peak_A; cos_phi if given)",
                             required[i]);
        }
    }
    ratings r;
    scenario_ratings_to_plate(sc, &r);
    ratings_error e = ratings_check(&r);
    if (e.reason == RATINGS_OK) {
        /* and what the derivation judges with the control period (RATINGS_E_PERIOD) */
        ctl_cfg c;
        ctl_cfg_default(&c);
        c.period_s = (real_t)sc->period_s;
        e = ratings_derive_cfg(&c, &r, NULL);
    }
    if (e.reason != RATINGS_OK) {
        char msg[192];
        snprintf(msg, sizeof msg, "%s (refused as a CAN write: 0x%08X)", ratings_reason_text(e.reason),
                 (unsigned)ratings_abort_code(e.reason));
        return fail_key(sc, err, errlen, "ratings", ratings_field_name(e.field), msg);
    }
    return 0;
}

int scenario_finish(scenario *sc, char *err, size_t errlen)
{
    sc->plant.supply = sc->supply_mode == PLANT_SUPPLY_SINE ? PLANT_SUPPLY_SINE : PLANT_SUPPLY_INVERTER;
    sc->plant.sine.phase_rad = sc->phase_rad;
    sc->plant.sensor.seed = (uint32_t)sc->seed;

    double us = sc->period_s * 1e6;
    if (fabs(us - floor(us + 0.5)) > 1e-6)
        return fail_key(sc, err, errlen, "sim", "period_s", "must be a whole number of microseconds");
    if (sc->trace_interval_s < sc->period_s * (1.0 - 1e-9))
        return fail_key(sc, err, errlen, "sim", "trace_interval_s", "must be >= period_s");
    if (sc->duration_s < sc->period_s)
        return fail_key(sc, err, errlen, "sim", "duration_s", "must be at least one control period");

    /* Order of entries that came from different sources (--set) is checked here too. */
    for (int i = 1; i < sc->n_ref; i++)
        if (sc->ref[i].t0_s < sc->ref[i - 1].t1_s)
            return fail_line(err, errlen, sc, sc->ref[i].line, "reference", "[reference] entry at %g s is out of time order",
                             sc->ref[i].t0_s);

    int rc = check_ratings(sc, err, errlen);
    if (rc != 0)
        return rc;

    const char *what = NULL;
    if (plant_check_config(&sc->plant, &what) != 0)
        return map_plant_error(sc, what != NULL ? what : "rejected by plant_check_config", err, errlen);
    return 0;
}
