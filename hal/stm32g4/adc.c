/**
 * @file adc.c
 * @brief ADC1/ADC2 (dual injected simultaneous) and ADC3 sampling the phase
 *        currents and the capacitor voltages (RM0440 21).
 */
#include "adc.h"

#include <stddef.h>

#include "board.h"
#include "chip.h"
#include "clock.h"

/* Sensor scaling of the power board (docs/motor-10hp.json "drive", docs/board.md). */
#define BOARD_ADC_FULL_CODE 4095.0f /* 12-bit converter, 0..3.3 V */
#define BOARD_I_FULL_SCALE_A 150.0f /* currents: code 0 = -150 A, 4095 = +150 A */
#define BOARD_V_FULL_SCALE_V 500.0f /* capacitor voltages: code 0 = 0 V, 4095 = 500 V */
#define BOARD_ADC_MID_CODE 2048u
#define BOARD_ADC_SAT_LOW 2u     /* codes at or beyond these are saturated */
#define BOARD_ADC_SAT_HIGH 4093u
#define BOARD_OFFSET_TOL_CODE 205u /* +-5 % of full scale accepted as a current offset */
#define BOARD_OFFSET_SAMPLES 64u

/* ADC channels: ADC1 ranks [ia, vc1], ADC2 ranks [ib, vc2] (dual injected
 * simultaneous), ADC3 rank [ic] on the same trigger: the three currents are
 * sampled at one instant, the two capacitor voltages at the next rank. */
#define ADC1_CH_IA 1u
#define ADC1_CH_VC1 6u
#define ADC2_CH_IB 2u
#define ADC2_CH_VC2 7u
#define ADC3_CH_IC 1u /* PB1 = ADC3_IN1 (datasheet pin table, LQFP64) */

typedef struct {
    uint32_t code[5];     /* this tick's ADC codes (ia, ib, ic, vc1, vc2), latched by the tick ISR */
    bool sample_fresh;    /* cleared by the one allowed read, which converts code[] */
    bool calibrated;      /* calibration and offsets valid */
    uint32_t seq;         /* tick sequence number */
    float offset_code[3]; /* current-sensor zero, ADC codes (ia, ib, ic) */
} adc_driver;

static adc_driver g_adc;

static bool adc_power_up(uint32_t base)
{
    /* Exit deep power-down, start the regulator, wait tADCVREG_STUP (20 us,
     * datasheet), calibrate single-ended (RM0440 21.4.6, 21.4.8). */
    ADC_REG(base, ADC_CR_OFS) = 0u; /* DEEPPWD = 0 */
    ADC_REG(base, ADC_CR_OFS) = ADC_CR_ADVREGEN;
    clock_delay_ns(20000u);
    ADC_REG(base, ADC_CR_OFS) = ADC_CR_ADVREGEN | ADC_CR_ADCAL; /* ADCALDIF = 0: single-ended */
    if (!chip_wait(&ADC_REG(base, ADC_CR_OFS), ADC_CR_ADCAL, 0u, CHIP_WAIT_LOOPS))
        return false;
    clock_delay_ns(1000u); /* 4 ADC clocks between ADCAL = 0 and ADEN = 1 */
    ADC_REG(base, ADC_ISR_OFS) = ADC_ISR_ADRDY;
    ADC_REG(base, ADC_CR_OFS) = ADC_CR_ADVREGEN | ADC_CR_ADEN;
    if (!chip_wait(&ADC_REG(base, ADC_ISR_OFS), ADC_ISR_ADRDY, ADC_ISR_ADRDY, CHIP_WAIT_LOOPS))
        return false;
    ADC_REG(base, ADC_ISR_OFS) = ADC_ISR_ADRDY;
    return true;
}

static uint32_t smp_bits(uint32_t ch) { return ADC_SMP_24C5 << (ADC_SMPR_BITS * (ch % 10u)); }

static void adc_set_sampling(uint32_t base, uint32_t ch)
{
    uint32_t ofs = ch < 10u ? ADC_SMPR1_OFS : ADC_SMPR2_OFS;
    uint32_t sh = ADC_SMPR_BITS * (ch % 10u);
    ADC_REG(base, ofs) = (ADC_REG(base, ofs) & ~(7u << sh)) | smp_bits(ch);
}

