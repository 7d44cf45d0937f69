/* Flash interface, RM0440 §5: wait states against HCLK (§5.3.3), the KEYR unlock sequence
 * and its lock-out (§5.3.5), double-word programming (§5.3.7) and page/bank erase (§5.3.6)
 * with the status flags, in dual-bank mode (OPTR.DBANK=1, the factory setting: two banks of
 * 128 pages of 2 KiB).
 *
 * NVM persistence: every 2 KiB page the firmware erases or programs is marked dirty and
 * saved to --nvm FILE (after each completed operation and at reset/close); at start-up the
 * saved pages are laid over the freshly loaded ELF. So whatever pages the firmware uses as
 * NVM persist, without the twin knowing which ones they are. File: "DTCNVM01", then
 * records {uint32 LE global page index 0..255, 2048 bytes}.
 *
 * Power cuts (test hook, board_flash_power_cut): the supply fails when a chosen erase/program
 * starts, the operation undone or half done; half-done double words carry a broken ECC, whose
 * read sets FLASH_ECCR.ECCD and raises the NMI (double errors are detected, not corrected). */
#include "board_priv.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PAGE 2048u
#define BANK_SIZE (256u * 1024u)
#define T_PROG_S 82e-6   /* double-word programming time, order of the datasheet's typical */
#define T_ERASE_S 22e-3  /* page erase */
#define T_MASS_S 23e-3

#define SR_ERRS                                                                                             \
  (FLASH_SR_PROGERR | FLASH_SR_WRPERR | FLASH_SR_PGAERR | FLASH_SR_SIZERR | FLASH_SR_PGSERR | FLASH_SR_MISSERR | \
   FLASH_SR_FASTERR)

/* pending operation completed at busy_until */
enum { OP_NONE, OP_PROG, OP_ERASE, OP_MASS };

void flash_reset(board *b) {
  flash_state *f = &b->fl;
  uint8_t dirty[256];
  memcpy(dirty, f->dirty, sizeof dirty); /* persistence bookkeeping survives resets */
  memset(f, 0, sizeof *f);
  memcpy(f->dirty, dirty, sizeof dirty);
  f->acr = 0x00040600u; /* SVD: 0x00040601; RM0440 §5.7.1 gives LATENCY=0 at reset (HSI16 needs 0 WS) */
  f->cr = FLASH_CR_LOCK | FLASH_CR_OPTLOCK;
  f->busy_until = -1;
  b->fl.op = OP_NONE;
}

/* RM0440 §5.3.3 Table 29: HCLK limit per wait state. */
double flash_max_hclk(const board *b, uint32_t lat) {
  double step, top;
  if (pwr_range(b) == 2) {
    static const double r2[3] = {12e6, 24e6, 26e6};
    return lat >= 2 ? r2[2] : r2[lat];
  }
  if (pwr_boost(b)) { step = 34e6; top = 170e6; }
  else { step = 30e6; top = 150e6; }
  double m = step * (double)(lat + 1u);
  return m > top ? top : m;
}

static void bus_error(board *b) {
  /* an imprecise bus error: BusFault if enabled, else escalated to HardFault (B1.5.13) */
  b->scs.cfsr |= 1u << 10; /* BFSR.IMPRECISERR */
  if (b->scs.shcsr & (1u << 17)) scs_set_pending(b, 5);
  else { b->scs.hfsr |= 1u << 30; scs_set_pending(b, 3); }
}

