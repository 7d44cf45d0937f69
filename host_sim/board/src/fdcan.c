/* FDCAN1 registers and message RAM, RM0440 "FD controller area network (FDCAN)" chapter:
 * the FDCAN_CCCR INIT/CCE handshake and the protected registers, nominal bit timing from the
 * FDCAN kernel clock (RCC_CCIPR.FDCANSEL, FDCAN_CKDIV), the status and FIFO registers, the
 * interrupt lines, and the fixed STM32G4 message RAM at SRAMCAN (word access).
 * The bus side (transmission, reception, filters, the host backend) is fdcan_bus.c.
 *
 * Wrong use stops the run (board_fault) where the chip would silently ignore or misbehave:
 * a protected register written without CCE=1 and INIT=1, CCE set before INIT reads back as 1,
 * reserved bits, read-only registers written, a Tx request for an element outside the FIFO,
 * an acknowledge of an Rx/Tx-event element that is not in its FIFO, nominal bit timing outside
 * the field ranges or ISO 11898-1, a kernel clock that is stopped when the node has to run. */
#include "board_priv.h"
#include <math.h>
#include <string.h>

/* FDCAN_CCCR bits */
#define CCCR_INIT (1u << 0)
#define CCCR_CCE (1u << 1)
#define CCCR_ASM (1u << 2)
#define CCCR_CSA (1u << 3)
#define CCCR_CSR (1u << 4)
#define CCCR_MON (1u << 5)
#define CCCR_TEST (1u << 7)
/* bits writable only with CCE=1 and INIT=1 (FDCAN_CCCR description): ASM (set only; cleared at
 * any time), MON, DAR, TEST, FDOE, BRSE, PXHD, EFBI, TXP, NISO */
#define CCCR_PROTECTED 0xF3E4u
#define CCCR_WRITABLE 0xF3F7u /* all but CSA (read-only) and the reserved bits 10, 11 */

void fdcan_reset(board *b) {
  fdcan_state *f = &b->fdcan;
  hal_host_can_backend *be = f->be; /* the wiring survives a reset of the MCU */
  uint32_t bus_bitrate = f->bus_bitrate;
  bool inject = f->inject_errors;
  memset(f, 0, sizeof *f);
  f->be = be;
  f->bus_bitrate = bus_bitrate;
  f->inject_errors = inject;
  /* reset values, RM0440 FDCAN register descriptions (and the vendor SVD) */
  f->dbtp = 0x00000A33u;
  f->cccr = CCCR_INIT;
  f->nbtp = 0x06000A03u;
  f->tocc = 0xFFFF0000u;
  f->xidam = 0x1FFFFFFFu;
  f->lec = 7;
  f->init_sync_t = -1;
  f->on_bus_t = -1;
  f->tx_cur = -1;
  f->rx_poll_t = -1;
  /* the message RAM is not initialised by a reset: start from a recognisable pattern */
  memset(f->ram, 0xA5, sizeof f->ram);
}

/* ---- clocks and bit timing ---- */

static double pclk1_hz(board *b) {
  uint32_t ppre1 = (b->rcc.cfgr >> 8) & 7u; /* RCC_CFGR.PPRE1: 0xx /1, 100 /2 .. 111 /16 */
  return rcc_hclk_hz(b) / (ppre1 < 4 ? 1.0 : (double)(1u << (ppre1 - 3u)));
}

/* fdcan_ker_ck: RCC_CCIPR.FDCANSEL (RM0440 RCC chapter): 00 HSE, 01 PLL "Q", 10 PCLK1, 11 reserved.
 * 0 when the selected source is not running. */
