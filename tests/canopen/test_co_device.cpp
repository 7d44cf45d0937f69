// Unit tests of the CANopen layer alone (firmware/canopen) with a small test
// application (co_test_app.hpp): SDO, NMT and heartbeat, PDO, EMCY, CiA 402.
// This executable links dtc_canopen only: if the layer called anything of the
// drive or the control law, it would not link.
#include "co_test_app.hpp"

#include <cmath>

using namespace coapp;

namespace {

std::vector<uint8_t> upload(uint16_t index, uint8_t sub) { return {0x40, uint8_t(index), uint8_t(index >> 8), sub}; }

std::vector<uint8_t> download(uint16_t index, uint8_t sub, std::vector<uint8_t> v)
{
    std::vector<uint8_t> r = {uint8_t(0x23 | ((4 - v.size()) << 2)), uint8_t(index), uint8_t(index >> 8), sub};
    for (uint8_t b : v) // (vector::insert trips GCC 12's -Warray-bounds here)
        r.push_back(b);
    return r;
}

std::vector<uint8_t> f32(float x)
{
    uint32_t w;
    std::memcpy(&w, &x, 4);
    return {uint8_t(w), uint8_t(w >> 8), uint8_t(w >> 16), uint8_t(w >> 24)};
}

struct Booted : App {
    Booted()
    {
        step();
        sent.clear();
        calls.clear();
    }
};

} // namespace

TEST(CoDevice, BootUpOpensAtTheConfiguredRateAndAnnouncesItself)
{
    App a;
    a.step();
    ASSERT_EQ(a.with_id(0x700 + kNode).size(), 1u);
    EXPECT_EQ(a.with_id(0x700 + kNode)[0].data[0], 0x00);
    EXPECT_EQ(a.bitrate, 250000u); // the test dictionary's default, not the drive's
    EXPECT_EQ(a.calls, (std::vector<std::string>{"open", "booted"}));
    EXPECT_EQ(a.dev.nmt.state, CO_NMT_PRE_OPERATIONAL);
}

TEST(CoDevice, ExpeditedUploadOfConstantsNodeIdAndApplicationValues)
{
    Booted a;
    hal_can_frame r = a.sdo(upload(0x1000, 0));
    EXPECT_EQ(r.data[0], 0x43);
    EXPECT_EQ(le32(&r.data[4]), 0x00020192u);
    r = a.sdo(upload(0x1200, 1));
    EXPECT_EQ(le32(&r.data[4]), 0x600u + kNode);
    a.vars.gain = 2.5f;
    r = a.sdo(upload(0x2000, 0));
    float g;
    std::memcpy(&g, &r.data[4], 4);
    EXPECT_EQ(g, 2.5f);
    a.vars.offset_A = -3.26f; // INTEGER16 raw = 10 x A, rounded half away from zero
    r = a.sdo(upload(0x2001, 0));
    EXPECT_EQ(r.data[0], 0x4B);
    EXPECT_EQ(int16_t(r.data[4] | (r.data[5] << 8)), -33);
}

TEST(CoDevice, DownloadIsCheckedBeforeTheApplicationSeesIt)
{
    Booted a;
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, f32(4.0f)))), 0u);
    EXPECT_EQ(a.vars.gain, 4.0f);
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, f32(10.5f)))), CO_ABORT_VALUE_HIGH);
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, f32(-0.1f)))), CO_ABORT_VALUE_LOW);
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, f32(std::nanf(""))))), CO_ABORT_INVALID_VALUE);
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, {1, 2}))), CO_ABORT_LENGTH);
    EXPECT_EQ(abort_of(a.sdo(download(0x2002, 0, {3}))), CO_ABORT_INVALID_VALUE);
    EXPECT_EQ(abort_of(a.sdo(download(0x1000, 0, {1, 0, 0, 0}))), CO_ABORT_READ_ONLY);
    EXPECT_EQ(abort_of(a.sdo(download(0x2FFF, 0, {1}))), CO_ABORT_NO_OBJECT);
    EXPECT_EQ(abort_of(a.sdo(download(0x2500, 2, {1}))), CO_ABORT_NO_SUB);
    EXPECT_EQ(a.vars.gain, 4.0f);
    EXPECT_EQ(a.vars.mode, 1u);
    // Only the one accepted write reached the application.
    EXPECT_EQ(a.calls, (std::vector<std::string>{"write:gain"}));
    // Scaled: raw 25 -> 2.5 A.
    EXPECT_EQ(abort_of(a.sdo(download(0x2001, 0, {25, 0}))), 0u);
    EXPECT_FLOAT_EQ(a.vars.offset_A, 2.5f);
}

