/* The engine: Unicorn's Cortex-M4 with the STM32G474 memory map, reset, virtual time and
 * the run loop that interleaves instruction slices with peripheral events and exceptions.
 *
 * Time: one instruction = one core (HCLK) cycle (CPI 1.0; a real Cortex-M4 from flash with
 * wait states runs about 1.2-2 cycles per instruction, so virtual time runs ahead of nothing
 * and firmware sees *more* headroom than on the chip). A slice runs until the next
 * peripheral event (the code hook counts instructions and stops at the limit, before the
 * instruction executes). WFI/WFE skip virtual time to the next event. */
#include "board_priv.h"
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#define PERIPH_BASE 0x40000000u
#define PERIPH_SIZE 0x20000000u /* APB1/APB2/AHB1/AHB2 up to 0x5FFFFFFF */
#define PPB_BASE 0xE0000000u
#define PPB_SIZE 0x00100000u

static uint32_t reg32(board *b, int r) {
  uint32_t v = 0;
  uc_reg_read(b->uc, r, &v);
  return v;
}

double board_now(const board *b) {
  if (!(b->hclk_hz > 0)) return b->t_base_s; /* between a reset and the first clock query */
  return b->t_base_s + (double)(b->cycles - b->cyc_base) / b->hclk_hz;
}

const char *board_func_name(const board *b, uint32_t addr) {
  const elf_symbol *s = elf_func_at(&b->elf, addr);
  return s ? s->name : "?";
}

void board_fault(board *b, const char *fmt, ...) {
  if (b->fault) return; /* keep the first cause */
  char text[384];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(text, sizeof text, fmt, ap);
  va_end(ap);
  snprintf(b->msg, sizeof b->msg, "%s (PC 0x%08X in %s, t=%.6f s)", text, b->pc, board_func_name(b, b->pc),
           board_now(b));
  b->fault = true;
  board_end_slice(b);
}

/* Stopping Unicorn from inside an MMIO callback restarts the faulting instruction (its
 * store would be repeated), so the slice ends at the next instruction boundary instead:
 * the code hook stops before that instruction executes. */
void board_end_slice(board *b) { b->limit = b->cycles; }

void board_request_reset(board *b, uint32_t csr_flags) {
  b->reset_request = true;
  b->reset_flags |= csr_flags;
  board_end_slice(b);
}

void board_clock_changed(board *b) {
  double hz = rcc_hclk_hz(b);
  if (hz == b->hclk_hz) return;
  if (b->hclk_hz > 0) b->t_base_s = board_now(b); /* at reset hclk_hz is 0: time stays where it was */
  b->cyc_base = b->cycles;
  b->hclk_hz = hz;
}

/* ---- Unicorn callbacks ---- */

static void hook_code(uc_engine *uc, uint64_t addr, uint32_t size, void *u) {
  (void)size;
  board *b = u;
  if (b->cycles >= b->limit || (b->poll && exc_poll_unmasked(b))) { uc_emu_stop(uc); return; }
  b->cycles++;
  b->pc = (uint32_t)addr;
}

static void hook_intr(uc_engine *uc, uint32_t intno, void *u) {
  board *b = u;
  b->stop_intno = (int)intno;
  uc_emu_stop(uc);
}

static bool hook_unmapped(uc_engine *uc, uc_mem_type type, uint64_t addr, int size, int64_t value, void *u) {
  (void)uc; (void)value;
  board *b = u;
  const char *what = type == UC_MEM_FETCH_UNMAPPED ? "instruction fetch from" :
                     type == UC_MEM_WRITE_UNMAPPED ? "write to" : "read of";
  board_fault(b, "%s unmapped address 0x%08X (%d bytes)", what, (uint32_t)addr, size);
  return false;
}

static bool hook_write_prot(uc_engine *uc, uc_mem_type type, uint64_t addr, int size, int64_t value, void *u) {
  (void)uc; (void)type;
  board *b = u;
  uint32_t a = (uint32_t)addr;
  if (a >= FLASH_BASE && a - FLASH_BASE < FLASH_SIZE) {
    flash_mem_write(b, a, (unsigned)size, (uint32_t)value); /* the flash interface decides */
    return true;                                             /* the store itself is dropped */
  }
  board_fault(b, "write to read-only memory at 0x%08X (boot alias, system memory or OTP)", a);
  return false;
}

