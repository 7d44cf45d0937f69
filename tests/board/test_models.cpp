// HRTIM and ADC models of the twin (host_sim/board/src/hrtim.c, adc.c) driven directly through
// their register interface: the dead-time waveform against closed-form edge times, and the
// refusals RM0440 calls for (locked registers, modes the model does not support).
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <string>

extern "C" {
#include "board_priv.h"
}

namespace {

constexpr uint32_t TIM(int t) { return 0x80u + 0x80u * (uint32_t)t; }
constexpr uint32_t COMMON = 0x380u;

struct Board : ::testing::Test {
  board *b = nullptr;
  void SetUp() override {
    board_config cfg;
    board_config_default(&cfg);
    cfg.elf_path = DTC_SOURCE_DIR "/build/stm32g4/dtc-fw.elf";
    char err[256];
    b = board_open(&cfg, err, sizeof err);
    if (!b) GTEST_SKIP() << "no image: " << err;
  }
  void TearDown() override { board_close(b); }
  std::string msg() const { return board_message(b); }
  bool faulted() const { return b->fault; }
  // master + A-F: prescaler 5 (fCOUNTER = fHRTIM), continuous, period `per`
  void timers(uint32_t per) {
    hrtim_write(b, 0x00, 5u | 8u);
    hrtim_write(b, 0x14, per);
    for (int t = 0; t < 6; t++) {
      hrtim_write(b, TIM(t) + 0x00, 5u | 8u);
      hrtim_write(b, TIM(t) + 0x14, per);
    }
  }
};

TEST_F(Board, DeadTimeWaveformMatchesClosedForm) {
  const double f = rcc_hclk_hz(b);  // fHRTIM after reset: HSI16
  ASSERT_EQ(f, 16e6);
  timers(1000);
  // timer A output 1: set at CMP1 = 300, reset at CMP2 = 700; dead time DTPRSC 3 -> tDTG = tHRTIM,
  // rising 16 x 62.5 ns = 1 us, falling 24 x 62.5 ns = 1.5 us
  hrtim_write(b, TIM(0) + 0x1C, 300);
  hrtim_write(b, TIM(0) + 0x24, 700);
  hrtim_write(b, TIM(0) + 0x3C, 1u << 3);
  hrtim_write(b, TIM(0) + 0x40, 1u << 4);
  hrtim_write(b, TIM(0) + 0x38, 16u | (3u << 10) | (24u << 16));
  hrtim_write(b, TIM(0) + 0x64, 1u << 8);
  hrtim_write(b, COMMON + 0x14, 3u);                  // OENR TA1, TA2
  const double t0 = board_now(b);
  hrtim_write(b, 0x00, 5u | 8u | (0x7Fu << 16));      // start master and A-F together
  ASSERT_FALSE(faulted()) << msg();
  const double tc = 1.0 / f, rise = 1e-6, fall = 1.5e-6;
  struct { double t; unsigned lv; } expect[] = {
    {t0 + 0.5e-6, 0u},                 // both off: output 2's rising dead time (falling: 1.5 us)
    {t0 + fall + 0.1e-6, 2u},          // output 2 on
    {t0 + 300 * tc + 0.1e-6, 0u},      // reference rose: output 2 off at once
    {t0 + 300 * tc + rise - 0.01e-6, 0u},
    {t0 + 300 * tc + rise + 0.01e-6, 1u},  // output 1 on after the rising dead time
    {t0 + 700 * tc + 0.01e-6, 0u},     // reference fell: output 1 off at once
    {t0 + 700 * tc + fall - 0.01e-6, 0u},
    {t0 + 700 * tc + fall + 0.01e-6, 2u},
  };
  for (const auto &e : expect) EXPECT_EQ(hrtim_levels(b, e.t) & 3u, e.lv) << "at " << (e.t - t0) * 1e6 << " us";
  EXPECT_DOUBLE_EQ(hrtim_next_edge(b, t0 + 300 * tc + 0.1e-6), t0 + 300 * tc + rise);
  // ODISR: both outputs to their idle (inactive) level at once
  hrtim_write(b, COMMON + 0x18, 3u);
  EXPECT_EQ(hrtim_levels(b, t0 + 300 * tc + rise + 0.01e-6) & 3u, 0u);
}

TEST_F(Board, PulseShorterThanTheDeadTimeDisappears) {
  timers(1000);
  hrtim_write(b, TIM(0) + 0x1C, 300);
  hrtim_write(b, TIM(0) + 0x24, 310);                 // 10 counts = 625 ns < 1 us
  hrtim_write(b, TIM(0) + 0x3C, 1u << 3);
  hrtim_write(b, TIM(0) + 0x40, 1u << 4);
  hrtim_write(b, TIM(0) + 0x38, 16u | (3u << 10) | (16u << 16));
  hrtim_write(b, TIM(0) + 0x64, 1u << 8);
  hrtim_write(b, COMMON + 0x14, 3u);
  const double t0 = board_now(b), tc = 1.0 / rcc_hclk_hz(b);
  hrtim_write(b, 0x00, 5u | 8u | (0x7Fu << 16));
  for (double t = 300 * tc; t < 320 * tc + 1e-6; t += 50e-9) EXPECT_EQ(hrtim_levels(b, t0 + t) & 1u, 0u);
}

// The master's flags at a period end with the port's preload scheme (PREEN, MREPU: an update at
// every repetition event), RM0440 HRTIM_MISR: the repetition MREP (bit 4) and the update MUPD
// (bit 6), never the sync input's SYNC (bit 5), which nothing drives; MICR clears them.
TEST_F(Board, MasterPeriodEndSetsRepetitionAndUpdateFlags) {
  timers(1000);
  hrtim_write(b, 0x00, 5u | 8u | (1u << 27) | (1u << 29));
  const double t0 = board_now(b), per = 1000.0 / rcc_hclk_hz(b);
  hrtim_write(b, 0x00, 5u | 8u | (1u << 27) | (1u << 29) | (0x7Fu << 16));
  ASSERT_FALSE(faulted()) << msg();
  hrtim_write(b, 0x08, 0x7Fu);  // MICR: the start's own flags cleared
  EXPECT_EQ(hrtim_read(b, 0x04) & 0x7Fu, 0u);
  b->cycles = (uint64_t)std::llround((t0 + 1.5 * per) * board_core_hz(b));  // into the second period
  hrtim_event(b);
  EXPECT_EQ(hrtim_read(b, 0x04) & 0x70u, (1u << 4) | (1u << 6)) << "MREP and MUPD, not SYNC";
  hrtim_write(b, 0x08, (1u << 4) | (1u << 6));
  EXPECT_EQ(hrtim_read(b, 0x04) & 0x70u, 0u);
}

// External event 6 (the fault line's second input, PB5) as a reset of output 1, through its digital
// filter EE6F = 1100 (N = 8 samples at fEEVS / 16, fEEVS = fHRTIM) and 3 tHRTIM of resynchronisation
// (RM0440 HRTIM_EECR2/3, §27.3.7): output 1 falls at the 8th sample of the low level, stays reset
// through the next period's set event while the line is low (a reset request beats a set), stays
// reset after the line is released until the next set event, and a low pulse of fewer than 8
// samples changes nothing. Output 2 (complement) follows with its dead time. The software set (SST)
// loses against the held reset too, and sets output 1 at once after the event.
TEST_F(Board, ExternalEvent6ResetsOutput1AfterItsFilter) {
  const double f = rcc_hclk_hz(b), tc = 1.0 / f, ts = 16 * tc, sync = 3 * tc;  // 16 MHz: ts = 1 us
  auto advance_to = [&](double t) {  // through every HRTIM event on the way, each at its instant
    if (t < board_now(b) - 1e-12) ADD_FAILURE() << "the test went back in time";
    for (;;) {
      double n = hrtim_next_event(b);
      if (!(n <= t)) break;
      b->cycles = (uint64_t)std::llround(n * board_core_hz(b));
      hrtim_event(b);
    }
    b->cycles = (uint64_t)std::llround(t * board_core_hz(b));
    hrtim_event(b);
  };
  auto off_instant = [&](double t_edge) { return std::ceil(t_edge / ts - 1e-6) * ts + 7 * ts + sync; };
  gpio_write(b, 1, 0x0C, 1u << 10, 3u << 10);    // GPIOB PUPDR: PB5 pull-up
  gpio_write(b, 1, 0x20, 13u << 20, 15u << 20);  // AFRL: PB5 AF13 (HRTIM_EEV6)
  gpio_write(b, 1, 0x00, 2u << 10, 3u << 10);    // MODER: PB5 alternate function
  hrtim_write(b, COMMON + 0x34, 1u << 2);        // EECR2: EE6SRC pin, EE6POL active low, EE6SNS level
  hrtim_write(b, COMMON + 0x38, 12u);            // EECR3: EE6F = 1100, EEVSD = 0
  timers(1000);                                   // 62.5 us periods
  hrtim_write(b, TIM(0) + 0x1C, 100);
  hrtim_write(b, TIM(0) + 0x24, 900);
  hrtim_write(b, TIM(0) + 0x3C, 1u << 3);              // set at CMP1
  hrtim_write(b, TIM(0) + 0x40, (1u << 4) | (1u << 26));  // reset at CMP2 and on external event 6
  hrtim_write(b, TIM(0) + 0x38, 16u | (3u << 10) | (16u << 16));  // 1 us dead times
  hrtim_write(b, TIM(0) + 0x64, 1u << 8);
  hrtim_write(b, COMMON + 0x14, 3u);
  const double t0 = board_now(b), per = 1000 * tc;
  hrtim_write(b, 0x00, 5u | 8u | (0x7Fu << 16));
  ASSERT_FALSE(faulted()) << msg();
  advance_to(t0 + 20e-6);
  ASSERT_EQ(hrtim_levels(b, board_now(b)) & 3u, 1u) << "output 1 on after CMP1";
  const double t_line = board_now(b) + 0.3e-6;  // between two samples
  advance_to(t_line);
  board_drive_pin(b, 'B', 5, 0);
  const double t_off = off_instant(t_line);
  advance_to(t_off + 0.1 * tc);
  ASSERT_FALSE(faulted()) << msg();
  EXPECT_EQ(hrtim_levels(b, t_off - 0.5 * tc) & 1u, 1u) << "still on just before the 8th sample";
  EXPECT_EQ(hrtim_levels(b, t_off + 0.5 * tc) & 1u, 0u) << "reset at the 8th sample + 3 tHRTIM";
  EXPECT_NEAR(t_off - t_line, 7.7e-6 + sync, 1e-9) << "0.7 us to the next sample, then 7 more";
  advance_to(t_off + 1e-6 + 0.5 * tc);
  EXPECT_EQ(hrtim_levels(b, board_now(b)) & 3u, 2u) << "output 2 on after its dead time";
  // the next period's CMP1 set meets the reset request: output 1 stays off
  advance_to(t0 + per + 100 * tc + 2e-6);
  EXPECT_EQ(hrtim_levels(b, board_now(b)) & 1u, 0u) << "the set event lost against the held reset";
  hrtim_write(b, TIM(0) + 0x3C, (1u << 3) | 1u);  // SST while the reset is held: loses too
  advance_to(board_now(b) + 2e-6);
  EXPECT_EQ(hrtim_levels(b, board_now(b)) & 1u, 0u) << "a software set loses against the held reset";
  EXPECT_EQ(hrtim_read(b, TIM(0) + 0x3C), 1u << 3) << "SST reads 0, the programme is unchanged";
  // released: off until the following set event, then on after the rising dead time
  advance_to(t0 + per + 20e-6);
  board_drive_pin(b, 'B', 5, 1);
  advance_to(t0 + per + 35e-6);
  EXPECT_EQ(hrtim_levels(b, board_now(b)) & 1u, 0u) << "released, but no set event yet";
  advance_to(t0 + per + 40e-6);
  const double t_sst = board_now(b);
  hrtim_write(b, TIM(0) + 0x3C, (1u << 3) | 1u);  // SST (what hal_gate_enable does before OENR)
  advance_to(t_sst + 1e-6 + tc);
  EXPECT_EQ(hrtim_levels(b, t_sst + 0.5 * tc) & 3u, 0u) << "output 2 off at once, output 1 in its dead time";
  EXPECT_EQ(hrtim_levels(b, board_now(b)) & 3u, 1u) << "output 1 on 1 us after the software set";
  advance_to(t0 + 2 * per);
  EXPECT_EQ(hrtim_levels(b, board_now(b)) & 1u, 0u) << "reset by CMP2 as programmed";
  advance_to(t0 + 2 * per + 100 * tc + 1e-6 + tc);
  EXPECT_EQ(hrtim_levels(b, board_now(b)) & 1u, 1u) << "set again by CMP1 (+ 1 us dead time)";
  // a low pulse of 5 samples: filtered out
  advance_to(t0 + 2 * per + 20e-6);
  board_drive_pin(b, 'B', 5, 0);
  advance_to(t0 + 2 * per + 25e-6);
  board_drive_pin(b, 'B', 5, 1);
  for (double t = board_now(b); t < t0 + 2 * per + 40e-6; t += 0.25e-6) {  // it would act from 27 us on
    advance_to(t);
    ASSERT_EQ(hrtim_levels(b, t) & 1u, 1u) << "a 5 us pulse does not pass the 8 us filter, at " << (t - t0) * 1e6;
  }
  ASSERT_FALSE(faulted()) << msg();
}

TEST_F(Board, ExternalEventConfigurationsNotOnThisBoardAreRefused) {
  hrtim_write(b, COMMON + 0x34, 1u << 9);  // EE7POL: event 7 has no pin on this board
  EXPECT_NE(msg().find("external event 7 is not wired"), std::string::npos) << msg();
}

TEST_F(Board, ExternalEvent6EdgeSensitivityIsRefused) {
  hrtim_write(b, COMMON + 0x34, (1u << 2) | (2u << 3));  // EE6SNS = falling edge
  EXPECT_NE(msg().find("EE6SNS 2: edge sensitivity not modelled"), std::string::npos) << msg();
}

TEST_F(Board, ExternalEventAsSetSourceIsRefused) {
  hrtim_write(b, TIM(1) + 0x3C, 1u << 26);  // SETB1R.EXTEVNT6
  EXPECT_NE(msg().find("event sources 0x04000000 not modelled"), std::string::npos) << msg();
}

TEST_F(Board, ExternalEvent7ResetIsRefused) {
  hrtim_write(b, TIM(1) + 0x40, 1u << 27);  // RSTB1R.EXTEVNT7
  EXPECT_NE(msg().find("event sources 0x08000000 not modelled"), std::string::npos) << msg();
}

TEST_F(Board, ExternalEventConfigurationWhileCountingIsRefused) {
  timers(1000);
  hrtim_write(b, 0x00, 5u | 8u | (0x7Fu << 16));
  hrtim_write(b, COMMON + 0x38, 12u);
  EXPECT_NE(msg().find("HRTIM_EECR3 written while the counters run"), std::string::npos) << msg();
}

TEST_F(Board, DelayedProtectionIsRefused) {
  hrtim_write(b, TIM(0) + 0x64, (1u << 8) | (1u << 9));  // OUTAR DLYPRTEN: not the board's mechanism
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("HRTIM_OUTAR"), std::string::npos) << msg();
}