double fdcan_kernel_hz(board *b, const char **src) {
  const rcc_state *r = &b->rcc;
  uint32_t sel = (r->ccipr >> 24) & 3u;
  static const char *names[] = {"HSE", "PLLQ", "PCLK1", "reserved"};
  if (src) *src = names[sel];
  switch (sel) {
  case 0: return (r->cr & (1u << 17)) ? b->cfg.hse_hz : 0.0; /* HSERDY */
  case 1: {
    uint32_t p = r->pllcfgr;
    if (!(r->cr & (1u << 25)) || !(p & (1u << 20))) return 0.0; /* PLLRDY, PLLQEN */
    double in = (p & 3u) == 2u ? 16e6 : (p & 3u) == 3u ? b->cfg.hse_hz : 0.0;
    double m = (double)(((p >> 4) & 0xFu) + 1u), n = (double)((p >> 8) & 0x7Fu);
    double q = 2.0 * (double)(((p >> 21) & 3u) + 1u);
    return in / m * n / q;
  }
  case 2: return pclk1_hz(b);
  default: return 0.0;
  }
}

/* Nominal bit timing from FDCAN_NBTP (fields hold value - 1) and FDCAN_CKDIV.PDIV
 * (0: /1, n: /2n), RM0440 FDCAN_NBTP / FDCAN_CKDIV and "Bit timing". */
void fdcan_timing(board *b, fdcan_bit_timing *t) {
  const fdcan_state *f = &b->fdcan;
  memset(t, 0, sizeof *t);
  t->kernel_hz = fdcan_kernel_hz(b, &t->kernel_src);
  uint32_t pdiv = f->ckdiv & 0xFu;
  t->ckdiv = pdiv ? 2u * pdiv : 1u;
  t->prescaler = ((f->nbtp >> 16) & 0x1FFu) + 1u;
  t->tseg1 = ((f->nbtp >> 8) & 0xFFu) + 1u;
  t->tseg2 = (f->nbtp & 0x7Fu) + 1u;
  t->sjw = ((f->nbtp >> 25) & 0x7Fu) + 1u;
  t->ntq = 1u + t->tseg1 + t->tseg2;
  t->sample_point = (double)(1u + t->tseg1) / (double)t->ntq;
  t->bitrate = t->kernel_hz / (double)t->ckdiv / (double)t->prescaler / (double)t->ntq;
}

double fdcan_bit_s(board *b) {
  fdcan_bit_timing t;
  fdcan_timing(b, &t);
  return t.bitrate > 0 ? 1.0 / t.bitrate : INFINITY;
}

/* Check the nominal timing when the node is about to use it (INIT cleared). */
bool fdcan_check_timing(board *b) {
  fdcan_bit_timing t;
  fdcan_timing(b, &t);
  const fdcan_state *f = &b->fdcan;
  if (t.kernel_hz <= 0) {
    board_fault(b, "FDCAN1 leaves INIT with its kernel clock stopped (RCC_CCIPR.FDCANSEL=%s is not running)",
                t.kernel_src);
    return false;
  }
  if (((f->nbtp >> 8) & 0xFFu) == 0 || (f->nbtp & 0x7Fu) == 0) {
    board_fault(b, "FDCAN_NBTP 0x%08X: NTSEG1 and NTSEG2 must be at least 1 (RM0440 FDCAN_NBTP: 0 is forbidden)",
                f->nbtp);
    return false;
  }
  if (t.sjw > t.tseg2) {
    board_fault(b, "FDCAN_NBTP 0x%08X: SJW %u tq exceeds phase segment 2 (%u tq), ISO 11898-1 bit timing", f->nbtp,
                t.sjw, t.tseg2);
    return false;
  }
  if (t.bitrate > 1e6 * (1.0 + 1e-9)) {
    board_fault(b, "FDCAN1 nominal bit rate %.0f bit/s exceeds 1 Mbit/s (classic CAN, ISO 11898-1); kernel %.3f MHz"
                " /%u / NBRP %u / %u tq", t.bitrate, t.kernel_hz / 1e6, t.ckdiv, t.prescaler, t.ntq);
    return false;
  }
  if (f->bus_bitrate && fabs(t.bitrate - (double)f->bus_bitrate) > 0.005 * (double)f->bus_bitrate) {
    board_fault(b, "FDCAN1 joins the bus at %.0f bit/s but the bus runs at %u bit/s (NBTP 0x%08X, kernel %.3f MHz):"
                " every frame would be an error", t.bitrate, f->bus_bitrate, f->nbtp, t.kernel_hz / 1e6);
    return false;
  }
  return true;
}

