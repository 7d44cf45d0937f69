// The host HAL binding: the contract of hal/include/hal/hal.h on a simulated
// board (sample once per tick, actuation checks, gates and fault input,
// simulated milliseconds, NVM with power loss and file mirror, CAN backends).
#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include <time.h>

#include "hal_host/hal_host.h"
#include "temp_files.hpp"

namespace {

// A bound board for one test, unbound afterwards.
class Board : public ::testing::Test {
protected:
    void SetUp() override
    {
        b = std::make_unique<hal_host_board>();
        hal_host_board_init(b.get());
        hal_host_bind(b.get());
    }
    void TearDown() override { hal_host_bind(nullptr); }
    std::unique_ptr<hal_host_board> b;
};

void count_tick(void *ctx) { ++*static_cast<int *>(ctx); }

hal_can_frame frame(uint16_t id, uint8_t dlc, uint8_t first)
{
    hal_can_frame f;
    std::memset(&f, 0, sizeof f);
    f.id = id;
    f.dlc = dlc;
    for (int i = 0; i < 8; ++i)
        f.data[i] = (uint8_t)(first + i);
    return f;
}

} // namespace

TEST_F(Board, PowersUpSafe)
{
    EXPECT_FALSE(hal_gate_enabled());
    EXPECT_FALSE(hal_fault_input_active());
    EXPECT_EQ(hal_millis(), 0u);
    EXPECT_EQ(hal_nvm_size(), 4096u);
    uint8_t buf[16];
    ASSERT_EQ(hal_nvm_read(100, buf, sizeof buf), HAL_OK);
    for (uint8_t x : buf)
        EXPECT_EQ(x, 0xFF); // erased
    hal_actuation a;
    bool on = true;
    hal_host_take_actuation(b.get(), &a, &on);
    EXPECT_FALSE(on);
    for (int i = 0; i < 3; ++i)
        EXPECT_EQ(a.vector[0].leg[i], HAL_LEG_O);
}

TEST_F(Board, TickRunsOnlyWhenStartedAndChecksThePeriod)
{
    int ticks = 0;
    hal_host_run_tick(b.get());
    EXPECT_EQ(hal_tick_start(count_tick, &ticks, 49), HAL_EINVAL);
    EXPECT_EQ(hal_tick_start(count_tick, &ticks, 1001), HAL_EINVAL);
    EXPECT_EQ(ticks, 0);
    ASSERT_EQ(hal_tick_start(count_tick, &ticks, 200), HAL_OK);
    EXPECT_EQ(b->period_us, 200u);
    hal_host_run_tick(b.get());
    hal_host_run_tick(b.get());
    EXPECT_EQ(ticks, 2);
    hal_gate_enable(true);
    hal_tick_stop();
    EXPECT_FALSE(hal_gate_enabled()); // stopping disables the gates first
    hal_host_run_tick(b.get());
    EXPECT_EQ(ticks, 2);
}

TEST_F(Board, SampleCanBeReadOncePerTick)
{
    hal_sample s{};
    s.ia_A = 1.5f;
    s.vc1_V = 155.0f;
    s.seq = 7;
    hal_sample out{};
    EXPECT_EQ(hal_sample_read(&out), HAL_EAGAIN); // nothing yet
    hal_host_set_sample(b.get(), &s);
    ASSERT_EQ(hal_sample_read(&out), HAL_OK);
    EXPECT_EQ(out.seq, 7u);
    EXPECT_FLOAT_EQ(out.ia_A, 1.5f);
    EXPECT_EQ(hal_sample_read(&out), HAL_EAGAIN); // stale: refused
}

TEST_F(Board, ActuationIsCheckedAndLatched)
{
    hal_actuation a{};
    a.vector[0] = { { HAL_LEG_P, HAL_LEG_O, HAL_LEG_N } };
    a.vector[1] = { { HAL_LEG_O, HAL_LEG_O, HAL_LEG_O } };
    a.duty0 = 0.25f;
    ASSERT_EQ(hal_actuate(&a), HAL_OK);
    hal_actuation bad = a;
    bad.vector[1].leg[2] = 3;
    EXPECT_EQ(hal_actuate(&bad), HAL_EINVAL);
    bad = a;
    bad.duty0 = 1.5f;
    EXPECT_EQ(hal_actuate(&bad), HAL_EINVAL);
    bad.duty0 = std::nanf("");
    EXPECT_EQ(hal_actuate(&bad), HAL_EINVAL);
    bad.duty0 = -0.1f;
    EXPECT_EQ(hal_actuate(&bad), HAL_EINVAL);

    hal_actuation got;
    bool on = true;
    hal_host_take_actuation(b.get(), &got, &on);
    EXPECT_FALSE(on); // gates off: the zero vector, not the latched one
    EXPECT_EQ(got.vector[0].leg[0], HAL_LEG_O);
    hal_gate_enable(true);
    hal_host_take_actuation(b.get(), &got, &on);
    EXPECT_TRUE(on);
    EXPECT_EQ(got.vector[0].leg[0], HAL_LEG_P); // the refused ones kept the previous
    EXPECT_EQ(got.vector[0].leg[2], HAL_LEG_N);
    EXPECT_FLOAT_EQ(got.duty0, 0.25f);
}

