// The opt-in settled start (simulation.settle_s, issue 24 item 6): the in-process closed loop
// runs before t = 0, so the run starts on its own steady state (here the synchronous orbit of
// an unbalance) instead of the levitated equilibrium, and `fit` starts its closed-loop runs the
// same way as `sim`.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "controller_if/loop/offline_run.hpp"
#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"
#include "test_configs.hpp"
#include "tools/fit/measured_record_maker.hpp"
#include "tools/fit/record_cost.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop::settled_start_test {
namespace {

constexpr const char* kRig = "jarroux2019_industrial_pid.toml";
constexpr double kSpin_rad_s = 680.67840827778852;  // the rig's 6500 rpm

// A static unbalance of 1 g m at mid-span (about G2.5 for this 200 kg rotor at 6500 rpm).
std::vector<std::string> Unbalanced(double settle_s) {
  return {"trigger.enabled=false",
          "simulation.duration_s=0.06",
          "simulation.settle_s=" + std::to_string(settle_s),
          "unbalance.u.position_m=0.55",
          "unbalance.u.mass_kg=1.0",
          "unbalance.u.eccentricity_m=1e-3",
          "unbalance.u.phase_rad=0.0"};
}

// The rotor's x at the DE sensor plane, one row per output interval.
std::vector<double> SensorX(const ModelParams& params, OfflineRunResult* result) {
  const Model model = BuildModel(params);
  std::vector<double> x;
  *result = RunOffline(model, [&](const Observation& o) { x.push_back(o.sensor_xy_m[1][0]); });
  return x;
}

// How far the orbit over rows [from, from + n) is from the one `shift` rows later, relative to
// the later one's amplitude.
double OrbitChange(const std::vector<double>& x, std::size_t from, std::size_t n,
                   std::size_t shift) {
  double diff = 0.0, amplitude = 0.0;
  for (std::size_t j = from; j < from + n; ++j) {
    diff = std::max(diff, std::abs(x[j] - x[j + shift]));
    amplitude = std::max(amplitude, std::abs(x[j + shift]));
  }
  return diff / amplitude;
}

TEST(SettledStart, StartsOnTheSteadyOrbit) {
  const ModelParams rig = testing::LoadTestConfig(kRig, Unbalanced(0.0));
  const double row_s = rig.simulation.output_interval_s;
  // Whole revolutions apart, to the nearest row: 40 ms is 4.33 revolutions, so take 4.
  const double revolution_s = 2.0 * std::numbers::pi / kSpin_rad_s;
  const auto rows = [&](double s) { return static_cast<std::size_t>(std::llround(s / row_s)); };
  const std::size_t one_rev = rows(revolution_s);
  const std::size_t four_revs = rows(4.0 * revolution_s);

  OfflineRunResult cold;
  const std::vector<double> from_equilibrium = SensorX(rig, &cold);
  ASSERT_EQ(cold.status, StepStatus::kOk) << cold.failure_message;
  EXPECT_EQ(cold.settle_steps, 0);
  // From the equilibrium the orbit still builds up over the first revolutions.
  const double cold_change = OrbitChange(from_equilibrium, 0, one_rev, four_revs);

  OfflineRunResult warm;
  const std::vector<double> settled =
      SensorX(testing::LoadTestConfig(kRig, Unbalanced(0.4)), &warm);
  ASSERT_EQ(warm.status, StepStatus::kOk) << warm.failure_message;
  EXPECT_NEAR(static_cast<double>(warm.settle_steps) * rig.simulation.step_s, 0.4, 1e-9);
  const double warm_change = OrbitChange(settled, 0, one_rev, four_revs);
  std::printf(
      "orbit change over 4 revolutions from t = 0: equilibrium start %.3g, settled %.3g "
      "(last revolution of the settling: %.3g m)\n",
      cold_change, warm_change, warm.settle_last_change_m);
  EXPECT_GT(cold_change, 0.5);
  // What is left is the controller answering its sensors' noise.
  EXPECT_LT(warm_change, 0.1);
  EXPECT_LT(warm.settle_last_change_m, 0.05 * *std::max_element(settled.begin(), settled.end()));
}

// The unbalanced rig (settled for `settle_s`) with its power failing at 0.05 s, and a
// displacement-only record of it.
std::vector<std::string> Dropped(double settle_s) {
  std::vector<std::string> truth = Unbalanced(settle_s);
  truth.push_back("trigger.enabled=true");
  truth.push_back("trigger.time_s=0.05");
  return truth;
}
SyntheticMeasurement DisplacementRecord(const std::vector<std::string>& truth) {
  MeasureOptions options;
  options.channels.current = false;
  return MakeMeasuredRecord(testing::LoadTestConfig(kRig, truth), options);
}

// A record made from the settled rig: `fit` runs the declared closed loop from time 0 as `sim`
// does, so with the same settle_s its levitated prediction follows the record's orbit, and
// without it the prediction is still building its orbit while the record's is steady.
TEST(SettledStart, TheFitsClosedLoopSettlesAsSimDoes) {
  const std::vector<std::string> truth = Dropped(0.4);
  const SyntheticMeasurement made = DisplacementRecord(truth);
  const auto levitated_rms = [&](double settle_s) {
    std::vector<std::string> declared = truth;
    declared.push_back("simulation.settle_s=" + std::to_string(settle_s));
    const SimulatedRecord sim = SimulateOnRecord(testing::LoadTestConfig(kRig, declared),
                                                 made.measurement, made.record, {});
    EXPECT_TRUE(sim.closed_loop);
    EXPECT_EQ(sim.failure, "");
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t c = 0; c < made.measurement.channels.size(); ++c) {
      if (made.measurement.channels[c].quantity != MeasuredQuantity::kDisplacement) continue;
      for (std::size_t j = 0; j < made.record.time_s.size() && made.record.time_s[j] < 0.05; ++j) {
        const double e = made.record.values[c][j] - sim.values[c][j];
        sum += e * e;
        ++n;
      }
    }
    return std::sqrt(sum / static_cast<double>(n));
  };
  const double settled = levitated_rms(0.4);
  const double cold = levitated_rms(0.0);
  std::printf(
      "levitated displacement rms against the settled record: settled %.3g m, from the "
      "equilibrium %.3g m\n",
      settled, cold);
  // The record's sensors are noisy and quantised (0.1 um); the prediction is neither.
  EXPECT_LT(settled, 0.35e-6);
  EXPECT_GT(cold, 3.0 * settled);
}

