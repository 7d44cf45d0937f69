/* docs/board.md pin table: `| Pin | Mode | AF | Signal | Scaling |`, and the check
 * of the firmware's GPIO configuration against it. */
#ifndef BOARD_TWIN_PINMAP_H
#define BOARD_TWIN_PINMAP_H
#include <stddef.h>
#include "board_twin/board.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  char port;
  int pin;
  int mode; /* 0 input, 1 output, 2 AF, 3 analog */
  int af;   /* -1 for `-` */
  char signal[48];
} pinmap_row;

/* Parses the first table with the exact header. Returns rows (>=0) or -1 with err
 * ("file:line: problem"). */
int pinmap_parse(const char *path, pinmap_row *rows, size_t max, char *err, size_t err_len);
/* Every changed pin is in the table with the same mode/AF and every table pin is in
 * that state. Returns the number of mismatches, each described on `report`. */
int pinmap_check(const pinmap_row *rows, size_t nrows, const board_pin *pins, size_t npins,
                 FILE *report);

#ifdef __cplusplus
}
#endif

#endif