uint32_t flash_read(board *b, uint32_t off) {
  flash_state *f = &b->fl;
  double now = board_now(b);
  switch (off) {
  case FLASH_ACR_OFS: return f->acr;
  case FLASH_SR_OFS: return f->sr | (f->busy_until >= now ? FLASH_SR_BSY : 0u);
  case FLASH_CR_OFS: return f->cr;
  case FLASH_ECCR_OFS: return f->eccr;
  case FLASH_OPTR_OFS: return 0xFFEFF8AAu; /* factory value: RDP level 0, DBANK=1, nBOOT0=1 */
  case FLASH_PCROP1SR_OFS: case FLASH_PCROP2SR_OFS: return 0xFFFF0000u; /* factory values */
  case FLASH_PCROP1ER_OFS: case FLASH_PCROP2ER_OFS: return 0;
  case FLASH_WRP1AR_OFS: case FLASH_WRP1BR_OFS: case FLASH_WRP2AR_OFS: case FLASH_WRP2BR_OFS:
    return 0x000000FFu; /* WRP areas empty (start > end) */
  case FLASH_SEC1R_OFS: return 0xFFF0FF00u;
  case FLASH_SEC2R_OFS: return 0xFFFFFF00u;
  case FLASH_PDKEYR_OFS: case FLASH_KEYR_OFS: case FLASH_OPTKEYR_OFS: return 0;
  }
  board_fault(b, "read of reserved FLASH offset 0x%02X", off);
  return 0;
}

/* ---- power cuts and ECC ---- */

static bool ecc_is_bad(const board *b, uint32_t off) { return (b->cut.ecc_bad[off / 64u] >> ((off / 8u) % 8u)) & 1u; }

static void ecc_mark(board *b, uint32_t off, bool bad) {
  uint8_t *by = &b->cut.ecc_bad[off / 64u], bit = (uint8_t)(1u << ((off / 8u) % 8u));
  if (bad && !(*by & bit)) { *by |= bit; b->cut.n_bad++; }
  if (!bad && (*by & bit)) { *by &= (uint8_t)~bit; b->cut.n_bad--; }
}

/* A deterministic pattern per double word and cut (the bits an interrupted operation did not
 * reach): about half the bits. */
static uint32_t cut_pattern(const board *b, uint32_t off, unsigned half) {
  uint32_t x = (uint32_t)b->cut.cut_at * 0x9E3779B9u ^ (off + half * 4u) * 0x85EBCA6Bu;
  x ^= x >> 15; x *= 0x2C1B3C6Du; x ^= x >> 12;
  return x;
}

/* The supply fails while operation `op` runs: leave it undone or half done. */
static void power_cut(board *b, int op, uint32_t off, uint32_t len, uint32_t w0, uint32_t w1) {
  b->cut.cut = true;
  if (b->cut.cut_torn) {
    if (op == OP_PROG) { /* programming clears bits: some of the target's zeros are still ones */
      uint32_t w[2] = {w0 | (cut_pattern(b, off, 0) & ~w0), w1 | (cut_pattern(b, off, 1) & ~w1)};
      memcpy(b->flash + off, w, 8);
    } else {             /* erasing sets bits: some are still as they were */
      for (uint32_t a = off; a < off + len; a += 4) {
        uint32_t v;
        memcpy(&v, b->flash + a, 4);
        v |= cut_pattern(b, a & ~7u, (a >> 2) & 1u);
        memcpy(b->flash + a, &v, 4);
      }
    }
    for (uint32_t a = off; a < off + len; a += 8) { /* a dword still all ones reads as erased */
      uint32_t w[2];
      memcpy(w, b->flash + a, 8);
      if (op == OP_PROG || w[0] != 0xFFFFFFFFu || w[1] != 0xFFFFFFFFu) ecc_mark(b, a, true);
    }
    for (uint32_t p = off / PAGE; p <= (off + len - 1) / PAGE; p++) b->fl.dirty[p] = 1;
    board_flash_update(b, off, len);
    board_flash_read_hook(b);
  }
  if (b->cfg.nvm_path) flash_nvm_save(b);
  board_end_slice(b);
}

/* A data read of the flash array (hook installed once a double word is marked): a marked
 * double word sets ECCD with its address (bank-relative, only when ECCD is clear) and raises
 * the NMI (RM0440 §5.3, FLASH_ECCR). The data read is the array's content. */