// A candidate model that stops while settling (here at an excursion bound it cannot keep)
// predicts nothing of the record: every row NaN, and the fit's cost is the unreached one (the
// run once returned no rows at all, and the fit read past them).
TEST(SettledStart, AModelThatStopsWhileSettlingReachesNoRow) {
  const std::vector<std::string> truth = Dropped(0.0);
  const SyntheticMeasurement made = DisplacementRecord(truth);
  std::vector<std::string> declared = truth;
  declared.push_back("simulation.settle_s=0.2");
  declared.push_back("simulation.max_excursion_over_clearance=0.001");
  const ModelParams params = testing::LoadTestConfig(kRig, declared);
  const SimulatedRecord sim = SimulateOnRecord(params, made.measurement, made.record, {});
  EXPECT_THAT(sim.failure, ::testing::HasSubstr("while settling"));
  ASSERT_EQ(sim.values.size(), made.measurement.channels.size());
  for (const std::vector<double>& channel : sim.values) {
    ASSERT_EQ(channel.size(), made.record.time_s.size());
    EXPECT_TRUE(
        std::all_of(channel.begin(), channel.end(), [](double v) { return std::isnan(v); }));
  }
  const RecordCost cost(params, made.measurement, made.record, {});
  const Eigen::VectorXd r = cost.Residual(sim);
  EXPECT_EQ(r, cost.Unreached());
  EXPECT_GT(r.norm(), 0.0);
}

TEST(SettledStart, NeedsTheInProcessController) {
  try {
    LoadConfigFromString("base = \"" + testing::ConfigPath("jarroux2019_industrial.toml") +
                             "\"\n[simulation]\nsettle_s = 0.1\n",
                         "settle.toml");
    ADD_FAILURE() << "loaded";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("settle.toml:3: key 'simulation.settle_s': "
                                               "expected 0 unless [controller] kind is"));
  }
}

}  // namespace
}  // namespace ambdrop::settled_start_test
