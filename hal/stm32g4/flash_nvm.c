/**
 * @file flash_nvm.c
 * @brief The parameter store in flash bank 2 (RM0440 5): reads with the
 *        double-ECC NMI caught, page erase and double-word programming.
 */
#include "flash_nvm.h"

#include <stdbool.h>
#include <string.h>

#include "board.h"
#include "chip.h"
#include "hal/hal_types.h"
#include "iwdg.h"

/* NVM area, from stm32g474.ld. */
extern const uint8_t __nvm_start[];
extern const uint8_t __nvm_size[];
#define NVM_PAGE_SIZE 2048u
#define FLASH_BANK2_START 0x08040000u

#define WAIT_FLASH_LOOPS 20000000u /* page erase: 40 ms max (datasheet), generous */

#define FLASH_SR_ERRORS                                                                                  \
    (FLASH_SR_OPERR | FLASH_SR_PROGERR | FLASH_SR_WRPERR | FLASH_SR_PGAERR | FLASH_SR_SIZERR |          \
     FLASH_SR_PGSERR | FLASH_SR_MISSERR | FLASH_SR_FASTERR | FLASH_SR_RDERR | FLASH_SR_OPTVERR)

typedef struct {
    /* A double ECC error in the parameter pages is an interrupted write, not a broken chip. */
    volatile bool reading; /* the background is reading the parameter pages */
    volatile bool ecc_hit; /* the NMI saw FLASH_ECCR.ECCD meanwhile */
    uint32_t ecc_errors;
} flash_nvm_driver;

static flash_nvm_driver g_nvm;

/* One page's new contents, assembled before it is written. */
static uint8_t g_page_buf[NVM_PAGE_SIZE] __attribute__((aligned(8)));

uint32_t flash_nvm_size(void) { return (uint32_t)(uintptr_t)__nvm_size; }

static int nvm_check(uint32_t offset, const void *buf, size_t len)
{
    uint32_t size = flash_nvm_size();
    if (buf == NULL && len != 0u)
        return HAL_EINVAL;
    if (offset > size || len > (size_t)(size - offset))
        return HAL_ENOSPC;
    return HAL_OK;
}

/*
 * Reads of the parameter pages go between these two: a power loss during an
 * erase or a program leaves double words whose ECC does not match, and reading
 * one raises the NMI with FLASH_ECCR.ECCD (RM0440, FLASH chapter, "Error code
 * correction"). Inside the window the NMI handler takes that as "this copy is
 * unreadable" instead of a fatal error. nvm_read_end() returns false if an
 * ECC error was seen. Context: BG.
 */
static void nvm_read_begin(void)
{
    g_nvm.ecc_hit = false;
    g_nvm.reading = true;
    __asm volatile("" ::: "memory");
}

static bool nvm_read_end(void)
{
    __asm volatile("dsb\n\tisb" ::: "memory"); /* the last read's NMI is taken by now */
    g_nvm.reading = false;
    return !g_nvm.ecc_hit;
}

/** NMI: a double ECC error while the background reads the parameter pages is
 * cleared and reported to that read (the data are unusable, the persist layer
 * falls back to the other slot); any other cause (clock security system, an
 * ECC error in code or constants) forces the safe state. Context: NMI. */
void NMI_Handler(void)
{
    uint32_t ecc = FLASH_ECCR;
    if ((ecc & FLASH_ECCR_ECCD) != 0u && g_nvm.reading) {
        FLASH_ECCR = (ecc & FLASH_ECCR_ECCCIE) | FLASH_ECCR_ECCD; /* rc_w1 */
        g_nvm.ecc_hit = true;
        g_nvm.ecc_errors++;
        board_fault_record(BOARD_FAULT_NVM);
        return;
    }
    Default_Handler();
}

int flash_nvm_read(uint32_t offset, void *buf, size_t len)
{
    int rc = nvm_check(offset, buf, len);
    if (rc != HAL_OK)
        return rc;
    /* Flash is memory-mapped: reading is a copy (erased bytes read 0xFF). */
    if (len == 0u)
        return HAL_OK;
    nvm_read_begin();
    memcpy(buf, __nvm_start + offset, len);
    return nvm_read_end() ? HAL_OK : HAL_EIO;
}

/* The flash data cache may hold a page's old contents after an erase or a
 * program: reset it (RM0440, FLASH chapter, FLASH_ACR DCRST: only while DCEN = 0). */
static void flash_dcache_reset(void)
{
    uint32_t acr = FLASH_ACR;
    FLASH_ACR = acr & ~FLASH_ACR_DCEN;
    FLASH_ACR = (acr & ~FLASH_ACR_DCEN) | FLASH_ACR_DCRST;
    FLASH_ACR = acr & ~(FLASH_ACR_DCEN | FLASH_ACR_DCRST);
    FLASH_ACR = acr & ~FLASH_ACR_DCRST;
}

/* Let the watchdog through during long flash operations: the caller is the
 * background, so only the tick still has to prove itself. */
static bool flash_wait(void)
{
    for (uint32_t n = 0u; n < WAIT_FLASH_LOOPS; n++) {
        if ((FLASH_SR & FLASH_SR_BSY) == 0u)
            break;
        if ((n & 0xFFFFu) == 0u)
            iwdg_service();
    }
    uint32_t sr = FLASH_SR;
    FLASH_SR = sr & (FLASH_SR_ERRORS | FLASH_SR_EOP); /* rc_w1 */
    return (sr & (FLASH_SR_BSY | FLASH_SR_ERRORS)) == 0u;
}

