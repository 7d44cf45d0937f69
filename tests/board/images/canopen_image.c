/* Test image: the real firmware's drive and CANopen device (firmware/drive, firmware/canopen,
 * firmware/control as built for the target in build/stm32g4) with the port's binding
 * (hal/stm32g4, every driver, linked unchanged: the drive calls every hal.h function), started
 * like hal/stm32g4/main.c but without the watchdog and the control tick. Everything CANopen
 * does runs in drive_background(), so the boot-up, NMT, SDO and heartbeat are the firmware's
 * own. */
#include "dtc/drive.h"
#include "semihost_min.h"

void HardFault_Handler(void);
void HardFault_Handler(void)
{
    sh_puts("canopen_image: HardFault\n");
    sh_exit(90);
}

static drive g_drive;

int main(void)
{
    drive_init(&g_drive);
    for (;;)
        drive_background(&g_drive);
}
