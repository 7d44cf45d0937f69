/* Test image: the real firmware's drive and CANopen device (firmware/drive, firmware/canopen,
 * firmware/control as built for the target in build/stm32g4) with the port's HAL
 * (hal/stm32g4/hal_stm32g4.c, unchanged), started like hal/stm32g4/main.c but without the
 * control tick: board_init()'s HRTIM/ADC start-up and hal_tick_start() need HRTIM and ADC
 * models the twin in this branch lacks. Everything CANopen does runs in drive_background(),
 * so the boot-up, NMT, SDO and heartbeat are the firmware's own. */
#include "../../../hal/stm32g4/hal_stm32g4.c"
#include "dtc/drive.h"
#include "semihost_min.h"

void test_early_init(void);
void test_early_init(void) {}

void HardFault_Handler(void);
void HardFault_Handler(void)
{
    sh_puts("canopen_image: HardFault\n");
    sh_exit(90);
}

static drive g_drive;

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
    drive_init(&g_drive);
    for (;;)
        drive_background(&g_drive);
}