TEST(CoDevice, RunningLocksNonRuntimeEntriesAndTheApplicationMayRefuse)
{
    Booted a;
    a.running = true;
    EXPECT_EQ(abort_of(a.sdo(download(0x2001, 0, {10, 0}))), CO_ABORT_STATE);
    EXPECT_EQ(a.vars.offset_A, 0.0f);
    // A runtime entry with max_step 0.5: from 1.0, 1.5 is allowed, then 2.25, not 3.5.
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, f32(1.5f)))), 0u);
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, f32(3.5f)))), CO_ABORT_STATE);
    EXPECT_EQ(a.vars.gain, 1.5f);
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, f32(2.25f)))), 0u);
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, f32(1.0f)))), CO_ABORT_STATE); // down by 1.25 > 1.125
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, f32(1.2f)))), 0u);
    a.refuse_next = true;
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, f32(1.5f)))), CO_ABORT_PARAM_INCOMPAT);
    EXPECT_EQ(a.vars.gain, 1.2f);
    // Stopped: any value in range.
    a.running = false;
    EXPECT_EQ(abort_of(a.sdo(download(0x2000, 0, f32(9.0f)))), 0u);
    EXPECT_EQ(a.vars.gain, 9.0f);
}

TEST(CoDevice, SegmentedUploadOfAStringAndADomain)
{
    Booted a;
    auto read_all = [&](uint16_t index) {
        hal_can_frame r = a.sdo(upload(index, 0));
        EXPECT_EQ(r.data[0], 0x41);
        uint32_t size = le32(&r.data[4]);
        std::vector<uint8_t> got;
        uint8_t toggle = 0;
        while (got.size() < size) {
            r = a.sdo({uint8_t(0x60 | (toggle << 4))});
            EXPECT_EQ((r.data[0] >> 4) & 1, toggle);
            size_t n = 7 - ((r.data[0] >> 1) & 7);
            for (size_t k = 0; k < n && k < 7; k++)
                got.push_back(r.data[1 + k]);
            toggle ^= 1;
            if (r.data[0] & 1)
                break;
        }
        EXPECT_EQ(got.size(), size);
        return got;
    };
    auto s = read_all(0x1008);
    EXPECT_EQ(std::string(s.begin(), s.end()), "test application");
    for (int k = 0; k < 20; k++)
        a.log.push_back(uint8_t(3 * k + 1));
    EXPECT_EQ(read_all(0x2100), a.log);
}

TEST(CoDevice, SegmentedDownloadToggleAndTimeout)
{
    Booted a;
    auto v = f32(7.0f);
    // Initiate (size 4), 3 bytes with toggle 0, the last byte with toggle 1.
    EXPECT_EQ(a.sdo({0x21, 0x00, 0x20, 0x00, 4, 0, 0, 0}).data[0], 0x60);
    EXPECT_EQ(a.sdo({0x08, v[0], v[1], v[2]}).data[0], 0x20);
    EXPECT_EQ(a.vars.gain, 1.0f); // nothing applied before the last segment
    EXPECT_EQ(a.sdo({0x1D, v[3]}).data[0], 0x30);
    EXPECT_EQ(a.vars.gain, 7.0f);
    // Toggle not alternated: the second segment repeats toggle 0.
    EXPECT_EQ(a.sdo({0x21, 0x00, 0x20, 0x00, 4, 0, 0, 0}).data[0], 0x60);
    auto w = f32(2.0f);
    EXPECT_EQ(a.sdo({0x08, w[0], w[1], w[2]}).data[0], 0x20);
    EXPECT_EQ(abort_of(a.sdo({0x0D, w[3]})), CO_ABORT_TOGGLE);
    EXPECT_EQ(a.vars.gain, 7.0f);
    // A fresh transfer, then silence: aborted after 1000 ms of the pass clock.
    EXPECT_EQ(a.sdo({0x21, 0x00, 0x20, 0x00, 4, 0, 0, 0}).data[0], 0x60);
    a.sent.clear();
    a.pass.now_ms += 1000;
    a.step();
    EXPECT_TRUE(a.with_id(0x580 + kNode).empty());
    a.pass.now_ms += 1;
    a.step();
    ASSERT_EQ(a.with_id(0x580 + kNode).size(), 1u);
    EXPECT_EQ(abort_of(a.with_id(0x580 + kNode)[0]), CO_ABORT_TIMEOUT);
    // Block transfers are not supported.
    EXPECT_EQ(abort_of(a.sdo({0xC0, 0x00, 0x20, 0x00})), CO_ABORT_CMD);
}