void flash_data_read(board *b, uint32_t addr, unsigned size) {
  uint32_t off = addr - FLASH_BASE;
  for (uint32_t a = off & ~7u; a < off + size; a += 8) {
    if (a >= FLASH_SIZE || !ecc_is_bad(b, a)) continue;
    b->cut.ecc_errors++;
    if (!(b->fl.eccr & FLASH_ECCR_ECCD))
      b->fl.eccr = (b->fl.eccr & FLASH_ECCR_ECCCIE) | FLASH_ECCR_ECCD | (a >= BANK_SIZE ? FLASH_ECCR_BK_ECC : 0u) |
                   ((a % BANK_SIZE) & FLASH_ECCR_ADDR_ECC);
    scs_set_pending(b, 2);
    return;
  }
}

void board_flash_power_cut(board *b, uint64_t op, int torn) {
  b->cut.cut_at = op;
  b->cut.cut_torn = torn;
}
uint64_t board_flash_ops(const board *b) { return b->cut.ops; }
uint64_t board_flash_ecc_errors(const board *b) { return b->cut.ecc_errors; }

static void start_op(board *b, int op, uint32_t off, uint32_t len, double dt) {
  b->cut.ops++;
  if (b->cut.cut_at != 0 && b->cut.ops == b->cut.cut_at) {
    b->cut.cut_at = 0;
    power_cut(b, op, off, len, b->fl.op_w0, b->fl.op_w1);
    return;
  }
  b->fl.op = op;
  b->fl.op_off = off;
  b->fl.op_len = len;
  b->fl.busy_until = board_now(b) + dt;
}

static void complete_op(board *b) {
  flash_state *f = &b->fl;
  if (b->fl.op == OP_NONE) return;
  if (b->fl.op == OP_PROG) {
    memcpy(b->flash + b->fl.op_off, &b->fl.op_w0, 4);
    memcpy(b->flash + b->fl.op_off + 4, &b->fl.op_w1, 4);
  } else {
    memset(b->flash + b->fl.op_off, 0xFF, b->fl.op_len);
  }
  if (b->cut.n_bad) /* an erased or freshly programmed double word has a good ECC again */
    for (uint32_t a = b->fl.op_off; a < b->fl.op_off + b->fl.op_len; a += 8) ecc_mark(b, a, false);
  for (uint32_t p = b->fl.op_off / PAGE; p <= (b->fl.op_off + b->fl.op_len - 1) / PAGE; p++) f->dirty[p] = 1;
  board_flash_update(b, b->fl.op_off, b->fl.op_len);
  if (f->cr & FLASH_CR_EOPIE) f->sr |= FLASH_SR_EOP; /* EOP only with EOPIE (§5.7.5) */
  f->cr &= ~FLASH_CR_STRT;
  b->fl.op = OP_NONE;
  f->busy_until = -1;
  if (b->cfg.nvm_path) flash_nvm_save(b);
}

double flash_next_event(board *b) { return b->fl.op != OP_NONE ? b->fl.busy_until : INFINITY; }
void flash_event(board *b) {
  if (b->fl.op != OP_NONE && board_now(b) >= b->fl.busy_until) complete_op(b);
}

