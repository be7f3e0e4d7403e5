// The drop's start's sensitivity to the rotor's jitter at the trigger (StartSensitivity,
// tools/fit/start_sensitivity.cpp), on the independent generator's 4-DOF rig (tools/truth, no
// code shared with ambdrop) through its translation (tests/truth/rigid_fourdof_c.toml). The
// generator's controller answers its sensors' noise; after power loss the held currents leave
// its rotor on the magnets' negative stiffness for a millisecond and more, so the way it moved
// when the power failed grows through the free fall. On a clean record (seed 202) the rotor
// started 0.4 mm/s off the model's rest and its start departed 1.36 noise floors: beyond a limit
// set by a synchronous orbit shift, within one that runs the declared model with its own
// controller answering noise of the record's level. The widened limit must still see an
// effect the battery draws: the DE clearance worn 40 % larger.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "drop_run.hpp"
#include "effects.hpp"
#include "io/config/config_variants.hpp"
#include "io/files/measured_record_si.hpp"
#include "record_files.hpp"
#include "rig.hpp"
#include "scratch_directory.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/record_cost.hpp"
#include "tools/fit/reduced_rotor_cache.hpp"

namespace ambdrop::fit_start_jitter_test {
namespace {

const std::string kSource = AMBDROP_SOURCE_DIR;

TEST(FitStartJitter, TheStartsLimitHoldsACleanRecordsJitterAndStillSeesAWornClearance) {
  const ConfigVariants config =
      ConfigVariants::Load(kSource + "/tests/truth/rigid_fourdof_c.toml", {});
  const ModelParams& declared = config.declared().params;
  const MeasurementParams m = config.declared().measurement.value();

  ambdrop_truth::Rig rig =
      ambdrop_truth::ReadRig(kSource + "/tools/truth/rigs/rigid_fourdof_c.json");
  ambdrop_truth::ApplyEffect("clean", 202, &rig);
  const ambdrop_truth::RunResult run = ambdrop_truth::RunDrop(rig, 202, {});
  ASSERT_TRUE(run.finite);
  const testing::ScratchDirectory dir("fit_start_jitter");
  const std::filesystem::path csv = dir.path() / "record.csv";
  ambdrop_truth::WriteRecordCsv(csv, rig, run, ambdrop_truth::CsvUnits::kAcquisition);
  const MeasuredRecord record = ReadMeasuredRecord(csv, m);

  RecordRunOptions options;
  options.step_s = 5e-6;  // the step the fit chooses for this rig's records
  options.rotor_cache = std::make_shared<ReducedRotorCache>();
  const RecordCost start(declared, m, record, options, 3000, CostScope::kEarly);
  const Eigen::VectorXd before = start.Residual(declared);
  const double rms = OverallRms(start, before.squaredNorm());
  const double noise = start.NoiseFloor();
  const double sensitivity = StartSensitivity(config, start, before, 2);
  const SelectionRules rules;
  const double limit =
      std::hypot(rules.explained_over_floor * noise, rules.model_floor_factor * sensitivity);

  // A worn DE clearance in the middle of the battery's draw (1.2 to 1.5 times the declared).
  // Measured moves of the start: 1.1x 0.0044, 1.2x 0.0095, 1.3x 0.0174, 1.4x 0.0273, 1.5x
  // 0.0376: below 1.3x this record's jitter (0.0094 above its noise) moves it as far.
  const ModelParams worn = config.With({"tdb.de.clearance_m=0.42e-3"}).params;
  const double worn_moves = OverallRms(start, (start.Residual(worn) - before).squaredNorm());
  std::printf(
      "start %.5f (noise %.5f), sensitivity %.5f, limit %.5f; a worn clearance moves "
      "it %.5f\n",
      rms, noise, sensitivity, limit, worn_moves);
  // The record departs beyond its noise by the jitter alone...
  EXPECT_GT(rms, rules.explained_over_floor * noise);
  // ...within the limit that spans that jitter...
  EXPECT_LE(rms, limit);
  // ...which is the model's own spread, not the record's whole departure...
  EXPECT_LT(rules.model_floor_factor * sensitivity, 0.8 * rms);
  // ...and an effect the battery draws still moves the start well beyond it.
  EXPECT_GT(worn_moves, 1.5 * limit);
}

}  // namespace
}  // namespace ambdrop::fit_start_jitter_test
