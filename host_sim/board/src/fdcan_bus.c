/* FDCAN1 on the bus: bus integration and bus-off recovery, transmission from the Tx buffers
 * (FIFO or queue order) with the emulated frame time, fault confinement (TEC/REC, error
 * warning/passive, bus-off), acceptance filtering of received frames into Rx FIFO 0/1, the Tx
 * event FIFO, and the bridge to a host CAN backend (hal_host_can_backend).
 * RM0440 FDCAN chapter: "Operating modes", "Transmit handling", "Acceptance filtering",
 * "Rx FIFOs", "Tx event handling", "Bus-off recovery"; ISO 11898-1 fault confinement.
 *
 * One frame occupies the bus at a time: ours or one taken from the backend; when both wait,
 * the lower identifier wins arbitration. A frame from the backend counts as on the bus from
 * the moment it is taken, and is stored in its Rx FIFO when it ends. */
#include "board_priv.h"
#include "board_twin/can.h"
#include <math.h>
#include <string.h>

#define CCCR_INIT (1u << 0)
#define CCCR_ASM (1u << 2)
#define CCCR_MON (1u << 5)
#define CCCR_DAR (1u << 6)
#define TEST_LBCK (1u << 4)

#define IR_RF0N (1u << 0)
#define IR_RF0F (1u << 1)
#define IR_RF0L (1u << 2)
#define IR_HPM (1u << 6)
#define IR_TC (1u << 7)
#define IR_TCF (1u << 8)
#define IR_TFE (1u << 9)
#define IR_TEFN (1u << 10)
#define IR_TEFF (1u << 11)
#define IR_TEFL (1u << 12)
#define IR_ELO (1u << 16)
#define IR_EP (1u << 17)
#define IR_EW (1u << 18)
#define IR_BO (1u << 19)

#define LEC_NONE 0u
#define LEC_ACK 3u
#define LEC_BIT0 5u

#define POLL_BITS 47.0        /* shortest frame + intermission: the backend is looked at once per frame slot */
#define OFFLINE_POLL_S 1e-3   /* frames that arrive while the node is off the bus are dropped this often */
#define RECOVERY_BITS (129.0 * 11.0) /* bus-off recovery: 129 x 11 recessive bits (M_CAN; ISO says 128) */

static double now_s(board *b) { return board_now(b); }

static void elem_frame(const board *b, uint32_t base, hal_can_frame *fr, uint32_t *t0, uint32_t *t1) {
  *t0 = fdcan_ram_word(b, base);
  *t1 = fdcan_ram_word(b, base + 4u);
  memset(fr, 0, sizeof *fr);
  fr->id = (uint16_t)((*t0 >> 18) & 0x7FFu);
  fr->rtr = (*t0 >> 29) & 1u;
  uint32_t dlc = (*t1 >> 16) & 0xFu;
  fr->dlc = (uint8_t)(dlc > 8u ? 8u : dlc); /* classic CAN: DLC 9..15 carry 8 bytes */
  uint32_t w0 = fdcan_ram_word(b, base + 8u), w1 = fdcan_ram_word(b, base + 12u);
  for (unsigned k = 0; k < 8; k++) fr->data[k] = (uint8_t)((k < 4 ? w0 : w1) >> (8u * (k % 4u)));
}

/* ---- error state ---- */

static void update_error_state(board *b) {
  fdcan_state *f = &b->fdcan;
  bool ew = f->tec >= 96u || f->rec >= 96u, ep = f->tec >= 128u || f->rec >= 128u;
  uint32_t ir = 0;
  if (ew != f->ew) ir |= IR_EW;
  if (ep != f->ep) ir |= IR_EP;
  f->ew = ew;
  f->ep = ep;
  if (ir) fdcan_set_ir(b, ir);
}

static void go_bus_off(board *b) {
  fdcan_state *f = &b->fdcan;
  f->tec = 256u;
  f->bo = true;
  f->cccr |= CCCR_INIT; /* the FDCAN sets INIT itself; the software starts the recovery by clearing it */
  f->cccr &= ~(1u << 1);
  f->init_sync_t = -1;
  f->on_bus = false;
  f->on_bus_t = -1;
  f->act = 0;
  f->tx_cur = -1; /* the request stays pending (TXBRP) and is sent after the recovery */
  f->rx_cur = false;
  f->lec = LEC_BIT0;
  f->recovery_lec_seq = 0;
  f->n_busoff++;
  update_error_state(b);
  fdcan_set_ir(b, IR_BO);
}

/* ---- INIT ---- */