static void write_cr(board *b, uint32_t v) {
  flash_state *f = &b->fl;
  if (f->cr & FLASH_CR_LOCK) {
    board_fault(b, "FLASH_CR 0x%08X written while LOCK=1: the write is ignored by the hardware (RM0440 §5.3.5)", v);
    return;
  }
  if (v & (FLASH_CR_OPTSTRT | FLASH_CR_FSTPG)) { board_fault(b, "FLASH_CR: option-byte and fast programming are not modelled"); return; }
  if (b->fl.op != OP_NONE) complete_op(b); /* the CPU stalls on a busy flash */
  /* OPTLOCK is cleared only by the OPTKEYR sequence, LOCK only by KEYR: software can set them */
  f->cr = (v & FLASH_CR_SOFTWARE) | (v & (FLASH_CR_LOCK | FLASH_CR_OPTLOCK)) | (f->cr & FLASH_CR_OPTLOCK);
  if (v & FLASH_CR_STRT) {
    uint32_t ops = (v & FLASH_CR_PER ? 1u : 0u) + (v & (FLASH_CR_MER1 | FLASH_CR_MER2) ? 1u : 0u) + (v & FLASH_CR_PG ? 1u : 0u);
    if (ops != 1 || (v & FLASH_CR_PG) || (f->sr & SR_ERRS)) { f->sr |= FLASH_SR_PGSERR; f->cr &= ~FLASH_CR_STRT; return; }
    if (v & FLASH_CR_PER) {
      uint32_t page = reg_field(v, FLASH_CR_PNB), bank = (v & FLASH_CR_BKER) ? 1u : 0u;
      start_op(b, OP_ERASE, bank * BANK_SIZE + page * PAGE, PAGE, T_ERASE_S);
    } else {
      uint32_t from = (v & FLASH_CR_MER1) ? 0u : BANK_SIZE, to = (v & FLASH_CR_MER2) ? 2u * BANK_SIZE : BANK_SIZE;
      start_op(b, OP_MASS, from, to - from, T_MASS_S);
    }
  }
}

void flash_write(board *b, uint32_t off, uint32_t v) {
  flash_state *f = &b->fl;
  switch (off) {
  case FLASH_ACR_OFS: {
    uint32_t lat = reg_field(v, FLASH_ACR_LATENCY);
    if (v & ~FLASH_ACR_WRITABLE) { board_fault(b, "FLASH_ACR 0x%08X writes reserved bits", v); return; }
    double hclk = rcc_hclk_hz(b);
    if (hclk > flash_max_hclk(b, lat) + 1.0) {
      board_fault(b, "FLASH_ACR.LATENCY=%u is too few wait states for HCLK %.3f MHz (RM0440 §5.3.3)", lat, hclk / 1e6);
      return;
    }
    f->acr = v & ~(FLASH_ACR_ICRST | FLASH_ACR_DCRST); /* pulses */
    return;
  }
  case FLASH_PDKEYR_OFS: return;
  case FLASH_KEYR_OFS: /* KEY1 then KEY2 unlocks CR; anything else locks it out until reset */
    if (f->key_locked_out || !(f->cr & FLASH_CR_LOCK) || v != (f->key_stage ? FLASH_KEY2 : FLASH_KEY1)) {
      f->key_locked_out = true;
      f->key_stage = 0;
      bus_error(b);
      return;
    }
    if (f->key_stage == 0) f->key_stage = 1;
    else { f->key_stage = 0; f->cr &= ~FLASH_CR_LOCK; }
    return;
  case FLASH_OPTKEYR_OFS: board_fault(b, "FLASH_OPTKEYR: option-byte programming is not modelled"); return;
  case FLASH_SR_OFS: f->sr &= ~(v & (FLASH_SR_EOP | FLASH_SR_OPERR | SR_ERRS | FLASH_SR_RDERR | FLASH_SR_OPTVERR)); return;
  case FLASH_CR_OFS: write_cr(b, v); return;
  case FLASH_ECCR_OFS: f->eccr &= ~(v & (FLASH_ECCR_ECCC | FLASH_ECCR_ECCD)); return; /* rc_w1 */
  }
  board_fault(b, "write 0x%08X to FLASH offset 0x%02X (reserved or option bytes, not modelled)", v, off);
}

