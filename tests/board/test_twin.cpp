// The emulated STM32G474: each case runs a test image and asserts on what it reports.
#include <gtest/gtest.h>
#include <chrono>
#include <cstdio>
#include <sys/wait.h>
#include <cstdlib>
#include <string>
#include <unistd.h>
#include "board_twin/board.h"
#include "board_twin/elf.h"
#include "board_twin/pinmap.h"
#include "board_twin/twin.h"

namespace {

struct Outcome {
  board_status status = BOARD_FAULT;
  int exit_code = -1;
  std::string message;
  uint32_t r[32] = {};
  uint32_t resets = 0;
  double t = 0, hz = 0;
  uint64_t instructions = 0;
};

std::string image(const char *name) { return std::string(TB_DIR) + "/" + name + ".elf"; }

Outcome run(const char *name, double seconds = 5.0, const char *nvm = nullptr, board **keep = nullptr) {
  board_config cfg;
  board_config_default(&cfg);
  std::string path = image(name);
  cfg.elf_path = path.c_str();
  cfg.nvm_path = nvm;
  char err[512];
  board *b = board_open(&cfg, err, sizeof err);
  Outcome out;
  if (!b) { out.message = err; return out; }
  out.status = board_run(b, seconds);
  out.exit_code = board_exit_code(b);
  out.message = board_message(b);
  for (uint32_t i = 0; i < 32; i++) board_read_symbol(b, "tb_result", 4 * i, &out.r[i]);
  out.resets = board_resets(b);
  out.t = board_time_s(b);
  out.hz = board_core_hz(b);
  out.instructions = board_instructions(b);
  if (keep) *keep = b;
  else board_close(b);
  return out;
}

#define EXPECT_EXITED(run)                                         \
  do {                                                             \
    ASSERT_EQ((run).status, BOARD_EXITED) << (run).message;        \
    ASSERT_EQ((run).exit_code, 0);                                 \
  } while (0)

}  // namespace

TEST(twin, reset_and_vector_table) {
  Outcome r = run("reset");
  EXPECT_EXITED(r);
  elf_image img;
  char err[256];
  ASSERT_EQ(elf_load(image("reset").c_str(), &img, err, sizeof err), 0) << err;
  const elf_symbol *estack = elf_find(&img, "_estack");
  ASSERT_NE(estack, nullptr);
  EXPECT_EQ(r.r[0], 0xC0FFEE01u) << ".data not initialised from its flash image";
  EXPECT_EQ(r.r[1], 0u);
  EXPECT_EQ(r.r[2], 0x410FC241u);                   // Cortex-M4 r0p1
  EXPECT_EQ(r.r[3], 0u);                            // VTOR at reset
  EXPECT_EQ(r.r[4], estack->addr);                  // SP from vector 0
  EXPECT_EQ(r.r[5], 1u);                            // flash aliased at 0
  EXPECT_EQ(r.r[6], 0x00000500u);                   // RCC_CR: HSI16 on and ready
  EXPECT_EQ(r.r[7], 0x00000005u);                   // RCC_CFGR: SW=SWS=HSI16
  EXPECT_EQ(r.r[8], 1u);                            // PendSV through the relocated table
  EXPECT_EQ(r.r[9], 0x08000000u);
  EXPECT_DOUBLE_EQ(r.hz, 16e6);
  elf_free(&img);
}

TEST(twin, fp_registers_survive_an_interrupt) {
  Outcome r = run("fpirq");
  EXPECT_EXITED(r);
  EXPECT_EQ(r.r[1], 1000u) << "interrupts taken";
  EXPECT_EQ(r.r[0], 0u) << "s0-s15 values changed by the handler";
  EXPECT_EQ(r.r[2], 0u) << "FPSCR changed by the handler";
  EXPECT_EQ(r.r[3], 0xFFFFFFE9u) << "EXC_RETURN: thread, MSP, extended frame";
}

TEST(twin, nested_preemption_tail_chaining_and_masking) {
  Outcome r = run("nested");
  EXPECT_EXITED(r);
  std::string log(reinterpret_cast<const char *>(r.r), r.r[8]);
  EXPECT_EQ(log, "ABaCMBmCpBe");
  EXPECT_EQ(r.r[9], 1u) << "IRQ2 did not tail-chain on IRQ0's frame";
}

