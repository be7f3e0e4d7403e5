// The declared model against the rig (issue 24 item 7): a residual that no candidate removes is
// named by its channel, its shape in numbers and the key families that could explain it, and
// over several records of one rig what they share is said once.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "rt_core/model.hpp"
#include "test_configs.hpp"
#include "tools/fit/measured_record_maker.hpp"
#include "tools/fit/model_discrepancy.hpp"
#include "tools/fit/record_cost.hpp"
#include "tools/fit/residuals.hpp"

namespace ambdrop::model_discrepancy_test {
namespace {

constexpr const char* kRig = "jarroux2019_industrial_pid.toml";

std::vector<std::string> Timing() {
  return {"simulation.duration_s=0.25", "trigger.time_s=0.1"};
}

// A drop of the PID rig whose rotor loses `extra_rad_s2` more speed per second after the trigger
// than declared (a constant coast-down torque the declared model lacks), held against the
// declared model as a fit that found nothing would leave it.
RecordDiscrepancy DropWithExtraDeceleration(double extra_rad_s2, std::uint64_t seed) {
  const ModelParams declared = testing::LoadTestConfig(kRig, Timing());
  const double ip = BuildModel(declared).rotor.polar_inertia_kg_m2;
  std::vector<std::string> truth = Timing();
  truth.push_back("simulation.step_s=2.5e-6");
  if (extra_rad_s2 > 0.0) {
    truth.push_back("rotor.coast_down.enabled=true");
    truth.push_back("rotor.coast_down.constant_torque_N_m=" + std::to_string(extra_rad_s2 * ip));
  }
  MeasureOptions options;
  options.channels.current = false;
  options.channels.tdb_normal_force = false;
  options.channels.tdb_speed = false;
  options.speed_noise_rad_s = 0.01;
  options.seed = seed;
  const SyntheticMeasurement made =
      MakeMeasuredRecord(testing::LoadTestConfig(kRig, truth), options);
  const RecordCost cost(declared, made.measurement, made.record, RecordRunOptions{});
  const SimulatedRecord sim = cost.Simulate(declared);
  ResidualReport residual =
      ComputeResiduals(declared, made.measurement, made.record, sim, cost.compare_from_s());
  const std::vector<double> sse = cost.ChannelSse(cost.Residual(sim));
  double total = 0.0;
  for (const double v : sse) total += v;
  for (std::size_t c = 0; c < sse.size(); ++c) residual.channels[c].cost_share = sse[c] / total;
  Selection nothing_removes_it;
  nothing_removes_it.verdict = extra_rad_s2 > 0.0 ? "unexplained" : "no_effect_needed";
  RecordDiscrepancy r;
  r.record = "drop_" + std::to_string(seed);
  r.verdict = nothing_removes_it.verdict;
  r.discrepancy = DescribeDiscrepancy(declared, made.measurement, made.record, sim, residual,
                                      nothing_removes_it);
  r.signatures = residual.signatures;
  return r;
}

// The TDB friction slows both alike; what the record adds is T0 / Ip on the speed's slope.
TEST(ModelDiscrepancy, ASpeedThatFallsFasterIsNamedWithItsRateAndTheKeysThatSetIt) {
  const double extra = 40.0;  // rad/s^2
  const RecordDiscrepancy r = DropWithExtraDeceleration(extra, 3);
  const Discrepancy& d = r.discrepancy;
  std::printf("%s (%s, %.0f %% of the cost): %s\n", d.channel.c_str(), d.phase.c_str(),
              100 * d.share, d.shape.c_str());
  ASSERT_TRUE(d.dominant);
  EXPECT_EQ(d.channel, "w_rotor");
  EXPECT_EQ(d.phase, "after_trigger");
  EXPECT_GT(d.share, 0.5);
  EXPECT_NEAR(d.record_value - d.model_value, -extra, 0.1 * extra);
  EXPECT_NE(d.shape.find("faster than the model's"), std::string::npos) << d.shape;
  EXPECT_TRUE(std::any_of(d.key_families.begin(), d.key_families.end(), [](const std::string& f) {
    return f.rfind("rotor.coast_down", 0) == 0;
  }));
}

TEST(ModelDiscrepancy, RecordsOfOneRigShareWhatTheModelLacks) {
  const std::vector<RecordDiscrepancy> two = {DropWithExtraDeceleration(30.0, 3),
                                              DropWithExtraDeceleration(60.0, 4)};
  const std::vector<std::string> shared = SharedDiscrepancies(two);
  for (const std::string& line : shared) std::printf("shared: %s\n", line.c_str());
  ASSERT_FALSE(shared.empty());
  EXPECT_NE(shared.front().find("'w_rotor' (after_trigger), the record lower than the model"),
            std::string::npos)
      << shared.front();
  // A record of the declared rig itself shares nothing of it.
  std::vector<RecordDiscrepancy> three = two;
  three.push_back(DropWithExtraDeceleration(0.0, 5));
  for (const std::string& line : SharedDiscrepancies(three)) {
    EXPECT_EQ(line.find("w_rotor"), std::string::npos) << line;
  }
}

}  // namespace
}  // namespace ambdrop::model_discrepancy_test