static void system_reset(board *b, bool power_on);

static void hook_flash_read(uc_engine *uc, uc_mem_type type, uint64_t addr, int size, int64_t value, void *u) {
  (void)uc; (void)type; (void)value;
  flash_data_read(u, (uint32_t)addr, (unsigned)size);
}

/* Only once the array has a double word with a broken ECC: a read hook costs every load.
 * Requested from inside Unicorn's callbacks, installed by board_run between slices. */
void board_flash_read_hook(board *b) { b->cut.want_hook = true; }

static void install_flash_read_hook(board *b) {
  if (b->cut.hooked || !b->cut.want_hook) return;
  uc_hook h;
  uc_hook_add(b->uc, &h, UC_HOOK_MEM_READ, (void *)hook_flash_read, b, FLASH_BASE, FLASH_BASE + FLASH_SIZE - 1u);
  /* code translated before the hook existed reads without it: drop the translations */
  uc_ctl_remove_cache(b->uc, FLASH_BASE, FLASH_BASE + FLASH_SIZE);
  b->cut.hooked = true;
}

void board_power_on(board *b) {
  b->cut.cut = false;
  b->fault = false;
  system_reset(b, true);
  b->resets++;
}

/* The peripheral map: every modelled peripheral, the addresses it answers, its clock gate and
 * its model's register callbacks. An access is routed by address to its slot; a slot whose clock
 * is off in RCC, or an address no slot answers, stops the run with a message. */
typedef struct {
  uint32_t base, size;      /* the addresses the slot answers */
  const char *name;
  uint32_t gate_ofs;        /* RCC enable register of its clock (RCC_*ENR_OFS), 0: always clocked */
  uint32_t gate_bit;        /* and its enable bit */
  uint32_t origin;          /* the model's offsets count from here (one model may answer several slots) */
  uint32_t (*read)(board *b, uint32_t off);
  void (*write)(board *b, uint32_t off, uint32_t v);                      /* 32-bit writes only */
  void (*write_lanes)(board *b, uint32_t off, uint32_t v, uint32_t mask); /* byte, half-word, word */
} periph_slot;

#define GATE(enr, bit) RCC_##enr##_OFS, RCC_##enr##_##bit
#define GPIO_SLOT(x, name) \
  {GPIOA_BASE + (x) * GPIO_PORT_STRIDE, GPIO_PORT_STRIDE, name, RCC_AHB2ENR_OFS, RCC_AHB2ENR_GPIOAEN << (x), \
   GPIOA_BASE, gpio_mmio_read, NULL, gpio_mmio_write}

/* RM0440 §2.2 (memory map) and §7.4.16-7.4.22 (clock enables). GPIO takes byte, half-word and
 * word accesses (RM0440 §9.4); the other models take 32-bit writes. */