/* ---- interrupts: IR -> IE -> ILS group -> ILE line -> NVIC (FDCAN1_IT0 = IRQ 21, IT1 = IRQ 22) ---- */

static uint32_t ils_group(int bit) {
  /* FDCAN_ILS groups on the STM32G4: RXFIFO0 = RF0N..RF0L, RXFIFO1 = RF1N..RF1L, SMSG = HPM, TC, TCF,
   * TFERR = TFE..TEFL, MISC = TSW, MRAF, TOO, BERR = ELO, EP, PERR = EW, BO, WDI, PEA, PED, ARA */
  if (bit <= 2) return 0;
  if (bit <= 5) return 1;
  if (bit <= 8) return 2;
  if (bit <= 12) return 3;
  if (bit <= 15) return 4;
  if (bit <= 17) return 5;
  return 6;
}

void fdcan_update_irq(board *b) {
  fdcan_state *f = &b->fdcan;
  uint32_t act = f->ir & f->ie;
  bool line[2] = {false, false};
  for (int i = 0; i < 24; i++)
    if (act & (1u << i)) line[(f->ils >> ils_group(i)) & 1u] = true;
  for (int l = 0; l < 2; l++) {
    int exc = 16 + 21 + l;
    if (line[l] && (f->ile & (1u << l)) && !b->scs.pending[exc] && !b->scs.active[exc]) scs_set_pending(b, exc);
  }
}

void fdcan_set_ir(board *b, uint32_t bits) {
  b->fdcan.ir |= bits;
  fdcan_update_irq(b);
}

/* ---- INIT / CCE ---- */

static bool init_effective(const fdcan_state *f) { return (f->cccr & CCCR_INIT) != 0; }

static bool config_enabled(const fdcan_state *f) { return (f->cccr & (CCCR_INIT | CCCR_CCE)) == (CCCR_INIT | CCCR_CCE); }

static bool protected_ok(board *b, const char *reg, uint32_t v) {
  const fdcan_state *f = &b->fdcan;
  if (config_enabled(f)) return true;
  board_fault(b, "FDCAN1 %s written (0x%08X) with CCCR.CCE=%u INIT=%u: a protected register, write access only with"
              " CCE=1 and INIT=1 (RM0440 FDCAN_CCCR); the chip ignores the write", reg, v,
              (f->cccr & CCCR_CCE) ? 1u : 0u, (f->cccr & CCCR_INIT) ? 1u : 0u);
  return false;
}

static bool reserved_ok(board *b, const char *reg, uint32_t v, uint32_t writable) {
  if (!(v & ~writable)) return true;
  board_fault(b, "FDCAN1 %s written with reserved bits 0x%08X (value 0x%08X)", reg, v & ~writable, v);
  return false;
}

/* A synchronisation into the kernel clock domain: a few kernel and APB clocks. */
static double sync_s(board *b) {
  double k = fdcan_kernel_hz(b, NULL);
  return 4.0 / k + 4.0 / pclk1_hz(b);
}

