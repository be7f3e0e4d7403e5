// The AMB currents of each output row of an offline run (timeseries.csv's amb_* columns): while
// powered the coils carry the command within the amplifier limit; after power loss the current
// held at the trigger falls as exp(-t/tau) (the flux decay's coil L/R) while the command goes
// on; and asking for the currents changes no observation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "controller_if/loop/offline_run.hpp"
#include "rt_core/amb_force.hpp"
#include "test_configs.hpp"

namespace ambdrop::offline_currents_test {
namespace {

struct Row {
  Observation obs;
  AmbCurrents currents;
};

TEST(OfflineCurrents, CoilCurrentsFollowTheCommandThenDecay) {
  const double tau = 2e-3;
  const Model model = BuildModel(testing::LoadTestConfig(
      "jarroux2019_industrial_pid.toml",
      {"simulation.duration_s=0.03", "trigger.time_s=0.02", "amb.nde.flux_decay.enabled=true",
       "amb.de.flux_decay.enabled=true"}));
  std::vector<Row> rows;
  const OfflineRunResult result =
      RunOfflineWithCurrents(model, [&](const Observation& o, const AmbCurrents& c) {
        rows.push_back({o, c});
      });
  ASSERT_EQ(result.status, StepStatus::kOk);
  ASSERT_GT(rows.size(), 500u);

  // The same observations as a run that does not ask for the currents, bit for bit.
  std::vector<Observation> plain;
  RunOffline(model, [&](const Observation& o) { plain.push_back(o); });
  ASSERT_EQ(plain.size(), rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    EXPECT_EQ(plain[r].time_s, rows[r].obs.time_s);
    EXPECT_EQ(plain[r].sensor_xy_m[0][1], rows[r].obs.sensor_xy_m[0][1]);
  }

  const double trigger_s = 0.02;
  const auto at_trigger = std::find_if(
      rows.begin(), rows.end(), [&](const Row& r) { return r.obs.time_s >= trigger_s - 1e-12; });
  ASSERT_NE(at_trigger, rows.end());
  for (std::size_t a = 0; a < 2; ++a) {
    const double limit = ControlCurrentLimit(model.params.ambs[a]);
    // y carries the weight: the levitated command is far from zero.
    EXPECT_GT(std::abs(rows[rows.size() / 3].currents.command_A[a][1]), 0.1);
    for (auto r = rows.begin(); r != at_trigger; ++r) {
      for (int axis = 0; axis < 2; ++axis) {
        EXPECT_EQ(r->currents.coil_A[a][axis],
                  std::clamp(r->currents.command_A[a][axis], -limit, limit));
      }
    }
    // After power loss: the held current, falling with the coils' time constant.
    const double held_A = at_trigger->currents.coil_A[a][1];
    EXPECT_GT(std::abs(held_A), 0.1);
    bool command_goes_on = false;
    for (auto r = at_trigger; r != rows.end(); ++r) {
      const double t = r->obs.time_s - at_trigger->obs.time_s;
      EXPECT_NEAR(r->currents.coil_A[a][1], held_A * std::exp(-t / tau), 1e-9 * std::abs(held_A))
          << "t = " << t;
      command_goes_on |= r->currents.command_A[a][1] != r->currents.coil_A[a][1];
    }
    EXPECT_TRUE(command_goes_on);
  }
}

}  // namespace
}  // namespace ambdrop::offline_currents_test