static const periph_slot k_slots[] = {
  {TIM6_BASE, APB_AHB_BLOCK, "TIM6", GATE(APB1ENR1, TIM6EN), TIM6_BASE, tim6_read, tim6_write, NULL},
  {IWDG_BASE, APB_AHB_BLOCK, "IWDG", 0, 0, IWDG_BASE, iwdg_read, iwdg_write, NULL}, /* LSI, no enable bit */
  {PWR_BASE, APB_AHB_BLOCK, "PWR", GATE(APB1ENR1, PWREN), PWR_BASE, pwr_read, pwr_write, NULL},
  {HRTIM_MASTER_BASE, HRTIM_SIZE, "HRTIM", GATE(APB2ENR, HRTIM1EN), HRTIM_MASTER_BASE, hrtim_read, hrtim_write, NULL},
  {RCC_BASE, APB_AHB_BLOCK, "RCC", 0, 0, RCC_BASE, rcc_read, rcc_write, NULL},
  {FLASH_R_BASE, APB_AHB_BLOCK, "FLASH", GATE(AHB1ENR, FLASHEN), FLASH_R_BASE, flash_read, flash_write, NULL},
  GPIO_SLOT(0, "GPIOA"), GPIO_SLOT(1, "GPIOB"), GPIO_SLOT(2, "GPIOC"), GPIO_SLOT(3, "GPIOD"),
  GPIO_SLOT(4, "GPIOE"), GPIO_SLOT(5, "GPIOF"), GPIO_SLOT(6, "GPIOG"),
  /* ADC1, ADC2 and their common registers; ADC3 (ADC4, ADC5 refused) and theirs: one model */
  {ADC1_BASE, APB_AHB_BLOCK, "ADC12", GATE(AHB2ENR, ADC12EN), ADC1_BASE, adc_read, adc_write, NULL},
  {ADC3_BASE, APB_AHB_BLOCK, "ADC345", GATE(AHB2ENR, ADC345EN), ADC1_BASE, adc_read, adc_write, NULL},
  {FDCAN1_BASE, APB_AHB_BLOCK, "FDCAN1", GATE(APB1ENR1, FDCANEN), FDCAN1_BASE, fdcan_read, fdcan_write, NULL},
  /* FDCAN message RAM, behind the same clock gate */
  {SRAMCAN_BASE, APB_AHB_BLOCK, "SRAMCAN", GATE(APB1ENR1, FDCANEN), SRAMCAN_BASE, fdcan_ram_read, fdcan_ram_write, NULL},
};
_Static_assert(GPIOA_BASE + 6u * GPIO_PORT_STRIDE == GPIOG_BASE, "GPIO ports A-G");

static const periph_slot *find_slot(board *b, uint32_t addr, bool write) {
  for (size_t i = 0; i < sizeof k_slots / sizeof k_slots[0]; i++) {
    const periph_slot *s = &k_slots[i];
    if (addr - s->base >= s->size) continue;
    if (s->gate_ofs && !rcc_clock_enabled(b, s->gate_ofs, s->gate_bit)) {
      board_fault(b, "%s of %s register 0x%08X while its clock is disabled in RCC", write ? "write" : "read",
                  s->name, addr);
      return NULL;
    }
    return s;
  }
  board_fault(b, "%s of unmodelled peripheral %s at 0x%08X", write ? "write" : "read", periph_name(addr), addr);
  return NULL;
}

static uint64_t mmio_periph_read(uc_engine *uc, uint64_t offset, unsigned size, void *u) {
  (void)uc;
  board *b = u;
  uint32_t addr = PERIPH_BASE + (uint32_t)offset;
  const periph_slot *s = find_slot(b, addr, false);
  if (!s) return 0;
  uint32_t v = s->read(b, (addr - s->origin) & ~3u);
  unsigned sh = (addr & 3u) * 8u;
  return size >= 4 ? v : (v >> sh) & ((1u << (size * 8)) - 1u);
}

static void mmio_periph_write(uc_engine *uc, uint64_t offset, unsigned size, uint64_t value, void *u) {
  (void)uc;
  board *b = u;
  uint32_t addr = PERIPH_BASE + (uint32_t)offset;
  const periph_slot *s = find_slot(b, addr, true);
  if (!s) return;
  uint32_t off = (addr - s->origin) & ~3u;
  uint32_t v = (uint32_t)value;
  if (s->write_lanes) {
    unsigned sh = (addr & 3u) * 8u;
    uint32_t mask = size >= 4 ? 0xFFFFFFFFu : ((1u << (size * 8)) - 1u) << sh;
    s->write_lanes(b, off, v << sh, mask);
  } else if (size != 4) {
    board_fault(b, "%u-byte write to %s register 0x%08X: the model accepts 32-bit writes only", size, s->name, addr);
    return;
  } else {
    s->write(b, off, v);
  }
  /* A write may schedule an earlier event (oscillator ready, flash busy, timer): shorten the
   * slice to it. Interrupts pended by models end the slice themselves (scs_set_pending).
   * Not ending every slice here keeps frequent writes (watchdog refresh) cheap. */
  board_reschedule(b);
}