void fdcan_bus_init_set(board *b) {
  fdcan_state *f = &b->fdcan;
  f->on_bus = false;
  f->on_bus_t = -1;
  f->act = 0;
  f->tx_cur = -1; /* an attempt in progress is abandoned; the request stays pending */
  f->rx_cur = false;
  f->rx_poll_t = now_s(b);
}

void fdcan_bus_init_cleared(board *b) {
  fdcan_state *f = &b->fdcan;
  double bit = fdcan_bit_s(b);
  /* bus integration: 11 consecutive recessive bits; after bus-off, 129 of them */
  f->on_bus_t = now_s(b) + (f->bo ? RECOVERY_BITS : 11.0) * bit;
  f->act = 0;
}

/* ---- transmission ---- */

bool fdcan_bus_check_tx_element(board *b, uint32_t i) {
  uint32_t base = FDCAN_RAM_TXB + i * FDCAN_ELEM;
  uint32_t t0 = fdcan_ram_word(b, base), t1 = fdcan_ram_word(b, base + 4u);
  if (t0 & (1u << 30)) {
    board_fault(b, "FDCAN1 Tx buffer %u holds an extended (29-bit) identifier: the host CAN backends carry 11-bit"
                " frames only", i);
    return false;
  }
  if (t1 & (1u << 21)) {
    board_fault(b, "FDCAN1 Tx buffer %u requests a CAN FD frame (T1.FDF=1): only classic CAN is modelled", i);
    return false;
  }
  return true;
}

/* Next request to send: the Tx FIFO's get element, or in queue mode the lowest identifier
 * (lowest buffer number on a tie), RM0440 "Tx FIFO" / "Tx queue". */
static int next_tx(board *b) {
  fdcan_state *f = &b->fdcan;
  if (!f->txbrp) return -1;
  if (!(f->txbc & (1u << 24))) return (f->txbrp & (1u << f->tx_get)) ? (int)f->tx_get : -1;
  int best = -1;
  uint32_t best_id = 0xFFFFFFFFu;
  for (uint32_t i = 0; i < FDCAN_N_FIFO; i++) {
    if (!(f->txbrp & (1u << i))) continue;
    uint32_t id = (fdcan_ram_word(b, FDCAN_RAM_TXB + i * FDCAN_ELEM) >> 18) & 0x7FFu;
    if (id < best_id) { best_id = id; best = (int)i; }
  }
  return best;
}

/* The request of element i is finished (sent or cancelled): Tx FIFO bookkeeping. */
static void tx_release(board *b, uint32_t i) {
  fdcan_state *f = &b->fdcan;
  f->txbrp &= ~(1u << i);
  if (f->txbc & (1u << 24)) return;
  if (f->tx_count) f->tx_count--;
  /* the get index moves to the next pending element in FIFO order */
  f->tx_get = f->tx_put;
  for (uint32_t k = 0; k < FDCAN_N_FIFO; k++) {
    uint32_t j = (f->tx_put + FDCAN_N_FIFO - f->tx_count + k) % FDCAN_N_FIFO;
    if (f->txbrp & (1u << j)) { f->tx_get = j; break; }
  }
  if (f->tx_count == 0) fdcan_set_ir(b, IR_TFE);
}

void fdcan_bus_cancel(board *b, uint32_t mask) {
  fdcan_state *f = &b->fdcan;
  for (uint32_t i = 0; i < FDCAN_N_FIFO; i++) {
    if (!(mask & (1u << i)) || !(f->txbrp & (1u << i))) continue;
    if (f->tx_cur == (int)i) continue; /* on the bus: finishes; TXBTO and TXBCF tell the outcome */
    tx_release(b, i);
    f->txbcf |= 1u << i;
    if (f->txbcie & (1u << i)) fdcan_set_ir(b, IR_TCF);
  }
}

static void store_tx_event(board *b, uint32_t t0, uint32_t t1, uint32_t ts) {
  fdcan_state *f = &b->fdcan;
  if (f->tef_fill == FDCAN_N_FIFO) { fdcan_set_ir(b, IR_TEFL); return; }
  uint32_t put = (f->tef_get + f->tef_fill) % FDCAN_N_FIFO, base = FDCAN_RAM_TEF + put * 8u;
  fdcan_ram_put(b, base, t0 & 0xFFFFFFFFu);
  fdcan_ram_put(b, base + 4u, (t1 & 0xFF000000u) | (1u << 22) | (t1 & 0x003F0000u) | (ts & 0xFFFFu));
  f->tef_fill++;
  fdcan_set_ir(b, IR_TEFN | (f->tef_fill == FDCAN_N_FIFO ? IR_TEFF : 0u));
}