TEST_F(Board, LockedDeadTimeIsRefused) {
  hrtim_write(b, TIM(1) + 0x38, 16u | (3u << 10) | (1u << 15) | (16u << 16));  // DTRLK
  ASSERT_FALSE(faulted()) << msg();
  hrtim_write(b, TIM(1) + 0x38, 20u | (3u << 10) | (1u << 15) | (16u << 16));
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("HRTIM_DTBR written while locked"), std::string::npos) << msg();
}

TEST_F(Board, DeadTimeFinerThanTHrtimNeedsTheDll) {
  hrtim_write(b, TIM(2) + 0x38, 16u | (2u << 10) | (16u << 16));
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("DTPRSC 2"), std::string::npos) << msg();
}

TEST_F(Board, LockedFaultConfigurationIsRefused) {
  hrtim_write(b, TIM(3) + 0x68, (1u << 2) | (1u << 31));
  ASSERT_FALSE(faulted()) << msg();
  hrtim_write(b, TIM(3) + 0x68, 0u);
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("FLTLCK"), std::string::npos) << msg();
}

TEST_F(Board, FaultPolarityChangeWhileEnabledIsRefused) {
  hrtim_write(b, COMMON + 0x50, 1u << 16);                 // FLT3E
  ASSERT_FALSE(faulted()) << msg();
  hrtim_write(b, COMMON + 0x50, (1u << 16) | (1u << 17));  // FLT3P with FLT3E = 1
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("while FLT3E = 1"), std::string::npos) << msg();
}