static void write_cccr(board *b, uint32_t v) {
  fdcan_state *f = &b->fdcan;
  if (!reserved_ok(b, "CCCR", v & ~CCCR_CSA, CCCR_WRITABLE)) return; /* CSA: read-only, RMW tolerated */
  uint32_t old = f->cccr;
  bool init_req = (v & CCCR_INIT) != 0;
  bool init_now = (old & CCCR_INIT) != 0;
  if (f->init_sync_t >= 0 && init_req != f->init_target) {
    board_fault(b, "FDCAN_CCCR.INIT written %u before the previous value %u was accepted (RM0440 FDCAN_CCCR: read"
                " INIT back before writing a new value)", init_req ? 1u : 0u, f->init_target ? 1u : 0u);
    return;
  }
  if (init_req != init_now && f->init_sync_t < 0) {
    if (fdcan_kernel_hz(b, NULL) <= 0) {
      const char *src;
      fdcan_kernel_hz(b, &src);
      board_fault(b, "FDCAN_CCCR.INIT written while the FDCAN kernel clock is stopped (RCC_CCIPR.FDCANSEL=%s not"
                  " running): INIT would never read back", src);
      return;
    }
    f->init_target = init_req;
    f->init_sync_t = board_now(b) + sync_s(b);
  }
  /* CCE: set only while INIT reads 1; cleared by hardware together with INIT */
  if ((v & CCCR_CCE) && !(old & CCCR_CCE)) {
    if (!init_now) {
      board_fault(b, "FDCAN_CCCR.CCE set while INIT reads 0%s (RM0440 FDCAN_CCCR: CCE can be set only when INIT=1;"
                  " the chip ignores it)", f->init_sync_t >= 0 ? " (INIT was written but not yet accepted)" : "");
      return;
    }
  }
  uint32_t prot_change = (v ^ old) & CCCR_PROTECTED;
  uint32_t asm_clear = (old & CCCR_ASM) & ~v; /* ASM may be cleared at any time */
  prot_change &= ~asm_clear;
  if (prot_change && !config_enabled(f)) {
    board_fault(b, "FDCAN_CCCR protected bits 0x%04X changed with CCE=%u INIT=%u (write 0x%08X): MON, DAR, TEST,"
                " FDOE, BRSE, PXHD, EFBI, TXP, NISO and setting ASM need CCE=1 and INIT=1 (RM0440 FDCAN_CCCR)",
                prot_change, (old & CCCR_CCE) ? 1u : 0u, init_now ? 1u : 0u, v);
    return;
  }
  uint32_t keep = CCCR_INIT | CCCR_CSA;
  f->cccr = (old & keep) | (v & ~keep & CCCR_WRITABLE);
  if (!init_req) f->cccr &= ~CCCR_CCE; /* cleared as soon as INIT is being cleared */
  if (!(f->cccr & CCCR_TEST)) f->test = 0; /* TEST register back to reset when CCCR.TEST is cleared */
  if ((v & CCCR_CSR) && !(old & CCCR_CSR)) {
    /* clock stop request: the model finishes at once (no transfer is ever half-way in the registers);
     * INIT and CSA are set (RM0440 "Power down (sleep mode)") */
    f->cccr |= CCCR_INIT | CCCR_CSA;
    f->init_sync_t = -1;
    fdcan_bus_init_set(b);
  }
  if (!(v & CCCR_CSR) && (old & CCCR_CSR)) f->cccr &= ~CCCR_CSA;
}

/* INIT takes effect (read-back) after its synchronisation. */
static void init_sync_done(board *b) {
  fdcan_state *f = &b->fdcan;
  f->init_sync_t = -1;
  if (f->init_target) {
    f->cccr |= CCCR_INIT;
    fdcan_bus_init_set(b);
  } else {
    f->cccr &= ~(CCCR_INIT | CCCR_CCE);
    if (fdcan_check_timing(b)) fdcan_bus_init_cleared(b);
  }
}

/* ---- FIFO bookkeeping ---- */

static uint32_t rxfs(const fdcan_state *f, int n) {
  uint32_t put = (f->rxf_get[n] + f->rxf_fill[n]) % FDCAN_N_FIFO;
  uint32_t lost = (f->ir >> (n ? 5 : 2)) & 1u; /* a copy of IR.RFnL */
  return f->rxf_fill[n] | (f->rxf_get[n] << 8) | (put << 16) | ((f->rxf_fill[n] == FDCAN_N_FIFO) ? 1u << 24 : 0u) |
         (lost << 25);
}

