/* Test image for the twin's FDCAN1 model: the port's own CAN driver (hal/stm32g4/fdcan.c,
 * linked unchanged with the clock tree, the pin map and the fault word it needs) at 170 MHz,
 * without the rest of the binding.
 *   CAN_BITRATE   bit rate passed to fdcan_open (default 500000, the port's default)
 * Behaviour: open FDCAN1, send one frame (id 0x181, dlc 3, 11 22 33), then echo every received
 * frame as id 0x580 | (id & 0x7F) with the same data (the SDO-server shape), forever. The host
 * test checks the bit timing, the frames on its backend, and the bus-off recovery the driver
 * runs from its background (fdcan_recv -> can_service, 100 ms after bus-off). */
#include "board.h"
#include "clock.h"
#include "fdcan.h"
#include "pins.h"
#include "semihost_min.h"
#include "stm32g474_regs.h"

#ifndef CAN_BITRATE
#define CAN_BITRATE 500000u
#endif

/* Start of the vector table, from stm32g474.ld. */
extern const uint32_t __isr_vector_start[];

/* The port's reset handler (startup_stm32g474.c) calls these two: here the clock tree, the
 * pins and the 1 ms time base the CAN driver needs, and no gates to make safe. */
void board_init(void)
{
    SCB_VTOR = (uint32_t)(uintptr_t)__isr_vector_start;
    clock_cycle_counter_start();
    (void)clock_init();
    pins_init();
    clock_systick_start(15u);
}

void board_safe_state(void) {}

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
    g_test_stage = 1u;
    if (clock_sysclk_hz() != 170000000u) {
        sh_puts("can_driver_image: clock_init did not reach 170 MHz\n");
        sh_exit(3);
    }
    int rc = fdcan_open(CAN_BITRATE);
    if (rc != HAL_OK) {
        sh_puts("can_driver_image: fdcan_open failed\n");
        sh_exit(4);
    }
    g_test_stage = 2u;
    hal_can_frame f = {.id = 0x181u, .dlc = 3u, .rtr = false, .data = {0x11u, 0x22u, 0x33u}};
    while (fdcan_send(&f) != HAL_OK) {
    }
    g_test_tx++;
    g_test_stage = 3u;
    for (;;) {
        hal_can_frame r;
        if (fdcan_recv(&r) != HAL_OK)
            continue;
        g_test_rx++;
        hal_can_frame e = r;
        e.id = (uint16_t)(0x580u | (r.id & 0x7Fu));
        while ((rc = fdcan_send(&e)) == HAL_EBUSY)
            g_test_tx_busy++;
        if (rc == HAL_OK)
            g_test_tx++;
    }
}