static bool flash_unlock(void)
{
    if ((FLASH_CR & FLASH_CR_LOCK) != 0u) {
        FLASH_KEYR = FLASH_KEY1; /* RM0440 5.3.5 */
        FLASH_KEYR = FLASH_KEY2;
    }
    return (FLASH_CR & FLASH_CR_LOCK) == 0u;
}

static bool flash_erase_page(uint32_t addr)
{
    /* Dual-bank mode: 2 KiB pages, bank 2 from 0x08040000 (RM0440 5.3.8). */
    uint32_t bank2 = addr >= FLASH_BANK2_START ? 1u : 0u;
    uint32_t page = ((addr - (bank2 ? FLASH_BANK2_START : 0x08000000u)) / NVM_PAGE_SIZE) & 0x7Fu;
    if (!flash_wait())
        return false;
    FLASH_CR = FLASH_CR_PER | (bank2 ? FLASH_CR_BKER : 0u) | (page << FLASH_CR_PNB_SHIFT);
    FLASH_CR |= FLASH_CR_STRT;
    bool ok = flash_wait();
    FLASH_CR &= ~(FLASH_CR_PER | FLASH_CR_BKER | FLASH_CR_PNB_MASK);
    return ok;
}

static bool flash_program_dword(uint32_t addr, uint32_t lo, uint32_t hi)
{
    if (!flash_wait())
        return false;
    FLASH_CR = FLASH_CR_PG;
    REG32(addr) = lo; /* double word: two 32-bit writes, low word first (RM0440 5.3.7) */
    REG32(addr + 4u) = hi;
    bool ok = flash_wait();
    FLASH_CR &= ~FLASH_CR_PG;
    return ok;
}

/* Write one page: program in place if every changed double word is erased,
 * otherwise read-modify-erase-write the whole page. */
static bool nvm_write_page(uint32_t page_addr, uint32_t from, const uint8_t *src, uint32_t n)
{
    const uint8_t *flash = (const uint8_t *)(uintptr_t)page_addr;
    flash_dcache_reset();
    nvm_read_begin();
    memcpy(g_page_buf, flash, NVM_PAGE_SIZE);
    memcpy(g_page_buf + from, src, n);

    bool need_erase = false;
    for (uint32_t dw = from & ~7u; dw < from + n; dw += 8u) {
        if (memcmp(flash + dw, g_page_buf + dw, 8u) == 0)
            continue;
        for (uint32_t k = 0u; k < 8u; k++) {
            if (flash[dw + k] != 0xFFu)
                need_erase = true;
        }
    }
    /* A double word with a broken ECC (an interrupted write) may even read as
     * erased but cannot be programmed: only an erase makes the page usable. */
    if (!nvm_read_end())
        need_erase = true;
    uint32_t lo = need_erase ? 0u : from & ~7u;
    uint32_t hi = need_erase ? NVM_PAGE_SIZE : from + n;
    if (need_erase && !flash_erase_page(page_addr))
        return false;
    for (uint32_t dw = lo; dw < hi; dw += 8u) {
        uint32_t w[2];
        memcpy(w, g_page_buf + dw, 8u);
        if (w[0] == 0xFFFFFFFFu && w[1] == 0xFFFFFFFFu)
            continue; /* erased already */
        if (!need_erase && memcmp(flash + dw, g_page_buf + dw, 8u) == 0)
            continue;
        if (!flash_program_dword(page_addr + dw, w[0], w[1])) {
            flash_dcache_reset();
            return false;
        }
    }
    flash_dcache_reset();
    nvm_read_begin();
    bool same = memcmp(flash + from, src, n) == 0; /* read back through the bus */
    return nvm_read_end() && same;
}

int flash_nvm_write(uint32_t offset, const void *buf, size_t len)
{
    int rc = nvm_check(offset, buf, len);
    if (rc != HAL_OK)
        return rc;
    if (len == 0u)
        return HAL_OK;
    /* Never from an interrupt (erase takes tens of ms); single-bank mode
     * (4 KiB pages) would put both slots in one page: refused. */
    if (chip_in_interrupt() || (FLASH_OPTR & FLASH_OPTR_DBANK) == 0u) {
        board_fault_record(BOARD_FAULT_NVM);
        return HAL_EIO;
    }
    if (!flash_unlock()) {
        board_fault_record(BOARD_FAULT_NVM);
        return HAL_EIO;
    }
    bool ok = true;
    const uint8_t *src = (const uint8_t *)buf;
    uint32_t base = (uint32_t)(uintptr_t)__nvm_start;
    uint32_t at = offset;
    uint32_t left = (uint32_t)len;
    while (ok && left > 0u) {
        uint32_t page = (base + at) & ~(NVM_PAGE_SIZE - 1u);
        uint32_t from = (base + at) - page;
        uint32_t n = NVM_PAGE_SIZE - from < left ? NVM_PAGE_SIZE - from : left;
        ok = nvm_write_page(page, from, src, n);
        src += n;
        at += n;
        left -= n;
    }
    FLASH_CR |= FLASH_CR_LOCK;
    if (!ok) {
        board_fault_record(BOARD_FAULT_NVM);
        return HAL_EIO;
    }
    return HAL_OK;
}