TEST(CoDevice, NmtStatesResetsAndHeartbeat)
{
    Booted a;
    a.step({App::frame(0x000, {0x01, kNode})});
    EXPECT_EQ(a.dev.nmt.state, CO_NMT_OPERATIONAL);
    a.calls.clear();
    a.step({App::frame(0x000, {0x02, 0})}); // broadcast stop
    EXPECT_EQ(a.dev.nmt.state, CO_NMT_STOPPED);
    EXPECT_EQ(a.calls, (std::vector<std::string>{"event:3"})); // CO_EVENT_NMT_STOPPED, once
    a.step({App::frame(0x000, {0x02, 0})});
    EXPECT_EQ(a.calls.size(), 1u);
    EXPECT_TRUE(a.sdo(upload(0x1000, 0)).dlc == 0); // no SDO in stopped
    a.step({App::frame(0x000, {0x01, kNode + 1})}); // another node
    EXPECT_EQ(a.dev.nmt.state, CO_NMT_STOPPED);
    // Reset communication with a new node id: boot-up under the new id, no application reset.
    a.step({App::frame(0x000, {0x80, kNode})});
    EXPECT_EQ(abort_of(a.sdo(download(0x2500, 1, {9}))), 0u);
    a.calls.clear();
    a.sent.clear();
    a.step({App::frame(0x000, {0x82, kNode})});
    EXPECT_EQ(a.dev.node_id, 9u);
    EXPECT_EQ(a.with_id(0x709).size(), 1u);
    EXPECT_EQ(a.calls, (std::vector<std::string>{"event:4", "open", "booted"}));
    // Reset node: told first (CO_EVENT_RESET); it waits while the application
    // is not ready (a machine still stopping), then resets the application.
    a.calls.clear();
    a.hold_reset = true;
    a.step({App::frame(0x000, {0x81, 9})});
    a.step();
    EXPECT_EQ(a.calls, (std::vector<std::string>{"event:4"}));
    a.hold_reset = false;
    a.step();
    EXPECT_EQ(a.calls, (std::vector<std::string>{"event:4", "reset_node", "open", "booted"}));
    // Heartbeat every 100 ms of the pass clock.
    EXPECT_EQ(abort_of(a.sdo(download(0x1017, 0, {100, 0}))), 0u);
    a.sent.clear();
    for (int k = 0; k < 100; k++) {
        a.pass.now_ms += 10;
        a.step();
    }
    EXPECT_EQ(a.with_id(0x709).size(), 10u);
}

TEST(CoDevice, TelemetryTpdoAtTheConfiguredRateOnlyWhenOperational)
{
    Booted a;
    a.vars.tel_speed = 10.0f; // rad/s -> 95.49 rpm on the bus
    a.vars.tel_state = 3;
    for (int k = 0; k < 50; k++) { // pre-operational: nothing
        a.pass.tick += 100;
        a.step();
    }
    EXPECT_TRUE(a.with_id(0x180 + kNode).empty());
    a.step({App::frame(0x000, {0x01, 0})});
    a.sent.clear();
    for (int k = 0; k < 5000; k++) { // one second of 5 kHz ticks at 100 Hz telemetry
        a.pass.tick += 1;
        a.step();
    }
    auto t = a.with_id(0x180 + kNode);
    EXPECT_NEAR(double(t.size()), 100.0, 1.0);
    ASSERT_FALSE(t.empty());
    EXPECT_EQ(t[0].dlc, 6u);
    float rpm;
    std::memcpy(&rpm, &t[0].data[0], 4);
    EXPECT_NEAR(rpm, 95.49296f, 1e-3f);
    EXPECT_EQ(t[0].data[4], 3u);
}

TEST(CoDevice, RpdoAppliesTheControlwordLastAndReportsShortFrames)
{
    Booted a;
    a.step({App::frame(0x000, {0x01, 0})});
    auto g = f32(6.0f);
    a.calls.clear();
    a.step({App::frame(0x200 + kNode, {0x06, 0x00, g[0], g[1], g[2], g[3]})});
    EXPECT_EQ(a.calls, (std::vector<std::string>{"write:gain", "write:controlword"}));
    EXPECT_EQ(a.vars.gain, 6.0f);
    a.sent.clear();
    a.calls.clear();
    a.step({App::frame(0x200 + kNode, {0x0F, 0x00, g[0]})});
    EXPECT_TRUE(a.calls.empty());
    auto e = a.with_id(0x080 + kNode);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(e[0].data[0] | (e[0].data[1] << 8), 0x8210);
}

TEST(CoDevice, EmcyOncePerNewFaultGenericForUnknownBitsAndResetWhenCleared)
{
    Booted a;
    a.pass.faults = 1u << 1;
    a.step();
    auto e = a.with_id(0x080 + kNode);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(e[0].data[0] | (e[0].data[1] << 8), 0x3210);
    EXPECT_EQ(e[0].data[2], 0x05); // voltage bit 2 + generic bit 0
    a.sent.clear();
    a.step(); // same fault: nothing new
    EXPECT_TRUE(a.with_id(0x080 + kNode).empty());
    a.pass.faults |= 1u << 7; // no table entry
    a.step();
    e = a.with_id(0x080 + kNode);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(e[0].data[0] | (e[0].data[1] << 8), 0x1000);
    a.sent.clear();
    a.pass.faults = 0;
    a.step();
    e = a.with_id(0x080 + kNode);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(e[0].data[0] | (e[0].data[1] << 8), 0x0000);
}

