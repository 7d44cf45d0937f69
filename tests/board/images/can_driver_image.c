/* Test image for the twin's FDCAN1 model: the port's own CAN driver (hal/stm32g4/hal_stm32g4.c,
 * compiled into this image unchanged) on the 170 MHz clock tree the port sets up, without the
 * HRTIM/ADC start-up of board_init().
 *   CAN_BITRATE   bit rate passed to hal_can_open (default 500000, the port's default)
 * Behaviour: open FDCAN1, send one frame (id 0x181, dlc 3, 11 22 33), then echo every received
 * frame as id 0x580 | (id & 0x7F) with the same data (the SDO-server shape), forever. The host
 * test checks the bit timing, the frames on its backend, and the bus-off recovery the driver
 * runs from its background (hal_can_recv -> can_service, 100 ms after bus-off). */
#include "../../../hal/stm32g4/hal_stm32g4.c"
#include "semihost_min.h"

#ifndef CAN_BITRATE
#define CAN_BITRATE 500000u
#endif

/* The image is linked with the port's startup file compiled with -Dboard_init=test_early_init:
 * its vector table and reset handler, but not the HRTIM/ADC start-up of board_init(). */
void test_early_init(void);
void test_early_init(void) {}

/* A fault is a test failure, with the fault status for the log. */
void HardFault_Handler(void);
void HardFault_Handler(void)
{
    sh_puts("can_driver_image: HardFault\n");
    sh_exit(90);
}

/* Counters the host reads by symbol. */
volatile uint32_t g_test_rx, g_test_tx, g_test_tx_busy, g_test_stage;

int main(void)
{
    SCB_VTOR = (uint32_t)(uintptr_t)__isr_vector_start;
    DEMCR |= DEMCR_TRCENA;
    DWT_CYCCNT = 0u;
    DWT_CTRL |= DWT_CTRL_CYCCNTENA;
    clock_init_170mhz();
    gpio_init();
    SCB_SHPR3 = (SCB_SHPR3 & 0x00FFFFFFu) | ((PRIO_SYSTICK << NVIC_PRIO_SHIFT) << 24);
    SYST_RVR = g_board.sysclk_hz / 1000u - 1u;
    SYST_CVR = 0u;
    SYST_CSR = SYST_CSR_CLKSOURCE | SYST_CSR_TICKINT | SYST_CSR_ENABLE;
    g_test_stage = 1u;
    if (g_board.sysclk_hz != 170000000u) {
        sh_puts("can_driver_image: clock_init_170mhz did not reach 170 MHz\n");
        sh_exit(3);
    }
    int rc = hal_can_open(CAN_BITRATE);
    if (rc != HAL_OK) {
        sh_puts("can_driver_image: hal_can_open failed\n");
        sh_exit(4);
    }
    g_test_stage = 2u;
    hal_can_frame f = {.id = 0x181u, .dlc = 3u, .rtr = false, .data = {0x11u, 0x22u, 0x33u}};
    while (hal_can_send(&f) != HAL_OK) {
    }
    g_test_tx++;
    g_test_stage = 3u;
    for (;;) {
        hal_can_frame r;
        if (hal_can_recv(&r) != HAL_OK)
            continue;
        g_test_rx++;
        hal_can_frame e = r;
        e.id = (uint16_t)(0x580u | (r.id & 0x7Fu));
        while ((rc = hal_can_send(&e)) == HAL_EBUSY)
            g_test_tx_busy++;
        if (rc == HAL_OK)
            g_test_tx++;
    }
}
