/**
 * @file ctl_protect.c
 * @brief The control step's protection (see ctl_protect.h): the sample's
 *        limits in one pass for the common case, which limit it crosses in
 *        the rare one, the run state's checks and the latch.
 */
#include "ctl_protect.h"

#include "dtc/bringup.h"
#include "dtc/ctl_schedule.h"
#include "real_bits.h"

/* The common case in one pass: every sample value finite and no limit of
 * sample_faults() crossed. False sends the tick to sample_faults(), which
 * says which. The phase currents compare as integers (one compare for the
 * largest of the three; a NaN or infinite current fails it); a NaN or an
 * infinity in vc1 or vc2 makes vdc or their difference fail its compare. */
static inline bool sample_within_limits(const ctl_cfg *cfg, const hal_sample *x, real_t vdc, bool uv_judged)
{
    uint32_t ia = abs_bits(x->ia_A), ib = abs_bits(x->ib_A), ic = abs_bits(x->ic_A);
    uint32_t imax = ia > ib ? ia : ib;
    imax = imax > ic ? imax : ic;
    /* vdc in [vdc_min_V, vdc_max_V] as one unsigned compare of the bits
     * (ctl_cfg_check: 0 <= vdc_min_V < vdc_max_V; a negative vdc, a NaN or
     * an infinity fails it, so does -0, which sample_faults() then passes);
     * undervoltage not judged: |vdc| <= vdc_max_V, only an impossible vdc
     * takes the slow path */
    uint32_t v = uv_judged ? f32_bits(vdc) : abs_bits(vdc);
    uint32_t lo = uv_judged ? f32_bits(cfg->vdc_min_V) : 0u;
    return imax <= abs_bits(cfg->i_trip_A) && v - lo <= f32_bits(cfg->vdc_max_V) - lo &&
           num_abs(x->vc1_V - x->vc2_V) <= cfg->np_trip_V;
}

/* Which limits the sample crosses (the rare case; enum ctl_fault bits). */
static uint32_t sample_faults(const ctl_cfg *cfg, const hal_sample *x, real_t vdc, bool uv_judged)
{
    /* one test for all five: a NaN or an infinity in any of them makes the sum NaN */
    if (!finite_r((x->ia_A - x->ia_A) + (x->ib_A - x->ib_A) + (x->ic_A - x->ic_A) + (x->vc1_V - x->vc1_V) +
                  (x->vc2_V - x->vc2_V)))
        return CTL_FAULT_SAMPLE_INVALID;
    uint32_t f = 0u;
    if (num_abs(x->ia_A) > cfg->i_trip_A || num_abs(x->ib_A) > cfg->i_trip_A || num_abs(x->ic_A) > cfg->i_trip_A)
        f |= CTL_FAULT_OVERCURRENT;
    if (vdc > cfg->vdc_max_V)
        f |= CTL_FAULT_DC_OVERVOLT;
    if (uv_judged && vdc < cfg->vdc_min_V)
        f |= CTL_FAULT_DC_UNDERVOLT;
    if (num_abs(x->vc1_V - x->vc2_V) > cfg->np_trip_V)
        f |= CTL_FAULT_NP_IMBALANCE;
    return f;
}

/* Magnetising or running: the states whose checks judge the machine. */
static inline bool active_state(const ctl_state *s)
{
    return s->run_state == CTL_MAGNETISING || s->run_state == CTL_RUNNING;
}

uint32_t ctl_protect_detect(const ctl_state *s, const ctl_cfg *cfg, const ctl_in *in, bool *judged)
{
    const hal_sample *x = &in->sample;
    uint32_t f = 0u;
    bool active = active_state(s);

    *judged = false;
    if (in->fault_input)
        f |= CTL_FAULT_HW;
    if (in->overrun)
        f |= CTL_FAULT_OVERRUN;
    if (!in->sample_fresh)
        return f | CTL_FAULT_STALE_SAMPLE; /* the values are not this tick's: judge nothing on them */
    /* bring-up levels 1 and 2 need no DC link */
    bool uv_judged = active && cfg->bringup_level > BRINGUP_ADC;
    real_t vdc = x->vc1_V + x->vc2_V;
    if (!sample_within_limits(cfg, x, vdc, uv_judged)) {
        uint32_t sf = sample_faults(cfg, x, vdc, uv_judged);
        if (sf & CTL_FAULT_SAMPLE_INVALID)
            return f | sf; /* judge nothing else on a value that is not a number */
        f |= sf;
    }
    /* Written as "not within" so that a diverged (NaN) estimate trips too. */
    if (active && !(num_abs(s->obs.omega_m_filt_rad_s) <= cfg->overspeed_rad_s))
        f |= CTL_FAULT_OVERSPEED;
    /* the loss-of-control and stall verdicts as their monitors last gave them (in their slots) */
    if (active)
        f |= s->monitor_faults;
    *judged = true;
    return f;
}

uint32_t ctl_protect_plausibility(ctl_state *s, const ctl_cfg *cfg, const hal_sample *x)
{
    real_t omega_e = num_mul(cfg->motor.pole_pairs, s->obs.omega_m_filt_rad_s);
    return plaus_check(&s->plaus, x, active_state(s), s->run_state == CTL_STOPPED, omega_e, cfg->period_s,
                       ctl_slot_plaus(s->slow_slot));
}

bool ctl_protect_latch(ctl_state *s, uint32_t f)
{
    s->faults_active = f;
    s->faults |= f;
    if (s->faults != 0u)
        s->run_state = CTL_FAULTED;
    return s->faults != 0u;
}