TEST_F(Board, OutputConfigurationWithOutputsEnabledIsRefused) {
  hrtim_write(b, COMMON + 0x14, 1u);
  hrtim_write(b, TIM(0) + 0x64, 1u << 8);
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("HRTIM_OUTAR written while"), std::string::npos) << msg();
}

TEST_F(Board, AdcCalibrationBeforeTheRegulatorSettledIsRefused) {
  adc_write(b, 0x08, 0u);          // DEEPPWD = 0
  adc_write(b, 0x08, 1u << 28);    // ADVREGEN
  adc_write(b, 0x08, (1u << 28) | (1u << 31));  // ADCAL at once: < tADCVREG_STUP
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("tADCVREG_STUP"), std::string::npos) << msg();
}

TEST_F(Board, AdcRegularConversionsAndDualModesNotModelledAreRefused) {
  adc_write(b, 0x308, (3u << 16) | 6u);  // DUAL = 6 (regular simultaneous)
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("DUAL 6"), std::string::npos) << msg();
}

// The logic analyser must see what the port's planner never does: a direct P<->N step (both pairs
// of leg a commutating at once) and a pair overlap (leg b, timer C without dead time).
TEST_F(Board, LogicAnalyserCountsPnStepsAndOverlaps) {
  plant_config pc;
  plant_default_config(&pc);
  ASSERT_EQ(board_attach_plant(b, &pc), 0);
  timers(1000);
  const uint32_t dt = 16u | (3u << 10) | (16u << 16);
  // leg a: S1 (A output 2, the complement of S3 = A output 1) and S2 (B output 1) turn on together
  // at CMP1 and off together at CMP2; A output 1 is set at CMP3 = 3 so the leg starts in N
  for (int t = 0; t < 2; t++) {
    hrtim_write(b, TIM(t) + 0x1C, 300);
    hrtim_write(b, TIM(t) + 0x24, 700);
    hrtim_write(b, TIM(t) + 0x28, 3);
    hrtim_write(b, TIM(t) + 0x3C, t == 0 ? (1u << 5) | (1u << 4) : 1u << 3);
    hrtim_write(b, TIM(t) + 0x40, t == 0 ? 1u << 3 : 1u << 4);
    hrtim_write(b, TIM(t) + 0x38, dt);
    hrtim_write(b, TIM(t) + 0x64, 1u << 8);
  }
  // leg b: timer C without dead time, outputs 1 and 2 both set at CMP1 = S1 and S3 together
  hrtim_write(b, TIM(2) + 0x1C, 300);
  hrtim_write(b, TIM(2) + 0x24, 700);
  hrtim_write(b, TIM(2) + 0x3C, 1u << 3);
  hrtim_write(b, TIM(2) + 0x40, 1u << 4);
  hrtim_write(b, TIM(2) + 0x44, 1u << 3);
  hrtim_write(b, TIM(2) + 0x48, 1u << 4);
  hrtim_write(b, COMMON + 0x14, 0x3Fu);  // A, B, C outputs
  const double t0 = board_now(b), tc = 1.0 / rcc_hclk_hz(b);
  hrtim_write(b, 0x00, 5u | 8u | (0x7Fu << 16));
  ASSERT_FALSE(faulted()) << msg();
  twin_sync(b, t0 + 900 * tc);
  board_la_stats la;
  board_la_get(b, &la);
  EXPECT_EQ(la.pn_steps, 2u);  // N -> P at CMP1, P -> N at CMP2
  EXPECT_GE(la.overlaps, 1u);
  EXPECT_NEAR(la.min_dead_time_s, 1e-6, 1e-12);  // leg a's pairs still have their dead time
}

