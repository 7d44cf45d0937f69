/* Internal state of the twin, shared by the engine, the SCS and the peripheral models. */
#ifndef BOARD_PRIV_H
#define BOARD_PRIV_H
#include <unicorn/unicorn.h>
#include <stdbool.h>
#include "board_twin/board.h"
#include "board_twin/elf.h"
#include "fdcan_model.h"
#include "board_twin/twin.h"
#include "hrtim.h"
#include "adc.h"
#include "g474_regs.h"

/* Memory map, RM0440 §2.2 (Figure 3, Table 4). */
#define FLASH_BASE 0x08000000u
#define FLASH_SIZE (512u * 1024u)
#define SRAM_BASE 0x20000000u
#define SRAM1_SIZE (80u * 1024u)  /* SRAM1 0x20000000-0x20013FFF */
#define SRAM2_SIZE (16u * 1024u)  /* SRAM2 0x20014000-0x20017FFF */
#define CCM_BASE 0x10000000u      /* CCM SRAM, also aliased at 0x20018000 */
#define CCM_SIZE (32u * 1024u)
#define CCM_ALIAS (SRAM_BASE + SRAM1_SIZE + SRAM2_SIZE)
#define SYSMEM_BASE 0x1FFF0000u   /* system memory (bootloader), 28 KiB */
#define SYSMEM_SIZE (28u * 1024u)
#define OTP_BASE 0x1FFF7000u      /* OTP 1 KiB, then option bytes bank 1 at 0x1FFF7800 */
#define OTP_SIZE 0x1000u

#define NUM_IRQ 102 /* STM32G474: IRQ 0..101 (RM0440 §16.3 Table 97) */
#define NUM_EXC (16 + NUM_IRQ)

typedef struct {
  /* NVIC */
  uint8_t enabled[NUM_EXC], pending[NUM_EXC], active[NUM_EXC];
  uint8_t prio[NUM_EXC];       /* as written, low nibble read-as-zero (4 bits on STM32G4) */
  /* SCB */
  uint32_t vtor, aircr_prigroup, scr, ccr, shcsr, cfsr, hfsr, cpacr, fpccr, fpcar, fpdscr;
  /* SysTick (ARMv7-M B3.3): value derived from the cycle count while enabled */
  uint32_t st_csr, st_rvr, st_val;
  uint64_t st_base_cycle;       /* cycle at which st_val was the counter value */
  uint64_t st_next_zero;        /* cycle of the next 1->0 transition, UINT64_MAX: none */
  /* DWT / CoreDebug */
  uint32_t demcr, dwt_ctrl, dwt_cyccnt;
  uint64_t dwt_base_cycle;
  uint32_t dbgmcu[4];           /* DBGMCU CR, APB1FZR1, APB1FZR2, APB2FZR */
} scs_state;

typedef struct {
  uint32_t cr, icscr, cfgr, pllcfgr, cier, cifr;
  uint32_t rstr[7];   /* AHB1RSTR..APB2RSTR at 0x28..0x40 */
  uint32_t enr[7];    /* AHB1ENR..APB2ENR at 0x48..0x60 */
  uint32_t smenr[7];  /* AHB1SMENR..APB2SMENR at 0x68..0x80 */
  uint32_t ccipr, bdcr, csr, crrcr, ccipr2;
  double hse_ready_t, hsi_ready_t, pll_ready_t, lsi_ready_t; /* <0: not starting */
  double hclk_changed_t;
  uint32_t csr_flags_at_reset; /* reset flags survive a system reset (RM0440 §7.4.29) */
} rcc_state;

typedef struct {
  uint32_t cr1, cr2, cr3, cr4, scr, cr5;
  uint32_t pucr[14]; /* PUCRA/PDCRA..PUCRG/PDCRG */
} pwr_state;

typedef struct {
  uint32_t acr, pdkeyr_seq, sr, cr, eccr;
  int key_stage;       /* 0: expect KEY1, 1: expect KEY2 */
  bool key_locked_out; /* wrong key: CR locked until the next reset (RM0440 §5.3.5) */
  bool pg_half;        /* first word of a double word written */
  uint32_t pg_addr, pg_word0;
  double busy_until;   /* BSY while >= now */
  int op;              /* operation in progress, done at busy_until */
  uint32_t op_off, op_len, op_w0, op_w1;
  uint8_t dirty[256];  /* 2 KiB pages touched by erase/program, to persist */
} flash_state;

/* Power cuts during flash operations and the double-word ECC they break (flash.c). Not reset
 * by a system reset: the array's state outlives the core. */
