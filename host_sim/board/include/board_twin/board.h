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

/* GPIO configuration as the firmware left it (mode 0 input, 1 output, 2 AF, 3 analog). */
typedef struct {
  char port;        /* 'A'..'G' */
  int pin;          /* 0..15 */
  int mode;
  int af;
  int changed;      /* differs, or differed, from the reset state */
} board_pin;
size_t board_pins(const board *b, board_pin *out, size_t max);

/* HRTIM output `out` (0: TxI1, 1: TxI2) of timer 0-5 (A-F) at virtual time t: 0/1 pin level,
 * -1 high impedance. For the plant binding and tests. */
int board_hrtim_output(board *b, int timer, int out, double t);
/* The value an ADC converts: adc 1 or 2, channel 0-18, at virtual time t; a 12-bit code. */
typedef int (*board_adc_source)(void *ctx, int adc, int channel, double t);
void board_set_adc_source(board *b, board_adc_source fn, void *ctx);

/* A fault input FLT1-6 becoming active (already filtered and polarity-resolved). */
void board_hrtim_fault(board *b, int n, int active);

#ifdef __cplusplus
}
#endif

#endif