static uint64_t mmio_ppb_read(uc_engine *uc, uint64_t offset, unsigned size, void *u) {
  (void)uc;
  return scs_read(u, PPB_BASE + (uint32_t)offset, size);
}

static void mmio_ppb_write(uc_engine *uc, uint64_t offset, unsigned size, uint64_t value, void *u) {
  board *b = u;
  (void)uc;
  scs_write(b, PPB_BASE + (uint32_t)offset, size, (uint32_t)value);
  /* an NVIC/SCB write may make an exception take effect: end the slice after this store */
  (void)uc;
  board_end_slice(b);
}

/* ---- reset ---- */

static void core_reset(board *b) {
  uc_engine *uc = b->uc;
  uint32_t zero = 0;
  for (int r = UC_ARM_REG_R0; r <= UC_ARM_REG_R12; r++) uc_reg_write(uc, r, &zero);
  for (int r = UC_ARM_REG_S0; r <= UC_ARM_REG_S31; r++) uc_reg_write(uc, r, &zero);
  uc_reg_write(uc, UC_ARM_REG_FPSCR, &zero);
  uc_reg_write(uc, UC_ARM_REG_PRIMASK, &zero);
  uc_reg_write(uc, UC_ARM_REG_BASEPRI, &zero);
  uc_reg_write(uc, UC_ARM_REG_CONTROL, &zero);
  uint32_t xpsr = 1u << 24, lr = 0xFFFFFFFFu;
  uc_reg_write(uc, UC_ARM_REG_XPSR, &xpsr);
  uc_reg_write(uc, UC_ARM_REG_LR, &lr);
  /* ARMv7-M B1.5.5: SP_main and the reset vector from the table at 0 (the flash boot alias). */
  uint32_t sp, pc;
  memcpy(&sp, b->flash, 4);
  memcpy(&pc, b->flash + 4, 4);
  uc_reg_write(uc, UC_ARM_REG_SP, &sp);
  b->pc = pc & ~1u;
  if (!(pc & 1u)) board_fault(b, "reset vector 0x%08X has no Thumb bit: the core would lock up", pc);
  uc_reg_write(uc, UC_ARM_REG_PC, &b->pc);
}

static void system_reset(board *b, bool power_on) {
  /* RAM and peripherals back to reset values; flash (and so the NVM) is kept. */
  memset(b->sram, 0, SRAM1_SIZE + SRAM2_SIZE);
  memset(b->ccm, 0, CCM_SIZE);
  double now = b->hclk_hz > 0 ? board_now(b) : 0.0;
  rcc_reset(b, power_on);
  b->t_base_s = now;
  b->cyc_base = b->cycles;
  b->hclk_hz = rcc_hclk_hz(b);
  pwr_reset(b);
  flash_reset(b);
  gpio_reset(b);
  iwdg_reset(b);
  tim6_reset(b);
  hrtim_reset(b);
  adc_reset(b);
  fdcan_reset(b);
  b->irq.depth = 0;
  scs_reset(b);
  b->sleeping = false;
  b->reset_request = false;
  b->reset_flags = 0;
  core_reset(b);
}

/* ---- open/close ---- */

void board_flash_update(board *b, uint32_t off, uint32_t len) {
  uc_mem_write(b->uc, FLASH_BASE + off, b->flash + off, len);
  uc_mem_write(b->uc, off, b->flash + off, len);
  /* the emulator may hold code translated from this range */
  uc_ctl_remove_cache(b->uc, FLASH_BASE + off, FLASH_BASE + off + len);
  uc_ctl_remove_cache(b->uc, off, off + len);
}

void board_config_default(board_config *cfg) {
  memset(cfg, 0, sizeof *cfg);
  cfg->hse_hz = 24e6;
}

static uint8_t *page_alloc(size_t size, int fill) {
  uint8_t *p = aligned_alloc(4096, (size + 4095u) & ~(size_t)4095u);
  if (p) memset(p, fill, size);
  return p;
}