typedef struct {
  uint64_t ops;        /* erase and program operations started since board_open */
  uint64_t cut_at;     /* cut the power when operation number cut_at starts (1-based); 0: never */
  int cut_torn;        /* 1: the operation is left half done, 0: it never takes effect */
  bool cut;            /* the power is off: board_run returns BOARD_POWER_OFF until board_power_on */
  uint8_t ecc_bad[FLASH_SIZE / 8u / 8u]; /* one bit per 64-bit double word: ECC does not match */
  uint32_t n_bad;      /* double words marked */
  bool want_hook;      /* a double word was marked: install the data-read hook */
  bool hooked;         /* the data-read hook on the flash is installed */
  uint64_t ecc_errors; /* reads of a marked double word (ECCD, NMI) */
} flash_cut_state;

typedef struct {
  uint32_t moder, otyper, ospeedr, pupdr, idr_in, odr, lckr, afr[2];
  uint32_t lck_seq;    /* LCKR key sequence stage */
  uint32_t ext_mask, ext_level; /* pins driven from outside the chip (board_drive_pin) */
  uint32_t changed;    /* pins whose mode/AF left the reset state */
} gpio_port;


#define IRQSTAT_DEPTH 16
typedef struct {
  struct { int exc; uint64_t start, nested; } stack[IRQSTAT_DEPTH];
  int depth;
  board_irq_stat per[NUM_EXC];
} irq_stats;

typedef struct {
  bool started, write_access;
  uint32_t pr, rlr, winr;
  uint32_t pr_eff, rlr_eff; /* values in effect in the LSI domain */
  double reload_t;          /* last reload */
  double pvu_until, rvu_until, wvu_until;
} iwdg_state;

typedef struct {
  uint32_t cr1, cr2, dier, sr, psc, arr;
  uint32_t psc_eff, arr_eff; /* shadow registers */
  uint32_t cnt0;             /* counter value at cycle `base` */
  uint64_t base, next_update;
} tim6_state;


struct board {
  board_config cfg;
  uc_engine *uc;
  elf_image elf;
  uint8_t *flash, *sram, *ccm, *sysmem, *otp;
  /* time: core (HCLK) cycles; seconds rebased whenever HCLK changes */
  uint64_t cycles, idle, limit; /* idle: cycles skipped asleep */
  double t_base_s;
  uint64_t cyc_base;
  double hclk_hz;
  uint32_t pc;          /* address of the instruction being executed (code hook) */
  bool sleeping;        /* WFI */
  /* stop requests raised inside Unicorn callbacks */
  int stop_intno;       /* UC_HOOK_INTR number, -1 none */
  bool fault;
  char msg[512];
  bool exited;
  int exit_code;
  bool reset_request;
  uint32_t reset_flags; /* RCC_CSR flags to set on the pending reset */
  uint32_t resets;
  bool trace;
  bool poll;            /* pending but masked: the code hook watches PRIMASK/BASEPRI */
  int poll_prio, poll_active_ep;
  scs_state scs;
  rcc_state rcc;
  pwr_state pwr;
  flash_state fl;
  flash_cut_state cut;
  gpio_port gpio[7];
  iwdg_state iwdg;
  tim6_state tim6;
  hrtim_state hrtim;
  adc_state adc;
  fdcan_state fdcan;
  irq_stats irq;
  struct twin_bind *bind; /* the plant on the pins (twin_plant.c); NULL: nothing connected */
};

