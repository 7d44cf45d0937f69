/**
 * @file sensors.c
 * @brief The board's measurement chain: gain and offset error, seeded white
 *        noise, then ADC quantisation with clamping at the rails.
 *
 * Noise: splitmix64 (a 64-bit state in plant_state.rng, so equal seeds give
 * equal runs and there are no globals) feeding Box-Muller for normal deviates.
 */
#include <math.h>

#include "plant_internal.h"

void plant_rng_seed(plant_state *s, uint32_t seed)
{
    s->rng = (uint64_t)seed;
}

static uint64_t splitmix64(uint64_t *st)
{
    uint64_t z = (*st += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in (0, 1]: never 0, so log() below is finite. */
static double uniform01(uint64_t *st)
{
    return (double)((splitmix64(st) >> 11) + 1u) * (1.0 / 9007199254740992.0);
}

/* Two independent standard normal deviates (Box-Muller). */
static void normal_pair(uint64_t *st, double *n0, double *n1)
{
    double r = sqrt(-2.0 * log(uniform01(st)));
    double a = PLANT_TWO_PI * uniform01(st);
    *n0 = r * cos(a);
    *n1 = r * sin(a);
}

/* Round to the nearest code and clamp into 0..max (NaN gives 0). */
static uint16_t quantise(double code, double max_code)
{
    double c = floor(code + 0.5);
    if (!(c > 0.0))
        return 0;
    if (c > max_code)
        c = max_code;
    return (uint16_t)c;
}

/* Largest code; the resolution is clamped to 1..16 bits so a bad
 * configuration cannot make an undefined shift. */
static double max_code_of(int bits)
{
    if (bits < 1)
        bits = 1;
    if (bits > 16)
        bits = 16;
    return (double)((1u << bits) - 1u);
}

void plant_sample(plant_state *s, plant_adc *out)
{
    const plant_sensor_params *sp = &s->cfg.sensor;
    double max_code = max_code_of(sp->adc_bits);
    double n[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    plant_truth t;
    double i_abc[3], v[2];
    int k;

    plant_get_truth(s, &t);
    i_abc[0] = t.ia_A;
    i_abc[1] = t.ib_A;
    i_abc[2] = t.ic_A;
    v[0] = t.vc1_V;
    v[1] = t.vc2_V;

    if (sp->i_noise_A > 0.0 || sp->v_noise_V > 0.0) {
        normal_pair(&s->rng, &n[0], &n[1]);
        normal_pair(&s->rng, &n[2], &n[3]);
        normal_pair(&s->rng, &n[4], &n[5]);
    }
    for (k = 0; k < 3; ++k) {
        double i_m = sp->i_gain[k] * i_abc[k] + sp->i_offset_A[k] + sp->i_noise_A * n[k];
        if (s->sensor_fault[PLANT_CH_IA + k] == PLANT_SENSOR_LOST)
            i_m = 0.0;
        out->i_code[k] = quantise((i_m / sp->i_fs_A + 1.0) * 0.5 * max_code, max_code);
    }
    for (k = 0; k < 2; ++k) {
        double v_m = sp->v_gain[k] * v[k] + sp->v_offset_V[k] + sp->v_noise_V * n[3 + k];
        if (s->sensor_fault[PLANT_CH_VC1 + k] == PLANT_SENSOR_LOST)
            v_m = 0.0;
        out->v_code[k] = quantise(v_m / sp->v_fs_V * max_code, max_code);
    }
    /* A stuck channel repeats its last conversion (the first one if it was
     * stuck from the start); the noise generator advances as usual, so a
     * fault does not shift the noise of the other channels. */
    for (k = 0; k < PLANT_N_CH; ++k) {
        uint16_t *code = k < 3 ? &out->i_code[k] : &out->v_code[k - 3];
        if (s->sensor_fault[k] == PLANT_SENSOR_STUCK && s->code_valid)
            *code = s->code_last[k];
        s->code_last[k] = *code;
    }
    s->code_valid = 1;
    out->omega_m_rad_s = t.omega_m_rad_s;
}

void plant_set_sensor_gain(plant_state *s, int ch, double gain)
{
    if (s == NULL || ch < 0 || ch >= PLANT_N_CH || !isfinite(gain) || !(gain > 0.0))
        return;
    if (ch < 3)
        s->cfg.sensor.i_gain[ch] = gain;
    else
        s->cfg.sensor.v_gain[ch - 3] = gain;
}

void plant_set_sensor_offset(plant_state *s, int ch, double offset)
{
    if (s == NULL || ch < 0 || ch >= PLANT_N_CH || !isfinite(offset))
        return;
    if (ch < 3)
        s->cfg.sensor.i_offset_A[ch] = offset;
    else
        s->cfg.sensor.v_offset_V[ch - 3] = offset;
}

void plant_set_sensor_fault(plant_state *s, int ch, plant_sensor_fault f)
{
    if (s == NULL || ch < 0 || ch >= PLANT_N_CH)
        return;
    if (f == PLANT_SENSOR_OK || f == PLANT_SENSOR_STUCK || f == PLANT_SENSOR_LOST)
        s->sensor_fault[ch] = (uint8_t)f;
}

void plant_adc_to_units(const plant_config *cfg, const plant_adc *adc, double i_A[3], double v_V[2])
{
    const plant_sensor_params *sp = &cfg->sensor;
    double max_code = max_code_of(sp->adc_bits);
    int k;
    for (k = 0; k < 3; ++k)
        i_A[k] = ((double)adc->i_code[k] / max_code * 2.0 - 1.0) * sp->i_fs_A;
    for (k = 0; k < 2; ++k)
        v_V[k] = (double)adc->v_code[k] / max_code * sp->v_fs_V;
}