static void rxfa(board *b, int n, uint32_t v) {
  fdcan_state *f = &b->fdcan;
  if (!reserved_ok(b, n ? "RXF1A" : "RXF0A", v, 7u)) return;
  uint32_t rel = (v + FDCAN_N_FIFO - f->rxf_get[n]) % FDCAN_N_FIFO;
  if (v >= FDCAN_N_FIFO || rel >= f->rxf_fill[n]) {
    board_fault(b, "FDCAN_RXF%dA acknowledges element %u, which is not in Rx FIFO %d (get index %u, fill level %u):"
                " RM0440 FDCAN_RXF%dA takes the index of the last element read", n, v, n, f->rxf_get[n],
                f->rxf_fill[n], n);
    return;
  }
  f->rxf_get[n] = (v + 1u) % FDCAN_N_FIFO;
  f->rxf_fill[n] -= rel + 1u;
}

static uint32_t txfqs(const fdcan_state *f) {
  if (f->txbc & (1u << 24)) { /* Tx queue: TFQPI = first free buffer; TFFL, TFGI unused */
    uint32_t free_idx = 0;
    while (free_idx < FDCAN_N_FIFO && (f->txbrp & (1u << free_idx))) free_idx++;
    return free_idx >= FDCAN_N_FIFO ? (1u << 21) : (free_idx << 16);
  }
  return (FDCAN_N_FIFO - f->tx_count) | (f->tx_get << 8) | (f->tx_put << 16) |
         (f->tx_count == FDCAN_N_FIFO ? 1u << 21 : 0u);
}

static void txbar(board *b, uint32_t v) {
  fdcan_state *f = &b->fdcan;
  if (v & ~7u) {
    board_fault(b, "FDCAN_TXBAR 0x%08X requests Tx buffer(s) beyond element 2: the STM32G4 has 3 Tx buffers", v);
    return;
  }
  bool queue = (f->txbc & (1u << 24)) != 0;
  for (uint32_t k = 0; k < FDCAN_N_FIFO && v; k++) {
    uint32_t i = queue ? k : (f->tx_put + k) % FDCAN_N_FIFO;
    if (!(v & (1u << i))) {
      if (!queue) break;
      continue;
    }
    v &= ~(1u << i);
    if (f->txbrp & (1u << i)) {
      board_fault(b, "FDCAN_TXBAR requests Tx buffer %u, which is still pending (TXBRP 0x%X): the chip ignores it", i,
                  f->txbrp);
      return;
    }
    if (!queue) {
      if (f->tx_count == FDCAN_N_FIFO) {
        board_fault(b, "FDCAN_TXBAR request with the Tx FIFO full (TXFQS.TFQF=1)");
        return;
      }
      f->tx_put = (f->tx_put + 1u) % FDCAN_N_FIFO;
      f->tx_count++;
    }
    if (!fdcan_bus_check_tx_element(b, i)) return;
    f->txbrp |= 1u << i;
    f->txbto &= ~(1u << i);
    f->txbcf &= ~(1u << i);
  }
  if (v) {
    board_fault(b, "FDCAN_TXBAR requests Tx buffer(s) 0x%X outside the Tx FIFO's free elements (put index %u, %u"
                " pending): in FIFO mode the request is for the element TXFQS.TFQPI names, RM0440 \"Tx FIFO\"", v,
                f->tx_put, f->tx_count);
  }
}

static void txefa(board *b, uint32_t v) {
  fdcan_state *f = &b->fdcan;
  if (!reserved_ok(b, "TXEFA", v, 3u)) return;
  uint32_t rel = (v + FDCAN_N_FIFO - f->tef_get) % FDCAN_N_FIFO;
  if (v >= FDCAN_N_FIFO || rel >= f->tef_fill) {
    board_fault(b, "FDCAN_TXEFA acknowledges element %u, which is not in the Tx event FIFO (get %u, fill %u)", v,
                f->tef_get, f->tef_fill);
    return;
  }
  f->tef_get = (v + 1u) % FDCAN_N_FIFO;
  f->tef_fill -= rel + 1u;
}

