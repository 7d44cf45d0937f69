/* Placeholder FDCAN1 (RM0440 §44) until the CAN model of branch twin-can is merged: a controller
 * on a bus where every frame is acknowledged and nobody else transmits. It keeps the register
 * values, honours INIT/CCE (configuration registers writable only with both set, §44.3.2),
 * reports error-active (PSR: no bus-off), a Tx FIFO that never fills (frames are counted and
 * dropped; board_can_take is the hook the real model will implement) and an empty Rx FIFO 0.
 * The message RAM (0x4000A400, 0x350 bytes used) is plain 32-bit memory. */
#include "board_priv.h"
#include <string.h>

void canstub_reset(board *b) {
  canstub_state *c = &b->can;
  memset(c, 0, sizeof *c);
  c->cccr = 1u;           /* INIT */
  c->nbtp = 0x06000A03u;  /* reset value */
  c->psr = 0x707u;        /* LEC/DLEC = 7: no change */
  c->txfqs = 3u;          /* 3 free Tx FIFO elements */
}

uint32_t canstub_read(board *b, uint32_t off) {
  canstub_state *c = &b->can;
  if (off >= 0x4000u) { /* message RAM */
    uint32_t o = off - 0x4000u;
    if (o >= sizeof c->ram) { board_fault(b, "read of FDCAN message RAM offset 0x%03X beyond 1 KiB", o); return 0; }
    return c->ram[o / 4];
  }
  switch (off) {
  case 0x018: return c->cccr;
  case 0x01C: return c->nbtp;
  case 0x040: return 0;        /* ECR: no errors */
  case 0x044: return c->psr;
  case 0x050: return c->ir;
  case 0x054: return c->ie;
  case 0x058: return c->ils;
  case 0x05C: return c->ile;
  case 0x080: return c->rxgfc;
  case 0x090: return 0;        /* RXF0S: empty */
  case 0x0C0: return c->txbc;
  case 0x0C4: return c->txfqs;
  case 0x0CC: return 0;
  case 0x0D8: return 0;        /* TXBTO */
  case 0x100: return c->ckdiv;
  }
  board_fault(b, "read of FDCAN1 register offset 0x%03X: not in the placeholder CAN model", off);
  return 0;
}

void canstub_write(board *b, uint32_t off, uint32_t v) {
  canstub_state *c = &b->can;
  if (off >= 0x4000u) {
    uint32_t o = off - 0x4000u;
    if (o >= sizeof c->ram) { board_fault(b, "write to FDCAN message RAM offset 0x%03X beyond 1 KiB", o); return; }
    c->ram[o / 4] = v;
    return;
  }
  bool cfg = (c->cccr & 3u) == 3u; /* INIT and CCE */
  switch (off) {
  case 0x018:
    if (!(v & 1u)) v &= ~2u;   /* clearing INIT clears CCE */
    if ((v & 2u) && !(c->cccr & 1u) && !(v & 1u)) { board_fault(b, "FDCAN_CCCR: CCE set without INIT"); return; }
    c->cccr = v;
    return;
  case 0x050: c->ir &= ~v; return;
  case 0x054: c->ie = v; return;
  case 0x058: c->ils = v; return;
  case 0x05C: c->ile = v; return;
  case 0x0CC: /* TXBAR: the frames go out and are acknowledged (Tx buffers at 0x278, 18 words each) */
    for (unsigned i = 0; i < 3; i++) {
      if (!(v & (1u << i))) continue;
      const uint32_t *e = &c->ram[(0x278u + 72u * i) / 4u];
      board_can_frame fr;
      fr.id = (e[0] >> 18) & 0x7FFu;
      fr.rtr = (uint8_t)((e[0] >> 29) & 1u);
      fr.dlc = (uint8_t)((e[1] >> 16) & 0xFu);
      if (fr.dlc > 8) fr.dlc = 8;
      for (int k = 0; k < 8; k++) fr.data[k] = (uint8_t)(e[2 + k / 4] >> (8 * (k % 4)));
      c->tx_frames++;
      if (c->tx_count < CANSTUB_TXQ) c->txq[(c->tx_head + c->tx_count++) % CANSTUB_TXQ] = fr;
      else { c->txq[c->tx_head] = fr; c->tx_head = (c->tx_head + 1) % CANSTUB_TXQ; } /* keep the newest */
    }
    c->ir |= 1u << 9; /* TC */
    return;
  case 0x01C: case 0x080: case 0x0C0: case 0x100: {
    if (!cfg) { board_fault(b, "FDCAN1 register 0x%03X written without INIT and CCE (RM0440 §44.3.2)", off); return; }
    if (off == 0x01C) c->nbtp = v;
    else if (off == 0x080) c->rxgfc = v;
    else if (off == 0x0C0) c->txbc = v;
    else c->ckdiv = v;
    return;
  }
  }
  board_fault(b, "write 0x%08X to FDCAN1 register offset 0x%03X: not in the placeholder CAN model", v, off);
}

int board_can_take(board *b, board_can_frame *f) {
  canstub_state *c = &b->can;
  if (!c->tx_count) return 0;
  *f = c->txq[c->tx_head];
  c->tx_head = (c->tx_head + 1) % CANSTUB_TXQ;
  c->tx_count--;
  return 1;
}

int board_can_inject(board *b, const board_can_frame *f) {
  (void)b; (void)f;
  return -1; /* the placeholder has no receive path: the FDCAN model of branch twin-can provides it */
}