static int map(board *b, uint32_t base, uint32_t size, uint32_t perms, void *mem, char *err, size_t n) {
  uc_err e = uc_mem_map_ptr(b->uc, base, size, perms, mem);
  if (e != UC_ERR_OK) { snprintf(err, n, "cannot map 0x%08X: %s", base, uc_strerror(e)); return -1; }
  return 0;
}

board *board_open(const board_config *cfg, char *err, size_t n) {
  board *b = calloc(1, sizeof *b);
  b->cfg = *cfg;
  if (!b->cfg.console) b->cfg.console = stderr;
  if (b->cfg.hse_hz <= 0) b->cfg.hse_hz = 24e6;
  if (elf_load(cfg->elf_path, &b->elf, err, n) != 0) { free(b); return NULL; }
  /* Unicorn's TLB needs page-aligned host memory behind uc_mem_map_ptr */
  b->flash = page_alloc(FLASH_SIZE, 0xFF); /* erased */
  b->sram = page_alloc(SRAM1_SIZE + SRAM2_SIZE, 0);
  b->ccm = page_alloc(CCM_SIZE, 0);
  b->sysmem = page_alloc(SYSMEM_SIZE, 0);
  b->otp = page_alloc(OTP_SIZE, 0xFF);
  for (size_t i = 0; i < b->elf.nseg; i++) {
    const elf_segment *s = &b->elf.seg[i];
    if (s->filesz == 0) continue; /* .bss and friends: zeroed by the startup code */
    if (s->paddr < FLASH_BASE || (uint64_t)s->paddr + s->filesz > (uint64_t)FLASH_BASE + FLASH_SIZE) {
      snprintf(err, n, "%s: load segment at 0x%08X (+%u bytes) is outside the 512 KiB flash", cfg->elf_path,
               s->paddr, s->filesz);
      board_close(b);
      return NULL;
    }
    memcpy(b->flash + (s->paddr - FLASH_BASE), s->data, s->filesz);
  }
  if (cfg->nvm_path && flash_nvm_load(b, err, n) != 0) { board_close(b); return NULL; }

  uc_err e = uc_open(UC_ARCH_ARM, UC_MODE_THUMB | UC_MODE_MCLASS, &b->uc);
  if (e != UC_ERR_OK) { snprintf(err, n, "uc_open: %s", uc_strerror(e)); board_close(b); return NULL; }
  uc_ctl_set_cpu_model(b->uc, UC_CPU_ARM_CORTEX_M4);
  const uint32_t RX = UC_PROT_READ | UC_PROT_EXEC;
  /* Flash and its boot alias (BOOT0=0) are Unicorn-owned read-only memory: a CPU store into
   * them reaches hook_write_prot and is dropped (with uc_mem_map_ptr the store would land).
   * b->flash is the shadow the flash model works on; board_flash_update() mirrors it. */
  if (uc_mem_map(b->uc, FLASH_BASE, FLASH_SIZE, RX) != UC_ERR_OK || uc_mem_map(b->uc, 0, FLASH_SIZE, RX) != UC_ERR_OK) {
    snprintf(err, n, "cannot map the flash");
    board_close(b);
    return NULL;
  }
  board_flash_update(b, 0, FLASH_SIZE);
  if (map(b, SRAM_BASE, SRAM1_SIZE + SRAM2_SIZE, UC_PROT_ALL, b->sram, err, n) ||
      map(b, CCM_BASE, CCM_SIZE, UC_PROT_ALL, b->ccm, err, n) ||
      map(b, CCM_ALIAS, CCM_SIZE, UC_PROT_ALL, b->ccm, err, n) ||
      map(b, SYSMEM_BASE, SYSMEM_SIZE, RX, b->sysmem, err, n) ||
      map(b, OTP_BASE, OTP_SIZE, UC_PROT_READ, b->otp, err, n)) {
    board_close(b);
    return NULL;
  }
  uc_mmio_map(b->uc, PERIPH_BASE, PERIPH_SIZE, mmio_periph_read, b, mmio_periph_write, b);
  uc_mmio_map(b->uc, PPB_BASE, PPB_SIZE, mmio_ppb_read, b, mmio_ppb_write, b);
  uc_hook h;
  uc_hook_add(b->uc, &h, UC_HOOK_CODE, (void *)hook_code, b, 1, 0);
  uc_hook_add(b->uc, &h, UC_HOOK_INTR, (void *)hook_intr, b, 1, 0);
  uc_hook_add(b->uc, &h, UC_HOOK_MEM_UNMAPPED, (void *)hook_unmapped, b, 1, 0);
  uc_hook_add(b->uc, &h, UC_HOOK_MEM_WRITE_PROT, (void *)hook_write_prot, b, 1, 0);
  b->stop_intno = -1;
  b->trace = getenv("DTC_BOARD_TRACE") != NULL;
  system_reset(b, true);
  return b;
}