/* engine.c */
double board_now(const board *b);
void board_fault(board *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
const char *board_func_name(const board *b, uint32_t addr);
void board_request_reset(board *b, uint32_t csr_flags);
void board_end_slice(board *b);
void board_reschedule(board *b); /* a model's next event may have moved earlier */
void board_flash_update(board *b, uint32_t off, uint32_t len); /* shadow -> emulator */
void board_flash_read_hook(board *b); /* install the data-read hook on the flash (ECC errors) */
void flash_data_read(board *b, uint32_t addr, unsigned size); /* flash.c: a data read of the array */
void board_clock_changed(board *b); /* HCLK may have changed */

/* scs.c */
void scs_reset(board *b);
uint32_t scs_read(board *b, uint32_t addr, unsigned size);
void scs_write(board *b, uint32_t addr, unsigned size, uint32_t value);
void scs_set_pending(board *b, int exc);
uint64_t scs_next_event(board *b);
void scs_event(board *b);

/* exc.c */
int exc_priority(const board *b, int exc);
int exc_pending_to_take(board *b);  /* exception number that would preempt now, 0: none */
bool exc_any_pending_enabled(const board *b);
int exc_enter(board *b, int exc);   /* 0 ok, -1 fault raised */
int exc_return(board *b, uint32_t exc_return_value);
bool exc_prepare_poll(board *b);
bool exc_poll_unmasked(board *b);

/* peripherals: each returns the register value / handles a write at offset */
void rcc_reset(board *b, bool power_on);
uint32_t rcc_read(board *b, uint32_t off);
void rcc_write(board *b, uint32_t off, uint32_t v);
bool rcc_clock_enabled(board *b, uint32_t enr_ofs, uint32_t bit); /* RCC_*ENR_OFS, its enable bit */
double rcc_sysclk_hz(board *b);
double rcc_hclk_hz(board *b);
void rcc_check_clocking(board *b, double hclk_hz, const char *why);
double rcc_next_event(board *b);
void rcc_event(board *b);

void pwr_reset(board *b);
uint32_t pwr_read(board *b, uint32_t off);
void pwr_write(board *b, uint32_t off, uint32_t v);
bool pwr_boost(const board *b);
int pwr_range(const board *b);

void flash_reset(board *b);
uint32_t flash_read(board *b, uint32_t off);
void flash_write(board *b, uint32_t off, uint32_t v);
void flash_mem_write(board *b, uint32_t addr, unsigned size, uint32_t v);
double flash_max_hclk(const board *b, uint32_t latency);
double flash_next_event(board *b);
void flash_event(board *b);
int flash_nvm_load(board *b, char *err, size_t err_len);
int flash_nvm_save(board *b);

void gpio_reset(board *b);
uint32_t gpio_read(board *b, int port, uint32_t off);
void gpio_write(board *b, int port, uint32_t off, uint32_t v, uint32_t mask);
/* the same with offsets from GPIOA's base (port x at x * GPIO_PORT_STRIDE), for the peripheral map */
uint32_t gpio_mmio_read(board *b, uint32_t off);
void gpio_mmio_write(board *b, uint32_t off, uint32_t v, uint32_t mask);

void iwdg_reset(board *b);
uint32_t iwdg_read(board *b, uint32_t off);
void iwdg_write(board *b, uint32_t off, uint32_t v);
double iwdg_next_event(board *b);
void iwdg_event(board *b);

void tim6_reset(board *b);
uint32_t tim6_read(board *b, uint32_t off);
void tim6_write(board *b, uint32_t off, uint32_t v);
uint64_t tim6_next_event(board *b);
void tim6_event(board *b);

/* gpio.c: the external side of the pins */
bool gpio_flt3_low(const board *b);
bool gpio_eev6_low(const board *b); /* HRTIM_EEV6 (PB5, AF13) low as the HRTIM sees it */

/* hrtim.c (RM0440 §27); offsets from 0x40016800 */
void hrtim_reset(board *b);
uint32_t hrtim_read(board *b, uint32_t off);
void hrtim_write(board *b, uint32_t off, uint32_t v);
double hrtim_next_event(board *b);
void hrtim_event(board *b);
void hrtim_fault_input_update(board *b, bool line_low);
void hrtim_eev_input_update(board *b, bool pin_low); /* external event 6 input changed */
uint32_t hrtim_levels(board *b, double t);   /* pin levels of TA1..TF2 from t on */
double hrtim_next_edge(board *b, double t);  /* first output edge after t, INFINITY: none */
void hrtim_prune(board *b, double t);        /* forget edges up to t */

/* adc.c (RM0440 §21); offsets from 0x50000000 (ADC1 0x000, ADC2 0x100, ADC12 common 0x300, ADC3 0x400,
 * ADC345 common 0x700) */
void adc_reset(board *b);
uint32_t adc_read(board *b, uint32_t off);
void adc_write(board *b, uint32_t off, uint32_t v);
double adc_next_event(board *b);
void adc_event(board *b);
void adc_advance(board *b, double upto); /* process sampling instants and rank ends up to `upto` */
void adc_hrtim_trigger(board *b, int trg, double when); /* HRTIM ADC trigger trg (1..4) fired at `when` */

/* twin_plant.c */
void twin_sync(board *b, double t);          /* integrate the plant up to t */
double twin_pin_voltage(board *b, char port, int pin, double t);
void twin_free(board *b);

/* irqstat.c */
void irqstat_enter(board *b, int exc);
void irqstat_exit(board *b, int exc);

/* semihost.c: BKPT 0xAB. 0 handled, -1 fault raised. */
int semihost_call(board *b);

/* periph_names.c: the SVD's peripheral names, for messages */
const char *periph_name(uint32_t addr);

#endif
