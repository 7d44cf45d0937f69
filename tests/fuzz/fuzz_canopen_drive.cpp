// Fuzz harness 1: the drive's CANopen device, driven as a board drives it
// (drive_init, drive_isr, drive_background on the host HAL, frames through its
// CAN loopback), with the invariants of docs/fuzzing.md checked after every step.
//
// The input is a program: each step is one opcode byte and its operands
// (missing bytes read as 0, the program ends with the input or after
// kMaxSteps steps):
//   0 frame       id_hi id_lo dlc data[dlc]   any frame (id mod 0x800, dlc mod 9)
//   1 frame_to    kind dlc data[dlc]          to our node: NMT, SYNC, SDO, RPDO, master heartbeat
//   2 ticks       n s0 s1 s2 s3               n % 16 + 1 control ticks, the sample from s0..s3
//   3 pass                                    one background pass
//   4 sdo_write   w_hi w_lo how b0 b1 b2 b3   an expedited download to entry w % count, the
//                                             value b0..b3 (little-endian) or, by how, an edge
//                                             of the entry's range (docs/fuzzing.md)
//   5 sdo_read    w_hi w_lo                   an expedited upload of entry w % count
//   6 enable      halt                        controlword 0x06, 0x07, 0x0F (| 0x100 if halt odd)
//   7 time        ms                          the board's clock on by ms * 4 ms
//   8 bus_off     on                          the controller off (odd) or back on the bus (even)
//   9 power_cut   budget                      the next NVM writes land only budget * 8 bytes, a
//                                             save is asked for, then the power comes back
//  10 power_cycle                             drive_init again on the same board and NVM
//  11 save                                    0x1010:1 "save"
// An SDO download that the drive refuses must change no parameter (checked on
// the spot, step 4); the other invariants are checked after every step.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

extern "C" {
#include "dtc/drive.h"
#include "dtc/drive_co.h"
#include "dtc/param_table.h"
#include "hal_host/hal_host.h"
}

namespace {

constexpr uint8_t kNode = 1;
constexpr int kMaxSteps = 400;
constexpr double kRpmPerRadS = 60.0 / (2.0 * M_PI);

[[noreturn]] void violated(const std::string &what)
{
    std::fprintf(stderr, "fuzz_canopen_drive: invariant violated: %s\n", what.c_str());
    std::abort();
}

struct Input {
    const uint8_t *p;
    size_t n, at = 0;
    bool more() const { return at < n; }
    uint8_t u8() { return at < n ? p[at++] : 0u; }
    uint16_t u16() { return uint16_t(u8() << 8 | u8()); }
    uint32_t u32()
    {
        uint32_t v = 0;
        for (int i = 0; i < 4; i++)
            v |= uint32_t(u8()) << (8 * i);
        return v;
    }
};

struct Rig {
    hal_host_board board;
    hal_host_can_loopback loop;
    std::unique_ptr<drive> d;
    uint32_t seq = 0;

    Rig()
    {
        hal_host_board_init(&board);
        hal_host_bind(&board);
        boot();
    }
    ~Rig() { hal_host_bind(nullptr); }

    void boot()
    {
        hal_host_can_loopback_init(&loop, &board.can);
        board.can_open = false;
        board.nvm_write_budget = -1;
        d.reset(new drive);
        drive_init(d.get());
    }

    void drain()
    {
        hal_can_frame f;
        while (hal_host_can_loopback_take(&loop, &f) == HAL_OK) {
        }
    }

    void inject(const hal_can_frame &f) { (void)hal_host_can_loopback_inject(&loop, &f); }

    // One background pass; @return the last SDO response to our node, if any.
    bool pass(hal_can_frame *sdo_reply = nullptr)
    {
        drive_background(d.get());
        bool got = false;
        hal_can_frame f;
        while (hal_host_can_loopback_take(&loop, &f) == HAL_OK)
            if (f.id == 0x580 + kNode && sdo_reply != nullptr) {
                *sdo_reply = f;
                got = true;
            }
        return got;
    }