/*
 * ADC1 (master) + ADC2 (slave), dual injected simultaneous mode, 2 ranks
 * each, and ADC3 (independent, 1 rank), all three triggered by HRTIM ADC
 * trigger 2 (master compare 1) on the rising edge: JEXTSEL 19 is
 * hrtim_adc_trg2 in both the ADC1/2 and the ADC3/4/5 injected trigger tables
 * (RM0440, ADC chapter). Both ADC pairs are clocked HCLK / 4 = 42.5 MHz,
 * synchronous with the HRTIM, so the sampling instants have no jitter
 * (RM0440 21.4.3, 21.4.31). 24.5 + 12.5 ADC cycles = 0.87 us per rank:
 * ia, ib and ic are sampled at the trigger (rank 1), vc1 and vc2 one rank
 * later; ADC3's single rank ends one rank before ADC1's sequence.
 */
int adc_init(void)
{
    g_adc.calibrated = false;
    RCC_CCIPR = (RCC_CCIPR & ~(RCC_CCIPR_ADC12SEL_MASK | RCC_CCIPR_ADC345SEL_MASK)) | RCC_CCIPR_ADC12SEL_SYSCLK |
                RCC_CCIPR_ADC345SEL_SYSCLK;
    RCC_AHB2ENR |= RCC_AHB2ENR_ADC12EN | RCC_AHB2ENR_ADC345EN;
    (void)RCC_AHB2ENR;
    /* Clock mode and dual mode may be written only while the ADCs of the
     * pair are disabled (RM0440, ADC chapter, ADC_CCR description). */
    ADC12_CCR = (ADC12_CCR & ~(ADC12_CCR_CKMODE_MASK | ADC12_CCR_DUAL_MASK)) | ADC12_CCR_CKMODE_HCLK_DIV4 |
                ADC12_CCR_DUAL_INJ_SIMULT;
    ADC345_CCR = (ADC345_CCR & ~(ADC345_CCR_CKMODE_MASK | ADC345_CCR_DUAL_MASK)) | ADC345_CCR_CKMODE_HCLK_DIV4;

    if (!adc_power_up(ADC1_BASE) || !adc_power_up(ADC2_BASE) || !adc_power_up(ADC3_BASE)) {
        board_fault_record(BOARD_FAULT_ADC_CAL);
        return HAL_EIO;
    }

    ADC_REG(ADC1_BASE, ADC_CFGR_OFS) |= ADC_CFGR_JQDIS;
    ADC_REG(ADC2_BASE, ADC_CFGR_OFS) |= ADC_CFGR_JQDIS;
    ADC_REG(ADC3_BASE, ADC_CFGR_OFS) |= ADC_CFGR_JQDIS;
    adc_set_sampling(ADC1_BASE, ADC1_CH_IA);
    adc_set_sampling(ADC1_BASE, ADC1_CH_VC1);
    adc_set_sampling(ADC2_BASE, ADC2_CH_IB);
    adc_set_sampling(ADC2_BASE, ADC2_CH_VC2);
    adc_set_sampling(ADC3_BASE, ADC3_CH_IC);

    ADC_REG(ADC1_BASE, ADC_JSQR_OFS) = (1u << ADC_JSQR_JL_SHIFT) | (ADC_JEXTSEL_HRTIM_TRG2 << ADC_JSQR_JEXTSEL_SHIFT) |
                                      ADC_JSQR_JEXTEN_RISING | (ADC1_CH_IA << ADC_JSQR_JSQ1_SHIFT) |
                                      (ADC1_CH_VC1 << ADC_JSQR_JSQ2_SHIFT);
    /* The slave follows the master's trigger: its own trigger stays off. */
    ADC_REG(ADC2_BASE, ADC_JSQR_OFS) =
        (1u << ADC_JSQR_JL_SHIFT) | (ADC2_CH_IB << ADC_JSQR_JSQ1_SHIFT) | (ADC2_CH_VC2 << ADC_JSQR_JSQ2_SHIFT);
    ADC3_JSQR = (0u << ADC_JSQR_JL_SHIFT) | (ADC345_JEXTSEL_HRTIM_TRG2 << ADC_JSQR_JEXTSEL_SHIFT) |
                ADC_JSQR_JEXTEN_RISING | (ADC3_CH_IC << ADC_JSQR_JSQ1_SHIFT);

    ADC_REG(ADC1_BASE, ADC_ISR_OFS) = ADC_ISR_JEOS | ADC_ISR_JEOC;
    ADC_REG(ADC2_BASE, ADC_ISR_OFS) = ADC_ISR_JEOS | ADC_ISR_JEOC;
    ADC3_ISR = ADC_ISR_JEOS | ADC_ISR_JEOC;
    /* ADC3 armed first: both wait for the same HRTIM trigger edge. */
    ADC_REG(ADC3_BASE, ADC_CR_OFS) |= ADC_CR_JADSTART;
    ADC_REG(ADC1_BASE, ADC_CR_OFS) |= ADC_CR_JADSTART; /* the master starts both of its pair */
    return HAL_OK;
}

