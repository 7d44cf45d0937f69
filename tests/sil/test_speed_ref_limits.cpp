// A master asks for 2500 rpm (and for 3000 rpm, the most the CiA 402 objects
// take) through each of SDO 0x60FF, SDO 0x6042 and the RPDO while the drive
// runs a scenario at 500 rpm. Judged on the plant (the sample's speed_meas is
// the shaft's true speed in the SIL) and on every object that shows a speed:
// each stays inside its declared range at every tick, and the motor never
// runs faster than the envelope's top speed, overspeed_rad_s / 1.1 (docs/
// faults.md: 310 rad/s / 1.1 = 2691 rpm). A vl minimum above the maximum is
// refused on the way (abort 0x06090036) and changes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

extern "C" {
#include "dtc/drive.h"
#include "dtc/drive_co.h"
#include "dtc/param_table.h"
#include "hal_host/hal_host.h"
#include "sim/sim.h"
}
#include "sim_test_util.hpp"

namespace {

constexpr uint8_t kNode = 1;
constexpr double kRpmPerRadS = 60.0 / (2.0 * M_PI);
constexpr double kTopRpm = 310.0 / 1.1 * kRpmPerRadS; // 2691.2 rpm
constexpr uint32_t kAbortMaxBelowMin = 0x06090036u;

enum class Via { Sdo60FF, Sdo6042, Rpdo };

struct Master {
    Via via = Via::Sdo60FF;
    int target_rpm = 2500;
    hal_host_can_loopback loop{};
    hal_host_can_backend backend{};
    long tick = 0;
    double max_true_rpm = 0.0, last_true_rpm = 0.0;
    double ref_before_bad_write = NAN, ref_after_bad_write = NAN;
    std::vector<uint32_t> aborts;
    std::string out_of_range; // the first object found outside its declared range
    double max_ref_rpm = 0.0;

    void send(uint16_t id, std::vector<uint8_t> data)
    {
        hal_can_frame f;
        std::memset(&f, 0, sizeof f);
        f.id = id;
        f.dlc = uint8_t(data.size());
        for (size_t i = 0; i < data.size(); i++)
            f.data[i] = data[i];
        ASSERT_EQ(hal_host_can_loopback_inject(&loop, &f), HAL_OK);
    }
    void sdo_write(uint16_t index, uint8_t sub, uint32_t v, uint8_t len)
    {
        send(0x600 + kNode, {uint8_t(0x23 | ((4 - len) << 2)), uint8_t(index), uint8_t(index >> 8), sub, uint8_t(v),
                             uint8_t(v >> 8), uint8_t(v >> 16), uint8_t(v >> 24)});
    }
};

double bus_value(const co_param *p, const co_num &v)
{
    switch (p->dtype) {
    case CO_DT_REAL32:
        return double(v.f);
    case CO_DT_UNSIGNED32:
    case CO_DT_UNSIGNED16:
    case CO_DT_UNSIGNED8:
        return double(v.u);
    default:
        return double(v.i);
    }
}

void check_ranges(Master &m, drive *d)
{
    for (const char *name : {"speed_ref_rpm", "target_velocity", "vl_target_velocity", "vl_velocity_demand",
                             "vl_velocity_min", "vl_velocity_max"}) {
        const co_param *p = co_od_find_name(&drive_od, name);
        ASSERT_NE(p, nullptr) << name;
        // vl_velocity_demand (0x6043) has no limits of its own: it shows the
        // ramped reference, judged against speed_ref_rpm's declared range.
        const co_param *range = (p->flags & CO_F_LIMITS) ? p : co_od_find_name(&drive_od, "speed_ref_rpm");
        co_num v, lo, hi;
        v.u = 0;
        ASSERT_EQ(co_od_read_num(&d->co, p, &v), CO_ABORT_NONE) << name;
        lo = range->min;
        hi = range->max;
        double x = bus_value(p, v);
        if (name == std::string("speed_ref_rpm"))
            m.max_ref_rpm = std::max(m.max_ref_rpm, std::fabs(x));
        if (!(x >= bus_value(range, lo) && x <= bus_value(range, hi)) && m.out_of_range.empty())
            m.out_of_range = std::string(name) + " = " + std::to_string(x) + " at tick " + std::to_string(m.tick);
    }
}

void on_tick(void *user, double t_s, drive *d)
{
    Master &m = *static_cast<Master *>(user);
    (void)t_s;
    if (m.tick == 0) {
        m.send(0x000, {0x01, kNode}); // operational: RPDOs are applied
        if (m.target_rpm > 2610)
            m.sdo_write(0x6046, 2, 3000u, 4); // vl maximum up to what the objects take
    } else if (m.tick == 2500) {          // 0.5 s: a minimum of 200 rpm, then a maximum below it
        m.ref_before_bad_write = d->speed_ref_rad_s * kRpmPerRadS;
        m.sdo_write(0x6046, 1, 200u, 4);
        m.sdo_write(0x6046, 2, 100u, 4);
    } else if (m.tick == 2502) {
        m.ref_after_bad_write = d->speed_ref_rad_s * kRpmPerRadS;
        m.sdo_write(0x6046, 1, 0u, 4); // back to no minimum
    } else if (m.tick == 5000) { // 1.0 s: the master's target
        uint32_t t = uint32_t(m.target_rpm);
        switch (m.via) {
        case Via::Sdo60FF:
            m.sdo_write(0x60FF, 0, t, 4);
            break;
        case Via::Sdo6042:
            m.sdo_write(0x6042, 0, t & 0xFFFFu, 2);
            break;
        case Via::Rpdo: // controlword 0x000F (enable operation, the state it is in), then the velocity
            m.send(0x200 + kNode, {0x0F, 0x00, uint8_t(t), uint8_t(t >> 8), uint8_t(t >> 16), uint8_t(t >> 24)});
            break;
        }
    }
    hal_can_frame f;
    while (hal_host_can_loopback_take(&m.loop, &f) == HAL_OK)
        if (f.id == 0x580 + kNode && f.data[0] == 0x80)
            m.aborts.push_back(uint32_t(f.data[4]) | (uint32_t(f.data[5]) << 8) | (uint32_t(f.data[6]) << 16) |
                               (uint32_t(f.data[7]) << 24));
    check_ranges(m, d);
    m.last_true_rpm = d->snap.omega_meas_rad_s * kRpmPerRadS;
    m.max_true_rpm = std::max(m.max_true_rpm, std::fabs(m.last_true_rpm));
    m.tick++;
}

sim_result run(Master &m)
{
    // The ideal inverter, as field_weakening.ini: the envelope at the top speed is proven on it.
    auto l = simtest::parse_text("[sim]\nduration_s = 4.6\n[controller]\nname = rbfn\n[reference]\nstep = 0.3 500\n"
                                 "[inverter]\ndead_time_s = 0\nv_on_V = 0\n[control]\nv_drop_V = 0\n");
    EXPECT_EQ(l.rc, 0) << l.error;
    hal_host_can_loopback_init(&m.loop, &m.backend);
    sim_options o;
    sim_options_default(&o);
    o.can = &m.backend;
    o.on_tick = on_tick;
    o.user = &m;
    sim_result res;
    std::memset(&res, 0, sizeof res);
    sim_run(l.sc.get(), &o, &res);
    return res;
}

const char *name_of(Via v) { return v == Via::Sdo60FF ? "SDO 0x60FF" : v == Via::Sdo6042 ? "SDO 0x6042" : "RPDO"; }

} // namespace