    void tick(const hal_sample &s)
    {
        hal_host_set_sample(&board, &s);
        drive_isr(d.get());
        board.t_s += 200e-6;
    }
};

hal_can_frame make_frame(uint16_t id, uint8_t dlc, Input &in)
{
    hal_can_frame f;
    std::memset(&f, 0, sizeof f);
    f.id = uint16_t(id & 0x7FFu);
    f.dlc = uint8_t(dlc % 9u);
    for (uint8_t i = 0; i < f.dlc; i++)
        f.data[i] = in.u8();
    return f;
}

hal_can_frame sdo_download(uint16_t index, uint8_t sub, uint32_t value, size_t len)
{
    hal_can_frame f;
    std::memset(&f, 0, sizeof f);
    f.id = 0x600 + kNode;
    f.dlc = 8;
    f.data[0] = uint8_t(0x23 | ((4 - len) << 2));
    f.data[1] = uint8_t(index);
    f.data[2] = uint8_t(index >> 8);
    f.data[3] = sub;
    for (int i = 0; i < 4; i++)
        f.data[4 + i] = uint8_t(value >> (8 * i));
    return f;
}

// The bus value of an entry as a double (its type's reading of the raw word).
double as_number(const co_param *p, co_num v)
{
    switch (p->dtype) {
    case CO_DT_REAL32:
        return double(v.f);
    case CO_DT_INTEGER8:
    case CO_DT_INTEGER16:
    case CO_DT_INTEGER32:
        return double(v.i);
    default:
        return double(v.u);
    }
}

bool readable_number(const co_param *p) { return (p->flags & CO_F_READ) && co_dtype_size(p->dtype) != 0; }

double read_number(Rig &r, const char *name)
{
    const co_param *p = co_od_find_name(&drive_od, name);
    if (p == nullptr)
        violated(std::string("no entry ") + name);
    co_num v;
    v.u = 0;
    if (co_od_read_num(&r.d->co, p, &v) != CO_ABORT_NONE)
        violated(std::string(name) + " unreadable");
    return as_number(p, v);
}

// Every parameter as a raw bus word, for "a refused write changes nothing"
// (the entries test_can_fuzz.cpp compares: writable or configuration, not the
// commands that read constants, not the error history).
std::vector<std::pair<const co_param *, uint32_t>> dump(Rig &r)
{
    std::vector<std::pair<const co_param *, uint32_t>> out;
    for (uint32_t i = 0; i < CO_PARAM_COUNT; i++) {
        const co_param *p = &co_params[i];
        if (!readable_number(p) || !((p->flags & CO_F_WRITE) != 0 || p->bind == DRIVE_BIND_CFG))
            continue;
        if (p->bind == DRIVE_BIND_FN && (p->flags & CO_F_PERSIST) == 0 && p->index != 0x2000 && p->index != 0x60FF &&
            p->index != 0x6042)
            continue;
        if (p->bind == CO_BIND_ERRHIST)
            continue;
        co_num v;
        v.u = 0;
        (void)co_od_read_num(&r.d->co, p, &v);
        out.emplace_back(p, v.u);
    }
    return out;
}

void check_invariants(Rig &r)
{
    // 1. No parameter outside its declared range or allowed set.
    for (uint32_t i = 0; i < CO_PARAM_COUNT; i++) {
        const co_param *p = &co_params[i];
        if (!readable_number(p) || ((p->flags & CO_F_LIMITS) == 0 && p->allowed == nullptr))
            continue;
        if (p->bind == CO_BIND_ERRHIST)
            continue; // 0x1003:0 reads the count of errors; its allowed set {0} is what a write may clear it to
        co_num v;
        v.u = 0;
        if (co_od_read_num(&r.d->co, p, &v) != CO_ABORT_NONE)
            continue; // e.g. an entry readable only in some states
        if (p->dtype == CO_DT_REAL32 && !std::isfinite(v.f))
            violated(std::string(p->name) + " is not a finite number");
        if (p->flags & CO_F_LIMITS) {
            double x = as_number(p, v), lo = as_number(p, p->min), hi = as_number(p, p->max);
            // A scaled REAL32 entry reads internal * k in float: its rounding
            // (a few ulps of the range) is not a value outside the range.
            double slack = p->dtype == CO_DT_REAL32 && p->k != 1.0f
                               ? 4.0 * double(FLT_EPSILON) * std::max(std::fabs(lo), std::fabs(hi))
                               : 0.0;
            lo -= slack;
            hi += slack;
            if (!(x >= lo && x <= hi))
                violated(std::string(p->name) + " = " + std::to_string(x) + " outside " + std::to_string(lo) + ".." +
                         std::to_string(hi));
        }
        if (p->allowed != nullptr) {
            bool in = false;
            for (uint8_t k = 0; k < p->n_allowed; k++)
                in = in || p->allowed[k] == v.u;
            if (!in)
                violated(std::string(p->name) + " = " + std::to_string(v.u) + " not an allowed value");
        }
    }
    // 2. The speed reference within its limits: the declared range, the
    //    envelope's top speed and the vl limits (every reference here is a bus target).
    double ref = read_number(r, "speed_ref_rpm");
    const co_param *decl = co_od_find_name(&drive_od, "speed_ref_rpm");
    double top = read_number(r, "overspeed_rad_s") / 1.1 * kRpmPerRadS;
    double vl_min = read_number(r, "vl_velocity_min"), vl_max = read_number(r, "vl_velocity_max");
    const double tol = 0.01; // rpm: float rounding of rpm <-> rad/s
    double mag = std::fabs(ref);
    if (vl_min > vl_max)
        violated("vl_velocity_min " + std::to_string(vl_min) + " above vl_velocity_max " + std::to_string(vl_max));
    if (mag > double(decl->max.f) + tol || ref < double(decl->min.f) - tol)
        violated("speed reference " + std::to_string(ref) + " rpm outside its declared range");
    if (mag > top * (1.0 + 1e-6) + tol)
        violated("speed reference " + std::to_string(ref) + " rpm above the top speed " + std::to_string(top));
    if (mag > vl_max + tol)
        violated("speed reference " + std::to_string(ref) + " rpm above vl_velocity_max " + std::to_string(vl_max));
    double floor_rpm = std::min({vl_min, vl_max, top, double(decl->max.f)});
    if (mag != 0.0 && mag < floor_rpm * (1.0 - 1e-6) - tol)
        violated("speed reference " + std::to_string(ref) + " rpm below vl_velocity_min " + std::to_string(vl_min));
}

void step(Rig &r, Input &in)
{
    switch (in.u8() % 12u) {
    case 0: {
        uint16_t id = in.u16();
        uint8_t dlc = in.u8();
        r.inject(make_frame(id, dlc, in));
        break;
    }
    case 1: {
        static const uint16_t ids[] = {0x000, 0x080, 0x600 + kNode, 0x200 + kNode, 0x77F, 0x600};
        uint16_t id = ids[in.u8() % (sizeof ids / sizeof ids[0])];
        uint8_t dlc = in.u8();
        r.inject(make_frame(id, dlc, in));
        break;
    }
    case 2: {
        int n = in.u8() % 16 + 1;
        uint8_t s[4] = {in.u8(), in.u8(), in.u8(), in.u8()};
        for (int k = 0; k < n; k++) {
            hal_sample x;
            std::memset(&x, 0, sizeof x);
            // currents up to +-25 A (a few reach the trip), a DC link about its 311 V
            x.ia_A = float(int8_t(s[0])) * 0.2f;
            x.ib_A = float(int8_t(s[1])) * 0.2f;
            x.ic_A = -x.ia_A - x.ib_A;
            x.vc1_V = 155.5f + float(int8_t(s[2])) * 0.5f;
            x.vc2_V = 155.5f + float(int8_t(s[3])) * 0.5f;
            x.speed_meas_valid = false;
            x.seq = ++r.seq;
            r.tick(x);
        }
        break;
    }
    case 3:
        r.pass();
        break;
    case 4: {
        const co_param *p = &co_params[in.u16() % CO_PARAM_COUNT];
        uint8_t how = in.u8();
        uint32_t v = in.u32();
        size_t size = co_dtype_size(p->dtype);
        size_t len = size == 0 ? 4 : size;
        switch (how % 8u) { // bias the value to the edges of the entry's range
        case 0:
            v = p->min.u;
            break;
        case 1:
            v = p->max.u;
            break;
        case 2:
            v = p->def.u;
            break;
        case 3:
            v = p->dtype == CO_DT_REAL32 ? [&] {
                float f = p->max.f * 1.0001f + 1.0f;
                uint32_t u;
                std::memcpy(&u, &f, 4);
                return u;
            }()
                                         : p->max.u + 1u;
            break;
        case 4:
            len = 1 + (v >> 30); // any length
            break;
        default:
            break;
        }
        r.pass(); // what is queued is handled first, so the dump is the state the write meets
        auto before = dump(r);
        r.inject(sdo_download(p->index, p->sub, v, len));
        hal_can_frame reply;
        if (r.pass(&reply) && reply.data[0] == 0x80) {
            auto after = dump(r);
            for (size_t i = 0; i < before.size(); i++)
                if (before[i].second != after[i].second)
                    violated(std::string("a refused write of ") + p->name + " changed " + before[i].first->name);
        }
        break;
    }
    case 5: {
        const co_param *p = &co_params[in.u16() % CO_PARAM_COUNT];
        hal_can_frame f;
        std::memset(&f, 0, sizeof f);
        f.id = 0x600 + kNode;
        f.dlc = 8;
        f.data[0] = 0x40;
        f.data[1] = uint8_t(p->index);
        f.data[2] = uint8_t(p->index >> 8);
        f.data[3] = p->sub;
        r.inject(f);
        r.pass();
        break;
    }
    case 6: {
        uint32_t halt = (in.u8() & 1u) ? 0x100u : 0u;
        for (uint32_t cw : {0x06u, 0x07u, 0x0Fu}) {
            r.inject(sdo_download(0x6040, 0, cw | halt, 2));
            r.pass();
        }
        break;
    }
    case 7:
        r.board.t_s += double(in.u8()) * 4e-3;
        break;
    case 8:
        hal_host_can_loopback_set_bus_off(&r.loop, (in.u8() & 1u) != 0);
        break;
    case 9:
        r.board.nvm_write_budget = long(in.u8()) * 8;
        r.inject(sdo_download(0x1010, 1, 0x65766173u, 4));
        r.pass();
        r.boot(); // the power comes back: boot on what landed
        break;
    case 10:
        r.boot();
        break;
    default:
        r.inject(sdo_download(0x1010, 1, 0x65766173u, 4));
        r.pass();
        break;
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    Rig r;
    Input in{data, size};
    r.pass(); // boot-up
    check_invariants(r);
    for (int k = 0; k < kMaxSteps && in.more(); k++) {
        step(r, in);
        check_invariants(r);
    }
    r.drain();
    return 0;
}
