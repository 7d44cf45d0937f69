/* GPIO ports A-G, RM0440 §9.4: configuration registers (recorded per pin so the firmware's
 * pin map can be checked against docs/board.md), ODR/BSRR/BRR, IDR and the LCKR lock. */
#include "board_priv.h"
#include <string.h>

static const uint32_t k_moder_reset[7] = {0xABFFFFFFu, 0xFFFFFEBFu, 0xFFFFFFFFu, 0xFFFFFFFFu,
                                          0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu};

void gpio_reset(board *b) {
  for (int i = 0; i < 7; i++) {
    gpio_port *p = &b->gpio[i];
    uint32_t em = p->ext_mask, el = p->ext_level; /* the board's wiring survives a reset */
    memset(p, 0, sizeof *p);
    p->ext_mask = em;
    p->ext_level = el;
    p->moder = k_moder_reset[i];
  }
  b->gpio[0].ospeedr = 0x0C000000u; b->gpio[0].pupdr = 0x64000000u; /* SWD pins */
  b->gpio[1].ospeedr = 0x000000C0u; b->gpio[1].pupdr = 0x00000100u;
}

/* Level of an input-capable pin: driven from outside (board_drive_pin), else its pull. The
 * Schmitt trigger also samples in alternate-function mode (RM0440 §9.3.12), so an AF input such
 * as HRTIM_FLT3 reads its line in IDR too. */
/* A pin's 2-bit field (MODER, OSPEEDR, PUPDR) and its 4-bit alternate function. */
static uint32_t pin2(uint32_t reg, int pin) { return reg_field(reg >> (2 * pin), GPIO_MODER_MODE0); }

static uint32_t pin_af(const gpio_port *p, int pin) { return reg_field(p->afr[pin / 8] >> (4 * (pin % 8)), GPIO_AFRL_AF0); }

static uint32_t input_level(const gpio_port *p, int pin) {
  uint32_t bit = 1u << pin, pull = pin2(p->pupdr, pin);
  if (p->ext_mask & bit) return (p->ext_level & bit) ? 1u : 0u;
  return ((p->idr_in & bit) || pull == GPIO_PULL_UP) ? 1u : 0u;
}

static uint32_t idr(const gpio_port *p) {
  uint32_t v = 0;
  for (int pin = 0; pin < 16; pin++) {
    uint32_t mode = pin2(p->moder, pin);
    uint32_t bit = 1u << pin;
    if (mode == GPIO_MODE_OUTPUT) v |= p->odr & bit;
    else if (mode == GPIO_MODE_INPUT || mode == GPIO_MODE_AF) v |= input_level(p, pin) << pin;
  }
  return v;
}

/* HRTIM_FLT3 as the HRTIM sees it: PB10 in AF13 carries the line; any other pin mode gives the
 * peripheral a low input (docs/board.md: an analog pin reads low). */
bool gpio_flt3_low(const board *b) {
  const gpio_port *p = &b->gpio[1];
  if (pin2(p->moder, 10) != GPIO_MODE_AF || pin_af(p, 10) != 13u) return true;
  return input_level(p, 10) == 0u;
}

/* HRTIM_EEV6 (external event 6, source 1) as the HRTIM sees it: PB5 in AF13, else a low input. */
bool gpio_eev6_low(const board *b) {
  const gpio_port *p = &b->gpio[1];
  if (pin2(p->moder, 5) != GPIO_MODE_AF || pin_af(p, 5) != 13u) return true;
  return input_level(p, 5) == 0u;
}

void board_drive_pin(board *b, char port, int pin, int level) {
  gpio_port *p = &b->gpio[port - 'A'];
  uint32_t bit = 1u << pin;
  if (level < 0) p->ext_mask &= ~bit;
  else { p->ext_mask |= bit; p->ext_level = level ? (p->ext_level | bit) : (p->ext_level & ~bit); }
  hrtim_fault_input_update(b, gpio_flt3_low(b));
  hrtim_eev_input_update(b, gpio_eev6_low(b));
}

uint32_t gpio_read(board *b, int port, uint32_t off) {
  gpio_port *p = &b->gpio[port];
  switch (off) {
  case GPIO_MODER_OFS: return p->moder;
  case GPIO_OTYPER_OFS: return p->otyper;
  case GPIO_OSPEEDR_OFS: return p->ospeedr;
  case GPIO_PUPDR_OFS: return p->pupdr;
  case GPIO_IDR_OFS: return idr(p);
  case GPIO_ODR_OFS: return p->odr;
  case GPIO_BSRR_OFS: return 0; /* write-only */
  case GPIO_LCKR_OFS:
    if (p->lck_seq == 3) p->lck_seq = 4;
    return p->lckr;
  case GPIO_AFRL_OFS: return p->afr[0];
  case GPIO_AFRH_OFS: return p->afr[1];
  case GPIO_BRR_OFS: return 0;
  }
  board_fault(b, "read of reserved GPIO%c offset 0x%02X", 'A' + port, off);
  return 0;
}

/* Lock per pin (LCKR[15:0] once LCKK is set); `bits_per_pin` maps a register's field. */
static uint32_t locked_mask(const gpio_port *p, int bits_per_pin, int first_pin) {
  if (!(p->lckr & GPIO_LCKR_LCKK)) return 0;
  uint32_t m = 0;
  for (int i = 0; i < 32 / bits_per_pin; i++)
    if (p->lckr & (1u << (first_pin + i))) m |= ((1u << bits_per_pin) - 1u) << (i * bits_per_pin);
  return m;
}