// ADC1 + ADC2 in dual injected mode converting the plant's sensors at standstill: currents at
// mid-scale (1.65 V), capacitors at vdc/2 = 155.5 V through 151.5 V/V, against the closed form.
TEST_F(Board, DualInjectedConversionOfThePlantSensors) {
  plant_config pc;
  plant_default_config(&pc);
  ASSERT_EQ(board_attach_plant(b, &pc), 0);
  auto advance = [&](double s) {
    b->cycles += (uint64_t)std::ceil(s * board_core_hz(b));
    adc_event(b);
  };
  adc_write(b, 0x308, (3u << 16) | 5u);  // CKMODE HCLK/4, DUAL injected simultaneous
  for (uint32_t base : {0x000u, 0x100u}) {
    adc_write(b, base + 0x08, 0u);
    adc_write(b, base + 0x08, 1u << 28);
  }
  advance(25e-6);
  for (uint32_t base : {0x000u, 0x100u}) adc_write(b, base + 0x08, (1u << 28) | (1u << 31));
  advance(40e-6);
  for (uint32_t base : {0x000u, 0x100u}) {
    EXPECT_EQ(adc_read(b, base + 0x08) & (1u << 31), 0u) << "calibration done";
    adc_write(b, base + 0x08, (1u << 28) | 1u);
  }
  advance(2e-6);
  adc_write(b, 0x000 + 0x4C, 2u | (19u << 2) | (1u << 7) | (1u << 9) | (12u << 15) | (6u << 21));
  adc_write(b, 0x100 + 0x4C, 2u | (2u << 9) | (7u << 15) | (7u << 21));
  adc_write(b, 0x000 + 0x04, 1u << 6);                       // JEOSIE
  adc_write(b, 0x000 + 0x08, (1u << 28) | 1u | (1u << 3));  // JADSTART on the master
  ASSERT_FALSE(faulted()) << msg();
  adc_hrtim_trigger(b, 2, board_now(b));
  advance(10e-6);
  EXPECT_EQ(adc_read(b, 0x000) & (1u << 6), 0u) << "JEOS only after three ranks";
  advance(30e-6);
  ASSERT_FALSE(faulted()) << msg();
  EXPECT_NE(adc_read(b, 0x000) & (1u << 6), 0u);
  EXPECT_TRUE(b->scs.pending[16 + 18]) << "ADC1_2 interrupt pending";
  // the plant's sensor model quantises first (its 12-bit, 0..500 V), the pin then carries v x 3.3 / 500
  const double v_plant = (double)std::lround(155.5 / 500.0 * 4095.0) * 500.0 / 4095.0;
  const uint32_t v_code = (uint32_t)std::floor(v_plant * 3.3 / 500.0 / 3.3 * 4096.0);
  EXPECT_EQ(adc_read(b, 0x080), 2048u);    // ADC1 JDR1 ia
  EXPECT_EQ(adc_read(b, 0x084), 2048u);    // ADC1 JDR2 ic
  EXPECT_EQ(adc_read(b, 0x088), v_code);   // ADC1 JDR3 vc1
  EXPECT_EQ(adc_read(b, 0x180), 2048u);    // ADC2 JDR1 ib
  EXPECT_EQ(adc_read(b, 0x184), v_code);   // ADC2 JDR2 vc2
}