static uint32_t tscv(board *b) {
  const fdcan_state *f = &b->fdcan;
  if ((f->tscc & 3u) != 1u) return 0;
  double bits = (board_now(b) - f->tscv_base_t) / fdcan_bit_s(b);
  if (!isfinite(bits) || bits < 0) return 0;
  return (uint32_t)fmod(floor(bits / (double)(((f->tscc >> 16) & 0xFu) + 1u)), 65536.0);
}

uint32_t fdcan_timestamp(board *b) { return tscv(b); }

/* ---- register file ---- */

uint32_t fdcan_read(board *b, uint32_t off) {
  fdcan_state *f = &b->fdcan;
  switch (off) {
  case 0x000: return 0x32141218u; /* CREL */
  case 0x004: return 0x87654321u; /* ENDN */
  case 0x00C: return f->dbtp;
  case 0x010: return f->test | (f->on_bus || !init_effective(f) ? 1u << 7 : 0u); /* RX: recessive while idle */
  case 0x014: return f->rwd & 0xFFu;
  case 0x018: return f->cccr;
  case 0x01C: return f->nbtp;
  case 0x020: return f->tscc;
  case 0x024: return tscv(b);
  case 0x028: return f->tocc;
  case 0x02C: return 0xFFFFu; /* TOCV: the timeout counter is not modelled (ETOC faults) */
  case 0x040: {                /* ECR: CEL is cleared by the read; REC counts the recovery sequences */
    uint32_t r = f->bo ? fdcan_bus_recovery_sequences(b) : f->rec;
    uint32_t tec = f->tec > 255u ? 255u : f->tec, rec = r > 127u ? 127u : r;
    uint32_t v = tec | (rec << 8) | (f->rec >= 128u ? 1u << 15 : 0u) | (f->cel << 16);
    f->cel = 0;
    return v;
  }
  case 0x044: { /* PSR: LEC and DLEC go back to 7 ("no change") on a read */
    uint32_t seq = fdcan_bus_recovery_sequences(b);
    if (seq != f->recovery_lec_seq) { /* each 11 recessive bits of a recovery: Bit0Error */
      f->recovery_lec_seq = seq;
      f->lec = 5u;
    }
    uint32_t v = f->lec | ((uint32_t)f->act << 3) | (f->ep ? 1u << 5 : 0u) | (f->ew ? 1u << 6 : 0u) |
                 (f->bo ? 1u << 7 : 0u) | (7u << 8);
    f->lec = 7;
    return v;
  }
  case 0x048: return f->tdcr;
  case 0x050: return f->ir;
  case 0x054: return f->ie;
  case 0x058: return f->ils;
  case 0x05C: return f->ile;
  case 0x080: return f->rxgfc;
  case 0x084: return f->xidam;
  case 0x088: return f->hpms;
  case 0x090: return rxfs(f, 0);
  case 0x094: return 0; /* RXF0A */
  case 0x098: return rxfs(f, 1);
  case 0x09C: return 0;
  case 0x0C0: return f->txbc;
  case 0x0C4: return txfqs(f);
  case 0x0C8: return f->txbrp;
  case 0x0CC: return 0; /* TXBAR: bits clear once TXBRP is set */
  case 0x0D0: return 0; /* TXBCR: cancellations finish at once in the model */
  case 0x0D4: return f->txbto;
  case 0x0D8: return f->txbcf;
  case 0x0DC: return f->txbtie;
  case 0x0E0: return f->txbcie;
  case 0x0E4: {
    uint32_t put = (f->tef_get + f->tef_fill) % FDCAN_N_FIFO;
    return f->tef_fill | (f->tef_get << 8) | (put << 16) | (f->tef_fill == FDCAN_N_FIFO ? 1u << 24 : 0u) |
           (((f->ir >> 12) & 1u) << 25);
  }
  case 0x0E8: return 0;
  case 0x100: return f->ckdiv;
  }
  board_fault(b, "read of reserved FDCAN1 offset 0x%03X", off);
  return 0;
}

