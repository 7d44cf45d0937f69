/* The twin's FDCAN1 on a host CAN bus: frames the image transmits go to a host CAN backend
 * (hal_host's in-memory loopback or SocketCAN, the same ones dtc-sim uses) at the emulated time
 * their transmission ends; frames from the backend reach the image's Rx FIFOs through its
 * acceptance filters. Without a backend the node is alone on the bus: its frames get no
 * acknowledge (ACK errors, error passive), as on a bench with nothing connected. */
#ifndef BOARD_TWIN_CAN_H
#define BOARD_TWIN_CAN_H
#include <stdint.h>
#include "board_twin/board.h"
#include "hal_host/hal_host.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Nominal bit timing as FDCAN1 is programmed (FDCAN_NBTP, FDCAN_CKDIV, RCC_CCIPR.FDCANSEL). */
typedef struct {
  double kernel_hz;       /* fdcan_ker_ck; 0 when the selected source is not running */
  const char *kernel_src; /* "HSE", "PLLQ", "PCLK1", "reserved" */
  uint32_t ckdiv;         /* FDCAN_CKDIV divider (1, 2, 4, ... 30) */
  uint32_t prescaler;     /* NBRP + 1 */
  uint32_t tseg1, tseg2, sjw; /* in time quanta (field + 1) */
  uint32_t ntq;           /* 1 + tseg1 + tseg2 */
  double bitrate;         /* bit/s */
  double sample_point;    /* (1 + tseg1) / ntq */
} board_can_timing;

typedef struct {
  board_can_timing timing;
  uint32_t nbtp, cccr;
  int on_bus;             /* integrated and taking part in traffic */
  int bus_off, error_passive, error_warning;
  uint32_t tec, rec;
  uint64_t tx_frames;     /* transmitted successfully (acknowledged) */
  uint64_t tx_errors;     /* attempts that ended in an error */
  uint64_t rx_frames;     /* stored in an Rx FIFO */
  uint64_t rx_rejected;   /* dropped by the acceptance filters */
  uint64_t rx_lost;       /* accepted but the Rx FIFO was full (blocking mode) */
  uint64_t rx_offline;    /* arrived while the node was not on the bus (INIT, bus-off) */
  uint64_t bus_offs;
} board_can_status;

/* Connect FDCAN1 to `be` (NULL: no other node). `bus_bitrate`: the other nodes' bit rate; the
 * run stops with a message when the image joins at another rate (0: accept any). The backend
 * must outlive the board or be detached; it survives emulated resets. */
void board_can_attach(board *b, hal_host_can_backend *be, uint32_t bus_bitrate);
void board_can_get_status(board *b, board_can_status *st);
/* Fault injection: bus-off now (TEC past 255, FDCAN sets CCCR.INIT and PSR.BO); or every
 * transmission attempt ends in a bit error from now on (on != 0), which leads to bus-off
 * through the error counters. */
void board_can_inject_bus_off(board *b);
void board_can_set_bus_errors(board *b, int on);

#ifdef __cplusplus
}
#endif

#endif