// Power up, calibrate and enable the ADCs at these offsets (from 0x50000000), synchronous HCLK/4
// clock on both groups; `dual` puts ADC1/ADC2 in injected simultaneous mode.
static void adc_power_up(board *b, std::initializer_list<uint32_t> bases, bool dual) {
  auto advance = [&](double s) {
    b->cycles += (uint64_t)std::ceil(s * board_core_hz(b));
    adc_event(b);
  };
  adc_write(b, 0x308, (3u << 16) | (dual ? 5u : 0u));
  adc_write(b, 0x708, 3u << 16);
  for (uint32_t base : bases) {
    adc_write(b, base + 0x08, 0u);
    adc_write(b, base + 0x08, 1u << 28);
  }
  advance(25e-6);
  for (uint32_t base : bases) adc_write(b, base + 0x08, (1u << 28) | (1u << 31));
  advance(40e-6);
  for (uint32_t base : bases) adc_write(b, base + 0x08, (1u << 28) | 1u);
  advance(2e-6);
}

// The board's scheme (docs/board.md, "Sampling"): ADC1/ADC2 dual injected [ia, vc1] / [ib, vc2] and
// ADC3 [ic], all on HRTIM ADC trigger 2 (JEXTSEL 19 in both groups' tables). The three currents are
// sampled at the same instant, 24.5 ADC clocks after the trigger (the fixture runs on HSI16: HCLK/4
// = 4 MHz; 576 ns at 42.5 MHz on the board); ADC3's
// one rank ends before ADC1's two; every code against the closed form at standstill.
TEST_F(Board, Adc3SamplesIcAtTheInstantOfIaAndIb) {
  plant_config pc;
  plant_default_config(&pc);
  ASSERT_EQ(board_attach_plant(b, &pc), 0);
  adc_power_up(b, {0x000u, 0x100u, 0x400u}, true);
  for (uint32_t base : {0x000u, 0x100u, 0x400u}) adc_write(b, base + 0x14, 03333333333u);  // SMP = 3: 24.5 cycles, ch 0-9
  adc_write(b, 0x000 + 0x4C, 1u | (19u << 2) | (1u << 7) | (1u << 9) | (6u << 15));
  adc_write(b, 0x100 + 0x4C, 1u | (2u << 9) | (7u << 15));
  adc_write(b, 0x400 + 0x4C, 0u | (19u << 2) | (1u << 7) | (1u << 9));
  adc_write(b, 0x400 + 0x08, (1u << 28) | 1u | (1u << 3));  // ADC3 JADSTART
  adc_write(b, 0x000 + 0x08, (1u << 28) | 1u | (1u << 3));  // ADC1 JADSTART (starts both of the pair)
  ASSERT_FALSE(faulted()) << msg();
  const double t_adc = 4.0 / rcc_hclk_hz(b), t0 = board_now(b);
  adc_hrtim_trigger(b, 2, t0);
  b->cycles += (uint64_t)std::ceil(40 * t_adc * board_core_hz(b));  // one rank (24.5 + 12.5 clocks) + a bit
  adc_event(b);
  EXPECT_NE(adc_read(b, 0x400) & (1u << 6), 0u) << "ADC3 JEOS after its one rank";
  EXPECT_EQ(adc_read(b, 0x000) & (1u << 6), 0u) << "ADC1 JEOS only after its second rank";
  b->cycles += (uint64_t)std::ceil(40 * t_adc * board_core_hz(b));
  adc_event(b);
  ASSERT_FALSE(faulted()) << msg();
  EXPECT_NE(adc_read(b, 0x000) & (1u << 6), 0u);
  board_current_sampling cs;
  board_current_sampling_get(b, &cs);
  EXPECT_EQ(cs.triples, 1u);
  EXPECT_LE(cs.max_skew_s, t_adc);
  for (int k = 0; k < 3; k++) EXPECT_NEAR(cs.after_trigger_s[k], 24.5 * t_adc, 1e-12) << "current " << k;
  const double v_plant = (double)std::lround(155.5 / 500.0 * 4095.0) * 500.0 / 4095.0;
  const uint32_t v_code = (uint32_t)std::floor(v_plant * 3.3 / 500.0 / 3.3 * 4096.0);
  EXPECT_EQ(adc_read(b, 0x080), 2048u);   // ADC1 JDR1 ia
  EXPECT_EQ(adc_read(b, 0x180), 2048u);   // ADC2 JDR1 ib
  EXPECT_EQ(adc_read(b, 0x480), 2048u);   // ADC3 JDR1 ic
  EXPECT_EQ(adc_read(b, 0x084), v_code);  // ADC1 JDR2 vc1
  EXPECT_EQ(adc_read(b, 0x184), v_code);  // ADC2 JDR2 vc2
}

