/**
 * @file iwdg.c
 * @brief The independent watchdog (RM0440 41) and its two-flag refresh.
 */
#include "iwdg.h"

#include "chip.h"
#include "hal/hal_types.h"

typedef struct {
    bool started;
    bool tick_expected;       /* the control tick runs: it must prove itself */
    volatile bool tick_alive; /* set by the tick ISR, cleared by each refresh */
} iwdg_driver;

static iwdg_driver g_iwdg;

int iwdg_start(uint32_t timeout_ms)
{
    if (timeout_ms < 1u || timeout_ms > 4000u)
        return HAL_EINVAL;
    /* Stop the watchdog while the core is halted by a debugger. */
    DBGMCU_APB1L_FZ |= DBGMCU_APB1L_FZ_IWDG;
    /* LSI (about 32 kHz, +-several %) / 32 = one reload count per ms. The
     * start key also switches the LSI on; once started it cannot be stopped. */
    IWDG_KR = IWDG_KEY_START;
    IWDG_KR = IWDG_KEY_UNLOCK;
    IWDG_PR = IWDG_PR_DIV32;
    IWDG_RLR = timeout_ms;
    if (!chip_wait(&IWDG_SR, IWDG_SR_BUSY_MASK, 0u, CHIP_WAIT_LOOPS))
        return HAL_EIO;
    IWDG_KR = IWDG_KEY_REFRESH;
    g_iwdg.started = true;
    return HAL_OK;
}

void iwdg_expect_tick(bool running) { g_iwdg.tick_expected = running; }

void iwdg_tick_alive(void) { g_iwdg.tick_alive = true; }

void iwdg_service(void)
{
    if (!g_iwdg.started)
        return;
    if (g_iwdg.tick_expected && !g_iwdg.tick_alive)
        return; /* the tick has not run since the last refresh: let it bite */
    g_iwdg.tick_alive = false;
    IWDG_KR = IWDG_KEY_REFRESH;
}
