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

#define CR_HSION (1u << 8)
#define CR_HSIRDY (1u << 10)
#define CR_HSEON (1u << 16)
#define CR_HSERDY (1u << 17)
#define CR_HSEBYP (1u << 18)
#define CR_PLLON (1u << 24)
#define CR_PLLRDY (1u << 25)

void rcc_reset(board *b, bool power_on) {
  rcc_state *r = &b->rcc;
  uint32_t flags = power_on ? 0x0C000000u : (r->csr & 0xFE000000u); /* PINRSTF|BORRSTF at power-on */
  memset(r, 0, sizeof *r);
  r->cr = CR_HSION | CR_HSIRDY; /* RM0440 §7.4.1: 0x00000500 (the SVD says 0x63, bits that are reserved) */
  r->icscr = 0x40000000u;
  r->cfgr = 0x00000005u;   /* SW=SWS=HSI16 */
  r->pllcfgr = 0x00001000u;
  r->enr[0] = 0x00000100u; /* FLASHEN */
  r->enr[4] = 0x00000400u; /* RTCAPBEN */
  r->smenr[0] = 0x0000130Fu; r->smenr[1] = 0x050F667Fu; r->smenr[2] = 0x00000101u;
  r->smenr[4] = 0xD2FECD3Fu; r->smenr[5] = 0x00000103u; r->smenr[6] = 0x0437F801u;
  r->csr = flags;
  r->hse_ready_t = r->hsi_ready_t = r->pll_ready_t = r->lsi_ready_t = -1;
}

static uint32_t sws(const board *b) { return (b->rcc.cfgr >> 2) & 3u; }

static double pll_in_hz(board *b) {
  uint32_t src = b->rcc.pllcfgr & 3u;
  return src == 2 ? HSI_HZ : src == 3 ? b->cfg.hse_hz : 0.0;
}

static double pllr_hz(board *b) {
  uint32_t p = b->rcc.pllcfgr;
  double m = (double)(((p >> 4) & 0xFu) + 1u), n = (double)((p >> 8) & 0x7Fu);
  double r = 2.0 * (double)(((p >> 25) & 3u) + 1u); /* 00:/2 01:/4 10:/6 11:/8 */
  return pll_in_hz(b) / m * n / r;
}

double rcc_sysclk_hz(board *b) {
  switch (sws(b)) {
  case 1: return HSI_HZ;
  case 2: return b->cfg.hse_hz;
  case 3: return pllr_hz(b);
  default: return HSI_HZ;
  }
}

double rcc_hclk_hz(board *b) {
  uint32_t hpre = (b->rcc.cfgr >> 4) & 0xFu;
  static const double div[8] = {2, 4, 8, 16, 64, 128, 256, 512};
  return rcc_sysclk_hz(b) / (hpre < 8 ? 1.0 : div[hpre - 8]);
}

/* The PLL's limits, RM0440 §7.2.4 and §7.4.4: VCO input 2.66-16 MHz, PLLN 8..127,
 * VCO output 96-344 MHz, PLLR output at most 170 MHz. */