TEST(CoCia402, StateMachineActionsAndStatusword)
{
    co_cia402 c;
    co_cia402_init(&c);
    EXPECT_EQ(co_cia402_statusword(&c, false), 0x0240);
    EXPECT_EQ(co_cia402_controlword(&c, 0x0F), CO_CIA402_KEEP); // not from switch on disabled
    EXPECT_EQ(co_cia402_controlword(&c, 0x06), CO_CIA402_STOP);
    EXPECT_EQ(c.state, CO_CIA402_READY_TO_SWITCH_ON);
    EXPECT_EQ(co_cia402_controlword(&c, 0x07), CO_CIA402_KEEP);
    EXPECT_EQ(co_cia402_statusword(&c, false), 0x0223);
    EXPECT_EQ(co_cia402_controlword(&c, 0x0F), CO_CIA402_RUN);
    EXPECT_EQ(co_cia402_statusword(&c, false), 0x0227);
    EXPECT_EQ(co_cia402_statusword(&c, true), 0x0627);
    EXPECT_EQ(co_cia402_controlword(&c, 0x07), CO_CIA402_STOP); // disable operation
    EXPECT_EQ(c.state, CO_CIA402_SWITCHED_ON);
    EXPECT_EQ(co_cia402_controlword(&c, 0x0F), CO_CIA402_RUN);
    EXPECT_EQ(co_cia402_controlword(&c, 0x0B), CO_CIA402_QUICK_STOP); // quick stop from operation enabled
    EXPECT_EQ(c.state, CO_CIA402_QUICK_STOP_ACTIVE);
    EXPECT_EQ(co_cia402_statusword(&c, false), 0x0207); // bit 5 (quick stop) low
    EXPECT_EQ(co_cia402_controlword(&c, 0x0F), CO_CIA402_KEEP); // the ramp is not interrupted by enable
    co_cia402_sync(&c, false, true);
    EXPECT_EQ(c.state, CO_CIA402_QUICK_STOP_ACTIVE);
    co_cia402_quick_stop_done(&c);
    EXPECT_EQ(c.state, CO_CIA402_SWITCH_ON_DISABLED);
    EXPECT_EQ(co_cia402_controlword(&c, 0x02), CO_CIA402_STOP); // quick stop elsewhere: switch on disabled
    EXPECT_EQ(c.state, CO_CIA402_SWITCH_ON_DISABLED);
    co_cia402_sync(&c, true, false);
    EXPECT_EQ(co_cia402_statusword(&c, false), 0x0208);
    EXPECT_EQ(co_cia402_controlword(&c, 0x00), CO_CIA402_KEEP);
    EXPECT_EQ(co_cia402_controlword(&c, 0x80), CO_CIA402_FAULT_RESET); // rising edge of bit 7
    EXPECT_EQ(co_cia402_controlword(&c, 0x80), CO_CIA402_STOP); // no longer a fault: bit 1 clear = disable voltage
    EXPECT_EQ(c.state, CO_CIA402_SWITCH_ON_DISABLED);
    co_cia402_sync(&c, false, true); // started by someone else
    EXPECT_EQ(c.state, CO_CIA402_OPERATION_ENABLED);
}

TEST(CoDevice, HeartbeatConsumerLossIsACommunicationError)
{
    Booted a;
    a.step({App::frame(0x000, {0x01, 0})});
    ASSERT_EQ(abort_of(a.sdo(download(0x1016, 1, {200, 0, 0x7F, 0}))), 0u); // node 0x7F, 200 ms
    // Not monitored before the first heartbeat (CiA 301).
    a.calls.clear();
    for (int k = 0; k < 10; k++) {
        a.pass.now_ms += 100;
        a.step();
    }
    EXPECT_TRUE(a.calls.empty());
    a.sent.clear();
    for (int k = 0; k < 10; k++) { // master alive: a beat every 100 ms
        a.pass.now_ms += 100;
        a.step({App::frame(0x77F, {0x05})});
    }
    EXPECT_TRUE(a.calls.empty());
    a.pass.now_ms += 200;
    a.step();
    EXPECT_TRUE(a.calls.empty()) << "200 ms is still within the time";
    a.pass.now_ms += 1;
    a.step();
    EXPECT_EQ(a.calls, (std::vector<std::string>{"event:1"}));
    auto e = a.with_id(0x080 + kNode);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(e[0].data[0] | (e[0].data[1] << 8), 0x8130);
    EXPECT_EQ(e[0].data[2] & 0x10, 0x10); // communication bit
    EXPECT_EQ(a.dev.nmt.state, CO_NMT_PRE_OPERATIONAL); // 0x1029 default 0
    a.step();
    EXPECT_EQ(a.calls.size(), 1u) << "reported once";
    // A beat again, then loss again with 0x1029 = 2: stopped.
    ASSERT_EQ(abort_of(a.sdo(download(0x1029, 1, {2}))), 0u);
    a.step({App::frame(0x77F, {0x05})});
    a.pass.now_ms += 1000;
    a.step();
    EXPECT_EQ(a.dev.nmt.state, CO_NMT_STOPPED);
    EXPECT_EQ(a.calls.back(), "event:1");
}

