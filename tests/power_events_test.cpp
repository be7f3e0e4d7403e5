// Power can fail partly and come back: after a dip the reference controller lifts the rotor off
// its TDBs again; when one AMB fails only its end drops; when only the vertical axes fail the
// horizontal ones keep the rotor centred.
#include <gtest/gtest.h>

#include <cmath>

#include "controller_if/boundary/power_state.hpp"
#include "controller_if/loop/offline_run.hpp"
#include "rt_core/model.hpp"
#include "test_configs.hpp"

namespace ambdrop::power_events_test {
namespace {

struct Trace {
  Observation last;
  double de_peak_force_N = 0.0;
  double nde_peak_force_N = 0.0;
};

Trace RunScenario(std::vector<std::string> overrides) {
  overrides.push_back("simulation.duration_s=0.6");
  const Model model =
      BuildModel(testing::LoadTestConfig("jarroux2019_industrial_pid.toml", overrides));
  Trace t;
  const OfflineRunResult r = RunOffline(model, [&](const Observation& o) {
    t.last = o;
    // TDBs in model order: "de" then "nde".
    t.de_peak_force_N = std::max(t.de_peak_force_N, o.tdb[0].normal_force_N);
    t.nde_peak_force_N = std::max(t.nde_peak_force_N, o.tdb[1].normal_force_N);
  });
  EXPECT_EQ(r.status, StepStatus::kOk) << r.failure_message;
  return t;
}

TEST(PowerEvents, ReLevitationAfterAPowerDip) {
  const Trace t = RunScenario({"trigger.restore_time_s=0.24"});
  EXPECT_GT(t.de_peak_force_N, 1000.0);  // it did land on the TDBs
  // 0.36 s after power returned it floats again near the centre, touching nothing.
  EXPECT_EQ(t.last.tdb[0].normal_force_N, 0.0);
  EXPECT_EQ(t.last.tdb[1].normal_force_N, 0.0);
  EXPECT_LT(std::abs(t.last.sensor_xy_m[0][1]), 10e-6);
  EXPECT_LT(std::abs(t.last.sensor_xy_m[1][1]), 10e-6);
}

TEST(PowerEvents, OneAmbFailsOnlyItsEndDrops) {
  const Trace t = RunScenario({"trigger.ambs=[\"de\"]"});
  EXPECT_GT(t.de_peak_force_N, 100.0);
  EXPECT_EQ(t.nde_peak_force_N, 0.0);
  // The drive still runs: the spin speed is held.
  EXPECT_NEAR(t.last.spin_speed_rad_s, 680.67840827778852, 1e-9);
  EXPECT_LT(t.last.tdb_journal_xy_m[0][1], -0.2e-3);  // DE journal on its TDB
}

TEST(PowerEvents, VerticalAxesFailHorizontalStayCentred) {
  const Trace t = RunScenario({"trigger.axes=\"y\""});
  EXPECT_GT(t.de_peak_force_N, 100.0);
  EXPECT_LT(t.last.tdb_journal_xy_m[0][1], -0.2e-3);
  // x is still controlled: the journal rests at the bottom, not rolled off to one side.
  EXPECT_LT(std::abs(t.last.tdb_journal_xy_m[0][0]), 0.05e-3);
}

TEST(PowerState, FrozenCurrentsAndFluxDecay) {
  ModelParams p = testing::LoadTestConfig("jarroux2019_industrial_pid.toml",
                                          {"amb.de.flux_decay.enabled=true"});
  const Model model = BuildModel(p);
  PowerState power(model);
  ControlInput in;
  in.amb[0].current_A = {0.5, -1.5};
  PowerEvent fail;
  fail.amb_mask = 1u;  // "de" only
  fail.axis_x = false;
  fail.motor = false;
  power.Apply(fail, 100, in);
  in.amb[0].current_A = {2.0, 3.0};  // the controller moves on
  power.Fill(100 + 400, &in);        // 2 ms = one time constant later
  EXPECT_TRUE(in.motor_on);
  EXPECT_EQ(in.amb[0].current_A[0], 2.0);   // x still powered: the controller's current
  EXPECT_EQ(in.amb[0].current_A[1], -1.5);  // y frozen at the failure
  EXPECT_EQ(in.amb[0].force_scale[0], 1.0);
  EXPECT_NEAR(in.amb[0].force_scale[1], std::exp(-2.0), 1e-12);
  EXPECT_EQ(in.amb[1].force_scale[1], 1.0);  // nde untouched
  PowerEvent back = fail;
  back.restore = true;
  power.Apply(back, 600, in);
  power.Fill(600, &in);
  EXPECT_EQ(in.amb[0].force_scale[1], 1.0);
  EXPECT_EQ(power.events(), 2);
}

}  // namespace
}  // namespace ambdrop::power_events_test
