// A duty that uses the new plant features together (host_sim/scenarios/
// pump_duty.ini: real inverter, Coulomb + fan load, heating ramps of Rs and
// Rr, a supply sag, a load step): it must run to the end without a fault or
// a runaway, and the speed-controlled runs must end near the reference.
#include <gtest/gtest.h>

#include <cmath>

#include "sim_test_util.hpp"

TEST(Duty, PumpDutyRunsWithoutFaultOrRunaway)
{
    auto l = simtest::load_scenario(simtest::source_path("host_sim/scenarios/pump_duty.ini"));
    ASSERT_EQ(l.rc, 0) << l.error;
    // The file relies on the [inverter] defaults: the real inverter.
    EXPECT_DOUBLE_EQ(l.sc->plant.inverter.dead_time_s, 2e-6);
    EXPECT_DOUBLE_EQ(l.sc->plant.inverter.v_on_V, 1.0);
    for (int ctl : { SCENARIO_CTL_IP, SCENARIO_CTL_NOMINAL, SCENARIO_CTL_RBFN }) {
        sim_options o;
        sim_options_default(&o);
        o.controller = ctl;
        sim_result res;
        ASSERT_EQ(sim_run(l.sc.get(), &o, &res), SIM_OK) << res.error;
        const sim_metrics &m = res.metrics;
        EXPECT_EQ(m.faults, 0u) << ctl;
        EXPECT_FALSE(m.runaway) << ctl;
        EXPECT_LT(m.speed_true_max_abs_rpm, 1100.0) << ctl;
        if (ctl != SCENARIO_CTL_NOMINAL) {
            EXPECT_NEAR(m.speed_true_end_rpm, 1000.0, 20.0) << ctl;
            EXPECT_LT(m.steady_error_rpm, 20.0) << ctl;
        }
        // The fan load is there: the final torque is well above the 4 N m step alone.
        EXPECT_GT(m.te_final_nm, 10.0) << ctl;
    }
}