static void receive(board *b, const hal_can_frame *fr);

static void tx_done(board *b) {
  fdcan_state *f = &b->fdcan;
  uint32_t i = (uint32_t)f->tx_cur, base = FDCAN_RAM_TXB + i * FDCAN_ELEM;
  f->tx_cur = -1;
  f->act = 1;
  hal_can_frame fr;
  uint32_t t0, t1;
  elem_frame(b, base, &fr, &t0, &t1);
  if (f->tx_cur_fails) {
    f->n_tx_errors++;
    bool ack = !f->inject_errors;
    f->lec = ack ? LEC_ACK : LEC_BIT0;
    if (f->cel == 255u) fdcan_set_ir(b, IR_ELO);
    f->cel = (f->cel + 1u) & 0xFFu;
    /* ISO 11898-1 fault confinement: +8 per transmit error, except an ACK error while error passive */
    if (!(ack && f->ep)) f->tec += 8u;
    if (f->tec > 255u) { go_bus_off(b); return; }
    update_error_state(b);
    if (f->cccr & CCCR_DAR) { /* no automatic retransmission: the request ends as cancelled */
      tx_release(b, i);
      f->txbcf |= 1u << i;
      if (f->txbcie & (1u << i)) fdcan_set_ir(b, IR_TCF);
    }
    return;
  }
  f->lec = LEC_NONE;
  if (f->tec) f->tec--;
  update_error_state(b);
  f->n_tx++;
  bool internal = (f->test & TEST_LBCK) && (f->cccr & CCCR_MON);
  if (f->be && f->be->send && !internal) (void)f->be->send(f->be->ctx, &fr);
  f->txbto |= 1u << i;
  tx_release(b, i);
  if (f->txbtie & (1u << i)) fdcan_set_ir(b, IR_TC);
  if (t1 & (1u << 23)) store_tx_event(b, t0, t1, fdcan_timestamp(b)); /* T1.EFC */
  if (f->test & TEST_LBCK) receive(b, &fr); /* loop back: our own frame is received too */
}

/* ---- reception: acceptance filtering (standard frames), Rx FIFO 0/1 ---- */

static void store_rx(board *b, int n, const hal_can_frame *fr, int fidx) {
  fdcan_state *f = &b->fdcan;
  uint32_t lost = n ? (1u << 5) : IR_RF0L, full = n ? (1u << 4) : IR_RF0F, newm = n ? (1u << 3) : IR_RF0N;
  if (f->rxf_fill[n] == FDCAN_N_FIFO) {
    if (!(f->rxgfc & (n ? (1u << 8) : (1u << 9)))) { /* blocking mode: the new message is lost */
      f->n_rx_lost++;
      fdcan_set_ir(b, lost);
      return;
    }
    f->rxf_get[n] = (f->rxf_get[n] + 1u) % FDCAN_N_FIFO; /* overwrite mode: the oldest goes */
    f->rxf_fill[n]--;
  }
  uint32_t put = (f->rxf_get[n] + f->rxf_fill[n]) % FDCAN_N_FIFO;
  uint32_t base = (n ? FDCAN_RAM_RF1 : FDCAN_RAM_RF0) + put * FDCAN_ELEM;
  uint32_t r0 = ((uint32_t)fr->id << 18) | (fr->rtr ? 1u << 29 : 0u);
  uint32_t r1 = (fidx < 0 ? 1u << 31 : ((uint32_t)fidx & 0x7Fu) << 24) | ((uint32_t)fr->dlc << 16) |
                (fdcan_timestamp(b) & 0xFFFFu);
  uint32_t w0 = 0, w1 = 0;
  for (unsigned k = 0; k < 4; k++) {
    w0 |= (uint32_t)fr->data[k] << (8u * k);
    w1 |= (uint32_t)fr->data[4 + k] << (8u * k);
  }
  fdcan_ram_put(b, base, r0);
  fdcan_ram_put(b, base + 4u, r1);
  fdcan_ram_put(b, base + 8u, w0);
  fdcan_ram_put(b, base + 12u, w1);
  f->rxf_fill[n]++;
  f->n_rx++;
  fdcan_set_ir(b, newm | (f->rxf_fill[n] == FDCAN_N_FIFO ? full : 0u));
}

/* RM0440 "Acceptance filtering": standard filter elements 0..LSS-1 in order, the first enabled
 * matching element decides; no match: RXGFC.ANFS; remote frames rejected by RXGFC.RRFS. */
