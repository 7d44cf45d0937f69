// A small application for the CANopen layer's unit tests: its own object
// dictionary (a few entries of every binding and data type), hooks that record
// what the device asked for, and a client side that sends requests and collects
// the answers. It links only dtc_canopen: nothing of the drive or the control law.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

extern "C" {
#include "dtc/canopen/co_dev.h"
}

namespace coapp {

constexpr uint8_t kNode = 5;

// Application bindings (co_param.bind >= CO_BIND_APP).
enum : uint8_t { BIND_VARS = CO_BIND_APP, BIND_FN };
// Handler ids of BIND_FN entries.
enum : uint16_t { FN_CONTROLWORD, FN_STATUSWORD, FN_LOG };

struct Vars {
    float gain = 1.0f;        // 0x2000, rw, runtime, 0..10
    float offset_A = 0.0f;    // 0x2001, INTEGER16 raw = 10 x A, -100..100, not runtime
    uint8_t mode = 1;         // 0x2002, allowed {1, 2, 4}
    float tel_speed = 0.0f;   // 0x3000:1, telemetry (ro, TPDO)
    uint16_t tel_state = 0;   // 0x3000:2
};

inline co_num f(float x) { co_num v; v.f = x; return v; }
inline co_num u(uint32_t x) { co_num v; v.u = x; return v; }
inline co_num i(int32_t x) { co_num v; v.i = x; return v; }

constexpr uint8_t RW = CO_F_READ | CO_F_WRITE;
// name, index, sub, dtype, flags, bind, ckind, csize, offset, k, min, max, def, allowed, n_allowed, str,
// max_step (gain: at most 50 % of its present value per write while running)
static const uint32_t kModes[] = {1u, 2u, 4u};
static const co_param kParams[] = {
    {"device_type", 0x1000, 0, CO_DT_UNSIGNED32, CO_F_READ, CO_BIND_CONST, CO_CK_UINT, 4, 0, 1.0f, u(0), u(0), u(0x00020192u), nullptr, 0, nullptr, 0.0f},
    {"error_register", 0x1001, 0, CO_DT_UNSIGNED8, CO_F_READ, BIND_FN, CO_CK_UINT, 1, FN_LOG, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"error_count", 0x1003, 0, CO_DT_UNSIGNED8, RW | CO_F_RUNTIME, CO_BIND_ERRHIST, CO_CK_UINT, 1, 0, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"error_history_1", 0x1003, 1, CO_DT_UNSIGNED32, CO_F_READ, CO_BIND_ERRHIST, CO_CK_UINT, 4, 0, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"error_history_2", 0x1003, 2, CO_DT_UNSIGNED32, CO_F_READ, CO_BIND_ERRHIST, CO_CK_UINT, 4, 0, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"error_history_3", 0x1003, 3, CO_DT_UNSIGNED32, CO_F_READ, CO_BIND_ERRHIST, CO_CK_UINT, 4, 0, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"error_history_4", 0x1003, 4, CO_DT_UNSIGNED32, CO_F_READ, CO_BIND_ERRHIST, CO_CK_UINT, 4, 0, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"error_history_5", 0x1003, 5, CO_DT_UNSIGNED32, CO_F_READ, CO_BIND_ERRHIST, CO_CK_UINT, 4, 0, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"error_history_6", 0x1003, 6, CO_DT_UNSIGNED32, CO_F_READ, CO_BIND_ERRHIST, CO_CK_UINT, 4, 0, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"error_history_7", 0x1003, 7, CO_DT_UNSIGNED32, CO_F_READ, CO_BIND_ERRHIST, CO_CK_UINT, 4, 0, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"error_history_8", 0x1003, 8, CO_DT_UNSIGNED32, CO_F_READ, CO_BIND_ERRHIST, CO_CK_UINT, 4, 0, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"device_name", 0x1008, 0, CO_DT_VISIBLE_STRING, CO_F_READ, CO_BIND_CONST, CO_CK_BYTES, 0, 0, 1.0f, u(0), u(0), u(0), nullptr, 0, "test application", 0.0f},
    {"emcy_inhibit", 0x1015, 0, CO_DT_UNSIGNED16, RW | CO_F_RUNTIME, CO_BIND_COMM, CO_CK_UINT, 2, offsetof(co_comm_cfg, emcy_inhibit_100us), 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"hb_consumer", 0x1016, 1, CO_DT_UNSIGNED32, RW | CO_F_RUNTIME, CO_BIND_COMM, CO_CK_UINT, 4, offsetof(co_comm_cfg, hb_consumer), 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"heartbeat_ms", 0x1017, 0, CO_DT_UNSIGNED16, RW | CO_F_RUNTIME, CO_BIND_COMM, CO_CK_UINT, 2, offsetof(co_comm_cfg, heartbeat_ms), 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"error_behaviour", 0x1029, 1, CO_DT_UNSIGNED8, RW | CO_F_RUNTIME, CO_BIND_COMM, CO_CK_UINT, 1, offsetof(co_comm_cfg, error_behaviour), 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"sdo_rx_cob", 0x1200, 1, CO_DT_UNSIGNED32, CO_F_READ, CO_BIND_NODEID, CO_CK_UINT, 4, 0, 1.0f, u(0), u(0), u(0x600), nullptr, 0, nullptr, 0.0f},
    {"rpdo1_event_timer", 0x1400, 5, CO_DT_UNSIGNED16, RW | CO_F_RUNTIME, CO_BIND_COMM, CO_CK_UINT, 2, offsetof(co_comm_cfg, rpdo_timeout_ms), 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"gain", 0x2000, 0, CO_DT_REAL32, RW | CO_F_RUNTIME | CO_F_LIMITS, BIND_VARS, CO_CK_FLOAT, 4, offsetof(Vars, gain), 1.0f, f(0.0f), f(10.0f), f(1.0f), nullptr, 0, nullptr, 0.5f},
    {"offset_A", 0x2001, 0, CO_DT_INTEGER16, RW | CO_F_LIMITS, BIND_VARS, CO_CK_FLOAT, 4, offsetof(Vars, offset_A), 10.0f, i(-100), i(100), i(0), nullptr, 0, nullptr, 0.0f},
    {"mode", 0x2002, 0, CO_DT_UNSIGNED8, RW | CO_F_RUNTIME, BIND_VARS, CO_CK_UINT, 1, offsetof(Vars, mode), 1.0f, u(0), u(0), u(1), kModes, 3, nullptr, 0.0f},
    {"log", 0x2100, 0, CO_DT_DOMAIN, CO_F_READ, BIND_FN, CO_CK_BYTES, 0, FN_LOG, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"node_id", 0x2500, 1, CO_DT_UNSIGNED8, RW | CO_F_LIMITS, CO_BIND_COMM, CO_CK_UINT, 1, offsetof(co_comm_cfg, node_id), 1.0f, u(1), u(127), u(kNode), nullptr, 0, nullptr, 0.0f},
    {"bitrate_kbps", 0x2500, 3, CO_DT_UNSIGNED16, RW, CO_BIND_COMM, CO_CK_UINT, 2, offsetof(co_comm_cfg, bitrate_kbps), 1.0f, u(0), u(0), u(250), nullptr, 0, nullptr, 0.0f},
    {"telemetry_hz", 0x2500, 5, CO_DT_UNSIGNED16, RW | CO_F_RUNTIME, CO_BIND_COMM, CO_CK_UINT, 2, offsetof(co_comm_cfg, telemetry_hz), 1.0f, u(0), u(0), u(100), nullptr, 0, nullptr, 0.0f},
    {"tel_speed_rpm", 0x3000, 1, CO_DT_REAL32, CO_F_READ | CO_F_PDO, BIND_VARS, CO_CK_FLOAT, 4, offsetof(Vars, tel_speed), 9.549296f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"tel_state", 0x3000, 2, CO_DT_UNSIGNED16, CO_F_READ | CO_F_PDO, BIND_VARS, CO_CK_UINT, 2, offsetof(Vars, tel_state), 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"controlword", 0x6040, 0, CO_DT_UNSIGNED16, RW | CO_F_RUNTIME | CO_F_PDO, BIND_FN, CO_CK_UINT, 2, FN_CONTROLWORD, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
    {"statusword", 0x6041, 0, CO_DT_UNSIGNED16, CO_F_READ | CO_F_PDO, BIND_FN, CO_CK_UINT, 2, FN_STATUSWORD, 1.0f, u(0), u(0), u(0), nullptr, 0, nullptr, 0.0f},
};
constexpr uint16_t kCount = sizeof kParams / sizeof kParams[0];
constexpr uint16_t P_GAIN = 18, P_TEL_SPEED = 25, P_TEL_STATE = 26, P_CONTROLWORD = 27;
static_assert(P_CONTROLWORD < kCount, "positions follow kParams");

static const co_pdo_map kTpdo[] = {{0x180, 2, 6, {P_TEL_SPEED, P_TEL_STATE}}};
// Controlword first in the frame: the device must still apply it last.
static const co_pdo_map kRpdo[] = {{0x200, 2, 6, {P_CONTROLWORD, P_GAIN}}};
static const co_emcy_entry kEmcy[] = {{1u << 0, 0x2310, 1}, {1u << 1, 0x3210, 2}};

/** The application: hooks record what the device asked for. */
struct App {
    co_app app{};
    co_dev dev{};
    Vars vars;
    bool running = false;
    bool refuse_next = false;                // write hook refuses with PARAM_INCOMPAT once
    bool hold_reset = false;                 // reset_ready answers false (a machine still stopping)
    int send_budget = -1;                    // frames the transmit queue still takes (-1: any number)
    std::vector<hal_can_frame> sent;         // frames the device sent
    std::vector<std::string> calls;          // hook calls in order (open, write:NAME, reset_node, booted)
    std::vector<uint8_t> log;                // content of the domain 0x2100
    uint32_t bitrate = 0;
    co_cia402_action last_action = CO_CIA402_KEEP;
    co_pass pass{0, 0, 5000, 0, false, 0};

    App()
    {
        app.od = {kParams, kCount};
        app.tpdo = kTpdo;
        app.n_tpdo = 1;
        app.rpdo = kRpdo;
        app.n_rpdo = 1;
        app.emcy = kEmcy;
        app.n_emcy = 2;
        app.default_node_id = kNode;
        app.ctx = this;
        app.send = [](void *c, const hal_can_frame *fr) {
            auto *a = static_cast<App *>(c);
            if (a->send_budget == 0)
                return -1; // the transmit queue is full
            if (a->send_budget > 0)
                a->send_budget--;
            a->sent.push_back(*fr);
            return 0;
        };
        app.open = [](void *c, uint32_t bps) {
            auto *a = static_cast<App *>(c);
            a->bitrate = bps;
            a->calls.push_back("open");
            return 0;
        };
        app.read = [](void *c, const co_param *p, co_num *v) { return static_cast<App *>(c)->read(p, v); };
        app.write = [](void *c, const co_param *p, const co_num *v) { return static_cast<App *>(c)->write(p, v); };
        app.domain_size = [](void *c, const co_param *) { return uint32_t(static_cast<App *>(c)->log.size()); };
        app.domain_read = [](void *c, const co_param *, uint32_t off, uint8_t *buf, size_t n) {
            auto *a = static_cast<App *>(c);
            for (size_t k = 0; k < n; k++)
                buf[k] = off + k < a->log.size() ? a->log[off + k] : 0;
        };
        app.running = [](void *c) { return static_cast<App *>(c)->running; };
        app.event = [](void *c, co_event ev) {
            static_cast<App *>(c)->calls.push_back("event:" + std::to_string(int(ev)));
        };
        app.reset_ready = [](void *c) { return !static_cast<App *>(c)->hold_reset; };
        app.reset_node = [](void *c) { static_cast<App *>(c)->calls.push_back("reset_node"); };
        app.booted = [](void *c) { static_cast<App *>(c)->calls.push_back("booted"); };
        co_dev_init(&dev, &app);
    }
    App(const App &) = delete;
    App &operator=(const App &) = delete;

    uint32_t read(const co_param *p, co_num *v)
    {
        if (p->bind == BIND_VARS) {
            *v = co_field_get(&vars, p);
            return CO_ABORT_NONE;
        }
        switch (p->offset) {
        case FN_CONTROLWORD: v->u = dev.cia402.controlword; return CO_ABORT_NONE;
        case FN_STATUSWORD: v->u = co_cia402_statusword(&dev.cia402, true); return CO_ABORT_NONE;
        default: v->u = co_emcy_error_register(&dev); return CO_ABORT_NONE;
        }
    }

    uint32_t write(const co_param *p, const co_num *v)
    {
        if (refuse_next) {
            refuse_next = false;
            return CO_ABORT_PARAM_INCOMPAT;
        }
        calls.push_back(std::string("write:") + p->name);
        if (p->bind == BIND_VARS) {
            co_field_set(&vars, p, v);
            return CO_ABORT_NONE;
        }
        if (p->offset == FN_CONTROLWORD) {
            last_action = co_cia402_controlword(&dev.cia402, uint16_t(v->u));
            if (last_action == CO_CIA402_RUN)
                running = true;
            else if (last_action != CO_CIA402_KEEP)
                running = false;
            return CO_ABORT_NONE;
        }
        return CO_ABORT_READ_ONLY;
    }

    /** One background pass with @p frames received. */
    void step(const std::vector<hal_can_frame> &frames = {})
    {
        co_dev_begin_pass(&dev, &pass);
        for (const auto &fr : frames)
            co_dev_rx(&dev, &fr);
        co_dev_end_pass(&dev);
    }

    static hal_can_frame frame(uint16_t id, std::vector<uint8_t> data)
    {
        hal_can_frame fr;
        std::memset(&fr, 0, sizeof fr);
        fr.id = id;
        fr.dlc = uint8_t(data.size());
        for (size_t k = 0; k < data.size() && k < 8; k++)
            fr.data[k] = data[k];
        return fr;
    }

    /** Send an SDO request; return the response frame (dlc 0 if none). */
    hal_can_frame sdo(std::vector<uint8_t> req)
    {
        req.resize(8, 0);
        sent.clear();
        step({frame(uint16_t(0x600 + dev.node_id), req)});
        for (const auto &fr : sent)
            if (fr.id == 0x580u + dev.node_id)
                return fr;
        hal_can_frame none{};
        return none;
    }

    std::vector<hal_can_frame> with_id(uint32_t id) const
    {
        std::vector<hal_can_frame> out;
        for (const auto &fr : sent)
            if (fr.id == id)
                out.push_back(fr);
        return out;
    }
};

inline uint32_t le32(const uint8_t *b) { return b[0] | (b[1] << 8) | (b[2] << 16) | (uint32_t(b[3]) << 24); }
inline uint32_t abort_of(const hal_can_frame &fr) { return fr.data[0] == 0x80 ? le32(&fr.data[4]) : 0u; }

} // namespace coapp