TEST(CoDevice, RpdoEventTimerOnceStarted)
{
    Booted a;
    a.step({App::frame(0x000, {0x01, 0})});
    ASSERT_EQ(abort_of(a.sdo(download(0x1029, 1, {1}))), 0u); // no NMT change
    ASSERT_EQ(abort_of(a.sdo(download(0x1400, 5, {50, 0}))), 0u);
    a.pass.now_ms += 1000;
    a.calls.clear();
    a.step();
    EXPECT_TRUE(a.calls.empty()) << "not monitored before the first RPDO";
    auto g = f32(2.0f);
    for (int k = 0; k < 5; k++) {
        a.pass.now_ms += 40;
        a.step({App::frame(0x200 + kNode, {0x0F, 0x00, g[0], g[1], g[2], g[3]})});
    }
    a.calls.clear();
    a.sent.clear();
    a.pass.now_ms += 51;
    a.step();
    EXPECT_EQ(a.calls, (std::vector<std::string>{"event:2"}));
    auto e = a.with_id(0x080 + kNode);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(e[0].data[0] | (e[0].data[1] << 8), 0x8250);
    EXPECT_EQ(a.dev.nmt.state, CO_NMT_OPERATIONAL);
}

TEST(CoDevice, EmcyInhibitTimeQueuesDistinctEventsOnce)
{
    Booted a;
    a.step({App::frame(0x000, {0x01, 0})});
    ASSERT_EQ(abort_of(a.sdo(download(0x1015, 0, {0xE8, 0x03}))), 0u); // 1000 x 100 us = 100 ms
    a.sent.clear();
    // 50 short RPDOs within 50 ms: one EMCY now, one waiting, none more.
    for (int k = 0; k < 50; k++) {
        a.pass.now_ms += 1;
        a.step({App::frame(0x200 + kNode, {0x0F})});
    }
    EXPECT_EQ(a.with_id(0x080 + kNode).size(), 1u);
    a.pass.faults = 1u << 0; // a fault within the inhibit time waits as well
    a.step();
    EXPECT_EQ(a.with_id(0x080 + kNode).size(), 1u);
    a.pass.now_ms += 60; // 110 ms after the first message
    a.step();
    auto e = a.with_id(0x080 + kNode);
    ASSERT_EQ(e.size(), 2u);
    EXPECT_EQ(e[1].data[0] | (e[1].data[1] << 8), 0x8210); // the queued event first
    a.pass.now_ms += 100;
    a.step();
    e = a.with_id(0x080 + kNode);
    ASSERT_EQ(e.size(), 3u);
    EXPECT_EQ(e[2].data[0] | (e[2].data[1] << 8), 0x2310); // then the fault, not lost
}

// The controller's bus-off count moving is a communication error: the
// application's event once per entry (CO_EVENT_BUS_OFF), the NMT state per
// 0x1029, and EMCY 0x8140 (recovered from bus-off) only once back on the bus.
TEST(CoDevice, BusOffOncePerEntryEmcyAfterTheRecovery)
{
    App a;
    a.pass.bus_off_count = 7; // what the controller counted before the device started: not an event
    a.step();
    a.step();
    EXPECT_EQ(a.calls, (std::vector<std::string>{"open", "booted"})) << "the count at the first pass is the baseline";
    Booted b;
    b.step({App::frame(0x000, {0x01, 0})});
    b.calls.clear();
    b.sent.clear();
    b.pass.bus_off = true;
    b.pass.bus_off_count = 1;
    for (int k = 0; k < 5; k++) {
        b.pass.now_ms += 10;
        b.step();
    }
    EXPECT_EQ(b.calls, (std::vector<std::string>{"event:5"})) << "once for a long bus-off";
    EXPECT_EQ(b.dev.nmt.state, CO_NMT_PRE_OPERATIONAL); // 0x1029 default 0
    EXPECT_TRUE(b.with_id(0x080 + kNode).empty()) << "no EMCY while off the bus";
    b.pass.bus_off = false;
    b.step();
    auto e = b.with_id(0x080 + kNode);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(e[0].data[0] | (e[0].data[1] << 8), 0x8140);
    EXPECT_EQ(e[0].data[2] & 0x11, 0x11); // generic and communication bits
    b.step();
    EXPECT_EQ(b.with_id(0x080 + kNode).size(), 1u);
    // Two entries between two passes (a short bus-off not seen as a flag): one event.
    b.calls.clear();
    b.pass.bus_off_count = 3;
    b.pass.now_ms += 1000;
    b.step();
    EXPECT_EQ(b.calls, (std::vector<std::string>{"event:5"}));
    EXPECT_EQ(b.with_id(0x080 + kNode).size(), 2u) << "reported after the recovery it already made";
}