static void receive(board *b, const hal_can_frame *fr) {
  fdcan_state *f = &b->fdcan;
  if (f->rec) f->rec = f->rec > 127u ? 120u : f->rec - 1u;
  update_error_state(b);
  if (fr->rtr && (f->rxgfc & 2u)) { f->n_rx_rejected++; return; }
  uint32_t lss = (f->rxgfc >> 16) & 0x1Fu;
  for (uint32_t i = 0; i < lss; i++) {
    uint32_t w = fdcan_ram_word(b, FDCAN_RAM_FLS + 4u * i);
    uint32_t sft = w >> 30, sfec = (w >> 27) & 7u, id1 = (w >> 16) & 0x7FFu, id2 = w & 0x7FFu;
    if (sfec == 0u || sft == 3u) continue; /* disabled element */
    bool match = sft == 0u ? (fr->id >= id1 && fr->id <= id2)
               : sft == 1u ? (fr->id == id1 || fr->id == id2)
                           : ((fr->id & id2) == (id1 & id2));
    if (!match) continue;
    if (sfec == 7u) {
      board_fault(b, "FDCAN1 standard filter element %u has SFEC=111 (not used on the STM32G4)", i);
      return;
    }
    if (sfec >= 4u) { /* priority: HPMS names the element */
      f->hpms = (i << 8) | ((sfec == 4u ? 1u : sfec - 3u) << 6);
      fdcan_set_ir(b, IR_HPM);
    }
    if (sfec == 3u || sfec == 4u) { f->n_rx_rejected++; return; }
    store_rx(b, (sfec == 2u || sfec == 6u) ? 1 : 0, fr, (int)i);
    return;
  }
  uint32_t anfs = (f->rxgfc >> 4) & 3u;
  if (anfs >= 2u) { f->n_rx_rejected++; return; }
  store_rx(b, (int)anfs, fr, -1);
}

/* ---- the bus ---- */

/* Restricted operation (ASM) and bus monitoring (MON) send nothing, except in internal loop
 * back (TEST.LBCK with MON), RM0440 "Test modes". */
static bool can_transmit(const fdcan_state *f) {
  if (f->cccr & CCCR_ASM) return false;
  return !(f->cccr & CCCR_MON) || (f->test & TEST_LBCK);
}

static bool bus_busy(const fdcan_state *f) { return f->tx_cur >= 0 || f->rx_cur; }

static void start_tx(board *b, int i) {
  fdcan_state *f = &b->fdcan;
  hal_can_frame fr;
  uint32_t t0, t1;
  elem_frame(b, FDCAN_RAM_TXB + (uint32_t)i * FDCAN_ELEM, &fr, &t0, &t1);
  unsigned bits = can_frame_bits(fr.id, fr.rtr, (t1 >> 16) & 0xFu, fr.data);
  bool acked = (f->be != NULL) || (f->test & TEST_LBCK);
  f->tx_cur = i;
  f->tx_cur_fails = !acked || f->inject_errors;
  if (f->tx_cur_fails) bits = bits - 9u + 6u + 8u; /* error flag at the ACK delimiter, error delimiter */
  f->bus_free_t = now_s(b) + bits * fdcan_bit_s(b);
  f->act = 3;
}

static void start_rx(board *b) {
  fdcan_state *f = &b->fdcan;
  f->rx_cur = true;
  f->rx_held = false;
  unsigned bits = can_frame_bits(f->rx_hold.id, f->rx_hold.rtr, f->rx_hold.dlc, f->rx_hold.data);
  f->bus_free_t = now_s(b) + bits * fdcan_bit_s(b);
  f->act = 2;
}

static bool poll_backend(board *b) {
  fdcan_state *f = &b->fdcan;
  if (f->rx_held) return true;
  if (!f->be || !f->be->recv) return false;
  hal_can_frame fr;
  if (f->be->recv(f->be->ctx, &fr) != HAL_OK) return false;
  f->rx_hold = fr;
  f->rx_held = true;
  return true;
}