/* JADSTP, then ADDIS (RM0440, ADC chapter, "Stopping an ongoing conversion"
 * / "ADC on-off control"), so a later adc_init() finds them disabled as it
 * must. */
void adc_stop(void)
{
    ADC_REG(ADC1_BASE, ADC_IER_OFS) = 0u;
    const uint32_t masters[2] = {ADC1_BASE, ADC3_BASE};
    for (unsigned k = 0u; k < 2u; k++) {
        if ((ADC_REG(masters[k], ADC_CR_OFS) & ADC_CR_JADSTART) != 0u) {
            ADC_REG(masters[k], ADC_CR_OFS) |= ADC_CR_JADSTP;
            (void)chip_wait(&ADC_REG(masters[k], ADC_CR_OFS), ADC_CR_JADSTART, 0u, CHIP_WAIT_LOOPS);
        }
    }
    const uint32_t bases[3] = {ADC1_BASE, ADC2_BASE, ADC3_BASE};
    for (unsigned k = 0u; k < 3u; k++) {
        if ((ADC_REG(bases[k], ADC_CR_OFS) & ADC_CR_ADEN) != 0u) {
            ADC_REG(bases[k], ADC_CR_OFS) |= ADC_CR_ADDIS;
            (void)chip_wait(&ADC_REG(bases[k], ADC_CR_OFS), ADC_CR_ADEN, 0u, CHIP_WAIT_LOOPS);
        }
    }
}

/*
 * Read the five injected results (ia, ib, ic, vc1, vc2) once ADC1's sequence
 * has ended. ADC3's single rank ends one rank (0.87 us) before ADC1's two on
 * the same trigger, but its result is taken only with its own JEOS set: a
 * missed or late ADC3 conversion is refused, never read stale.
 * @return ADC_CODES_OK, or why the sample must be refused.
 */
enum adc_codes { ADC_CODES_OK, ADC_CODES_SATURATED, ADC_CODES_IC_MISSING };

static enum adc_codes adc_read_codes(uint32_t code[5])
{
    bool ic_done = (ADC3_ISR & ADC_ISR_JEOS) != 0u;
    code[0] = ADC_JDR(ADC1_BASE, 0u) & 0xFFFu; /* ia */
    code[1] = ADC_JDR(ADC2_BASE, 0u) & 0xFFFu; /* ib */
    code[2] = ADC3_JDR1 & 0xFFFu;               /* ic */
    code[3] = ADC_JDR(ADC1_BASE, 1u) & 0xFFFu; /* vc1 */
    code[4] = ADC_JDR(ADC2_BASE, 1u) & 0xFFFu; /* vc2 */
    ADC_REG(ADC1_BASE, ADC_ISR_OFS) = ADC_ISR_JEOS | ADC_ISR_JEOC;
    ADC_REG(ADC2_BASE, ADC_ISR_OFS) = ADC_ISR_JEOS | ADC_ISR_JEOC;
    ADC3_ISR = ADC_ISR_JEOS | ADC_ISR_JEOC;
    if (!ic_done)
        return ADC_CODES_IC_MISSING;
    for (unsigned k = 0u; k < 5u; k++) {
        if (k < 3u && (code[k] <= BOARD_ADC_SAT_LOW || code[k] >= BOARD_ADC_SAT_HIGH))
            return ADC_CODES_SATURATED; /* a current at the rail: the sensor or the converter is saturated */
        if (k >= 3u && code[k] >= BOARD_ADC_SAT_HIGH)
            return ADC_CODES_SATURATED; /* a capacitor voltage at full scale (0 V is a valid reading) */
    }
    return ADC_CODES_OK;
}

