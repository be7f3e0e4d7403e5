// A fitted value's share of the rotor's jitter at the trigger (AddStartJitterToSigmas,
// tools/fit/start_jitter_sigma.cpp), held against what it predicts: the spread of the values
// fitted to records that differ only in that jitter (and their noise). The records come from
// the independent generator (tools/truth, no code shared with ambdrop): the rigid rig's NDE
// TDB offset of seed 803, each record's noise and jitter drawn from its own run seed, fitted
// on the drop's start through the rig's translation (tests/truth/rigid_rotor_a.toml) as
// `ambdrop fit` judges it there. The generator's jitter is its own controller answering its
// own sensors' noise, not the model's draws the share is computed from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "drop_run.hpp"
#include "effects.hpp"
#include "io/config/config_variants.hpp"
#include "io/files/measured_record_si.hpp"
#include "record_files.hpp"
#include "rig.hpp"
#include "scratch_directory.hpp"
#include "tools/fit/effect_fit.hpp"
#include "tools/fit/effect_library.hpp"
#include "tools/fit/record_cost.hpp"
#include "tools/fit/reduced_rotor_cache.hpp"
#include "tools/fit/start_jitter_sigma.hpp"

namespace ambdrop::fit_start_jitter_sigma_test {
namespace {

const std::string kSource = AMBDROP_SOURCE_DIR;

TEST(FitStartJitterSigma, TheJittersShareSpansTheSpreadOfFitsToRecordsDifferingInTheirJitter) {
  const ConfigVariants config =
      ConfigVariants::Load(kSource + "/tests/truth/rigid_rotor_a.toml", {});
  const ModelParams& declared = config.declared().params;
  const MeasurementParams m = config.declared().measurement.value();
  const std::vector<Effect> library = EffectLibrary(config);
  const auto offset = std::find_if(library.begin(), library.end(), [](const Effect& e) {
    return e.name == "tdb_misalignment:nde";
  });
  ASSERT_NE(offset, library.end());

  ambdrop_truth::Rig rig = ambdrop_truth::ReadRig(kSource + "/tools/truth/rigs/rigid_rotor_a.json");
  ambdrop_truth::ApplyEffect("tdb_misalignment", 803, &rig);
  const testing::ScratchDirectory dir("fit_start_jitter_sigma");
  RecordRunOptions options;
  options.rotor_cache = std::make_shared<ReducedRotorCache>();

  constexpr int kRecords = 6;
  std::vector<double> ys;
  double predicted = std::nan("");
  double start_share = std::nan("");
  for (int k = 0; k < kRecords; ++k) {
    const std::uint64_t seed = 900 + static_cast<std::uint64_t>(k);
    const ambdrop_truth::RunResult run = ambdrop_truth::RunDrop(rig, seed, {});
    ASSERT_TRUE(run.finite);
    const std::filesystem::path csv = dir.path() / ("record_" + std::to_string(k) + ".csv");
    ambdrop_truth::WriteRecordCsv(csv, rig, run, ambdrop_truth::CsvUnits::kAcquisition);
    const MeasuredRecord record = ReadMeasuredRecord(csv, m);
    const RecordCost start(declared, m, record, options, 3000, CostScope::kEarly);
    EffectFit fit = FitEffects(config, start, {&*offset});
    ASSERT_EQ(fit.parameters.size(), 2U);
    if (k == 0) {
      AddStartJitterToSigmas(config, start, library, 8, 2, &fit);
      predicted = fit.parameters[1].sigma;
      start_share = fit.parameters[1].start_sigma;
    }
    ys.push_back(fit.parameters[1].value);
    std::printf("record %d: offset (%.2f, %.2f) um\n", k, 1e6 * fit.parameters[0].value,
                1e6 * fit.parameters[1].value);
  }
  double mean = 0.0;
  for (const double y : ys) mean += y / kRecords;
  double spread = 0.0;
  for (const double y : ys) spread += (y - mean) * (y - mean) / (kRecords - 1);
  spread = std::sqrt(spread);
  std::printf("y: spread of %d fits %.2f um; predicted sigma %.2f um (the jitter's share %.2f)\n",
              kRecords, 1e6 * spread, 1e6 * predicted, 1e6 * start_share);
  ASSERT_TRUE(std::isfinite(predicted));
  // The share is measured, and it is most of the sigma: the noise alone leaves far less.
  EXPECT_GT(start_share, 0.5 * predicted);
  // Six draws estimate a spread to about +-30 %: the prediction within a factor of three.
  EXPECT_GT(predicted, spread / 3.0);
  EXPECT_LT(predicted, 3.0 * spread);
}

}  // namespace
}  // namespace ambdrop::fit_start_jitter_sigma_test