// JEXTSEL 27 is HRTIM ADC trigger 1 for ADC3 (ADC3/4/5 table): trigger 2 does not start it, trigger 1
// does. For ADC1/2, 27 is a timer event (TIM16 CC1 in their table), not modelled: refused.
TEST_F(Board, Adc3ConvertsOnlyOnTheTriggerItsTableSelects) {
  adc_power_up(b, {0x000u, 0x400u}, false);
  adc_write(b, 0x400 + 0x4C, (27u << 2) | (1u << 7) | (1u << 9));
  adc_write(b, 0x400 + 0x08, (1u << 28) | 1u | (1u << 3));
  ASSERT_FALSE(faulted()) << msg();
  const double rank_s = 40 * 4.0 / rcc_hclk_hz(b);  // one rank of 37 ADC clocks (HCLK/4) + a bit
  adc_hrtim_trigger(b, 2, board_now(b));
  b->cycles += (uint64_t)std::ceil(rank_s * board_core_hz(b));
  adc_event(b);
  EXPECT_EQ(adc_read(b, 0x400) & (1u << 6), 0u) << "no conversion on another trigger";
  adc_hrtim_trigger(b, 1, board_now(b));
  b->cycles += (uint64_t)std::ceil(rank_s * board_core_hz(b));
  adc_event(b);
  EXPECT_NE(adc_read(b, 0x400) & (1u << 6), 0u) << "HRTIM ADC trigger 1 converts";
  ASSERT_FALSE(faulted()) << msg();
  adc_write(b, 0x000 + 0x4C, (27u << 2) | (1u << 7) | (1u << 9));
  adc_write(b, 0x000 + 0x08, (1u << 28) | 1u | (1u << 3));
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("JEXTSEL 27: not an HRTIM ADC trigger in ADC1/2"), std::string::npos) << msg();
}

