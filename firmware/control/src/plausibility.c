/**
 * @file plausibility.c
 * @brief Sensor plausibility checks (see dtc/plausibility.h).
 */
#include "dtc/plausibility.h"

#include "dtc/ctl.h"

#include <string.h>

void plaus_reset(plaus_state *p)
{
    /* member by member: called every tick while stopped or faulted, where a
     * call to memset would cost several times as much */
    p->sum_ticks = 0u;
    for (int k = 0; k < 3; k++) {
        p->stuck_ticks[k] = 0u;
        p->open_ticks[k] = 0u;
        p->open_peak_A[k] = R(0.0);
        p->last_A[k] = R(0.0);
    }
    p->cleared = true;
}

/* The bits of @p x. */
static inline uint32_t plaus_bits(real_t x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* Count ticks in a row while @p cond holds, PLAUS_CHECK_TICKS per check (saturating). */
static uint16_t count(uint16_t n, bool cond)
{
    return cond ? (uint16_t)(n < 0xFFFFu - PLAUS_CHECK_TICKS ? n + PLAUS_CHECK_TICKS : 0xFFFFu) : 0u;
}

/* Half an electrical period at |omega_e| = @p w_rad_s (above the judging
 * frequency), in ticks of @p period_s, at least PLAUS_OPEN_MIN_TICKS. */
static uint32_t half_period_ticks(real_t w_rad_s, real_t period_s)
{
    uint32_t n = (uint32_t)(NUM_PI / num_mul(w_rad_s, period_s));
    return n < PLAUS_OPEN_MIN_TICKS ? PLAUS_OPEN_MIN_TICKS : n;
}

uint32_t plaus_check(plaus_state *p, const hal_sample *x, bool active, bool stopped, real_t omega_e_rad_s,
                     real_t period_s, bool check)
{
    uint32_t f = 0u;

    if (stopped) {
        real_t vdc = x->vc1_V + x->vc2_V;
        if (num_abs(x->vc1_V - x->vc2_V) > num_mul(PLAUS_DIVIDER_REL, vdc))
            f |= CTL_FAULT_DC_DIVIDER;
    }
    if (!active) {
        if (!p->cleared)
            plaus_reset(p);
        return f;
    }
    if (!check)
        return f; /* the current checks run every PLAUS_CHECK_TICKS-th tick (the caller's schedule) */
    p->cleared = false;
    const real_t i[3] = {x->ia_A, x->ib_A, x->ic_A};

    real_t sq = num_mac(i[0], i[0], num_mac(i[1], i[1], num_mul(i[2], i[2])));
    real_t mag_A = num_sqrt(num_mul(R(0.6666667), sq)); /* space-vector magnitude */
    real_t sum = i[0] + i[1] + i[2];
    p->sum_ticks = count(p->sum_ticks, num_abs(sum) > num_mac(PLAUS_SUM_REL, mag_A, PLAUS_SUM_ABS_A));
    if (p->sum_ticks >= PLAUS_SUM_TICKS)
        f |= CTL_FAULT_CURRENT_SENSOR;

    /* No phase-loss judgement at low frequency. */
    real_t w = num_abs(omega_e_rad_s);
    bool judge_open = w > R(2.0) * NUM_PI * PLAUS_PHASE_MIN_HZ;

    /* on the bits too: mag_A is a square root, never negative nor NaN (one integer
     * compare, where a float compare would be redone per leg) */
    bool flowing = plaus_bits(mag_A) > plaus_bits(PLAUS_CURRENT_A);
    /* |i| against PLAUS_OPEN_A and i against the last reading compared as integers on
     * the bits (no FPU flag transfer per compare): for finite values (the protection
     * judges nothing else on a sample value that is not a number) |i| orders like its
     * magnitude bits, and readings of |i| >= PLAUS_OPEN_A are equal exactly when their
     * bits are */
    const uint32_t open_bits = plaus_bits(PLAUS_OPEN_A);
    for (int k = 0; k < 3; k++) {
        uint32_t bits = plaus_bits(i[k]);
        bool small = (bits & 0x7FFFFFFFu) < open_bits;
        /* A reading stuck at ~0 A is judged as phase loss or by the current sum. */
        p->stuck_ticks[k] = count(p->stuck_ticks[k], bits == plaus_bits(p->last_A[k]) && !small && flowing);
        if (p->stuck_ticks[k] >= PLAUS_STUCK_TICKS)
            f |= CTL_FAULT_CURRENT_SENSOR;
        p->last_A[k] = i[k];
        /* The two remaining currents cross zero too: the magnitude is judged by its
         * peak over the time the phase has been at ~0 A, not tick by tick. */
        bool open = small && judge_open; /* the rare condition first */
        if (!open) {
            /* the usual case: both reset, written only when not reset already (open_ticks is
             * 0 exactly when the phase was not open at the last check, and open_peak_A then
             * too: a load and a test in place of two stores per phase) */
            if (p->open_ticks[k] != 0u) {
                p->open_ticks[k] = 0u;
                p->open_peak_A[k] = R(0.0);
            }
            continue;
        }
        p->open_ticks[k] = count(p->open_ticks[k], true);
        p->open_peak_A[k] = mag_A > p->open_peak_A[k] ? mag_A : p->open_peak_A[k];
        /* the half period is at least PLAUS_OPEN_MIN_TICKS: worked out only past that */
        if (p->open_ticks[k] > PLAUS_OPEN_MIN_TICKS && p->open_ticks[k] > half_period_ticks(w, period_s) &&
            p->open_peak_A[k] > PLAUS_CURRENT_A)
            f |= CTL_FAULT_PHASE_LOSS;
    }
    return f;
}