void board_close(board *b) {
  if (!b) return;
  if (b->cfg.nvm_path && b->uc) flash_nvm_save(b);
  if (b->uc) uc_close(b->uc);
  twin_free(b);
  elf_free(&b->elf);
  free(b->flash); free(b->sram); free(b->ccm); free(b->sysmem); free(b->otp);
  free(b);
}

/* ---- run loop ---- */

static uint64_t cycles_at(const board *b, double t) {
  double now = board_now(b);
  if (t <= now) return b->cycles;
  double c = ceil((t - now) * b->hclk_hz);
  return c > 1e18 ? UINT64_MAX : b->cycles + (uint64_t)c;
}

static void process_events(board *b) {
  scs_event(b);
  rcc_event(b);
  flash_event(b);
  iwdg_event(b);
  tim6_event(b);
  hrtim_event(b);
  adc_event(b);
  fdcan_event(b);
}

static uint64_t next_event(board *b, double t_end) {
  uint64_t n = cycles_at(b, t_end);
  uint64_t s = scs_next_event(b);
  if (s < n) n = s;
  s = tim6_next_event(b);
  if (s < n) n = s;
  double t = rcc_next_event(b);
  double f = flash_next_event(b), w = iwdg_next_event(b), h = hrtim_next_event(b);
  if (f < t) t = f;
  if (h < t) t = h;
  h = adc_next_event(b);
  if (h < t) t = h;
  if (w < t) t = w;
  double can_t = fdcan_next_event(b);
  if (can_t < t) t = can_t;
  if (t < INFINITY) {
    uint64_t c = cycles_at(b, t);
    if (c < n) n = c;
  }
  return n;
}

void board_reschedule(board *b) {
  uint64_t n = next_event(b, INFINITY);
  if (n < b->limit) b->limit = n > b->cycles ? n : b->cycles;
}

static void handle_stop(board *b, uc_err e) {
  int intno = b->stop_intno;
  b->stop_intno = -1;
  if (b->fault || b->reset_request) return;
  uint32_t pc = reg32(b, UC_ARM_REG_PC);
  if (intno == 8) { /* EXCP_EXCEPTION_EXIT: bx/pop to an EXC_RETURN value */
    exc_return(b, pc | 1u);
    return;
  }
  if (intno == 7) { /* EXCP_BKPT */
    uint16_t insn = 0;
    uc_mem_read(b->uc, pc, &insn, 2);
    b->pc = pc;
    if (insn == 0xBEABu) {
      if (semihost_call(b) == 0) { pc += 2; uc_reg_write(b->uc, UC_ARM_REG_PC, &pc); }
    } else board_fault(b, "BKPT 0x%02X executed with no debugger attached", insn & 0xFFu);
    return;
  }
  if (intno >= 0) {
    static const char *names[] = {"?", "undefined instruction", "SVC", "prefetch abort", "data abort",
                                  "IRQ", "FIQ", "BKPT", "exception exit", "kernel trap", "?", "HVC",
                                  "hyp trap", "SMC", "VIRQ", "VFIQ", "semihosting", "no coprocessor (FPU off?)",
                                  "invalid state (Thumb bit clear)", "stack overflow", "lazy FP", "LSERR",
                                  "unaligned access"};
    const char *nm = intno < (int)(sizeof names / sizeof names[0]) ? names[intno] : "?";
    board_fault(b, "CPU exception %d (%s): the core would take a fault here", intno, nm);
    return;
  }
  if (e != UC_ERR_OK) { board_fault(b, "emulation error: %s", uc_strerror(e)); return; }
  if (b->cycles >= b->limit) return;
  /* Unicorn stops on WFI (EXCP_HLT) with PC after it. */
  uint16_t prev = 0;
  uc_mem_read(b->uc, pc - 2, &prev, 2);
  if (prev == 0xBF30u || prev == 0xBF20u) { b->sleeping = true; return; } /* WFI, WFE */
}

