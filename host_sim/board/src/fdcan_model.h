/* The FDCAN1 model's state and internal interface (fdcan.c: registers, bit timing and message
 * RAM; fdcan_bus.c: the bus side, transmission, acceptance filtering and the bridge to a host
 * CAN backend; can_frame_bits.c: frame length on the wire). Included by board_priv.h. */
#ifndef FDCAN_MODEL_H
#define FDCAN_MODEL_H
#include <stdbool.h>
#include <stdint.h>
#include "board_twin/can.h"
#include "hal_host/hal_host.h"

/* FDCAN1 message RAM, RM0440 "FDCAN message RAM" (fixed layout on the STM32G4): 212 words per
 * instance at SRAMCAN, FDCAN1 first; byte offsets of each section. */
#define SRAMCAN_BASE 0x4000A400u
#define FDCAN_RAM_SIZE 0x350u   /* 212 words; FDCAN2 follows at SRAMCAN + 0x350, FDCAN3 at + 0x6A0 */
#define FDCAN_RAM_FLS 0x000u    /* 28 standard ID filters, 1 word each */
#define FDCAN_RAM_FLE 0x070u    /* 8 extended ID filters, 2 words each */
#define FDCAN_RAM_RF0 0x0B0u    /* Rx FIFO 0: 3 elements, 18 words each */
#define FDCAN_RAM_RF1 0x188u    /* Rx FIFO 1: 3 elements */
#define FDCAN_RAM_TEF 0x260u    /* Tx event FIFO: 3 elements, 2 words each */
#define FDCAN_RAM_TXB 0x278u    /* Tx buffers: 3 elements, 18 words each */
#define FDCAN_ELEM 72u          /* bytes per Rx/Tx element (2 header words + 64 data bytes) */
#define FDCAN_N_STD 28u
#define FDCAN_N_EXT 8u
#define FDCAN_N_FIFO 3u
#define FDCAN1_BASE 0x40006400u

typedef struct {
  /* registers as written (protected ones only change with CCE=1 and INIT=1) */
  uint32_t dbtp, test, rwd, cccr, nbtp, tscc, tocc, tdcr, ir, ie, ils, ile, rxgfc, xidam, hpms;
  uint32_t txbc, txbrp, txbto, txbcf, txbtie, txbcie, ckdiv;
  double tscv_base_t;           /* timestamp counter restarted at this time */
  /* CCCR.INIT crosses into the kernel clock domain: it reads back its new value at init_sync_t */
  double init_sync_t;           /* <0: none in progress */
  bool init_target;
  /* protocol state */
  uint32_t tec, rec, cel;       /* tec > 255: bus-off */
  uint32_t lec;                 /* PSR.LEC, 7 = no change (reset by a PSR read) */
  bool bo, ew, ep;
  int act;                      /* PSR.ACT: 0 synchronising, 1 idle, 2 receiver, 3 transmitter */
  double on_bus_t;              /* integration (11 recessive bits) or bus-off recovery ends; <0 none */
  uint32_t recovery_lec_seq;    /* recovery sequences already shown as PSR.LEC = Bit0Error */
  bool on_bus;                  /* integrated: takes part in bus traffic */
  /* FIFOs: Rx FIFO 0/1, Tx FIFO (elements of the Tx buffer section), Tx event FIFO */
  uint32_t rxf_get[2], rxf_fill[2];
  bool rxf_lost[2];
  uint32_t tx_put, tx_get, tx_count; /* Tx FIFO, TFQM=0 */
  uint32_t tef_get, tef_fill;
  bool tef_lost;
  /* the bus: one frame at a time, ours or another node's */
  double bus_free_t;            /* end of the frame (or error frame) on the bus, + intermission */
  int tx_cur;                   /* element being transmitted, -1: none */
  bool tx_cur_fails;            /* the attempt ends in an error (no acknowledge / injected error) */
  bool rx_cur;                  /* rx_frame is on the bus, stored at bus_free_t */
  hal_can_frame rx_hold;        /* frame taken from the backend, waiting for the bus */
  bool rx_held;
  double rx_poll_t;             /* next look at the backend */
  /* the bridge */
  hal_host_can_backend *be;     /* NULL: no other node on the bus */
  uint32_t bus_bitrate;         /* the other nodes' bit rate; 0: whatever the node uses */
  bool inject_errors;           /* every transmission attempt ends in a bit error */
  bool self_rx_pending;         /* loopback test mode: our frame is received too */
  hal_can_frame self_rx;
  /* statistics */
  uint64_t n_tx, n_rx, n_rx_rejected, n_rx_lost, n_rx_offline, n_tx_errors, n_busoff;
  uint8_t ram[FDCAN_RAM_SIZE];
} fdcan_state;

typedef board_can_timing fdcan_bit_timing;

/* engine interface (fdcan.c): FDCAN1 registers at 0x40006400, message RAM at SRAMCAN */
void fdcan_reset(board *b);
uint32_t fdcan_read(board *b, uint32_t off);
void fdcan_write(board *b, uint32_t off, uint32_t v);
uint32_t fdcan_ram_read(board *b, uint32_t off);
void fdcan_ram_write(board *b, uint32_t off, uint32_t v);
double fdcan_next_event(board *b);
void fdcan_event(board *b);

/* fdcan.c, for the bus side */
double fdcan_kernel_hz(board *b, const char **src);
void fdcan_timing(board *b, fdcan_bit_timing *t);
double fdcan_bit_s(board *b);
bool fdcan_check_timing(board *b);
void fdcan_set_ir(board *b, uint32_t bits);
void fdcan_update_irq(board *b);
uint32_t fdcan_timestamp(board *b);
uint32_t fdcan_ram_word(const board *b, uint32_t off);
void fdcan_ram_put(board *b, uint32_t off, uint32_t v);

/* fdcan_bus.c */
void fdcan_bus_init_set(board *b);
void fdcan_bus_init_cleared(board *b);
bool fdcan_bus_check_tx_element(board *b, uint32_t i);
void fdcan_bus_cancel(board *b, uint32_t mask);
double fdcan_bus_next_event(board *b);
void fdcan_bus_event(board *b);
/* Bus-off recovery: sequences of 11 recessive bits monitored since INIT was cleared (0 when no
 * recovery is under way); M_CAN counts them in ECR.REC and shows each in PSR.LEC as Bit0Error. */
uint32_t fdcan_bus_recovery_sequences(board *b);

/* can_frame_bits.c: bits on the wire of a classic base-format frame, intermission included */
unsigned can_frame_bits(uint16_t id, bool rtr, unsigned dlc, const uint8_t *data);

#endif