TEST(twin, systick_counts_core_clocks) {
  Outcome r = run("systick");
  EXPECT_EXITED(r);
  EXPECT_EQ(r.r[0], 100u * 1000u);  // CLKSOURCE=1: RVR+1 core clocks per period
  EXPECT_EQ(r.r[1], 100u * 100u * 8u);  // CLKSOURCE=0: HCLK/8
  EXPECT_EQ(r.r[2], 0u) << "COUNTFLAG not cleared by reading SYST_CSR";
  EXPECT_EQ(r.r[3], 1u);
}

TEST(twin, tim6_update_interrupt_period_and_urs) {
  Outcome r = run("tim6");
  EXPECT_EXITED(r);
  EXPECT_EQ(r.r[0], 0u) << "UG with URS=1 must not set UIF";
  EXPECT_EQ(r.r[1], 1u) << "UG with URS=0 sets UIF";
  EXPECT_EQ(r.r[2], 12u);
  // 12 handler entries: 11 updates apart, but entry 4 is the level re-entry of update 3
  EXPECT_EQ(r.r[3], 10u * 16000u);
  EXPECT_EQ(r.r[4], 1u);
}

// The HRTIM and ADC models are tested through their register interface and against
// closed-form waveforms and codes in test_models.cpp (the plant binding's models).

TEST(twin, idle_loop_runs_fast) {
  board *b = nullptr;
  auto t0 = std::chrono::steady_clock::now();
  Outcome r = run("idle", 10.0, nullptr, &b);
  double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EXITED(r);
  EXPECT_NEAR(r.t, 5.0, 0.01);
  EXPECT_EQ(r.r[0], 5000u * 16000u);
  std::printf("idle: %.3f s simulated in %.3f s wall: %.1f simulated s per wall s (%llu instructions)\n", r.t, wall,
              r.t / wall, static_cast<unsigned long long>(r.instructions));
  board_close(b);
}

TEST(twin, busy_loop_speed) {
  auto t0 = std::chrono::steady_clock::now();
  Outcome r = run("busy", 60.0);
  double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EXITED(r);
  std::printf("busy: %llu instructions in %.3f s wall: %.1f M instructions/s, %.3f simulated s per wall s at 16 MHz\n",
              static_cast<unsigned long long>(r.instructions), wall, static_cast<double>(r.instructions) / wall / 1e6,
              r.t / wall);
}

