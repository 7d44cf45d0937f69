/**
 * @file reset_cause.c
 * @brief The reset cause from RCC_CSR (RM0440, RCC chapter, RCC_CSR).
 */
#include "reset_cause.h"

#include "hal/hal.h"
#include "stm32g474_regs.h"

uint32_t reset_cause_of_csr(uint32_t csr)
{
    if ((csr & RCC_CSR_IWDGRSTF) != 0u)
        return HAL_RESET_WATCHDOG;
    if ((csr & RCC_CSR_WWDGRSTF) != 0u)
        return HAL_RESET_WINDOW_WATCHDOG;
    if ((csr & RCC_CSR_SFTRSTF) != 0u)
        return HAL_RESET_SOFTWARE;
    if ((csr & RCC_CSR_LPWRRSTF) != 0u)
        return HAL_RESET_LOW_POWER;
    if ((csr & RCC_CSR_OBLRSTF) != 0u)
        return HAL_RESET_OPTION_LOAD;
    if ((csr & RCC_CSR_BORRSTF) != 0u)
        return HAL_RESET_POWER_ON;
    if ((csr & RCC_CSR_PINRSTF) != 0u)
        return HAL_RESET_PIN;
    return HAL_RESET_UNKNOWN;
}

uint32_t reset_cause_take(void)
{
    uint32_t cause = reset_cause_of_csr(RCC_CSR);
    RCC_CSR |= RCC_CSR_RMVF;
    return cause;
}
