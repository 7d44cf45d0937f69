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

#define CCCR_INIT FDCAN_CCCR_INIT
#define CCCR_CCE FDCAN_CCCR_CCE
#define CCCR_ASM FDCAN_CCCR_ASM
#define CCCR_CSA FDCAN_CCCR_CSA
#define CCCR_CSR FDCAN_CCCR_CSR
#define CCCR_TEST FDCAN_CCCR_TEST
/* bits writable only with CCE=1 and INIT=1 (FDCAN_CCCR description): ASM (set only; cleared at
 * any time), MON, DAR, TEST, FDOE, BRSE, PXHD, EFBI, TXP, NISO */
#define CCCR_PROTECTED                                                                                             \
  (FDCAN_CCCR_ASM | FDCAN_CCCR_MON | FDCAN_CCCR_DAR | FDCAN_CCCR_TEST | FDCAN_CCCR_FDOE | FDCAN_CCCR_BRSE |         \
   FDCAN_CCCR_PXHD | FDCAN_CCCR_EFBI | FDCAN_CCCR_TXP | FDCAN_CCCR_NISO)
/* all but CSA (read-only) and the reserved bits 10, 11 */
#define CCCR_WRITABLE (CCCR_PROTECTED | FDCAN_CCCR_INIT | FDCAN_CCCR_CCE | FDCAN_CCCR_CSR)
_Static_assert(CCCR_PROTECTED == 0xF3E4u && CCCR_WRITABLE == 0xF3F7u, "CCCR's protected and writable bits");

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
  f->tocc = FDCAN_TOCC_TOP;
  f->xidam = FDCAN_XIDAM_EIDM;
  f->lec = FDCAN_LEC_NO_CHANGE;
  f->init_sync_t = -1;
  f->on_bus_t = -1;
  f->tx_cur = -1;
  f->rx_poll_t = -1;
  /* the message RAM is not initialised by a reset: start from a recognisable pattern */
  memset(f->ram, 0xA5, sizeof f->ram);
}

/* ---- clocks and bit timing ---- */

static double pclk1_hz(board *b) {
  uint32_t ppre1 = reg_field(b->rcc.cfgr, RCC_CFGR_PPRE1); /* 0xx /1, 100 /2 .. 111 /16 */
  return rcc_hclk_hz(b) / (ppre1 < 4 ? 1.0 : (double)(1u << (ppre1 - 3u)));
}

/* fdcan_ker_ck: RCC_CCIPR.FDCANSEL (RM0440 RCC chapter): 00 HSE, 01 PLL "Q", 10 PCLK1, 11 reserved.
 * 0 when the selected source is not running. */