board_status board_run(board *b, double seconds) {
  double t_end = board_now(b) + seconds;
  for (;;) {
    if (b->exited) return BOARD_EXITED;
    install_flash_read_hook(b);
    if (b->cut.cut) return BOARD_POWER_OFF;
    if (b->fault) return BOARD_FAULT;
    if (b->reset_request) {
      uint32_t flags = b->reset_flags;
      if (b->cfg.nvm_path) flash_nvm_save(b);
      system_reset(b, false);
      b->rcc.csr |= flags;
      b->resets++;
      continue;
    }
    process_events(b);
    if (b->fault || b->reset_request) continue;
    int exc = exc_pending_to_take(b);
    if (exc) {
      b->sleeping = false;
      exc_enter(b, exc);
      continue;
    }
    if (board_now(b) >= t_end) return BOARD_TIME_UP;
    uint64_t next = next_event(b, t_end);
    if (next <= b->cycles) next = b->cycles + 1;
    if (b->sleeping) {
      if (exc_any_pending_enabled(b)) b->sleeping = false; /* wakes even when masked */
      else { b->idle += next - b->cycles; b->cycles = next; continue; }
    }
    exc_prepare_poll(b);
    b->limit = next;
    uint32_t pc = reg32(b, UC_ARM_REG_PC) | 1u;
    uc_err e = uc_emu_start(b->uc, pc, 0xFFFFFFFEu, 0, 0);
    if (b->trace) /* DTC_BOARD_TRACE=1: one line per slice, for debugging the engine */
      fprintf(stderr, "slice from 0x%08X to 0x%08X: cycles %llu limit %llu err %d intno %d\n", pc,
              reg32(b, UC_ARM_REG_PC), (unsigned long long)b->cycles, (unsigned long long)b->limit, e, b->stop_intno);
    handle_stop(b, e);
  }
}

int board_exit_code(const board *b) { return b->exit_code; }
const char *board_message(const board *b) { return b->msg; }
double board_time_s(const board *b) { return board_now(b); }
uint64_t board_instructions(const board *b) { return b->cycles - b->idle; }
uint32_t board_resets(const board *b) { return b->resets; }
double board_core_hz(const board *b) { return b->hclk_hz; }

int board_read_u32(board *b, uint32_t addr, uint32_t *value) {
  return uc_mem_read(b->uc, addr, value, 4) == UC_ERR_OK ? 0 : -1;
}

int board_write_u32(board *b, uint32_t addr, uint32_t value) {
  return uc_mem_write(b->uc, addr, &value, 4) == UC_ERR_OK ? 0 : -1;
}

int board_read_mem(board *b, uint32_t addr, void *out, size_t n) {
  return uc_mem_read(b->uc, addr, out, n) == UC_ERR_OK ? 0 : -1;
}

int board_symbol(board *b, const char *name, uint32_t *addr, uint32_t *size) {
  const elf_symbol *s = elf_find(&b->elf, name);
  if (!s) return -1;
  *addr = s->addr;
  *size = s->size;
  return 0;
}

double board_pwm_period_start(board *b, double *period_s) {
  hrtim_event(b);
  if (period_s) *period_s = b->hrtim.running ? (double)b->hrtim.mper * b->hrtim.t_count : 0.0;
  return b->hrtim.running ? b->hrtim.t_period : -1.0;
}

int board_read_symbol(board *b, const char *name, uint32_t offset, uint32_t *value) {
  const elf_symbol *s = elf_find(&b->elf, name);
  return s ? board_read_u32(b, s->addr + offset, value) : -1;
}
