/**
 * @file reset_cause.h
 * @brief Why the chip last started, from RCC_CSR's reset flags. Private to
 *        hal/stm32g4.
 */
#ifndef HAL_STM32G4_RESET_CAUSE_H
#define HAL_STM32G4_RESET_CAUSE_H

#include <stdint.h>

/**
 * @return the enum hal_reset_cause of the RCC_CSR value @p csr: the most
 * specific flag wins (an internal reset also drives NRST, so PINRSTF comes
 * with every other flag; a power-on sets BORRSTF and PINRSTF).
 * Context: ANY (pure).
 */
uint32_t reset_cause_of_csr(uint32_t csr);

/**
 * @return the cause of this start (reset_cause_of_csr(RCC_CSR)), with the
 * flags cleared so the next start reports its own. Context: BG, once, from
 * board_init().
 */
uint32_t reset_cause_take(void);

#endif /* HAL_STM32G4_RESET_CAUSE_H */