static bool pll_check(board *b) {
  uint32_t p = b->rcc.pllcfgr;
  double in = pll_in_hz(b), m = (double)(((p >> 4) & 0xFu) + 1u), n = (double)((p >> 8) & 0x7Fu);
  if (in == 0.0) { board_fault(b, "PLLON with PLLCFGR.PLLSRC=00 (no clock)"); return false; }
  if ((p & 3u) == 3u && !(b->rcc.cr & CR_HSERDY)) { board_fault(b, "PLLON with HSE as source before HSERDY"); return false; }
  if ((p & 3u) == 2u && !(b->rcc.cr & CR_HSIRDY)) { board_fault(b, "PLLON with HSI16 as source before HSIRDY"); return false; }
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
  if ((p & (1u << 24)) && pllr_hz(b) > 170e6) {
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
  uint32_t lat = b->fl.acr & 0xFu;
  if (hclk > flash_max_hclk(b, lat) + 1.0) {
    board_fault(b, "%s: HCLK %.3f MHz needs more than FLASH_ACR.LATENCY=%u wait states (RM0440 §5.3.3)", why,
                hclk / 1e6, lat);
  }
}

bool rcc_clock_enabled(board *b, int enr_index, int bit) { return (b->rcc.enr[enr_index] >> bit) & 1u; }

uint32_t rcc_read(board *b, uint32_t off) {
  rcc_state *r = &b->rcc;
  switch (off) {
  case 0x00: return r->cr;
  case 0x04: return r->icscr;
  case 0x08: return r->cfgr;
  case 0x0C: return r->pllcfgr;
  case 0x18: return r->cier;
  case 0x1C: return r->cifr;
  case 0x20: return 0;
  case 0x88: return r->ccipr;
  case 0x90: return r->bdcr;
  case 0x94: return r->csr;
  case 0x98: return r->crrcr;
  case 0x9C: return r->ccipr2;
  }
  if (off >= 0x28 && off <= 0x40) return r->rstr[(off - 0x28) / 4];
  if (off >= 0x48 && off <= 0x60) return r->enr[(off - 0x48) / 4];
  if (off >= 0x68 && off <= 0x80) return r->smenr[(off - 0x68) / 4];
  board_fault(b, "read of reserved RCC offset 0x%02X", off);
  return 0;
}

static void write_cr(board *b, uint32_t v) {
  rcc_state *r = &b->rcc;
  double now = board_now(b);
  uint32_t old = r->cr, src = sws(b), pllsrc = r->pllcfgr & 3u;
  if (v & ~0x030F0700u) { board_fault(b, "RCC_CR 0x%08X writes reserved bits", v); return; }
  /* an oscillator feeding SYSCLK (directly or through the PLL) cannot be stopped (§7.4.1) */
  if (src == 1 || (src == 3 && pllsrc == 2)) v |= CR_HSION;
  if (src == 2 || (src == 3 && pllsrc == 3)) v |= CR_HSEON;
  if (src == 3) v |= CR_PLLON;
  if ((old & CR_HSERDY) && (v & CR_HSEBYP) != (old & CR_HSEBYP)) {
    board_fault(b, "RCC_CR.HSEBYP changed while HSE is on (§7.4.1: only when HSEON=0)");
    return;
  }
  r->cr = (old & (CR_HSIRDY | CR_HSERDY | CR_PLLRDY)) | (v & ~(CR_HSIRDY | CR_HSERDY | CR_PLLRDY));
  if ((v & CR_HSION) && !(old & CR_HSION)) r->hsi_ready_t = now + HSI_STARTUP_S;
  if (!(v & CR_HSION)) { r->cr &= ~CR_HSIRDY; r->hsi_ready_t = -1; }
  if ((v & CR_HSEON) && !(old & CR_HSEON)) r->hse_ready_t = now + ((v & CR_HSEBYP) ? 1e-6 : HSE_STARTUP_S);
  if (!(v & CR_HSEON)) { r->cr &= ~CR_HSERDY; r->hse_ready_t = -1; }
  if ((v & CR_PLLON) && !(old & CR_PLLON)) {
    if (!pll_check(b)) return;
    r->pll_ready_t = now + PLL_LOCK_S;
  }
  if (!(v & CR_PLLON)) { r->cr &= ~CR_PLLRDY; r->pll_ready_t = -1; }
}

static void write_cfgr(board *b, uint32_t v) {
  rcc_state *r = &b->rcc;
  if (v & 0x80FFC000u) { board_fault(b, "RCC_CFGR 0x%08X writes reserved bits", v); return; }
  uint32_t sw = v & 3u;
  static const char *names[] = {"reserved", "HSI16", "HSE", "PLL"};
  if (sw == 0) { board_fault(b, "RCC_CFGR.SW=00 is reserved"); return; }
  uint32_t rdy = sw == 1 ? CR_HSIRDY : sw == 2 ? CR_HSERDY : CR_PLLRDY;
  if (!(r->cr & rdy)) { board_fault(b, "RCC_CFGR.SW=%s before the source is ready", names[sw]); return; }
  if (sw == 3 && !(r->pllcfgr & (1u << 24))) { board_fault(b, "RCC_CFGR.SW=PLL with PLLCFGR.PLLREN=0"); return; }
  /* evaluate the new HCLK before it takes effect */
  uint32_t old = r->cfgr;
  double hclk_old = rcc_hclk_hz(b);
  r->cfgr = (v & ~0xCu) | (sw << 2);
  double hclk = rcc_hclk_hz(b);
  r->cfgr = old;
  rcc_check_clocking(b, hclk, "RCC_CFGR clock switch");
  if (b->fault) return;
  /* RM0440 (RCC, system clock switch): going above 80 MHz needs an intermediate step with the
   * AHB prescaler at /2 held for at least 1 us, so the regulator absorbs the load step. */
  double now = board_now(b);
  if (hclk > 80e6 + 1.0 && hclk > hclk_old) {
    if (hclk_old <= 80e6 + 1.0 && ((v >> 4) & 0xFu) < 8u) {
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
  r->cfgr = (v & ~0xCu) | (sw << 2); /* SWS follows at once */
  board_clock_changed(b);
}

void rcc_write(board *b, uint32_t off, uint32_t v) {
  rcc_state *r = &b->rcc;
  switch (off) {
  case 0x00: write_cr(b, v); return;
  case 0x04: r->icscr = (r->icscr & 0xFFu) | (v & 0x7F000000u); return;
  case 0x08: write_cfgr(b, v); return;
  case 0x0C:
    if (r->cr & CR_PLLON) { board_fault(b, "RCC_PLLCFGR written while PLLON=1 (§7.4.4: only when the PLL is off)"); return; }
    if (v & 0x00888000u || (v & 0xCu)) { board_fault(b, "RCC_PLLCFGR 0x%08X writes reserved bits", v); return; }
    r->pllcfgr = v;
    return;
  case 0x18: r->cier = v; return;
  case 0x20: r->cifr &= ~v; return;
  case 0x88: r->ccipr = v; return;
  case 0x90: r->bdcr = v; return;
  case 0x94:
    if (v & (1u << 23)) r->csr &= ~0xFE000000u; /* RMVF */
    if ((v & 1u) && !(r->csr & 1u)) r->lsi_ready_t = board_now(b) + LSI_STARTUP_S;
    if (!(v & 1u) && !b->iwdg.started) { r->csr &= ~3u; r->lsi_ready_t = -1; }
    r->csr = (r->csr & ~1u) | (v & 1u) | (b->iwdg.started ? 1u : 0u);
    return;
  case 0x98: r->crrcr = v & 1u; return;
  case 0x9C: r->ccipr2 = v; return;
  }
  if (off >= 0x28 && off <= 0x40) { r->rstr[(off - 0x28) / 4] = v; return; }
  if (off >= 0x48 && off <= 0x60 && off != 0x54) { r->enr[(off - 0x48) / 4] = v; return; }
  if (off >= 0x68 && off <= 0x80 && off != 0x74) { r->smenr[(off - 0x68) / 4] = v; return; }
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
  if (r->hsi_ready_t >= 0 && now >= r->hsi_ready_t) { r->cr |= CR_HSIRDY; r->hsi_ready_t = -1; }
  if (r->hse_ready_t >= 0 && now >= r->hse_ready_t) { r->cr |= CR_HSERDY; r->hse_ready_t = -1; }
  if (r->pll_ready_t >= 0 && now >= r->pll_ready_t) { r->cr |= CR_PLLRDY; r->pll_ready_t = -1; }
  if (r->lsi_ready_t >= 0 && now >= r->lsi_ready_t) { r->csr |= 2u; r->lsi_ready_t = -1; }
}