// The error history 0x1003 (CiA 301 pre-defined error field), read over SDO:
// sub 0 the number of errors, sub 1 the newest; each entry the EMCY code and
// the error register it carried (hand-derived: fault bit 0 -> 0x2310 with
// register bit 1, bit 1 -> 0x3210 with bit 2, plus bit 0 generic). The return
// to no error is not recorded; the ninth error pushes out the oldest; only 0
// may be written to sub 0 (clears), sub 1.. are read only; an NMT reset keeps it.
TEST(CoDevice, ErrorHistoryNewestFirstClearedByWritingZero)
{
    Booted a;
    a.step({App::frame(0x000, {0x01, 0})});
    auto read = [&](uint8_t sub) {
        hal_can_frame r = a.sdo(upload(0x1003, sub));
        EXPECT_EQ(r.data[0] & 0xE0, 0x40) << "sub " << int(sub) << " abort " << std::hex << abort_of(r);
        return le32(&r.data[4]);
    };
    EXPECT_EQ(read(0), 0u);
    a.pass.faults = 1u << 0;
    a.step();
    a.pass.faults = (1u << 0) | (1u << 1);
    a.step();
    ASSERT_EQ(read(0), 2u);
    EXPECT_EQ(read(1), 0x3210u | (0x07u << 16)) << "newest: DC overvoltage with current+voltage+generic";
    EXPECT_EQ(read(2), 0x2310u | (0x03u << 16));
    EXPECT_EQ(read(3), 0u) << "above the count";
    a.pass.faults = 0;
    a.step();
    ASSERT_EQ(a.with_id(0x080 + kNode).back().data[0], 0x00) << "the reset EMCY was sent";
    EXPECT_EQ(read(0), 2u) << "the return to no error is not an error";
    for (int k = 0; k < 4; k++) { // eight more errors: the history holds 8
        a.pass.faults = 1u << 0;
        a.step();
        a.pass.faults = 1u << 1;
        a.step();
        a.pass.faults = 0;
        a.step();
    }
    EXPECT_EQ(read(0), 8u);
    EXPECT_EQ(read(1), 0x3210u | (0x05u << 16));
    EXPECT_EQ(read(8), 0x2310u | (0x03u << 16)) << "the first two errors fell out";
    EXPECT_EQ(abort_of(a.sdo(upload(0x1003, 9))), 0x06090011u);
    // NMT reset communication keeps it.
    a.step({App::frame(0x000, {0x82, 0})});
    a.step();
    EXPECT_EQ(read(0), 8u);
    // Writes: sub 0 only 0; the entries are read only; a refused write changes nothing.
    EXPECT_EQ(abort_of(a.sdo(download(0x1003, 0, {1}))), 0x06090030u);
    EXPECT_EQ(abort_of(a.sdo(download(0x1003, 1, {0, 0, 0, 0}))), 0x06010002u);
    EXPECT_EQ(read(0), 8u);
    EXPECT_EQ(abort_of(a.sdo(download(0x1003, 0, {0}))), 0u);
    EXPECT_EQ(read(0), 0u);
    EXPECT_EQ(read(1), 0u);
}

namespace {

// CRC-16/XMODEM (CCITT polynomial 0x1021, initial 0, no reflection) from its
// table definition, written independently of co_sdo_crc16.
uint16_t crc_ref(const std::vector<uint8_t> &d)
{
    uint16_t table[256];
    for (int i = 0; i < 256; i++) {
        uint16_t r = uint16_t(i << 8);
        for (int b = 0; b < 8; b++)
            r = uint16_t((r << 1) ^ ((r & 0x8000) ? 0x1021 : 0));
        table[i] = r;
    }
    uint16_t crc = 0;
    for (uint8_t x : d)
        crc = uint16_t((crc << 8) ^ table[((crc >> 8) ^ x) & 0xFF]);
    return crc;
}

std::vector<uint8_t> block_init(uint16_t index, uint8_t sub, uint8_t blksize, bool crc)
{
    return {uint8_t(0xA0 | (crc ? 0x04 : 0)), uint8_t(index), uint8_t(index >> 8), sub, blksize, 0, 0, 0};
}

// Everything the server sent on 0x580 + id in the last pass.
std::vector<hal_can_frame> sdo_out(App &a) { return a.with_id(0x580u + a.dev.node_id); }

std::vector<hal_can_frame> block_req(App &a, std::vector<uint8_t> req)
{
    req.resize(8, 0);
    a.sent.clear();
    a.step({App::frame(uint16_t(0x600 + a.dev.node_id), req)});
    return sdo_out(a);
}

} // namespace

