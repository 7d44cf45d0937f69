/**
 * @file pins.c
 * @brief The board's pin map and its set-up. docs/board.md has the same
 *        table; tools/svd/check_regs.py --pins (ctest hal_stm32g4.board_pins)
 *        compares the two.
 */
#include "pins.h"

#include <stddef.h>

/* One GPIO the firmware configures. */
typedef struct {
    uint32_t port_base;
    uint8_t pin;
    uint8_t mode; /* GPIO_MODE_* */
    uint8_t af;   /* alternate function when mode == GPIO_MODE_AF */
    uint8_t pupd; /* 0 none, 1 pull-up, 2 pull-down */
} board_pin;

#define PIN_AF(port, pin, af, pupd) {port, pin, GPIO_MODE_AF, af, pupd}
#define PIN_ANALOG(port, pin) {port, pin, GPIO_MODE_ANALOG, 0u, 0u}

static const board_pin g_pins[] = {
    /* HRTIM gate outputs (pull-downs hold the drivers off while the pins float). */
    PIN_AF(GPIOA_BASE, 8u, 13u, 2u),  /* CHA1 leg a S3 */
    PIN_AF(GPIOA_BASE, 9u, 13u, 2u),  /* CHA2 leg a S1 */
    PIN_AF(GPIOA_BASE, 10u, 13u, 2u), /* CHB1 leg a S2 */
    PIN_AF(GPIOA_BASE, 11u, 13u, 2u), /* CHB2 leg a S4 */
    PIN_AF(GPIOB_BASE, 12u, 13u, 2u), /* CHC1 leg b S3 */
    PIN_AF(GPIOB_BASE, 13u, 13u, 2u), /* CHC2 leg b S1 */
    PIN_AF(GPIOB_BASE, 14u, 13u, 2u), /* CHD1 leg b S2 */
    PIN_AF(GPIOB_BASE, 15u, 13u, 2u), /* CHD2 leg b S4 */
    PIN_AF(GPIOC_BASE, 8u, 3u, 2u),   /* CHE1 leg c S3 */
    PIN_AF(GPIOC_BASE, 9u, 3u, 2u),   /* CHE2 leg c S1 */
    PIN_AF(GPIOC_BASE, 6u, 13u, 2u),  /* CHF1 leg c S2 */
    PIN_AF(GPIOC_BASE, 7u, 13u, 2u),  /* CHF2 leg c S4 */
    /* Gate-driver fault line, active low, open drain: pull-up. */
    PIN_AF(GPIOB_BASE, 10u, 13u, 1u), /* HRTIM_FLT3: outer switches off */
    PIN_AF(GPIOB_BASE, 5u, 13u, 1u),  /* HRTIM_EEV6, the same line: inner switches off (filtered) */
    /* FDCAN1 to the transceiver. */
    PIN_AF(GPIOB_BASE, 8u, 9u, 1u), /* FDCAN1_RX */
    PIN_AF(GPIOB_BASE, 9u, 9u, 0u), /* FDCAN1_TX */
    /* Analog inputs. */
    PIN_ANALOG(GPIOA_BASE, 0u), /* ADC1_IN1 ia */
    PIN_ANALOG(GPIOA_BASE, 1u), /* ADC2_IN2 ib */
    PIN_ANALOG(GPIOB_BASE, 1u), /* ADC3_IN1 ic */
    PIN_ANALOG(GPIOC_BASE, 0u), /* ADC1_IN6 vc1 */
    PIN_ANALOG(GPIOC_BASE, 1u), /* ADC2_IN7 vc2 */
};

void pins_init(void)
{
    RCC_AHB2ENR |= RCC_AHB2ENR_GPIOAEN | RCC_AHB2ENR_GPIOBEN | RCC_AHB2ENR_GPIOCEN;
    (void)RCC_AHB2ENR;
    for (size_t i = 0u; i < sizeof g_pins / sizeof g_pins[0]; i++) {
        const board_pin *p = &g_pins[i];
        uint32_t b = p->port_base;
        uint32_t pin = p->pin;
        /* Pull and speed first, then the AF number, then the mode (RM0440 9.3.2). */
        GPIO_REG(b, GPIO_PUPDR_OFS) =
            (GPIO_REG(b, GPIO_PUPDR_OFS) & ~(3u << (2u * pin))) | ((uint32_t)p->pupd << (2u * pin));
        if (p->mode == GPIO_MODE_AF) {
            GPIO_REG(b, GPIO_OSPEEDR_OFS) |= 2u << (2u * pin); /* high speed: clean gate edges */
            uint32_t ofs = pin < 8u ? GPIO_AFRL_OFS : GPIO_AFRH_OFS;
            uint32_t sh = 4u * (pin & 7u);
            GPIO_REG(b, ofs) = (GPIO_REG(b, ofs) & ~(GPIO_AFR_MASK0 << sh)) | ((uint32_t)p->af << sh);
        }
        GPIO_REG(b, GPIO_MODER_OFS) = (GPIO_REG(b, GPIO_MODER_OFS) & ~(GPIO_MODER_MASK0 << (2u * pin))) |
                                      ((uint32_t)p->mode << (2u * pin));
    }
}