static bool read_only(board *b, const char *reg, uint32_t v) {
  board_fault(b, "write 0x%08X to read-only FDCAN1 %s", v, reg);
  return false;
}

void fdcan_write(board *b, uint32_t off, uint32_t v) {
  fdcan_state *f = &b->fdcan;
  board_end_slice(b); /* the bus schedule may change (INIT, a Tx request): end the slice after this store */
  switch (off) {
  case 0x000: read_only(b, "CREL", v); return;
  case 0x004: read_only(b, "ENDN", v); return;
  case 0x00C:
    if (protected_ok(b, "DBTP", v) && reserved_ok(b, "DBTP", v, 0x009F1FFFu)) f->dbtp = v;
    return;
  case 0x010:
    if (!protected_ok(b, "TEST", v)) return;
    if (!(f->cccr & CCCR_TEST)) {
      board_fault(b, "FDCAN_TEST written with CCCR.TEST=0 (RM0440 FDCAN_TEST: write access only in test mode)");
      return;
    }
    if (reserved_ok(b, "TEST", v & ~0x80u, 0x70u)) f->test = v & 0x70u;
    if ((f->test >> 5) & 3u) board_fault(b, "FDCAN_TEST.TX=%u (Tx pin control) is not modelled", (f->test >> 5) & 3u);
    return;
  case 0x014:
    if (protected_ok(b, "RWD", v) && reserved_ok(b, "RWD", v & ~0xFF00u, 0xFFu)) f->rwd = v & 0xFFu;
    return;
  case 0x018: write_cccr(b, v); return;
  case 0x01C:
    if (!protected_ok(b, "NBTP", v) || !reserved_ok(b, "NBTP", v, 0xFFFFFF7Fu)) return;
    f->nbtp = v;
    return;
  case 0x020:
    if (!protected_ok(b, "TSCC", v) || !reserved_ok(b, "TSCC", v, 0x000F0003u)) return;
    if ((v & 3u) == 2u) { board_fault(b, "FDCAN_TSCC.TSS=10 (external timestamp, TIM3) is not modelled"); return; }
    f->tscc = v;
    return;
  case 0x024: f->tscv_base_t = board_now(b); return; /* any write restarts the counter */
  case 0x028:
    if (!protected_ok(b, "TOCC", v) || !reserved_ok(b, "TOCC", v, 0xFFFF0007u)) return;
    if (v & 1u) { board_fault(b, "FDCAN_TOCC.ETOC=1: the timeout counter is not modelled"); return; }
    f->tocc = v;
    return;
  case 0x02C: return; /* TOCV: a write restarts a counter that is not enabled */
  case 0x040: read_only(b, "ECR", v); return;
  case 0x044: read_only(b, "PSR", v); return;
  case 0x048:
    if (protected_ok(b, "TDCR", v) && reserved_ok(b, "TDCR", v, 0x7F7Fu)) f->tdcr = v;
    return;
  case 0x050: /* IR: write 1 to clear; writing all ones (reserved bits included) is the usual idiom */
    f->ir &= ~v;
    return;
  case 0x054:
    if (reserved_ok(b, "IE", v, 0x00FFFFFFu)) { f->ie = v; fdcan_update_irq(b); }
    return;
  case 0x058:
    if (reserved_ok(b, "ILS", v, 0x7Fu)) { f->ils = v; fdcan_update_irq(b); }
    return;
  case 0x05C:
    if (reserved_ok(b, "ILE", v, 3u)) { f->ile = v; fdcan_update_irq(b); }
    return;
  case 0x080:
    if (!protected_ok(b, "RXGFC", v) || !reserved_ok(b, "RXGFC", v, 0x0F1F033Fu)) return;
    if (((v >> 16) & 0x1Fu) > FDCAN_N_STD || ((v >> 24) & 0xFu) > FDCAN_N_EXT) {
      board_fault(b, "FDCAN_RXGFC 0x%08X: LSS %u / LSE %u exceed the 28 standard / 8 extended filter elements of"
                  " the STM32G4 message RAM", v, (v >> 16) & 0x1Fu, (v >> 24) & 0xFu);
      return;
    }
    f->rxgfc = v;
    return;
  case 0x084:
    if (protected_ok(b, "XIDAM", v) && reserved_ok(b, "XIDAM", v, 0x1FFFFFFFu)) f->xidam = v;
    return;
  case 0x088: read_only(b, "HPMS", v); return;
  case 0x090: read_only(b, "RXF0S", v); return;
  case 0x094: rxfa(b, 0, v); return;
  case 0x098: read_only(b, "RXF1S", v); return;
  case 0x09C: rxfa(b, 1, v); return;
  case 0x0C0:
    if (!protected_ok(b, "TXBC", v) || !reserved_ok(b, "TXBC", v, 1u << 24)) return;
    f->txbc = v;
    return;
  case 0x0C4: read_only(b, "TXFQS", v); return;
  case 0x0C8: read_only(b, "TXBRP", v); return;
  case 0x0CC: txbar(b, v); return;
  case 0x0D0:
    if (reserved_ok(b, "TXBCR", v, 7u)) fdcan_bus_cancel(b, v);
    return;
  case 0x0D4: read_only(b, "TXBTO", v); return;
  case 0x0D8: read_only(b, "TXBCF", v); return;
  case 0x0DC:
    if (reserved_ok(b, "TXBTIE", v, 7u)) f->txbtie = v;
    return;
  case 0x0E0:
    if (reserved_ok(b, "TXBCIE", v, 7u)) f->txbcie = v;
    return;
  case 0x0E4: read_only(b, "TXEFS", v); return;
  case 0x0E8: txefa(b, v); return;
  case 0x100:
    if (!protected_ok(b, "CKDIV", v) || !reserved_ok(b, "CKDIV", v, 0xFu)) return;
    f->ckdiv = v;
    return;
  }
  board_fault(b, "write 0x%08X to reserved FDCAN1 offset 0x%03X", v, off);
}

