/* RCC, RM0440 §7: oscillators with start-up delays, the main PLL and its limits, the
 * system clock switch, peripheral clock enables and the reset flags in RCC_CSR. */
#include "board_priv.h"
#include <math.h>
#include <string.h>

#define HSI_HZ 16e6
#define LSI_HZ 32e3
/* Start-up times (datasheet DS12288 orders of magnitude; the model only needs "not at once"). */
#define HSI_STARTUP_S 4e-6
#define HSE_STARTUP_S 2e-3
#define PLL_LOCK_S 40e-6
#define LSI_STARTUP_S 130e-6

/* The bus registers (reset, enable, sleep enable): seven words each, index k of bus register k. */
#define BUS_REG(first, ofs) (((ofs) - (first)) / RCC_BUS_REG_STRIDE)
#define N_BUS_REGS 7
_Static_assert(BUS_REG(RCC_AHB1ENR_OFS, RCC_APB2ENR_OFS) == N_BUS_REGS - 1, "seven enable registers");
_Static_assert(BUS_REG(RCC_AHB1RSTR_OFS, RCC_APB2RSTR_OFS) == N_BUS_REGS - 1, "seven reset registers");
_Static_assert(BUS_REG(RCC_AHB1SMENR_OFS, RCC_APB2SMENR_OFS) == N_BUS_REGS - 1, "seven sleep enables");

static bool in_bus_regs(uint32_t off, uint32_t first) { return off >= first && BUS_REG(first, off) < N_BUS_REGS; }

void rcc_reset(board *b, bool power_on) {
  rcc_state *r = &b->rcc;
  uint32_t flags = power_on ? RCC_CSR_PINRSTF | RCC_CSR_BORRSTF : (r->csr & RCC_CSR_RESET_FLAGS);
  memset(r, 0, sizeof *r);
  r->cr = RCC_CR_HSION | RCC_CR_HSIRDY; /* RM0440 §7.4.1: 0x00000500 (the SVD says 0x63, bits that are reserved) */
  r->icscr = 0x40000000u;   /* reset value */
  r->cfgr = reg_value(RCC_CFGR_SW, RCC_SW_HSI16) | reg_value(RCC_CFGR_SWS, RCC_SW_HSI16);
  r->pllcfgr = 0x00001000u; /* reset value: PLLN = 16 */
  r->enr[BUS_REG(RCC_AHB1ENR_OFS, RCC_AHB1ENR_OFS)] = RCC_AHB1ENR_FLASHEN;
  r->enr[BUS_REG(RCC_AHB1ENR_OFS, RCC_APB1ENR1_OFS)] = RCC_APB1ENR1_RTCAPBEN;
  /* sleep-mode enables: their reset values, AHB1 .. APB2 */
  r->smenr[0] = 0x0000130Fu; r->smenr[1] = 0x050F667Fu; r->smenr[2] = 0x00000101u;
  r->smenr[4] = 0xD2FECD3Fu; r->smenr[5] = 0x00000103u; r->smenr[6] = 0x0437F801u;
  r->csr = flags;
  r->hse_ready_t = r->hsi_ready_t = r->pll_ready_t = r->lsi_ready_t = -1;
}

static uint32_t sws(const board *b) { return reg_field(b->rcc.cfgr, RCC_CFGR_SWS); }

static uint32_t pllsrc(const board *b) { return reg_field(b->rcc.pllcfgr, RCC_PLLCFGR_PLLSRC); }

static double pll_in_hz(board *b) {
  uint32_t src = pllsrc(b);
  return src == RCC_PLLSRC_HSI16 ? HSI_HZ : src == RCC_PLLSRC_HSE ? b->cfg.hse_hz : 0.0;
}

static double pll_m(uint32_t p) { return (double)(reg_field(p, RCC_PLLCFGR_PLLM) + 1u); }

static double pll_n(uint32_t p) { return (double)reg_field(p, RCC_PLLCFGR_PLLN); }

static double pllr_hz(board *b) {
  uint32_t p = b->rcc.pllcfgr;
  double r = 2.0 * (double)(reg_field(p, RCC_PLLCFGR_PLLR) + 1u); /* 00:/2 01:/4 10:/6 11:/8 */
  return pll_in_hz(b) / pll_m(p) * pll_n(p) / r;
}

double rcc_sysclk_hz(board *b) {
  switch (sws(b)) {
  case RCC_SW_HSI16: return HSI_HZ;
  case RCC_SW_HSE: return b->cfg.hse_hz;
  case RCC_SW_PLL: return pllr_hz(b);
  default: return HSI_HZ;
  }
}

double rcc_hclk_hz(board *b) {
  uint32_t hpre = reg_field(b->rcc.cfgr, RCC_CFGR_HPRE);
  static const double div[8] = {2, 4, 8, 16, 64, 128, 256, 512};
  return rcc_sysclk_hz(b) / (hpre < 8 ? 1.0 : div[hpre - 8]);
}