TEST(twin, unmapped_access_names_pc_and_function) {
  Outcome r = run("strict1");
  ASSERT_EQ(r.status, BOARD_FAULT);
  EXPECT_NE(r.message.find("0x30000000"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("tb_bad_read"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("PC 0x08"), std::string::npos) << r.message;
}

TEST(twin, unmodelled_peripheral_and_unclocked_access_stop) {
  Outcome r = run("strict2");
  ASSERT_EQ(r.status, BOARD_FAULT);
  EXPECT_NE(r.message.find("unmodelled peripheral USART1"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("tb_usart_read"), std::string::npos) << r.message;
  Outcome g = run("strict3");
  ASSERT_EQ(g.status, BOARD_FAULT);
  EXPECT_NE(g.message.find("GPIOA"), std::string::npos) << g.message;
  EXPECT_NE(g.message.find("clock is disabled"), std::string::npos) << g.message;
}

TEST(twin, cli_exit_status_is_1_on_a_strictness_stop) {
  std::string cmd = std::string(DTC_BOARD) + " exec --elf " + image("strict1") + " 2>&1";
  FILE *p = popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  char buf[1024] = {};
  size_t n = fread(buf, 1, sizeof buf - 1, p);
  buf[n] = 0;
  int st = pclose(p);
  ASSERT_TRUE(WIFEXITED(st));
  EXPECT_EQ(WEXITSTATUS(st), 1);
  EXPECT_NE(std::string(buf).find("tb_bad_read"), std::string::npos) << buf;
}

TEST(twin, wrong_flash_key_locks_until_reset) {
  Outcome r = run("flashkey");
  EXPECT_EXITED(r);
  EXPECT_EQ(r.r[0], 0u) << "KEY1, KEY2 did not unlock FLASH_CR";
  EXPECT_EQ(r.r[1], 1u);
  EXPECT_EQ(r.r[2], 1u) << "a wrong key must raise a bus error";
  EXPECT_TRUE(r.r[3] & (1u << 30)) << "HFSR.FORCED";
  EXPECT_TRUE(r.r[4] & (1u << 10)) << "CFSR.IMPRECISERR";
  EXPECT_EQ(r.r[5], 3u) << "keys after a lock-out are bus errors too";
  EXPECT_EQ(r.r[6], 1u) << "FLASH_CR must stay locked until reset";
}

TEST(twin, flash_program_and_erase_persist_across_resets_and_runs) {
  char nvm[] = "/tmp/dtc-board-nvm-XXXXXX";
  int fd = mkstemp(nvm);
  ASSERT_GE(fd, 0);
  close(fd);
  std::remove(nvm);
  Outcome a = run("nvm", 5.0, nvm);
  EXPECT_EXITED(a);
  EXPECT_EQ(a.resets, 2u);
  EXPECT_EQ(a.r[0], 2u) << "records programmed before the last boot of run 1";
  EXPECT_EQ(a.r[2], 0xB0070002u);
  EXPECT_TRUE(a.r[1] & (1u << 28)) << "SFTRSTF after SYSRESETREQ";
  EXPECT_EQ(a.r[3], 1u << 3) << "PROGERR";
  EXPECT_EQ(a.r[4], 1u << 5) << "PGAERR";
  EXPECT_EQ(a.r[5], 1u << 7) << "PGSERR";
  EXPECT_EQ(a.r[7], 0xFFFFFFFFu);
  Outcome b = run("nvm", 5.0, nvm);
  EXPECT_EXITED(b);
  EXPECT_EQ(b.r[0], 5u) << "run 2 must see run 1's records";
  Outcome c = run("nvm", 5.0, nvm);
  EXPECT_EXITED(c);
  EXPECT_EQ(c.r[0], 2u) << "the page erase on the seventh record did not persist";
  EXPECT_EQ(c.resets, 2u);
  std::remove(nvm);
}

TEST(twin, iwdg_expiry_resets_and_sets_iwdgrstf) {
  Outcome r = run("iwdg", 2.0);
  EXPECT_EXITED(r);
  EXPECT_EQ(r.resets, 1u);
  EXPECT_TRUE(r.r[0] & (1u << 29)) << std::hex << r.r[0];
  EXPECT_TRUE(r.r[0] & (1u << 26)) << "PINRSTF";
  EXPECT_FALSE(r.r[0] & (1u << 27)) << "BORRSTF was cleared by RMVF before the watchdog reset";
  EXPECT_NEAR(r.t, 0.1, 0.005);
  EXPECT_EQ(r.r[2], 0u) << "SRAM not reset by the watchdog reset";
}

TEST(twin, pll_to_170_mhz_with_boost_and_wait_states) {
  Outcome r = run("clock0");
  EXPECT_EXITED(r);
  EXPECT_EQ(r.r[0], 3u);
  EXPECT_DOUBLE_EQ(r.hz, 170e6);
}

TEST(twin, clock_mistakes_are_refused) {
  const struct { const char *img, *text; } cases[] = {
    {"clock1", "range 1 normal mode"},
    {"clock2", "LATENCY=3"},
    {"clock3", "VCO 360.000 MHz"},
    {"clock4", "PLLR output 172.000 MHz"},
    {"clock5", "before the source is ready"},
    {"clock6", "above 80 MHz switch with HPRE=/2 first"},
    {"clock7", "RM0440 asks for at least 1 us"},
  };
  for (const auto &c : cases) {
    Outcome r = run(c.img);
    EXPECT_EQ(r.status, BOARD_FAULT) << c.img;
    EXPECT_NE(r.message.find(c.text), std::string::npos) << c.img << ": " << r.message;
  }
}

TEST(twin, gpio_configuration_against_a_board_table) {
  board *b = nullptr;
  Outcome r = run("gpio", 1.0, nullptr, &b);
  EXPECT_EXITED(r);
  EXPECT_EQ(r.r[0], 1u) << "PA9 output high read back through IDR";
  EXPECT_EQ(r.r[1], 1u) << "PC13 pull-up";
  EXPECT_EQ(r.r[2], (1u << 16) | (1u << 8)) << "LCKR: LCKK set after the key sequence";
  Outcome locked = run("gpio1");
  ASSERT_EQ(locked.status, BOARD_FAULT);
  EXPECT_NE(locked.message.find("locked by LCKR"), std::string::npos) << locked.message;
  Outcome key = run("gpio2");
  ASSERT_EQ(key.status, BOARD_FAULT);
  EXPECT_NE(key.message.find("without VECTKEY"), std::string::npos) << key.message;
  board_pin pins[7 * 16];
  size_t np = board_pins(b, pins, 7 * 16);
  auto check = [&](const char *table) {
    char path[] = "/tmp/dtc-board-pins-XXXXXX";
    int fd = mkstemp(path);
    FILE *f = fdopen(fd, "w");
    std::fprintf(f, "# Board\n\nSome text.\n\n| Pin | Mode | AF | Signal | Scaling |\n|---|---|---|---|---|\n%s\nAfter.\n", table);
    std::fclose(f);
    pinmap_row rows[64];
    char err[256];
    int n = pinmap_parse(path, rows, 64, err, sizeof err);
    std::remove(path);
    if (n < 0) return -100;
    return pinmap_check(rows, static_cast<size_t>(n), pins, np, stdout);
  };
  const char *good = "| PA8 | AF | 13 | HRTIM_CHA1 | - |\n| PA9 | Output | - | LED | - |\n"
                     "| PC13 | Input | - | BUTTON | - |\n| PB0 | Analog | - | VDC_HI | 1/100 |\n";
  EXPECT_EQ(check(good), 0);
  EXPECT_EQ(check("| PA8 | AF | 6 | HRTIM_CHA1 | - |\n| PA9 | Output | - | LED | - |\n| PC13 | Input | - | B | - |\n"), 1);
  EXPECT_EQ(check("| PA8 | AF | 13 | HRTIM_CHA1 | - |\n| PC13 | Input | - | B | - |\n"), 1) << "PA9 missing";
  EXPECT_EQ(check("| PA8 | AF | 13 | X | - |\n| PA9 | Output | - | L | - |\n| PC13 | Input | - | B | - |\n| PB1 | Output | - | Y | - |\n"), 1)
      << "PB1 in the table but never configured";
  EXPECT_EQ(check("| PA8 | Alt | 13 | X | - |\n"), -100) << "bad mode must not parse";
  board_close(b);
}

// The twin's power cut (board_flash_power_cut) during a double-word program, torn: after the
// power-on the half-programmed double word reads with a broken ECC: FLASH_ECCR.ECCD, BK_ECC =
// bank 2, ADDR_ECC = its bank-relative address, and the NMI; a page erase repairs it. A clean
// cut leaves the double word erased and raises nothing.
TEST(twin, power_cut_torn_program_gives_ecc_double_error_and_nmi) {
  for (int torn = 0; torn < 2; torn++) {
    board_config cfg;
    board_config_default(&cfg);
    std::string path = image("ecc");
    cfg.elf_path = path.c_str();
    char err[512];
    board *b = board_open(&cfg, err, sizeof err);
    ASSERT_NE(b, nullptr) << err;
    board_flash_power_cut(b, 1, torn);
    ASSERT_EQ(board_run(b, 1.0), BOARD_POWER_OFF) << board_message(b);
    EXPECT_EQ(board_flash_ops(b), 1u);
    board_flash_power_cut(b, 0, 0);
    board_power_on(b);
    ASSERT_EQ(board_run(b, 1.0), BOARD_EXITED) << board_message(b);
    uint32_t r[8];
    for (uint32_t i = 0; i < 8; i++) board_read_symbol(b, "tb_result", 4 * i, &r[i]);
    if (torn) {
      EXPECT_GE(r[0], 1u) << "NMI on the read of the torn double word";
      EXPECT_EQ(r[1], (1u << 31) | (1u << 21) | 0x3F828u) << "ECCD, BK_ECC = bank 2, ADDR_ECC 0x3F828";
      EXPECT_TRUE((r[2] & 0x12345678u) == 0x12345678u && (r[3] & 0x9ABCDEF0u) == 0x9ABCDEF0u)
          << "programming only clears bits: the target's ones are ones";
      EXPECT_TRUE((r[2] != 0xFFFFFFFFu || r[3] != 0xFFFFFFFFu) && (r[2] != 0x12345678u || r[3] != 0x9ABCDEF0u))
          << "half programmed: neither erased nor the target";
      EXPECT_GE(board_flash_ecc_errors(b), 1u);
      EXPECT_EQ(r[6], 0xFFFFFFFFu) << "erased";
      EXPECT_EQ(r[7], 0u) << "no NMI after the erase";
    } else {
      EXPECT_EQ(r[0], 0u) << "a clean cut: the program never happened";
      EXPECT_EQ(r[2], 0xFFFFFFFFu);
      EXPECT_EQ(r[3], 0xFFFFFFFFu);
      EXPECT_EQ(r[5], 0x12345678u) << "programmed on the next boot";
      EXPECT_EQ(board_flash_ecc_errors(b), 0u);
    }
    EXPECT_EQ(r[4] & (1u << 31), 0u) << "ECCD cleared by writing 1";
    board_close(b);
  }
}