void fdcan_bus_event(board *b) {
  fdcan_state *f = &b->fdcan;
  double now = now_s(b);
  if (f->on_bus_t >= 0 && now >= f->on_bus_t) {
    if (f->bo) { /* recovery complete */
      f->bo = false;
      f->tec = f->rec = 0;
      update_error_state(b);
    }
    f->on_bus_t = -1;
    f->on_bus = true;
    f->act = 1;
    f->bus_free_t = now;
    f->rx_poll_t = now;
  }
  if (bus_busy(f) && now >= f->bus_free_t) {
    if (f->tx_cur >= 0) tx_done(b);
    if (f->rx_cur) {
      f->rx_cur = false;
      f->act = 1;
      receive(b, &f->rx_hold);
    }
    if (b->fault) return;
  }
  if (!f->on_bus) {
    /* off the bus: what the other nodes send meanwhile is not received */
    if (f->be && f->rx_poll_t >= 0 && now >= f->rx_poll_t) {
      hal_can_frame fr;
      if (f->rx_held) { f->rx_held = false; f->n_rx_offline++; }
      while (f->be->recv && f->be->recv(f->be->ctx, &fr) == HAL_OK) f->n_rx_offline++;
      f->rx_poll_t = now + OFFLINE_POLL_S;
    }
    return;
  }
  if (bus_busy(f) || now < f->bus_free_t) return;
  int tx = can_transmit(f) ? next_tx(b) : -1;
  bool rx = false;
  if (tx >= 0 || now >= f->rx_poll_t) {
    rx = poll_backend(b);
    if (!rx) f->rx_poll_t = now + POLL_BITS * fdcan_bit_s(b);
  }
  if (tx >= 0 && rx) { /* arbitration: the lower identifier wins, a data frame beats a remote frame */
    uint32_t our = fdcan_ram_word(b, FDCAN_RAM_TXB + (uint32_t)tx * FDCAN_ELEM);
    uint32_t our_key = (((our >> 18) & 0x7FFu) << 1) | ((our >> 29) & 1u);
    uint32_t their_key = ((uint32_t)f->rx_hold.id << 1) | (f->rx_hold.rtr ? 1u : 0u);
    if (their_key < our_key) tx = -1;
  }
  if (tx >= 0) start_tx(b, tx);
  else if (rx) start_rx(b);
}

double fdcan_bus_next_event(board *b) {
  fdcan_state *f = &b->fdcan;
  double t = INFINITY;
  if (f->on_bus_t >= 0) t = f->on_bus_t;
  if (bus_busy(f)) return f->bus_free_t < t ? f->bus_free_t : t;
  if (!f->on_bus) {
    if (f->be && f->rx_poll_t >= 0 && f->rx_poll_t < t) t = f->rx_poll_t;
    return t;
  }
  double free_t = f->bus_free_t;
  if ((can_transmit(f) && f->txbrp) || f->rx_held) return free_t < t ? free_t : t;
  if (f->be && f->rx_poll_t < t) t = f->rx_poll_t > free_t ? f->rx_poll_t : free_t;
  return t;
}

/* ---- the public interface (board_twin/can.h) ---- */

void board_can_attach(board *b, hal_host_can_backend *be, uint32_t bus_bitrate) {
  fdcan_state *f = &b->fdcan;
  f->be = be;
  f->bus_bitrate = bus_bitrate;
  f->rx_held = false;
  f->rx_poll_t = now_s(b);
}

uint32_t fdcan_bus_recovery_sequences(board *b) {
  const fdcan_state *f = &b->fdcan;
  if (!f->bo || f->on_bus_t < 0) return 0; /* not bus-off, or INIT still set: no recovery yet */
  double seq_s = 11.0 * fdcan_bit_s(b);
  double start = f->on_bus_t - RECOVERY_BITS * fdcan_bit_s(b);
  double n = floor((now_s(b) - start) / seq_s);
  return n < 0 ? 0u : (uint32_t)n;
}

void board_can_get_status(board *b, board_can_status *st) {
  fdcan_state *f = &b->fdcan;
  memset(st, 0, sizeof *st);
  fdcan_timing(b, &st->timing);
  st->nbtp = f->nbtp;
  st->cccr = f->cccr;
  st->on_bus = f->on_bus;
  st->bus_off = f->bo;
  st->error_passive = f->ep;
  st->error_warning = f->ew;
  st->tec = f->tec > 255u ? 255u : f->tec;
  st->rec = f->bo ? fdcan_bus_recovery_sequences(b) : f->rec;
  st->tx_frames = f->n_tx;
  st->tx_errors = f->n_tx_errors;
  st->rx_frames = f->n_rx;
  st->rx_rejected = f->n_rx_rejected;
  st->rx_lost = f->n_rx_lost;
  st->rx_offline = f->n_rx_offline;
  st->bus_offs = f->n_busoff;
}

void board_can_inject_bus_off(board *b) { go_bus_off(b); }

void board_can_set_bus_errors(board *b, int on) { b->fdcan.inject_errors = on != 0; }