/* The PLL's limits, RM0440 §7.2.4 and §7.4.4: VCO input 2.66-16 MHz, PLLN 8..127,
 * VCO output 96-344 MHz, PLLR output at most 170 MHz. */
static bool pll_check(board *b) {
  uint32_t p = b->rcc.pllcfgr;
  double in = pll_in_hz(b), m = pll_m(p), n = pll_n(p);
  if (in == 0.0) { board_fault(b, "PLLON with PLLCFGR.PLLSRC=00 (no clock)"); return false; }
  if (pllsrc(b) == RCC_PLLSRC_HSE && !(b->rcc.cr & RCC_CR_HSERDY)) { board_fault(b, "PLLON with HSE as source before HSERDY"); return false; }
  if (pllsrc(b) == RCC_PLLSRC_HSI16 && !(b->rcc.cr & RCC_CR_HSIRDY)) { board_fault(b, "PLLON with HSI16 as source before HSIRDY"); return false; }
  if (in / m < 2.66e6 || in / m > 16e6) {
    board_fault(b, "PLL input %.3f MHz (source / PLLM) is outside 2.66..16 MHz (RM0440 §7.4.4)", in / m / 1e6);
    return false;
  }
  if (n < 8 || n > 127) { board_fault(b, "PLLN=%g is outside 8..127 (RM0440 §7.4.4)", n); return false; }
  double vco = in / m * n;
  if (vco < 96e6 || vco > 344e6) {
    board_fault(b, "PLL VCO %.3f MHz is outside 96..344 MHz (RM0440 §7.4.4)", vco / 1e6);
    return false;
  }
  if ((p & RCC_PLLCFGR_PLLREN) && pllr_hz(b) > 170e6) {
    board_fault(b, "PLLR output %.3f MHz exceeds 170 MHz (RM0440 §7.4.4)", pllr_hz(b) / 1e6);
    return false;
  }
  return true;
}

/* SYSCLK/HCLK against the voltage range (PWR, RM0440 §6.1.5) and the flash wait states
 * (RM0440 §5.3.3 Table 29): called before any change takes effect. */
void rcc_check_clocking(board *b, double hclk, const char *why) {
  int range = pwr_range(b);
  bool boost = pwr_boost(b);
  double max = range == 2 ? 26e6 : boost ? 170e6 : 150e6;
  if (hclk > max + 1.0) {
    board_fault(b, "%s: HCLK %.3f MHz exceeds %.0f MHz allowed in %s (RM0440 §6.1.5)", why, hclk / 1e6, max / 1e6,
                range == 2 ? "range 2" : boost ? "range 1 boost" : "range 1 normal mode (PWR_CR5.R1MODE=1)");
    return;
  }
  uint32_t lat = reg_field(b->fl.acr, FLASH_ACR_LATENCY);
  if (hclk > flash_max_hclk(b, lat) + 1.0) {
    board_fault(b, "%s: HCLK %.3f MHz needs more than FLASH_ACR.LATENCY=%u wait states (RM0440 §5.3.3)", why,
                hclk / 1e6, lat);
  }
}

bool rcc_clock_enabled(board *b, uint32_t enr_ofs, uint32_t bit) {
  return (b->rcc.enr[BUS_REG(RCC_AHB1ENR_OFS, enr_ofs)] & bit) != 0;
}

uint32_t rcc_read(board *b, uint32_t off) {
  rcc_state *r = &b->rcc;
  switch (off) {
  case RCC_CR_OFS: return r->cr;
  case RCC_ICSCR_OFS: return r->icscr;
  case RCC_CFGR_OFS: return r->cfgr;
  case RCC_PLLCFGR_OFS: return r->pllcfgr;
  case RCC_CIER_OFS: return r->cier;
  case RCC_CIFR_OFS: return r->cifr;
  case RCC_CICR_OFS: return 0;
  case RCC_CCIPR_OFS: return r->ccipr;
  case RCC_BDCR_OFS: return r->bdcr;
  case RCC_CSR_OFS: return r->csr;
  case RCC_CRRCR_OFS: return r->crrcr;
  case RCC_CCIPR2_OFS: return r->ccipr2;
  }
  if (in_bus_regs(off, RCC_AHB1RSTR_OFS)) return r->rstr[BUS_REG(RCC_AHB1RSTR_OFS, off)];
  if (in_bus_regs(off, RCC_AHB1ENR_OFS)) return r->enr[BUS_REG(RCC_AHB1ENR_OFS, off)];
  if (in_bus_regs(off, RCC_AHB1SMENR_OFS)) return r->smenr[BUS_REG(RCC_AHB1SMENR_OFS, off)];
  board_fault(b, "read of reserved RCC offset 0x%02X", off);
  return 0;
}