TEST_F(Board, FaultInputKeepsGatesOff)
{
    b->fault_input = true;
    EXPECT_TRUE(hal_fault_input_active());
    hal_gate_enable(true);
    EXPECT_FALSE(hal_gate_enabled());
    b->fault_input = false;
    hal_gate_enable(true);
    EXPECT_TRUE(hal_gate_enabled());
    hal_gate_enable(false);
    EXPECT_FALSE(hal_gate_enabled());
}

TEST_F(Board, MillisFollowSimulatedTimeCyclesFollowTheHost)
{
    b->t_s = 0.0002 * 5; // tick 5
    EXPECT_EQ(hal_millis(), 1u);
    b->t_s = 0.0002 * 4999;
    EXPECT_EQ(hal_millis(), 999u);
    b->t_s = 0.0002 * 5000;
    EXPECT_EQ(hal_millis(), 1000u);
    b->t_s = 3600.0;
    EXPECT_EQ(hal_millis(), 3600000u);
    // The cycle counter measures host time at hal_cycles_hz(): the TSC on x86-64 (rate
    // calibrated once), CLOCK_MONOTONIC ns elsewhere. Judged against CLOCK_MONOTONIC read
    // around a 20 ms sleep: the counted interval lies inside the clock's, and is at least
    // the time slept (1 % allowed for the calibration).
    const double hz = hal_cycles_hz();
    EXPECT_GE(hz, 1e6);
    auto mono_s = [] {
        struct timespec t;
        clock_gettime(CLOCK_MONOTONIC, &t);
        return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
    };
    double m0 = mono_s();
    uint32_t c0 = hal_cycles();
    struct timespec ts = { 0, 20000000 };
    nanosleep(&ts, nullptr);
    uint32_t dc = hal_cycles() - c0; // modulo 2^32: right while the interval is under 2^32 / hz (> 0.9 s)
    double m1 = mono_s();
    EXPECT_GE((double)dc / hz, 0.020 * 0.99);
    EXPECT_LE((double)dc / hz, (m1 - m0) * 1.01 + 1e-5);
}

TEST_F(Board, WatchdogExpiresInSimulatedTime)
{
    EXPECT_EQ(hal_watchdog_start(0), HAL_EINVAL);
    EXPECT_EQ(hal_watchdog_start(4001), HAL_EINVAL);
    EXPECT_FALSE(hal_host_watchdog_expired(b.get()));
    ASSERT_EQ(hal_watchdog_start(100), HAL_OK);
    b->t_s = 0.099;
    EXPECT_FALSE(hal_host_watchdog_expired(b.get()));
    hal_watchdog_kick();
    b->t_s = 0.199;
    EXPECT_FALSE(hal_host_watchdog_expired(b.get()));
    b->t_s = 0.2;
    EXPECT_TRUE(hal_host_watchdog_expired(b.get()));
}

TEST_F(Board, NvmBoundsAndPowerLoss)
{
    uint8_t buf[8] = { 1, 2, 3, 4, 5, 6, 7, 8 };
    EXPECT_EQ(hal_nvm_write(4090, buf, 8), HAL_ENOSPC);
    EXPECT_EQ(hal_nvm_read(4097, buf, 0), HAL_ENOSPC);
    EXPECT_EQ(hal_nvm_read(0xFFFFFFFFu, buf, 2), HAL_ENOSPC);
    EXPECT_EQ(hal_nvm_write(4088, buf, 8), HAL_OK); // the last 8 bytes
    EXPECT_EQ(hal_nvm_read(4096, buf, 0), HAL_OK);

    // Power fails after 3 bytes: only the prefix lands, then nothing.
    b->nvm_write_budget = 3;
    uint8_t w[6] = { 0x10, 0x11, 0x12, 0x13, 0x14, 0x15 };
    EXPECT_EQ(hal_nvm_write(10, w, 6), HAL_EIO);
    uint8_t r[7];
    ASSERT_EQ(hal_nvm_read(10, r, 7), HAL_OK);
    const uint8_t expect[7] = { 0x10, 0x11, 0x12, 0xFF, 0xFF, 0xFF, 0xFF };
    EXPECT_EQ(std::memcmp(r, expect, 7), 0);
    EXPECT_EQ(hal_nvm_write(20, w, 1), HAL_EIO);
    ASSERT_EQ(hal_nvm_read(20, r, 1), HAL_OK);
    EXPECT_EQ(r[0], 0xFF);
}

