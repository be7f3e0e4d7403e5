// The in-process reference controller levitates the seed-000 rotor on its electromagnets
// (configs/jarroux2019_industrial_pid.toml) until the power fails, then the rotor drops; flux
// decay after the failure delays the drop.
#include <gtest/gtest.h>

#include <cmath>

#include "controller_if/controller/pid_controller.hpp"
#include "controller_if/loop/offline_run.hpp"
#include "rt_core/model.hpp"
#include "test_configs.hpp"

namespace ambdrop::reference_controller_test {
namespace {

struct DropTrace {
  double max_levitated_m = 0.0;  // largest |y| at the sensors before the trigger
  double first_contact_s = -1.0;
  double fall_after_1ms_m = 0.0;  // DE sensor y change from the trigger to 1 ms after it
};

DropTrace RunDrop(const std::vector<std::string>& overrides) {
  std::vector<std::string> all = {"simulation.duration_s=0.25"};
  all.insert(all.end(), overrides.begin(), overrides.end());
  const Model model = BuildModel(testing::LoadTestConfig("jarroux2019_industrial_pid.toml", all));
  DropTrace trace;
  const double trigger = model.params.trigger.time_s;
  double y_at_trigger = 0.0;
  const OfflineRunResult r = RunOffline(model, [&](const Observation& o) {
    if (std::abs(o.time_s - trigger) < 1e-9) y_at_trigger = o.sensor_xy_m[0][1];
    if (std::abs(o.time_s - trigger - 1e-3) < 1e-9) {
      trace.fall_after_1ms_m = y_at_trigger - o.sensor_xy_m[0][1];
    }
    if (o.time_s < trigger) {
      for (int s = 0; s < 2; ++s) {
        trace.max_levitated_m = std::max(trace.max_levitated_m, std::abs(o.sensor_xy_m[s][1]));
      }
    } else if (trace.first_contact_s < 0 && o.tdb[0].normal_force_N > 0.0) {
      trace.first_contact_s = o.time_s;
    }
  });
  EXPECT_EQ(r.status, StepStatus::kOk) << r.failure_message;
  return trace;
}

TEST(ReferenceController, LevitatesThenTheRotorDrops) {
  const DropTrace t = RunDrop({});
  EXPECT_LT(t.max_levitated_m, 2e-6);  // held within 2 um of the magnetic centre (noise on)
  ASSERT_GT(t.first_contact_s, 0.2);
  // Free fall over the 0.25 mm TDB clearance takes sqrt(2c/g) = 7.1 ms.
  EXPECT_NEAR(t.first_contact_s - 0.2, std::sqrt(2 * 0.25e-3 / 9.81), 1.5e-3);
}

TEST(ReferenceController, FluxDecayHoldsTheRotorUpAtFirst) {
  // Without flux the rotor falls freely: g t^2 / 2 = 4.9 um after 1 ms. With the field fading
  // over tau = 2 ms the magnets still carry most of the weight then.
  const DropTrace free_fall = RunDrop({});
  EXPECT_NEAR(free_fall.fall_after_1ms_m, 9.81 * 1e-6 / 2, 1.5e-6);
  const DropTrace fading =
      RunDrop({"amb.de.flux_decay.enabled=true", "amb.nde.flux_decay.enabled=true"});
  EXPECT_LT(fading.fall_after_1ms_m, 0.5 * free_fall.fall_after_1ms_m);
}

TEST(PidAxis, PushesBackAndIntegratesAwayAStaticError) {
  PidParams p;
  p.kp = 2.0;
  p.ki_per_s = 50.0;
  p.kd_s = 1e-3;
  p.derivative_filter_s = 1e-4;
  PidAxis axis(p, 5e-5, 0.0, 100.0);
  const double first = axis.Update(10e-6);
  EXPECT_LT(first, 0.0);  // rotor high → current that pulls it down
  double later = first;
  for (int k = 0; k < 2000; ++k) later = axis.Update(10e-6);
  EXPECT_LT(later, first);  // the integral keeps growing while the error stays
  EXPECT_NEAR(axis.integral_V(), -50.0 * 20000.0 * 10e-6 * 2001 * 5e-5, 1e-9);
}

}  // namespace
}  // namespace ambdrop::reference_controller_test