/* A CPU store into the flash array (the bus never writes flash directly). */
void flash_mem_write(board *b, uint32_t addr, unsigned size, uint32_t v) {
  flash_state *f = &b->fl;
  uint32_t off = addr - FLASH_BASE;
  if (b->fl.op != OP_NONE) complete_op(b); /* stall until not busy */
  if (!(f->cr & FLASH_CR_PG) || (f->cr & (FLASH_CR_PER | FLASH_CR_MER1 | FLASH_CR_MER2))) {
    f->sr |= FLASH_SR_PGSERR;
    f->pg_half = false;
    return;
  }
  if (size != 4) { f->sr |= FLASH_SR_SIZERR; f->pg_half = false; return; }
  if (!f->pg_half) {
    if (f->sr & SR_ERRS) { f->sr |= FLASH_SR_PGSERR; return; } /* errors of a previous operation not cleared */
    if (off & 7u) { f->sr |= FLASH_SR_PGAERR; return; }
    f->pg_half = true;
    f->pg_addr = off;
    f->pg_word0 = v;
    return;
  }
  f->pg_half = false;
  if (off != f->pg_addr + 4u) { f->sr |= FLASH_SR_PGAERR; return; }
  uint32_t cur0, cur1;
  memcpy(&cur0, b->flash + f->pg_addr, 4);
  memcpy(&cur1, b->flash + f->pg_addr + 4, 4);
  bool zeros = f->pg_word0 == 0 && v == 0;
  if ((cur0 != 0xFFFFFFFFu || cur1 != 0xFFFFFFFFu) && !zeros) { f->sr |= FLASH_SR_PROGERR; return; }
  b->fl.op_w0 = f->pg_word0;
  b->fl.op_w1 = v;
  start_op(b, OP_PROG, f->pg_addr, 8, T_PROG_S);
}

/* A debug probe's flash programming (erase the pages, program the bytes): the array takes the
 * bytes, the pages are marked for the NVM file and their double words get a good ECC again. */
int board_flash_program(board *b, uint32_t addr, const void *data, uint32_t len) {
  if (len == 0 || addr < FLASH_BASE || addr - FLASH_BASE > FLASH_SIZE - len || (addr - FLASH_BASE) % PAGE != 0 ||
      len % PAGE != 0)
    return -1;
  uint32_t off = addr - FLASH_BASE;
  memcpy(b->flash + off, data, len);
  for (uint32_t a = off; a < off + len; a += 8) ecc_mark(b, a, false);
  for (uint32_t p = off / PAGE; p < (off + len) / PAGE; p++) b->fl.dirty[p] = 1;
  board_flash_update(b, off, len);
  if (b->cfg.nvm_path && flash_nvm_save(b) != 0) return -1;
  return 0;
}

int flash_nvm_load(board *b, char *err, size_t n) {
  FILE *fp = fopen(b->cfg.nvm_path, "rb");
  if (!fp) return 0; /* a new file: the flash is what the ELF says */
  char magic[8];
  if (fread(magic, 1, 8, fp) != 8 || memcmp(magic, "DTCNVM01", 8) != 0) {
    fclose(fp);
    snprintf(err, n, "%s: not an NVM file of dtc-board (no DTCNVM01 header)", b->cfg.nvm_path);
    return -1;
  }
  uint8_t rec[4 + PAGE];
  while (fread(rec, 1, sizeof rec, fp) == sizeof rec) {
    uint32_t page = (uint32_t)rec[0] | (uint32_t)rec[1] << 8 | (uint32_t)rec[2] << 16 | (uint32_t)rec[3] << 24;
    if (page >= 256) { fclose(fp); snprintf(err, n, "%s: page %u out of range", b->cfg.nvm_path, page); return -1; }
    memcpy(b->flash + page * PAGE, rec + 4, PAGE);
    b->fl.dirty[page] = 1;
  }
  fclose(fp);
  return 0;
}

int flash_nvm_save(board *b) {
  char tmp[4096];
  snprintf(tmp, sizeof tmp, "%s.tmp", b->cfg.nvm_path);
  FILE *fp = fopen(tmp, "wb");
  if (!fp) return -1;
  fwrite("DTCNVM01", 1, 8, fp);
  for (uint32_t p = 0; p < 256; p++) {
    if (!b->fl.dirty[p]) continue;
    uint8_t idx[4] = {(uint8_t)p, (uint8_t)(p >> 8), 0, 0};
    fwrite(idx, 1, 4, fp);
    fwrite(b->flash + p * PAGE, 1, PAGE, fp);
  }
  int bad = fclose(fp) != 0;
  return bad ? -1 : rename(tmp, b->cfg.nvm_path);
}
