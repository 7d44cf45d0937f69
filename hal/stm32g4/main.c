/**
 * @file main.c
 * @brief Target entry point: start the 200 us control interrupt, then run the
 *        background loop forever, asleep (WFI) whenever it has nothing to do.
 */
#include "dtc/drive.h"
#include "hal/hal.h"

#include "board.h"

/* Background loop deadline: the watchdog resets the chip if one pass of
 * drive_background() (which kicks it) ever takes longer than this. */
#define WATCHDOG_TIMEOUT_MS 100u
#define CONTROL_PERIOD_US 200u

/* The drive is owned for the whole run and too large for the stack. */
static drive g_drive;

int main(void)
{
    /* The watchdog first: a start-up that hangs (e.g. in an exception while
     * reading the parameter store) ends in a reset, not in a dead drive. */
    (void)hal_watchdog_start(WATCHDOG_TIMEOUT_MS);
    drive_init(&g_drive);

    if (hal_tick_start(drive_isr, &g_drive, CONTROL_PERIOD_US) != HAL_OK) {
        /* Cannot control: stay safe and let the watchdog restart the chip. */
        hal_gate_enable(false);
        for (;;) {
        }
    }

    /* The background runs once per interrupt that can give it work and
     * sleeps in between (board_idle: WFI, the production way to save power;
     * the emulated board skips the idle time instead of emulating a loop). */
    for (;;) {
        uint32_t mark = board_idle_mark(&g_drive.tick);
        drive_background(&g_drive);
        board_idle(&g_drive.tick, mark);
    }
}