TEST_F(Board, Adc3JadstartWithoutAdenIsRefused) {
  adc_write(b, 0x708, 3u << 16);
  adc_write(b, 0x400 + 0x4C, (19u << 2) | (1u << 7) | (1u << 9));
  adc_write(b, 0x400 + 0x08, 1u << 3);
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("ADC3_CR: JADSTART while not enabled"), std::string::npos) << msg();
}

TEST_F(Board, Adc345DualModeAndAdc4AreRefused) {
  adc_write(b, 0x708, (3u << 16) | 5u);
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("ADC345_CCR DUAL 5"), std::string::npos) << msg();
}

TEST_F(Board, Adc4IsNotModelled) {
  adc_write(b, 0x500 + 0x08, 0u);
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("ADC4 is not modelled"), std::string::npos) << msg();
}

TEST_F(Board, Adc3ChannelOnAPinNotInAnalogModeIsRefused) {
  adc_power_up(b, {0x400u}, false);
  gpio_write(b, 1, 0x00, 0xFFFFFFF3u, 0xFFFFFFFFu);  // GPIOB MODER: PB1 input
  adc_write(b, 0x400 + 0x4C, (19u << 2) | (1u << 7) | (1u << 9));
  adc_write(b, 0x400 + 0x08, (1u << 28) | 1u | (1u << 3));
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("ADC3 channel 1: pin PB1 is not in analog mode"), std::string::npos) << msg();
}

TEST_F(Board, AdcChannelNotWiredIsRefused) {
  adc_write(b, 0x308, 3u << 16);
  adc_write(b, 0x08, 0u);
  adc_write(b, 0x08, 1u << 28);
  b->cycles += (uint64_t)(25e-6 * board_core_hz(b));
  adc_write(b, 0x08, (1u << 28) | (1u << 31));
  b->cycles += (uint64_t)(40e-6 * board_core_hz(b));
  adc_event(b);
  adc_write(b, 0x08, (1u << 28) | 1u);
  b->cycles += (uint64_t)(2e-6 * board_core_hz(b));
  adc_event(b);
  adc_write(b, 0x4C, (3u << 9));  // software trigger, channel 3: not wired on this board
  adc_write(b, 0x08, (1u << 28) | 1u | (1u << 3));
  EXPECT_TRUE(faulted());
  EXPECT_NE(msg().find("channel 3 is not wired"), std::string::npos) << msg();
}

}  // namespace