static void write_cr(board *b, uint32_t v) {
  rcc_state *r = &b->rcc;
  double now = board_now(b);
  uint32_t old = r->cr, src = sws(b), psrc = pllsrc(b);
  if (v & ~RCC_CR_WRITABLE) { board_fault(b, "RCC_CR 0x%08X writes reserved bits", v); return; }
  /* an oscillator feeding SYSCLK (directly or through the PLL) cannot be stopped (§7.4.1) */
  if (src == RCC_SW_HSI16 || (src == RCC_SW_PLL && psrc == RCC_PLLSRC_HSI16)) v |= RCC_CR_HSION;
  if (src == RCC_SW_HSE || (src == RCC_SW_PLL && psrc == RCC_PLLSRC_HSE)) v |= RCC_CR_HSEON;
  if (src == RCC_SW_PLL) v |= RCC_CR_PLLON;
  if ((old & RCC_CR_HSERDY) && (v & RCC_CR_HSEBYP) != (old & RCC_CR_HSEBYP)) {
    board_fault(b, "RCC_CR.HSEBYP changed while HSE is on (§7.4.1: only when HSEON=0)");
    return;
  }
  const uint32_t ready = RCC_CR_HSIRDY | RCC_CR_HSERDY | RCC_CR_PLLRDY; /* read-only */
  r->cr = (old & ready) | (v & ~ready);
  if ((v & RCC_CR_HSION) && !(old & RCC_CR_HSION)) r->hsi_ready_t = now + HSI_STARTUP_S;
  if (!(v & RCC_CR_HSION)) { r->cr &= ~RCC_CR_HSIRDY; r->hsi_ready_t = -1; }
  if ((v & RCC_CR_HSEON) && !(old & RCC_CR_HSEON)) r->hse_ready_t = now + ((v & RCC_CR_HSEBYP) ? 1e-6 : HSE_STARTUP_S);
  if (!(v & RCC_CR_HSEON)) { r->cr &= ~RCC_CR_HSERDY; r->hse_ready_t = -1; }
  if ((v & RCC_CR_PLLON) && !(old & RCC_CR_PLLON)) {
    if (!pll_check(b)) return;
    r->pll_ready_t = now + PLL_LOCK_S;
  }
  if (!(v & RCC_CR_PLLON)) { r->cr &= ~RCC_CR_PLLRDY; r->pll_ready_t = -1; }
}

static void write_cfgr(board *b, uint32_t v) {
  rcc_state *r = &b->rcc;
  if (v & RCC_CFGR_RESERVED) { board_fault(b, "RCC_CFGR 0x%08X writes reserved bits", v); return; }
  uint32_t sw = reg_field(v, RCC_CFGR_SW);
  static const char *names[] = {"reserved", "HSI16", "HSE", "PLL"};
  if (sw == 0) { board_fault(b, "RCC_CFGR.SW=00 is reserved"); return; }
  uint32_t rdy = sw == RCC_SW_HSI16 ? RCC_CR_HSIRDY : sw == RCC_SW_HSE ? RCC_CR_HSERDY : RCC_CR_PLLRDY;
  if (!(r->cr & rdy)) { board_fault(b, "RCC_CFGR.SW=%s before the source is ready", names[sw]); return; }
  if (sw == RCC_SW_PLL && !(r->pllcfgr & RCC_PLLCFGR_PLLREN)) { board_fault(b, "RCC_CFGR.SW=PLL with PLLCFGR.PLLREN=0"); return; }
  /* evaluate the new HCLK before it takes effect */
  uint32_t old = r->cfgr;
  double hclk_old = rcc_hclk_hz(b);
  r->cfgr = (v & ~RCC_CFGR_SWS) | reg_value(RCC_CFGR_SWS, sw);
  double hclk = rcc_hclk_hz(b);
  r->cfgr = old;
  rcc_check_clocking(b, hclk, "RCC_CFGR clock switch");
  if (b->fault) return;
  /* RM0440 (RCC, system clock switch): going above 80 MHz needs an intermediate step with the
   * AHB prescaler at /2 held for at least 1 us, so the regulator absorbs the load step. */
  double now = board_now(b);
  if (hclk > 80e6 + 1.0 && hclk > hclk_old) {
    if (hclk_old <= 80e6 + 1.0 && reg_field(v, RCC_CFGR_HPRE) < 8u) { /* HPRE 0xxx: /1 */
      board_fault(b, "RCC_CFGR: HCLK from %.3f to %.3f MHz at once; above 80 MHz switch with HPRE=/2 first",
                  hclk_old / 1e6, hclk / 1e6);
      return;
    }
    if (hclk_old > 80e6 + 1.0 && now - r->hclk_changed_t < 1e-6) {
      board_fault(b, "RCC_CFGR: HPRE /2 -> /1 %.3f us after the switch; RM0440 asks for at least 1 us",
                  (now - r->hclk_changed_t) * 1e6);
      return;
    }
  }
  if (hclk != hclk_old) r->hclk_changed_t = now;
  r->cfgr = (v & ~RCC_CFGR_SWS) | reg_value(RCC_CFGR_SWS, sw); /* SWS follows at once */
  board_clock_changed(b);
}

