// measurement.trigger_state = "record" on a record of the independent generator (tools/truth,
// which shares no code with ambdrop): its flexible, magnet-biased rig, through the rig's
// translation (tests/truth/flexible_pm_b.toml) as a user would take it. Its record is made
// with exact channels (ambdrop_truth --exact-record: the controller still reads noisy sensors,
// so the rotor jitters as on the rig, but the record shows that motion without noise), so
// that what is left is the estimate's own error: a state fitted only where the sensors' shapes
// see it left the bending modes at the model's own jitter and the drop's first 8 ms 3.6 % off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "drop_run.hpp"
#include "io/config/config_loader.hpp"
#include "io/files/measured_record_si.hpp"
#include "record_files.hpp"
#include "rig.hpp"
#include "scratch_directory.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop::truth_lead_estimate_test {
namespace {

// The first 8 ms after the trigger of every displacement channel (before the first impact,
// where the rotor has fallen 80 to 140 um): the RMS error against the distance fallen.
double EarlyDropError(std::uint64_t seed) {
  const std::string source = AMBDROP_SOURCE_DIR;
  const ambdrop_truth::Rig rig =
      ambdrop_truth::ReadRig(source + "/tools/truth/rigs/flexible_pm_b.json");
  ambdrop_truth::RunOptions options;
  options.exact_record = true;
  const ambdrop_truth::RunResult run = ambdrop_truth::RunDrop(rig, seed, options);
  EXPECT_TRUE(run.finite);
  const testing::ScratchDirectory dir("truth_lead_estimate");
  const std::filesystem::path csv = dir.path() / "record.csv";
  ambdrop_truth::WriteRecordCsv(csv, rig, run, ambdrop_truth::CsvUnits::kAcquisition);

  const LoadedConfig config = LoadConfig(source + "/tests/truth/flexible_pm_b.toml");
  const MeasurementParams& m = config.measurement.value();
  EXPECT_TRUE(m.trigger_state_from_record);
  const MeasuredRecord record = ReadMeasuredRecord(csv, m);
  const SimulatedRecord seated = SimulateOnRecord(config.params, m, record, {});
  EXPECT_EQ(seated.failure, "");
  EXPECT_NE(seated.lead_fit.rfind("not fitted", 0), 0u) << seated.lead_fit;
  // The estimate's uncertainty: its three largest axes where the sensors see it, and every
  // principal axis of it (at least those three).
  EXPECT_EQ(seated.lead_uncertainty.size(), 3u);
  EXPECT_GE(seated.lead_uncertainty_all.size(), 3u);

  const double trigger = seated.trigger_time_s;
  double sum = 0.0, travel = 0.0;
  std::size_t count = 0;
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    if (m.channels[c].quantity != MeasuredQuantity::kDisplacement) continue;
    const std::vector<double>& v =
        record.values[static_cast<std::size_t>(record.Column(m.channels[c].column))];
    for (std::size_t j = 0; j < record.time_s.size(); ++j) {
      const double t = record.time_s[j] - trigger;
      if (t < 0.0 || t > 8e-3 + 1e-9) continue;
      sum += std::pow(v[j] - seated.values[c][j], 2);
      travel = std::max(travel, std::abs(v[j]));
      ++count;
    }
  }
  EXPECT_GT(count, 4u * 150u);
  EXPECT_GT(travel, 50e-6);
  const double rms = std::sqrt(sum / static_cast<double>(count));
  std::printf("seed %llu: first 8 ms RMS error %.3g m over a travel of %.3g m (%.2f %%)\n",
              static_cast<unsigned long long>(seed), rms, travel, 100.0 * rms / travel);
  return rms / travel;
}

// Over five records (seeds 1 to 5) the error is 0.03 % to 0.12 % of the travel, 0.06 % on
// average; with the state fitted only where the sensors' shapes see it, 0.11 % to 0.51 %, 0.27 %
// on average (seed 1: 3.6 % off on one channel 8 ms after the trigger).
TEST(TruthLeadEstimate, TheGeneratorsJitterAtTheTriggerPredictsItsDrop) {
  double mean = 0.0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) mean += EarlyDropError(seed) / 5.0;
  EXPECT_LT(mean, 1.5e-3);
}

}  // namespace
}  // namespace ambdrop::truth_lead_estimate_test
