/**
 * @file flash_nvm.h
 * @brief The parameter store: two 2 KiB pages of flash bank 2 (the linker
 *        script's NVM area), read through the bus with double-ECC errors
 *        caught, written in place or by page erase. Private to hal/stm32g4.
 *
 * hal.h's "a power loss may leave any prefix written" reads here: a write
 * that needs an erase rewrites its whole 2 KiB page, so a power loss in the
 * middle can leave that page partly erased. The persist layer keeps each of
 * its two slots in its own page (slot size = flash_nvm_size() / 2 = one
 * page) and writes the header last, so the other slot is never touched and
 * a reset at any point leaves one valid slot.
 */
#ifndef HAL_STM32G4_FLASH_NVM_H
#define HAL_STM32G4_FLASH_NVM_H

#include <stddef.h>
#include <stdint.h>

/** @return the store's size, bytes (4096: two pages). Context: ANY. */
uint32_t flash_nvm_size(void);

/**
 * Copy @p len bytes at @p offset of the store into @p buf (erased bytes
 * read 0xFF). Context: BG.
 * @return HAL_OK, HAL_EINVAL for a NULL @p buf with @p len > 0, HAL_ENOSPC
 * past the end, HAL_EIO when a double ECC error was met (an interrupted
 * write: the data are unusable; BOARD_FAULT_NVM recorded).
 */
int flash_nvm_read(uint32_t offset, void *buf, size_t len);

/**
 * Write @p len bytes of @p buf at @p offset: each page touched is
 * programmed in place when every changed double word is erased, otherwise
 * erased and rewritten whole; read back through the bus. The watchdog is
 * serviced meanwhile (iwdg_service()). Blocks for up to about 2 x 40 ms (two
 * page erases) plus 90 us per double word. Context: BG only.
 * @return HAL_OK, HAL_EINVAL, HAL_ENOSPC as flash_nvm_read(); HAL_EIO from
 * an interrupt, in single-bank mode (both slots would share a 4 KiB page),
 * when the flash stays locked, on a program/erase error or a read-back
 * mismatch (BOARD_FAULT_NVM recorded).
 */
int flash_nvm_write(uint32_t offset, const void *buf, size_t len);

#endif /* HAL_STM32G4_FLASH_NVM_H */
