/**
 * @file iwdg.h
 * @brief The independent watchdog with a two-flag refresh: the background
 *        asks for a refresh, which happens only if the control tick has also
 *        run since the last one, so neither a stuck background nor a dead
 *        tick keeps the chip alive (docs/board.md, "Watchdog"). Private to
 *        hal/stm32g4.
 */
#ifndef HAL_STM32G4_IWDG_H
#define HAL_STM32G4_IWDG_H

#include <stdbool.h>
#include <stdint.h>

/**
 * Start the IWDG (LSI / 32: one count per ms) with a timeout of
 * @p timeout_ms (1..4000), frozen while a debugger halts the core. Once
 * started it cannot be stopped. Context: BG.
 * @return HAL_OK, HAL_EINVAL out of range, HAL_EIO when the prescaler and
 * reload were not taken.
 */
int iwdg_start(uint32_t timeout_ms);

/**
 * Tell the watchdog whether the control tick runs (@p running): while it
 * does, a refresh needs iwdg_tick_alive() since the last one. Context: BG.
 */
void iwdg_expect_tick(bool running);

/** The control tick proves itself alive. Context: ISR (the control tick). */
void iwdg_tick_alive(void);

/**
 * Refresh the watchdog if it runs and the tick (when expected) has proven
 * itself since the last refresh; otherwise let it bite. Context: BG.
 */
void iwdg_service(void);

#endif /* HAL_STM32G4_IWDG_H */