double fdcan_kernel_hz(board *b, const char **src) {
  const rcc_state *r = &b->rcc;
  uint32_t sel = reg_field(r->ccipr, RCC_CCIPR_FDCANSEL);
  static const char *names[] = {"HSE", "PLLQ", "PCLK1", "reserved"};
  if (src) *src = names[sel];
  switch (sel) {
  case 0: return (r->cr & RCC_CR_HSERDY) ? b->cfg.hse_hz : 0.0;
  case 1: {
    uint32_t p = r->pllcfgr;
    if (!(r->cr & RCC_CR_PLLRDY) || !(p & RCC_PLLCFGR_PLLQEN)) return 0.0;
    uint32_t psrc = reg_field(p, RCC_PLLCFGR_PLLSRC);
    double in = psrc == RCC_PLLSRC_HSI16 ? 16e6 : psrc == RCC_PLLSRC_HSE ? b->cfg.hse_hz : 0.0;
    double m = (double)(reg_field(p, RCC_PLLCFGR_PLLM) + 1u), n = (double)reg_field(p, RCC_PLLCFGR_PLLN);
    double q = 2.0 * (double)(reg_field(p, RCC_PLLCFGR_PLLQ) + 1u);
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
  uint32_t pdiv = reg_field(f->ckdiv, FDCAN_CKDIV_PDIV);
  t->ckdiv = pdiv ? 2u * pdiv : 1u;
  t->prescaler = reg_field(f->nbtp, FDCAN_NBTP_NBRP) + 1u;
  t->tseg1 = reg_field(f->nbtp, FDCAN_NBTP_NTSEG1) + 1u;
  t->tseg2 = reg_field(f->nbtp, FDCAN_NBTP_NTSEG2) + 1u;
  t->sjw = reg_field(f->nbtp, FDCAN_NBTP_NSJW) + 1u;
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
  if (!(f->nbtp & FDCAN_NBTP_NTSEG1) || !(f->nbtp & FDCAN_NBTP_NTSEG2)) {
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
    if (line[l] && (f->ile & (FDCAN_ILE_EINT0 << l)) && !b->scs.pending[exc] && !b->scs.active[exc]) scs_set_pending(b, exc);
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
  bool lost = (f->ir & (n ? FDCAN_IR_RF1L : FDCAN_IR_RF0L)) != 0; /* a copy of IR.RFnL */
  return reg_value(FDCAN_RXFS_FFL, f->rxf_fill[n]) | reg_value(FDCAN_RXFS_FGI, f->rxf_get[n]) |
         reg_value(FDCAN_RXFS_FPI, put) | (f->rxf_fill[n] == FDCAN_N_FIFO ? FDCAN_RXFS_FF : 0u) |
         (lost ? FDCAN_RXFS_RFL : 0u);
}

static void rxfa(board *b, int n, uint32_t v) {
  fdcan_state *f = &b->fdcan;
  if (!reserved_ok(b, n ? "RXF1A" : "RXF0A", v, FDCAN_RXFA_FAI)) return;
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
  if (f->txbc & FDCAN_TXBC_TFQM) { /* Tx queue: TFQPI = first free buffer; TFFL, TFGI unused */
    uint32_t free_idx = 0;
    while (free_idx < FDCAN_N_FIFO && (f->txbrp & (1u << free_idx))) free_idx++;
    return free_idx >= FDCAN_N_FIFO ? FDCAN_TXFQS_TFQF : reg_value(FDCAN_TXFQS_TFQPI, free_idx);
  }
  return reg_value(FDCAN_TXFQS_TFFL, FDCAN_N_FIFO - f->tx_count) | reg_value(FDCAN_TXFQS_TFGI, f->tx_get) |
         reg_value(FDCAN_TXFQS_TFQPI, f->tx_put) | (f->tx_count == FDCAN_N_FIFO ? FDCAN_TXFQS_TFQF : 0u);
}

static void txbar(board *b, uint32_t v) {
  fdcan_state *f = &b->fdcan;
  if (v & ~FDCAN_TXB_ALL) {
    board_fault(b, "FDCAN_TXBAR 0x%08X requests Tx buffer(s) beyond element 2: the STM32G4 has 3 Tx buffers", v);
    return;
  }
  bool queue = (f->txbc & FDCAN_TXBC_TFQM) != 0;
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
  if (!reserved_ok(b, "TXEFA", v, FDCAN_TXEFA_EFAI)) return;
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
  if (reg_field(f->tscc, FDCAN_TSCC_TSS) != FDCAN_TSS_INTERNAL) return 0;
  double bits = (board_now(b) - f->tscv_base_t) / fdcan_bit_s(b);
  if (!isfinite(bits) || bits < 0) return 0;
  return (uint32_t)fmod(floor(bits / (double)(reg_field(f->tscc, FDCAN_TSCC_TCP) + 1u)), 65536.0);
}

uint32_t fdcan_timestamp(board *b) { return tscv(b); }

/* ---- register file ---- */

uint32_t fdcan_read(board *b, uint32_t off) {
  fdcan_state *f = &b->fdcan;
  switch (off) {
  case FDCAN_CREL_OFS: return FDCAN_CREL_VALUE;
  case FDCAN_ENDN_OFS: return FDCAN_ENDN_VALUE;
  case FDCAN_DBTP_OFS: return f->dbtp;
  case FDCAN_TEST_OFS: return f->test | (f->on_bus || !init_effective(f) ? FDCAN_TEST_RX : 0u); /* RX: recessive while idle */
  case FDCAN_RWD_OFS: return f->rwd & FDCAN_RWD_WDC;
  case FDCAN_CCCR_OFS: return f->cccr;
  case FDCAN_NBTP_OFS: return f->nbtp;
  case FDCAN_TSCC_OFS: return f->tscc;
  case FDCAN_TSCV_OFS: return tscv(b);
  case FDCAN_TOCC_OFS: return f->tocc;
  case FDCAN_TOCV_OFS: return 0xFFFFu; /* the timeout counter is not modelled (ETOC faults) */
  case FDCAN_ECR_OFS: {                /* CEL is cleared by the read; REC counts the recovery sequences */
    uint32_t r = f->bo ? fdcan_bus_recovery_sequences(b) : f->rec;
    uint32_t tec = f->tec > 255u ? 255u : f->tec, rec = r > 127u ? 127u : r;
    uint32_t v = reg_value(FDCAN_ECR_TEC, tec) | reg_value(FDCAN_ECR_REC, rec) | (f->rec >= 128u ? FDCAN_ECR_RP : 0u) |
                 reg_value(FDCAN_ECR_CEL, f->cel);
    f->cel = 0;
    return v;
  }
  case FDCAN_PSR_OFS: { /* LEC and DLEC go back to 7 ("no change") on a read */
    uint32_t seq = fdcan_bus_recovery_sequences(b);
    if (seq != f->recovery_lec_seq) { /* each 11 recessive bits of a recovery: Bit0Error */
      f->recovery_lec_seq = seq;
      f->lec = FDCAN_LEC_BIT0;
    }
    uint32_t v = reg_value(FDCAN_PSR_LEC, f->lec) | reg_value(FDCAN_PSR_ACT, f->act) | (f->ep ? FDCAN_PSR_EP : 0u) |
                 (f->ew ? FDCAN_PSR_EW : 0u) | (f->bo ? FDCAN_PSR_BO : 0u) | reg_value(FDCAN_PSR_DLEC, FDCAN_LEC_NO_CHANGE);
    f->lec = FDCAN_LEC_NO_CHANGE;
    return v;
  }
  case FDCAN_TDCR_OFS: return f->tdcr;
  case FDCAN_IR_OFS: return f->ir;
  case FDCAN_IE_OFS: return f->ie;
  case FDCAN_ILS_OFS: return f->ils;
  case FDCAN_ILE_OFS: return f->ile;
  case FDCAN_RXGFC_OFS: return f->rxgfc;
  case FDCAN_XIDAM_OFS: return f->xidam;
  case FDCAN_HPMS_OFS: return f->hpms;
  case FDCAN_RXF0S_OFS: return rxfs(f, 0);
  case FDCAN_RXF0A_OFS: return 0;
  case FDCAN_RXF1S_OFS: return rxfs(f, 1);
  case FDCAN_RXF1A_OFS: return 0;
  case FDCAN_TXBC_OFS: return f->txbc;
  case FDCAN_TXFQS_OFS: return txfqs(f);
  case FDCAN_TXBRP_OFS: return f->txbrp;
  case FDCAN_TXBAR_OFS: return 0; /* bits clear once TXBRP is set */
  case FDCAN_TXBCR_OFS: return 0; /* cancellations finish at once in the model */
  case FDCAN_TXBTO_OFS: return f->txbto;
  case FDCAN_TXBCF_OFS: return f->txbcf;
  case FDCAN_TXBTIE_OFS: return f->txbtie;
  case FDCAN_TXBCIE_OFS: return f->txbcie;
  case FDCAN_TXEFS_OFS: {
    uint32_t put = (f->tef_get + f->tef_fill) % FDCAN_N_FIFO;
    return reg_value(FDCAN_TXEFS_EFFL, f->tef_fill) | reg_value(FDCAN_TXEFS_EFGI, f->tef_get) |
           reg_value(FDCAN_TXEFS_EFPI, put) | (f->tef_fill == FDCAN_N_FIFO ? FDCAN_TXEFS_EFF : 0u) |
           ((f->ir & FDCAN_IR_TEFL) ? FDCAN_TXEFS_TEFL : 0u);
  }
  case FDCAN_TXEFA_OFS: return 0;
  case FDCAN_CKDIV_OFS: return f->ckdiv;
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
  case FDCAN_CREL_OFS: read_only(b, "CREL", v); return;
  case FDCAN_ENDN_OFS: read_only(b, "ENDN", v); return;
  case FDCAN_DBTP_OFS:
    if (protected_ok(b, "DBTP", v) && reserved_ok(b, "DBTP", v, FDCAN_DBTP_WRITABLE)) f->dbtp = v;
    return;
  case FDCAN_TEST_OFS:
    if (!protected_ok(b, "TEST", v)) return;
    if (!(f->cccr & CCCR_TEST)) {
      board_fault(b, "FDCAN_TEST written with CCCR.TEST=0 (RM0440 FDCAN_TEST: write access only in test mode)");
      return;
    }
    if (reserved_ok(b, "TEST", v & ~FDCAN_TEST_RX, FDCAN_TEST_LBCK | FDCAN_TEST_TX)) f->test = v & (FDCAN_TEST_LBCK | FDCAN_TEST_TX);
    if (f->test & FDCAN_TEST_TX) board_fault(b, "FDCAN_TEST.TX=%u (Tx pin control) is not modelled", reg_field(f->test, FDCAN_TEST_TX));
    return;
  case FDCAN_RWD_OFS:
    if (protected_ok(b, "RWD", v) && reserved_ok(b, "RWD", v & ~FDCAN_RWD_WDV, FDCAN_RWD_WDC)) f->rwd = v & FDCAN_RWD_WDC;
    return;
  case FDCAN_CCCR_OFS: write_cccr(b, v); return;
  case FDCAN_NBTP_OFS:
    if (!protected_ok(b, "NBTP", v) ||
        !reserved_ok(b, "NBTP", v, FDCAN_NBTP_NTSEG2 | FDCAN_NBTP_NTSEG1 | FDCAN_NBTP_NBRP | FDCAN_NBTP_NSJW))
      return;
    f->nbtp = v;
    return;
  case FDCAN_TSCC_OFS:
    if (!protected_ok(b, "TSCC", v) || !reserved_ok(b, "TSCC", v, FDCAN_TSCC_TSS | FDCAN_TSCC_TCP)) return;
    if (reg_field(v, FDCAN_TSCC_TSS) == FDCAN_TSS_EXTERNAL) { board_fault(b, "FDCAN_TSCC.TSS=10 (external timestamp, TIM3) is not modelled"); return; }
    f->tscc = v;
    return;
  case FDCAN_TSCV_OFS: f->tscv_base_t = board_now(b); return; /* any write restarts the counter */
  case FDCAN_TOCC_OFS:
    if (!protected_ok(b, "TOCC", v) || !reserved_ok(b, "TOCC", v, FDCAN_TOCC_TOP | FDCAN_TOCC_TOS | FDCAN_TOCC_ETOC)) return;
    if (v & FDCAN_TOCC_ETOC) { board_fault(b, "FDCAN_TOCC.ETOC=1: the timeout counter is not modelled"); return; }
    f->tocc = v;
    return;
  case FDCAN_TOCV_OFS: return; /* a write restarts a counter that is not enabled */
  case FDCAN_ECR_OFS: read_only(b, "ECR", v); return;
  case FDCAN_PSR_OFS: read_only(b, "PSR", v); return;
  case FDCAN_TDCR_OFS:
    if (protected_ok(b, "TDCR", v) && reserved_ok(b, "TDCR", v, FDCAN_TDCR_TDCF | FDCAN_TDCR_TDCO)) f->tdcr = v;
    return;
  case FDCAN_IR_OFS: /* write 1 to clear; writing all ones (reserved bits included) is the usual idiom */
    f->ir &= ~v;
    return;
  case FDCAN_IE_OFS:
    if (reserved_ok(b, "IE", v, FDCAN_IR_ALL)) { f->ie = v; fdcan_update_irq(b); }
    return;
  case FDCAN_ILS_OFS:
    if (reserved_ok(b, "ILS", v, FDCAN_ILS_ALL)) { f->ils = v; fdcan_update_irq(b); }
    return;
  case FDCAN_ILE_OFS:
    if (reserved_ok(b, "ILE", v, FDCAN_ILE_EINT0 | FDCAN_ILE_EINT1)) { f->ile = v; fdcan_update_irq(b); }
    return;
  case FDCAN_RXGFC_OFS:
    if (!protected_ok(b, "RXGFC", v) || !reserved_ok(b, "RXGFC", v, FDCAN_RXGFC_WRITABLE)) return;
    if (reg_field(v, FDCAN_RXGFC_LSS) > FDCAN_N_STD || reg_field(v, FDCAN_RXGFC_LSE) > FDCAN_N_EXT) {
      board_fault(b, "FDCAN_RXGFC 0x%08X: LSS %u / LSE %u exceed the 28 standard / 8 extended filter elements of"
                  " the STM32G4 message RAM", v, reg_field(v, FDCAN_RXGFC_LSS), reg_field(v, FDCAN_RXGFC_LSE));
      return;
    }
    f->rxgfc = v;
    return;
  case FDCAN_XIDAM_OFS:
    if (protected_ok(b, "XIDAM", v) && reserved_ok(b, "XIDAM", v, FDCAN_XIDAM_EIDM)) f->xidam = v;
    return;
  case FDCAN_HPMS_OFS: read_only(b, "HPMS", v); return;
  case FDCAN_RXF0S_OFS: read_only(b, "RXF0S", v); return;
  case FDCAN_RXF0A_OFS: rxfa(b, 0, v); return;
  case FDCAN_RXF1S_OFS: read_only(b, "RXF1S", v); return;
  case FDCAN_RXF1A_OFS: rxfa(b, 1, v); return;
  case FDCAN_TXBC_OFS:
    if (!protected_ok(b, "TXBC", v) || !reserved_ok(b, "TXBC", v, FDCAN_TXBC_TFQM)) return;
    f->txbc = v;
    return;
  case FDCAN_TXFQS_OFS: read_only(b, "TXFQS", v); return;
  case FDCAN_TXBRP_OFS: read_only(b, "TXBRP", v); return;
  case FDCAN_TXBAR_OFS: txbar(b, v); return;
  case FDCAN_TXBCR_OFS:
    if (reserved_ok(b, "TXBCR", v, FDCAN_TXB_ALL)) fdcan_bus_cancel(b, v);
    return;
  case FDCAN_TXBTO_OFS: read_only(b, "TXBTO", v); return;
  case FDCAN_TXBCF_OFS: read_only(b, "TXBCF", v); return;
  case FDCAN_TXBTIE_OFS:
    if (reserved_ok(b, "TXBTIE", v, FDCAN_TXB_ALL)) f->txbtie = v;
    return;
  case FDCAN_TXBCIE_OFS:
    if (reserved_ok(b, "TXBCIE", v, FDCAN_TXB_ALL)) f->txbcie = v;
    return;
  case FDCAN_TXEFS_OFS: read_only(b, "TXEFS", v); return;
  case FDCAN_TXEFA_OFS: txefa(b, v); return;
  case FDCAN_CKDIV_OFS:
    if (!protected_ok(b, "CKDIV", v) || !reserved_ok(b, "CKDIV", v, FDCAN_CKDIV_PDIV)) return;
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