TEST(SpeedRefLimits, ATargetOf2500ThroughEachObjectStaysInsideTheDeclaredRangesAndTheEnvelope)
{
    for (Via via : {Via::Sdo60FF, Via::Sdo6042, Via::Rpdo}) {
        SCOPED_TRACE(name_of(via));
        Master m;
        m.via = via;
        sim_result r = run(m);
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        EXPECT_EQ(r.metrics.faults, 0u);
        EXPECT_EQ(m.out_of_range, "");
        EXPECT_LT(m.max_true_rpm, kTopRpm) << "the motor stays below the envelope's top speed";
        EXPECT_NEAR(m.last_true_rpm, 2500.0, 15.0) << "and follows the master's 2500 rpm";
        EXPECT_NEAR(m.max_ref_rpm, 2500.0, 0.01);
        // The refused minimum: one abort 0x06090036, the reference as it was.
        EXPECT_EQ(std::count(m.aborts.begin(), m.aborts.end(), kAbortMaxBelowMin), 1);
        EXPECT_EQ(m.ref_before_bad_write, m.ref_after_bad_write);
        std::printf("%s: 2500 rpm asked, true speed %.1f rpm at the end, at most %.1f rpm (top speed %.1f rpm)\n",
                    name_of(via), m.last_true_rpm, m.max_true_rpm, kTopRpm);
    }
}

// 3000 rpm (vl maximum raised to 3000): the reference in force stops at the
// top speed, and the motor with it.
TEST(SpeedRefLimits, TheMostTheObjectsTakeIsHeldAtTheTopSpeed)
{
    for (Via via : {Via::Sdo60FF, Via::Rpdo}) {
        SCOPED_TRACE(name_of(via));
        Master m;
        m.via = via;
        m.target_rpm = 3000;
        sim_result r = run(m);
        ASSERT_EQ(r.status, SIM_OK) << r.error;
        EXPECT_EQ(r.metrics.faults, 0u);
        EXPECT_EQ(m.out_of_range, "");
        EXPECT_NEAR(m.max_ref_rpm, kTopRpm, 0.01) << "the reference in force is the top speed";
        // The speed loop overshoots the end of its ramp by well under 1 % (15 rpm
        // here), far below the overspeed trip at 310 rad/s (2960 rpm), then holds.
        EXPECT_LT(m.max_true_rpm, 1.01 * kTopRpm);
        EXPECT_NEAR(m.last_true_rpm, kTopRpm, 10.0);
        std::printf("%s: 3000 rpm asked, true speed %.1f rpm at the end, at most %.1f rpm (top speed %.1f rpm)\n",
                    name_of(via), m.last_true_rpm, m.max_true_rpm, kTopRpm);
    }
}