/* ---- message RAM (SRAMCAN): FDCAN1's 212 words; FDCAN2/3's are not modelled ---- */

static bool ram_off(board *b, uint32_t off, bool write) {
  if (off < FDCAN_RAM_SIZE) return true;
  board_fault(b, "%s of SRAMCAN 0x%08X: beyond FDCAN1's message RAM (0x%08X-0x%08X); FDCAN2/3 are not modelled",
              write ? "write" : "read", SRAMCAN_BASE + off, SRAMCAN_BASE, SRAMCAN_BASE + FDCAN_RAM_SIZE - 1u);
  return false;
}

uint32_t fdcan_ram_read(board *b, uint32_t off) {
  if (!ram_off(b, off, false)) return 0;
  uint32_t v;
  memcpy(&v, b->fdcan.ram + off, 4);
  return v;
}

void fdcan_ram_write(board *b, uint32_t off, uint32_t v) {
  if (!ram_off(b, off, true)) return;
  memcpy(b->fdcan.ram + off, &v, 4);
}

uint32_t fdcan_ram_word(const board *b, uint32_t off) {
  uint32_t v;
  memcpy(&v, b->fdcan.ram + off, 4);
  return v;
}

void fdcan_ram_put(board *b, uint32_t off, uint32_t v) { memcpy(b->fdcan.ram + off, &v, 4); }

/* ---- events ---- */

double fdcan_next_event(board *b) {
  const fdcan_state *f = &b->fdcan;
  double t = fdcan_bus_next_event(b);
  if (f->init_sync_t >= 0 && f->init_sync_t < t) t = f->init_sync_t;
  return t;
}

void fdcan_event(board *b) {
  fdcan_state *f = &b->fdcan;
  if (f->init_sync_t >= 0 && board_now(b) >= f->init_sync_t) init_sync_done(b);
  if (!b->fault) fdcan_bus_event(b);
}
