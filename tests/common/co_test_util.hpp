// Test bench for the drive's CANopen device: a host board with the in-memory
// CAN loopback, a drive, and helpers that build CiA 301 frames BY HAND (byte
// layouts written out here, independently of the firmware's encoder).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

extern "C" {
#include "dtc/drive.h"
#include "dtc/drive_co.h"
#include "dtc/param_table.h"
#include "hal_host/hal_host.h"
}

namespace cotest {

constexpr uint8_t kNode = 1;             // the table's default node id
constexpr uint32_t kAbortToggle = 0x05030000u;
constexpr uint32_t kAbortTimeout = 0x05040000u;
constexpr uint32_t kAbortCmd = 0x05040001u;
constexpr uint32_t kAbortReadOnly = 0x06010002u;
constexpr uint32_t kAbortNoObject = 0x06020000u;
constexpr uint32_t kAbortIncompat = 0x06040043u;
constexpr uint32_t kAbortLength = 0x06070010u;
constexpr uint32_t kAbortNoSub = 0x06090011u;
constexpr uint32_t kAbortInvalid = 0x06090030u;
constexpr uint32_t kAbortHigh = 0x06090031u;
constexpr uint32_t kAbortLow = 0x06090032u;
constexpr uint32_t kAbortStore = 0x08000020u;
constexpr uint32_t kAbortState = 0x08000022u;

inline hal_can_frame frame(uint16_t id, std::vector<uint8_t> data, bool rtr = false)
{
    hal_can_frame f;
    std::memset(&f, 0, sizeof f);
    f.id = id;
    f.dlc = static_cast<uint8_t>(data.size());
    f.rtr = rtr;
    for (size_t i = 0; i < data.size() && i < 8; i++)
        f.data[i] = data[i];
    return f;
}

/** The frames of @p v with COB-ID @p id, in order. */
inline std::vector<hal_can_frame> with_id(const std::vector<hal_can_frame> &v, uint16_t id)
{
    std::vector<hal_can_frame> out;
    for (const auto &f : v)
        if (f.id == id)
            out.push_back(f);
    return out;
}

inline uint32_t le32(const uint8_t *b)
{
    return uint32_t(b[0]) | (uint32_t(b[1]) << 8) | (uint32_t(b[2]) << 16) | (uint32_t(b[3]) << 24);
}

inline std::vector<uint8_t> bytes_u32(uint32_t v)
{
    return {uint8_t(v), uint8_t(v >> 8), uint8_t(v >> 16), uint8_t(v >> 24)};
}

inline std::vector<uint8_t> bytes_f32(float f)
{
    uint32_t u;
    std::memcpy(&u, &f, 4);
    return bytes_u32(u);
}

inline float f32_of(uint32_t u)
{
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

/** The result of one SDO exchange as the client sees it. */
struct SdoReply {
    bool got = false;        // a response arrived
    hal_can_frame f{};       // the response
    bool aborted() const { return got && f.data[0] == 0x80u; }
    uint32_t abort_code() const { return le32(&f.data[4]); }
    uint16_t index() const { return uint16_t(f.data[1] | (f.data[2] << 8)); }
    uint8_t sub() const { return f.data[3]; }
};

class Bench {
public:
    explicit Bench(bool boot = true)
    {
        hal_host_board_init(&board);
        hal_host_bind(&board);
        hal_host_can_loopback_init(&loop, &board.can);
        d.reset(new drive);
        drive_init(d.get());
        if (boot) {
            pass();
            frames.clear(); // the boot-up message
        }
    }
    ~Bench() { hal_host_bind(nullptr); }

    /** Re-run drive_init on the same board and NVM, as after a power cycle. */
    void power_cycle(bool boot = true)
    {
        hal_host_can_loopback_init(&loop, &board.can);
        board.can_open = false;
        d.reset(new drive);
        drive_init(d.get());
        frames.clear();
        if (boot)
            pass();
    }

    /** One background pass; collects what the drive sent into `frames`. */
    void pass()
    {
        drive_background(d.get());
        hal_can_frame f;
        while (hal_host_can_loopback_take(&loop, &f) == HAL_OK)
            frames.push_back(f);
    }

    void inject(const hal_can_frame &f) { ASSERT_EQ(hal_host_can_loopback_inject(&loop, &f), HAL_OK); }

    void advance_ms(double ms) { board.t_s += ms * 1e-3; }

    /** Advance the telemetry snapshot's tick counter (as the ISR would). */
    void tick(uint32_t n = 1)
    {
        d->snap.seq++;
        d->snap.tick += n;
        d->snap.seq++;
    }

    /** Send one SDO request to @p node and return the response to it (if any). */
    SdoReply sdo(const std::vector<uint8_t> &req, uint8_t node = kNode)
    {
        frames.clear();
        inject(frame(uint16_t(0x600u + node), req));
        pass();
        SdoReply r;
        for (const auto &f : frames)
            if (f.id == 0x580u + node) {
                r.got = true;
                r.f = f;
            }
        return r;
    }

    static std::vector<uint8_t> req(uint8_t cmd, uint16_t index, uint8_t sub, std::vector<uint8_t> data = {})
    {
        std::vector<uint8_t> b = {cmd, uint8_t(index), uint8_t(index >> 8), sub, 0, 0, 0, 0};
        for (size_t i = 0; i < data.size() && i < 4; i++)
            b[4 + i] = data[i];
        return b;
    }

    /** Expedited upload (initiate upload, ccs = 2). */
    SdoReply upload(uint16_t index, uint8_t sub) { return sdo(req(0x40, index, sub)); }

    /** Expedited download of @p data (1..4 bytes, size indicated). */
    SdoReply download(uint16_t index, uint8_t sub, const std::vector<uint8_t> &data)
    {
        uint8_t n = uint8_t(4 - data.size());
        return sdo(req(uint8_t(0x23 | (n << 2)), index, sub, data));
    }

    SdoReply download_f32(uint16_t index, uint8_t sub, float v) { return download(index, sub, bytes_f32(v)); }
    SdoReply download_u32(uint16_t index, uint8_t sub, uint32_t v) { return download(index, sub, bytes_u32(v)); }

    /** Expedited upload of a 4-byte value; fails the test on an abort. */
    uint32_t read_u32(uint16_t index, uint8_t sub)
    {
        SdoReply r = upload(index, sub);
        EXPECT_TRUE(r.got);
        EXPECT_FALSE(r.aborted()) << std::hex << r.abort_code();
        EXPECT_EQ(r.f.data[0] & 0xE3u, 0x43u) << "expected an expedited response with size";
        uint32_t n = 4u - ((r.f.data[0] >> 2) & 3u);
        uint32_t v = 0;
        for (uint32_t i = 0; i < n; i++)
            v |= uint32_t(r.f.data[4 + i]) << (8 * i);
        return v;
    }

    float read_f32(uint16_t index, uint8_t sub) { return f32_of(read_u32(index, sub)); }

    /** Full segmented upload; returns the bytes, or sets *abort. */
    std::vector<uint8_t> upload_segmented(uint16_t index, uint8_t sub, uint32_t *abort = nullptr)
    {
        std::vector<uint8_t> out;
        SdoReply r = upload(index, sub);
        if (abort)
            *abort = r.aborted() ? r.abort_code() : 0u;
        if (!r.got || r.aborted())
            return out;
        if ((r.f.data[0] & 0x02u) != 0u) { // expedited after all
            uint32_t n = (r.f.data[0] & 1u) ? 4u - ((r.f.data[0] >> 2) & 3u) : 4u;
            out.assign(r.f.data + 4, r.f.data + 4 + n);
            return out;
        }
        uint32_t size = le32(&r.f.data[4]);
        uint8_t t = 0;
        for (int guard = 0; guard < 100000; guard++) {
            SdoReply s = sdo({uint8_t(0x60 | (t << 4)), 0, 0, 0, 0, 0, 0, 0});
            if (!s.got || s.aborted()) {
                if (abort)
                    *abort = s.got ? s.abort_code() : 0xFFFFFFFFu;
                return out;
            }
            EXPECT_EQ((s.f.data[0] >> 5), 0u) << "upload segment response scs";
            EXPECT_EQ((s.f.data[0] >> 4) & 1u, t) << "response toggle";
            uint32_t n = 7u - ((s.f.data[0] >> 1) & 7u);
            out.insert(out.end(), s.f.data + 1, s.f.data + 1 + n);
            if (s.f.data[0] & 1u)
                break;
            t ^= 1u;
        }
        EXPECT_EQ(out.size(), size);
        return out;
    }

    const co_param *param(const char *name)
    {
        const co_param *p = co_od_find_name(&drive_od, name);
        EXPECT_NE(p, nullptr) << name;
        return p;
    }

    /** The raw bus value of every parameter: writable entries and configuration
     *  (for "nothing else changed" checks; status words and telemetry excluded). */
    std::vector<std::pair<std::string, uint32_t>> dump()
    {
        std::vector<std::pair<std::string, uint32_t>> out;
        for (uint32_t i = 0; i < CO_PARAM_COUNT; i++) {
            const co_param *p = &co_params[i];
            if (co_dtype_size(p->dtype) == 0 || !((p->flags & CO_F_WRITE) != 0 || p->bind == DRIVE_BIND_CFG))
                continue;
            co_num v;
            v.u = 0;
            co_od_read_num(&d->co, p, &v);
            out.emplace_back(p->name, v.u);
        }
        return out;
    }

    hal_host_board board{};
    hal_host_can_loopback loop{};
    std::unique_ptr<drive> d;
    std::vector<hal_can_frame> frames;
};

/** Names of the entries whose value differs between two dumps. */
inline std::vector<std::string> changed(const std::vector<std::pair<std::string, uint32_t>> &a,
                                        const std::vector<std::pair<std::string, uint32_t>> &b)
{
    std::vector<std::string> out;
    for (size_t i = 0; i < a.size() && i < b.size(); i++)
        if (a[i].second != b[i].second)
            out.push_back(a[i].first);
    return out;
}

} // namespace cotest
