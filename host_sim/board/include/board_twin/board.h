/* The emulated STM32G474 ("the twin"): runs an unmodified flashable ELF on Unicorn's
 * Cortex-M4 with host models of the system control space and the peripherals.
 * Host code (C11). Not thread-safe: one board per thread. */
#ifndef BOARD_TWIN_BOARD_H
#define BOARD_TWIN_BOARD_H
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct board board;

typedef struct {
  const char *elf_path;  /* flashable image */
  const char *nvm_path;  /* flash pages written by the firmware persist here; NULL: none */
  double hse_hz;         /* board crystal; 24 MHz on the NUCLEO-G474RE */
  FILE *console;         /* semihosting output; NULL: stderr */
} board_config;

typedef enum {
  BOARD_TIME_UP = 0, /* ran the requested time */
  BOARD_EXITED = 1,  /* the image exited through semihosting; see board_exit_code() */
  BOARD_FAULT = 2,   /* strictness stop: see board_message() */
  BOARD_POWER_OFF = 3, /* a power cut armed with board_flash_power_cut happened; see board_power_on */
} board_status;

void board_config_default(board_config *cfg);
/* NULL on failure with the reason in err. */
board *board_open(const board_config *cfg, char *err, size_t err_len);
void board_close(board *b);

/* Run for `seconds` of virtual time (or until exit/fault). */
board_status board_run(board *b, double seconds);
int board_exit_code(const board *b);
const char *board_message(const board *b);

double board_time_s(const board *b);
uint64_t board_instructions(const board *b);
uint32_t board_resets(const board *b);      /* emulated resets since power-on */
double board_core_hz(const board *b);

/* Read a 32-bit word of the emulated memory at a symbol (+offset); 0 on success. */
int board_read_symbol(board *b, const char *name, uint32_t offset, uint32_t *value);
int board_read_u32(board *b, uint32_t addr, uint32_t *value);
/* Test-only access to the emulated RAM (a debugger's view); 0 on success. */
int board_write_u32(board *b, uint32_t addr, uint32_t value);
int board_read_mem(board *b, uint32_t addr, void *out, size_t n);
/* Test-only: clear interrupt `irq`'s NVIC enable (NVIC_ICER), as a debugger would; the firmware
 * can enable it again. */
void board_nvic_disable(board *b, int irq);
/* Address and size of an ELF symbol; 0 on success. */
int board_symbol(board *b, const char *name, uint32_t *addr, uint32_t *size);
/* Start of the current HRTIM master period and its length; -1 while the timers are stopped. */
double board_pwm_period_start(board *b, double *period_s);

/* GPIO configuration as the firmware left it (mode 0 input, 1 output, 2 AF, 3 analog). */
typedef struct {
  char port;        /* 'A'..'G' */
  int pin;          /* 0..15 */
  int mode;
  int af;
  int changed;      /* differs, or differed, from the reset state */
} board_pin;
size_t board_pins(const board *b, board_pin *out, size_t max);

/* Program whole 2 KiB flash pages at addr (0x08000000-based, page-aligned, len a multiple of
 * 2048) with `data`, as a debug probe would with the core halted: the pages persist in the NVM
 * file like pages the firmware wrote. 0, or -1 for a range outside the flash or unaligned. */
int board_flash_program(board *b, uint32_t addr, const void *data, uint32_t len);

/* Power-cut injection into the flash (test hook of the twin, nothing in the firmware):
 * when flash operation number `op` (1-based count of page erases and double-word programs
 * started since board_open, see board_flash_ops) starts, the supply fails. torn = 0: the
 * operation never takes effect; torn = 1: it is left half done (a page partly erased, a double
 * word partly programmed: bits of a deterministic pattern not yet changed) and the touched
 * double words no longer match their ECC, so a later read of one sets FLASH_ECCR.ECCD and
 * raises the NMI (RM0440 §5.3: double ECC errors are not corrected). board_run then returns
 * BOARD_POWER_OFF; board_power_on starts the MCU again from power-on reset (RAM cleared, RCC_CSR
 * BORRSTF|PINRSTF), the flash array as the cut left it. op = 0 disarms. */
void board_flash_power_cut(board *b, uint64_t op, int torn);
uint64_t board_flash_ops(const board *b);
void board_power_on(board *b);
/* Reads of a double word with a broken ECC since board_open. */
uint64_t board_flash_ecc_errors(const board *b);



#ifdef __cplusplus
}
#endif

#endif