int adc_calibrate_offsets(void)
{
    uint32_t sum[3] = {0u, 0u, 0u};
    for (uint32_t n = 0u; n < BOARD_OFFSET_SAMPLES; n++) {
        if (!chip_wait(&ADC_REG(ADC1_BASE, ADC_ISR_OFS), ADC_ISR_JEOS, ADC_ISR_JEOS, CHIP_WAIT_LOOPS)) {
            board_fault_record(BOARD_FAULT_ADC_OFFSET);
            return HAL_EIO;
        }
        uint32_t code[5];
        if (adc_read_codes(code) == ADC_CODES_IC_MISSING) { /* ADC3 did not convert with ADC1/2: no offset for ic */
            board_fault_record(BOARD_FAULT_ADC_OFFSET);
            return HAL_EIO;
        }
        for (unsigned k = 0u; k < 3u; k++)
            sum[k] += code[k];
    }
    bool ok = true;
    for (unsigned k = 0u; k < 3u; k++) {
        uint32_t mean = (sum[k] + BOARD_OFFSET_SAMPLES / 2u) / BOARD_OFFSET_SAMPLES;
        uint32_t dev = mean > BOARD_ADC_MID_CODE ? mean - BOARD_ADC_MID_CODE : BOARD_ADC_MID_CODE - mean;
        if (dev > BOARD_OFFSET_TOL_CODE)
            ok = false;
        g_adc.offset_code[k] = (float)sum[k] / (float)BOARD_OFFSET_SAMPLES;
    }
    if (!ok) {
        board_fault_record(BOARD_FAULT_ADC_OFFSET); /* samples refused: the drive stays safe */
        return HAL_EIO;
    }
    g_adc.calibrated = true;
    return HAL_OK;
}

bool adc_calibrated(void) { return g_adc.calibrated; }

void adc_tick_irq_enable(void)
{
    ADC_REG(ADC1_BASE, ADC_ISR_OFS) = ADC_ISR_JEOS | ADC_ISR_JEOC;
    ADC_REG(ADC1_BASE, ADC_IER_OFS) = ADC_IER_JEOSIE;
}

void adc_latch(void)
{
    enum adc_codes got = adc_read_codes(g_adc.code);
    g_adc.seq++;
    if (got == ADC_CODES_SATURATED)
        board_fault_record(BOARD_FAULT_ADC_RANGE);
    if (got == ADC_CODES_IC_MISSING)
        board_fault_record(BOARD_FAULT_ADC_SYNC);
    /* No trustworthy measurement: refuse it (the control core then sees a
     * stale sample and goes to its safe state). A good one is converted by
     * the one allowed read, straight into the reader's buffer: one copy of
     * the sample, not two. */
    g_adc.sample_fresh = g_adc.calibrated && got == ADC_CODES_OK;
}

int adc_sample_read(hal_sample *out)
{
    if (out == NULL)
        return HAL_EINVAL;
    if (!g_adc.sample_fresh)
        return HAL_EAGAIN;
    g_adc.sample_fresh = false;
    const float i_scale = 2.0f * BOARD_I_FULL_SCALE_A / BOARD_ADC_FULL_CODE;
    const float v_scale = BOARD_V_FULL_SCALE_V / BOARD_ADC_FULL_CODE;
    const uint32_t *code = g_adc.code;
    out->ia_A = ((float)code[0] - g_adc.offset_code[0]) * i_scale;
    out->ib_A = ((float)code[1] - g_adc.offset_code[1]) * i_scale;
    out->ic_A = ((float)code[2] - g_adc.offset_code[2]) * i_scale;
    out->vc1_V = (float)code[3] * v_scale;
    out->vc2_V = (float)code[4] * v_scale;
    out->speed_meas_rad_s = 0.0f;
    out->speed_meas_valid = false; /* no speed sensor on the board */
    out->seq = g_adc.seq;
    return HAL_OK;
}