TEST_F(Board, NvmMirrorFileSurvivesARestart)
{
    simtest::TempDir d;
    std::string path = d.file("nvm.bin");
    b->nvm_path = nullptr;
    EXPECT_EQ(hal_host_nvm_load(b.get(), path.c_str()), HAL_OK); // missing: erased
    b->nvm_path = path.c_str();
    const char msg[] = "persisted";
    ASSERT_EQ(hal_nvm_write(100, msg, sizeof msg), HAL_OK);
    std::string img = simtest::read_file(path);
    ASSERT_EQ(img.size(), 4096u);
    EXPECT_EQ(img.substr(100, sizeof msg - 1), "persisted");
    EXPECT_EQ((uint8_t)img[0], 0xFF);
    EXPECT_FALSE(simtest::file_exists(path + ".tmp"));

    // "Restart": a fresh board loads the file.
    hal_host_board fresh;
    hal_host_board_init(&fresh);
    ASSERT_EQ(hal_host_nvm_load(&fresh, path.c_str()), HAL_OK);
    EXPECT_EQ(std::memcmp(&fresh.nvm[100], msg, sizeof msg), 0);

    // A file of the wrong size is refused and neither it nor the memory changes.
    simtest::write_file(path, "short");
    EXPECT_EQ(hal_host_nvm_load(&fresh, path.c_str()), HAL_EIO);
    EXPECT_EQ(simtest::read_file(path), "short");
    EXPECT_EQ(std::memcmp(&fresh.nvm[100], msg, sizeof msg), 0);

    // An unwritable mirror is reported.
    b->nvm_path = "/nonexistent/dir/nvm.bin";
    EXPECT_EQ(hal_nvm_write(0, msg, 1), HAL_EIO);
}

TEST_F(Board, CanNeedsOpenAndChecksFrames)
{
    hal_can_frame f = frame(0x123, 8, 1);
    EXPECT_EQ(hal_can_send(&f), HAL_EIO); // not open
    EXPECT_EQ(hal_can_open(123456), HAL_EINVAL);
    ASSERT_EQ(hal_can_open(500000), HAL_OK);
    EXPECT_EQ(hal_can_send(&f), HAL_OK); // no backend: dropped
    hal_can_frame in;
    EXPECT_EQ(hal_can_recv(&in), HAL_EAGAIN);
    f.id = 0x800;
    EXPECT_EQ(hal_can_send(&f), HAL_EINVAL);
    f.id = 0x7FF;
    f.dlc = 9;
    EXPECT_EQ(hal_can_send(&f), HAL_EINVAL);
}

TEST_F(Board, LoopbackCarriesFramesBothWays)
{
    auto q = std::make_unique<hal_host_can_loopback>();
    hal_host_can_loopback_init(q.get(), &b->can);
    ASSERT_EQ(hal_can_open(1000000), HAL_OK);

    // Test -> drive, in order.
    for (int i = 0; i < 3; ++i) {
        hal_can_frame f = frame((uint16_t)(0x600 + i), 8, (uint8_t)(10 * i));
        ASSERT_EQ(hal_host_can_loopback_inject(q.get(), &f), HAL_OK);
    }
    hal_can_frame g;
    for (int i = 0; i < 3; ++i) {
        ASSERT_EQ(hal_can_recv(&g), HAL_OK);
        EXPECT_EQ(g.id, 0x600 + i);
        EXPECT_EQ(g.data[0], 10 * i);
    }
    EXPECT_EQ(hal_can_recv(&g), HAL_EAGAIN);

    // Drive -> test.
    hal_can_frame f = frame(0x581, 4, 0x43);
    ASSERT_EQ(hal_can_send(&f), HAL_OK);
    ASSERT_EQ(hal_host_can_loopback_take(q.get(), &g), HAL_OK);
    EXPECT_EQ(g.id, 0x581);
    EXPECT_EQ(g.dlc, 4);
    EXPECT_EQ(g.data[0], 0x43);
    EXPECT_EQ(hal_host_can_loopback_take(q.get(), &g), HAL_EAGAIN);

    // A full ring refuses (never blocks) and counts; wrap-around keeps order.
    for (unsigned i = 0; i < HAL_HOST_CAN_QUEUE_LEN; ++i) {
        hal_can_frame h = frame((uint16_t)(i & 0x7FF), 1, (uint8_t)i);
        ASSERT_EQ(hal_can_send(&h), HAL_OK);
    }
    EXPECT_EQ(hal_can_send(&f), HAL_EBUSY);
    EXPECT_EQ(q->from_drive.dropped, 1u);
    for (unsigned i = 0; i < HAL_HOST_CAN_QUEUE_LEN; ++i) {
        ASSERT_EQ(hal_host_can_loopback_take(q.get(), &g), HAL_OK);
        EXPECT_EQ(g.data[0], (uint8_t)i);
    }
    hal_can_frame bad = frame(0x900, 1, 0);
    EXPECT_EQ(hal_host_can_loopback_inject(q.get(), &bad), HAL_EINVAL);
}

TEST(SocketCan, OpenReportsWhyItCannot)
{
    hal_host_can_backend be;
    EXPECT_EQ(hal_host_socketcan_open("", &be), -EINVAL);
    EXPECT_EQ(hal_host_socketcan_open("an_interface_name_too_long", &be), -EINVAL);
    int rc = hal_host_socketcan_open("dtcnone0", &be);
    // Without kernel CAN: -EAFNOSUPPORT (97). With it: no such interface.
    EXPECT_TRUE(rc == -EAFNOSUPPORT || rc == -ENODEV) << rc;
    EXPECT_EQ(be.send, nullptr);
    hal_host_socketcan_close(&be); // harmless on a closed backend
}
