/**
 * @file board_faults.c
 * @brief The board's fault word (enum board_fault in board.h): every driver
 *        records into it, board_faults() and a debugger read it.
 */
#include "board.h"

volatile uint32_t g_board_faults;

uint32_t board_faults(void) { return g_board_faults; }