static void config_write(board *b, int port, const char *name, uint32_t *reg, uint32_t v, uint32_t mask,
                         int bits_per_pin, int first_pin) {
  gpio_port *p = &b->gpio[port];
  uint32_t nv = (*reg & ~mask) | (v & mask);
  uint32_t lk = locked_mask(p, bits_per_pin, first_pin);
  if ((nv ^ *reg) & lk) {
    board_fault(b, "GPIO%c_%s write changes pins locked by LCKR (RM0440 §9.4.8)", 'A' + port, name);
    return;
  }
  *reg = nv;
}

static void mark_changes(board *b, int port) {
  gpio_port *p = &b->gpio[port];
  for (int pin = 0; pin < 16; pin++) {
    if (pin2(p->moder, pin) != pin2(k_moder_reset[port], pin) || pin_af(p, pin) != 0u) p->changed |= 1u << pin;
  }
}

void gpio_write(board *b, int port, uint32_t off, uint32_t v, uint32_t mask) {
  gpio_port *p = &b->gpio[port];
  switch (off) {
  case GPIO_MODER_OFS: config_write(b, port, "MODER", &p->moder, v, mask, 2, 0); break;
  case GPIO_OTYPER_OFS:
    if (v & mask & ~GPIO_PINS) { board_fault(b, "GPIO%c_OTYPER bits 31:16 are reserved", 'A' + port); return; }
    config_write(b, port, "OTYPER", &p->otyper, v, mask, 1, 0);
    break;
  case GPIO_OSPEEDR_OFS: config_write(b, port, "OSPEEDR", &p->ospeedr, v, mask, 2, 0); break;
  case GPIO_PUPDR_OFS: {
    for (int pin = 0; pin < 16; pin++)
      if (pin2(mask, pin) == GPIO_PUPDR_PUPD0 && pin2(v, pin) == GPIO_PULL_RESERVED) {
        board_fault(b, "GPIO%c_PUPDR pin %d = 11 is reserved (RM0440 §9.4.4)", 'A' + port, pin);
        return;
      }
    config_write(b, port, "PUPDR", &p->pupdr, v, mask, 2, 0);
    break;
  }
  case GPIO_IDR_OFS: board_fault(b, "write to read-only GPIO%c_IDR", 'A' + port); return;
  case GPIO_ODR_OFS:
    if (v & mask & ~GPIO_PINS) { board_fault(b, "GPIO%c_ODR bits 31:16 are reserved", 'A' + port); return; }
    p->odr = (p->odr & ~mask) | (v & mask);
    break;
  case GPIO_BSRR_OFS: { /* set (bits 0-15) has priority over reset (bits 16-31), §9.4.7 */
    uint32_t w = v & mask;
    p->odr = (p->odr & ~(w >> 16)) | (w & GPIO_PINS);
    break;
  }
  case GPIO_LCKR_OFS: { /* key sequence: 1+pattern, 0+pattern, 1+pattern, read (§9.4.8) */
    if (mask != 0xFFFFFFFFu) { board_fault(b, "GPIO%c_LCKR needs a 32-bit write", 'A' + port); return; }
    if (p->lckr & GPIO_LCKR_LCKK) return; /* locked until reset */
    uint32_t k = v & GPIO_LCKR_LCKK, pat = v & GPIO_PINS;
    if (p->lck_seq == 0 && k) { p->lck_seq = 1; p->lckr = pat; }
    else if (p->lck_seq == 1 && !k && pat == p->lckr) p->lck_seq = 2;
    else if (p->lck_seq == 2 && k && pat == p->lckr) { p->lck_seq = 3; p->lckr = pat | GPIO_LCKR_LCKK; }
    else { p->lck_seq = 0; p->lckr = 0; }
    break;
  }
  case GPIO_AFRL_OFS: config_write(b, port, "AFRL", &p->afr[0], v, mask, 4, 0); break;
  case GPIO_AFRH_OFS: config_write(b, port, "AFRH", &p->afr[1], v, mask, 4, 8); break;
  case GPIO_BRR_OFS:
    if (v & mask & ~GPIO_PINS) { board_fault(b, "GPIO%c_BRR bits 31:16 are reserved", 'A' + port); return; }
    p->odr &= ~(v & mask);
    break;
  default: board_fault(b, "write to reserved GPIO%c offset 0x%02X", 'A' + port, off); return;
  }
  mark_changes(b, port);
  if (port == 1) {
    hrtim_fault_input_update(b, gpio_flt3_low(b));
    hrtim_eev_input_update(b, gpio_eev6_low(b));
  }
}

size_t board_pins(const board *b, board_pin *out, size_t max) {
  size_t n = 0;
  for (int port = 0; port < 7; port++)
    for (int pin = 0; pin < 16; pin++) {
      const gpio_port *p = &b->gpio[port];
      if (n >= max) return n;
      board_pin *o = &out[n++];
      o->port = (char)('A' + port);
      o->pin = pin;
      o->mode = (int)pin2(p->moder, pin);
      o->af = (int)pin_af(p, pin);
      o->changed = (p->changed >> pin) & 1u;
    }
  return n;
}

uint32_t gpio_mmio_read(board *b, uint32_t off) {
  return gpio_read(b, (int)(off / GPIO_PORT_STRIDE), off % GPIO_PORT_STRIDE);
}

void gpio_mmio_write(board *b, uint32_t off, uint32_t v, uint32_t mask) {
  gpio_write(b, (int)(off / GPIO_PORT_STRIDE), off % GPIO_PORT_STRIDE, v, mask);
}