void rcc_write(board *b, uint32_t off, uint32_t v) {
  rcc_state *r = &b->rcc;
  switch (off) {
  case RCC_CR_OFS: write_cr(b, v); return;
  case RCC_ICSCR_OFS: r->icscr = (r->icscr & RCC_ICSCR_HSICAL) | (v & RCC_ICSCR_HSITRIM); return; /* HSICAL: read-only */
  case RCC_CFGR_OFS: write_cfgr(b, v); return;
  case RCC_PLLCFGR_OFS:
    if (r->cr & RCC_CR_PLLON) { board_fault(b, "RCC_PLLCFGR written while PLLON=1 (§7.4.4: only when the PLL is off)"); return; }
    if (v & RCC_PLLCFGR_RESERVED) { board_fault(b, "RCC_PLLCFGR 0x%08X writes reserved bits", v); return; }
    r->pllcfgr = v;
    return;
  case RCC_CIER_OFS: r->cier = v; return;
  case RCC_CICR_OFS: r->cifr &= ~v; return;
  case RCC_CCIPR_OFS: r->ccipr = v; return;
  case RCC_BDCR_OFS: r->bdcr = v; return;
  case RCC_CSR_OFS:
    if (v & RCC_CSR_RMVF) r->csr &= ~RCC_CSR_RESET_FLAGS;
    if ((v & RCC_CSR_LSION) && !(r->csr & RCC_CSR_LSION)) r->lsi_ready_t = board_now(b) + LSI_STARTUP_S;
    if (!(v & RCC_CSR_LSION) && !b->iwdg.started) { r->csr &= ~(RCC_CSR_LSION | RCC_CSR_LSIRDY); r->lsi_ready_t = -1; }
    r->csr = (r->csr & ~RCC_CSR_LSION) | (v & RCC_CSR_LSION) | (b->iwdg.started ? RCC_CSR_LSION : 0u);
    return;
  case RCC_CRRCR_OFS: r->crrcr = v & RCC_CRRCR_HSI48ON; return;
  case RCC_CCIPR2_OFS: r->ccipr2 = v; return;
  }
  /* RCC_APB1RSTR2 .. and the AHB3 words are there; the reserved word between AHB3 and APB1 is not */
  if (in_bus_regs(off, RCC_AHB1RSTR_OFS)) { r->rstr[BUS_REG(RCC_AHB1RSTR_OFS, off)] = v; return; }
  if (in_bus_regs(off, RCC_AHB1ENR_OFS) && off != RCC_AHB3ENR_OFS + 4u) { r->enr[BUS_REG(RCC_AHB1ENR_OFS, off)] = v; return; }
  if (in_bus_regs(off, RCC_AHB1SMENR_OFS) && off != RCC_AHB3SMENR_OFS + 4u) { r->smenr[BUS_REG(RCC_AHB1SMENR_OFS, off)] = v; return; }
  board_fault(b, "write 0x%08X to reserved RCC offset 0x%02X", v, off);
}

double rcc_next_event(board *b) {
  rcc_state *r = &b->rcc;
  double t = INFINITY;
  if (r->hsi_ready_t >= 0 && r->hsi_ready_t < t) t = r->hsi_ready_t;
  if (r->hse_ready_t >= 0 && r->hse_ready_t < t) t = r->hse_ready_t;
  if (r->pll_ready_t >= 0 && r->pll_ready_t < t) t = r->pll_ready_t;
  if (r->lsi_ready_t >= 0 && r->lsi_ready_t < t) t = r->lsi_ready_t;
  return t;
}

void rcc_event(board *b) {
  rcc_state *r = &b->rcc;
  double now = board_now(b);
  if (r->hsi_ready_t >= 0 && now >= r->hsi_ready_t) { r->cr |= RCC_CR_HSIRDY; r->hsi_ready_t = -1; }
  if (r->hse_ready_t >= 0 && now >= r->hse_ready_t) { r->cr |= RCC_CR_HSERDY; r->hse_ready_t = -1; }
  if (r->pll_ready_t >= 0 && now >= r->pll_ready_t) { r->cr |= RCC_CR_PLLRDY; r->pll_ready_t = -1; }
  if (r->lsi_ready_t >= 0 && now >= r->lsi_ready_t) { r->csr |= RCC_CSR_LSIRDY; r->lsi_ready_t = -1; }
}