TEST(CoSdoBlock, Crc16MatchesThePublishedCheckValue)
{
    const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
    EXPECT_EQ(co_sdo_crc16(0, check, 9), 0x31C3u); // CRC-16/XMODEM check value
    std::vector<uint8_t> d;
    for (int i = 0; i < 300; i++)
        d.push_back(uint8_t(i * 37 + 11));
    EXPECT_EQ(co_sdo_crc16(0, d.data(), 300), crc_ref(d));
    EXPECT_EQ(co_sdo_crc16(co_sdo_crc16(0, d.data(), 100), d.data() + 100, 200), crc_ref(d)) << "continues";
}

// 100 bytes in blocks of 5 segments: 15 segments (14 x 7 + 2), blocks 5, 5, 5;
// the end says 5 bytes of the last segment are not data, and carries the CRC.
TEST(CoSdoBlock, UploadInBlocksWithCrcAndTheSizeIndicated)
{
    Booted a;
    for (int i = 0; i < 100; i++)
        a.log.push_back(uint8_t(i * 7 + 3));
    auto r = block_req(a, block_init(0x2100, 0, 5, true));
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].data[0], 0xC6) << "scs 6, CRC supported, size indicated";
    EXPECT_EQ(le32(&r[0].data[4]), 100u);
    EXPECT_EQ(r[0].data[1] | (r[0].data[2] << 8), 0x2100);
    std::vector<uint8_t> got;
    r = block_req(a, {0xA3}); // start
    for (int blk = 0; blk < 3; blk++) {
        ASSERT_EQ(r.size(), 5u) << "block " << blk;
        for (int k = 0; k < 5; k++) {
            EXPECT_EQ(r[k].data[0] & 0x7F, k + 1);
            EXPECT_EQ((r[k].data[0] & 0x80) != 0, blk == 2 && k == 4) << "c only on the last segment";
            got.insert(got.end(), r[k].data + 1, r[k].data + 8);
        }
        r = block_req(a, {0xA2, 5, 5});
    }
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].data[0], 0xC1 | (5 << 2)) << "end: 5 bytes of the last segment are padding";
    got.resize(100);
    EXPECT_EQ(got, a.log);
    EXPECT_EQ(r[0].data[1] | (r[0].data[2] << 8), crc_ref(a.log));
    r = block_req(a, {0xA1}); // end response: done, no answer
    EXPECT_TRUE(r.empty());
    EXPECT_EQ(a.dev.sdo.state, CO_SDO_IDLE);
    // The server is free again: an expedited upload works.
    EXPECT_EQ(a.sdo(upload(0x1000, 0)).data[0] & 0xE0, 0x40);
}

// The client acknowledged only 2 of 5 segments: the next block starts with
// the third segment's data. A transmit queue that refuses frames delays
// segments to later passes without losing or repeating one. Without the
// client's CRC request the end carries no CRC. Exactly 14 bytes: the last
// segment is full (n = 0).
TEST(CoSdoBlock, UnacknowledgedSegmentsAreSentAgainAndAFullQueueWaits)
{
    Booted a;
    for (int i = 0; i < 14; i++)
        a.log.push_back(uint8_t(0xA0 + i));
    ASSERT_EQ(block_req(a, block_init(0x2100, 0, 3, false))[0].data[0], 0xC6);
    auto r = block_req(a, {0xA3});
    ASSERT_EQ(r.size(), 2u) << "14 bytes: two segments, the second the last";
    EXPECT_EQ(r[1].data[0], 0x82);
    r = block_req(a, {0xA2, 1, 3}); // segment 2 lost
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].data[0], 0x81) << "resent as seqno 1 of a new block, still the last";
    EXPECT_EQ(r[0].data[1], 0xA7);
    r = block_req(a, {0xA2, 1, 3});
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].data[0], 0xC1) << "n = 0: the last segment was full";
    EXPECT_EQ(r[0].data[1] | (r[0].data[2] << 8), 0) << "no CRC asked for";
    block_req(a, {0xA1});

    // 40 bytes (6 segments) through a queue that takes 2 frames per pass.
    a.log.assign(40, 0x55);
    a.log[39] = 0x99;
    block_req(a, block_init(0x2100, 0, 10, true));
    a.send_budget = 2;
    r = block_req(a, {0xA3});
    EXPECT_EQ(r.size(), 2u);
    std::vector<hal_can_frame> all = r;
    for (int k = 0; k < 5; k++) {
        a.send_budget = 2;
        a.sent.clear();
        a.step();
        auto more = sdo_out(a);
        all.insert(all.end(), more.begin(), more.end());
    }
    a.send_budget = -1;
    ASSERT_EQ(all.size(), 6u) << "every segment once";
    for (int k = 0; k < 6; k++)
        EXPECT_EQ(all[k].data[0] & 0x7F, k + 1);
    EXPECT_EQ(all[5].data[0], 0x86);
    EXPECT_EQ(all[5].data[5], 0x99) << "byte 39 = the 5th of segment 6";
    r = block_req(a, {0xA2, 6, 10});
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].data[0], 0xC1 | (2 << 2));
    EXPECT_EQ(r[0].data[1] | (r[0].data[2] << 8), crc_ref(a.log));
}

TEST(CoSdoBlock, ProtocolErrorsGetTheirAbortCodes)
{
    Booted a;
    a.log.assign(50, 1);
    auto code = [&](std::vector<uint8_t> req) {
        auto r = block_req(a, req);
        return r.empty() ? 0u : abort_of(r.back());
    };
    EXPECT_EQ(code(block_init(0x2100, 0, 0, true)), 0x05040002u) << "block size 0";
    EXPECT_EQ(code(block_init(0x2100, 0, 128, true)), 0x05040002u) << "block size above 127";
    EXPECT_EQ(code(block_init(0x2900, 0, 10, true)), 0x06020000u) << "no such object";
    EXPECT_EQ(code({0xA3}), 0x05040001u) << "start without an initiate";
    EXPECT_EQ(code({0xA2, 1, 10}), 0x05040001u) << "acknowledge without a transfer";
    EXPECT_EQ(code({0xC0, 0x00, 0x21, 0, 0, 0, 0, 0}), 0x05040001u) << "block download is not supported";
    // Acknowledge before the start.
    ASSERT_EQ(block_req(a, block_init(0x2100, 0, 4, true))[0].data[0], 0xC6);
    EXPECT_EQ(code({0xA2, 0, 4}), 0x05040001u);
    // A sequence number that was never sent.
    block_req(a, block_init(0x2100, 0, 4, true));
    ASSERT_EQ(block_req(a, {0xA3}).size(), 4u);
    EXPECT_EQ(code({0xA2, 5, 4}), 0x05040003u);
    // A new block size of 0 in the acknowledge.
    block_req(a, block_init(0x2100, 0, 4, true));
    block_req(a, {0xA3});
    EXPECT_EQ(code({0xA2, 4, 0}), 0x05040002u);
    // End response before the end.
    block_req(a, block_init(0x2100, 0, 4, true));
    block_req(a, {0xA3});
    EXPECT_EQ(code({0xA1}), 0x05040001u);
    // A silent client: timeout after CO_SDO_TIMEOUT_MS.
    block_req(a, block_init(0x2100, 0, 4, true));
    block_req(a, {0xA3});
    a.sent.clear();
    a.pass.now_ms += 1000;
    a.step();
    EXPECT_TRUE(sdo_out(a).empty());
    a.pass.now_ms += 1;
    a.step();
    auto r = sdo_out(a);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(abort_of(r[0]), 0x05040000u);
    EXPECT_EQ(a.dev.sdo.state, CO_SDO_IDLE);
    // A client abort ends the transfer without an answer.
    block_req(a, block_init(0x2100, 0, 4, true));
    EXPECT_TRUE(block_req(a, {0x80, 0x00, 0x21, 0, 0, 0, 0x04, 0x05}).empty());
    EXPECT_EQ(a.dev.sdo.state, CO_SDO_IDLE);
}

// An answer the transmit queue refuses (full of TPDOs) is sent on the next
// pass, once; a new request makes a waiting answer stale.
TEST(CoDevice, SdoAnswerRefusedByAFullQueueIsSentOnTheNextPass)
{
    Booted a;
    a.send_budget = 0;
    EXPECT_EQ(a.sdo(upload(0x1000, 0)).dlc, 0) << "refused: nothing went out";
    a.send_budget = -1;
    a.sent.clear();
    a.step();
    auto r = a.with_id(0x580 + kNode);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].data[0], 0x43);
    EXPECT_EQ(le32(&r[0].data[4]), 0x00020192u);
    a.sent.clear();
    a.step();
    EXPECT_TRUE(a.with_id(0x580 + kNode).empty()) << "sent once";
    a.send_budget = 0;
    a.sdo(upload(0x1000, 0));
    a.send_budget = -1;
    r = {};
    hal_can_frame fresh = a.sdo(upload(0x1008, 0)); // the client moved on
    EXPECT_EQ(fresh.data[1] | (fresh.data[2] << 8), 0x1008);
    a.sent.clear();
    a.step();
    EXPECT_TRUE(a.with_id(0x580 + kNode).empty()) << "the stale answer about 0x1000 is not sent";
}
