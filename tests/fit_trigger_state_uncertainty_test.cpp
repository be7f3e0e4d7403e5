// measurement.trigger_state = "record" on the independent generator's magnet-biased flexible rig
// (tools/truth, no code shared with ambdrop), through its translation
// (tests/truth/flexible_pm_b.toml). The power loss leaves that rotor unstable (the magnets'
// negative stiffness stays), so the error of the estimated state at the trigger grows into the
// drop's start. Its exact motion (ambdrop_truth --exact-record: the rotor jitters as on the rig,
// the record shows it without noise) is redrawn here with the rig's acquisition noise: the
// spread of the declared model's start departures over those draws is what the start
// sensitivity (effect_selection.hpp) must predict. And where the start departs further, a shift
// of the state within the estimate's uncertainty (start_state_shift.hpp) tells the estimate's
// error from a hidden effect.
#include <gtest/gtest.h>

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
#include "noise.hpp"
#include "record_files.hpp"
#include "rig.hpp"
#include "scratch_directory.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/jitter_draws.hpp"
#include "tools/fit/record_cost.hpp"
#include "tools/fit/reduced_rotor_cache.hpp"
#include "tools/fit/start_state_shift.hpp"

namespace ambdrop::fit_trigger_state_uncertainty_test {
namespace {

const std::string kSource = AMBDROP_SOURCE_DIR;

// The generator's record of `effect` (seed `seed`), its channels exact or with the rig's
// acquisition noise, read through the translation's [measurement] table (SI).
MeasuredRecord Record(const std::string& effect, std::uint64_t seed, const MeasurementParams& m,
                      bool exact) {
  ambdrop_truth::Rig rig = ambdrop_truth::ReadRig(kSource + "/tools/truth/rigs/flexible_pm_b.json");
  ambdrop_truth::ApplyEffect(effect, seed, &rig);
  ambdrop_truth::RunOptions options;
  options.exact_record = exact;
  const ambdrop_truth::RunResult run = ambdrop_truth::RunDrop(rig, seed, options);
  EXPECT_TRUE(run.finite);
  EXPECT_EQ(run.left_physics, "");
  const testing::ScratchDirectory dir("fit_trigger_state_uncertainty");
  const std::filesystem::path csv = dir.path() / "record.csv";
  ambdrop_truth::WriteRecordCsv(csv, rig, run, ambdrop_truth::CsvUnits::kAcquisition);
  return ReadMeasuredRecord(csv, m);
}

// The rig sheet's acquisition noise (flexible_pm_b.json: 0.3 um and 0.1 um steps on the
// displacements, 5 mA on the currents), drawn from `draw`.
MeasuredRecord WithNoise(const MeasuredRecord& exact, const MeasurementParams& m,
                         std::uint64_t draw) {
  MeasuredRecord noisy = exact;
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    const MeasurementChannel& ch = m.channels[c];
    const bool displacement = ch.quantity == MeasuredQuantity::kDisplacement;
    if (!displacement && ch.quantity != MeasuredQuantity::kCurrent) continue;
    const int column = noisy.Column(ch.column);
    if (column < 0) continue;
    ambdrop_truth::GaussianNoise noise(0x5eed0000ULL + draw, c);
    for (double& v : noisy.values[static_cast<std::size_t>(column)]) {
      if (!std::isfinite(v)) continue;
      if (displacement) {
        v = std::round((v + 0.3e-6 * noise.Normal()) / 0.1e-6) * 0.1e-6;
      } else {
        v += 5e-3 * noise.Normal();
      }
    }
  }
  return noisy;
}

MeasuredRecord ExactRecord(const std::string& effect, std::uint64_t seed,
                           const MeasurementParams& m) {
  return Record(effect, seed, m, true);
}
MeasuredRecord NoisyRecord(const std::string& effect, std::uint64_t seed,
                           const MeasurementParams& m) {
  return Record(effect, seed, m, false);
}

struct StartJudgement {
  double departure = 0.0;    // the declared model's start residual beyond the record's noise
  double sensitivity = 0.0;  // what the estimate's uncertainty predicts for it
  double noise_limit = 0.0;  // the agreement limit of the record's noise alone
  StartStateShift shift;     // the state shifted within the estimate's uncertainty
};

StartJudgement JudgeStart(const ConfigVariants& config, const MeasurementParams& m,
                          const MeasuredRecord& record, bool shift = false) {
  RecordRunOptions run;
  run.step_s = 5e-6;  // the step the fit chooses for this rig's records
  run.rotor_cache = std::make_shared<ReducedRotorCache>();
  const ModelParams& declared = config.declared().params;
  const RecordCost early(declared, m, record, run, 3000, CostScope::kEarly);
  const Eigen::VectorXd before = early.Residual(declared);
  StartJudgement j;
  j.departure = AboveNoise(OverallRms(early, before.squaredNorm()), early.NoiseFloor());
  j.sensitivity = StartSensitivity(config, early, before, 2);
  Selection noise_only;
  noise_only.noise_floor = early.NoiseFloor();
  j.noise_limit = AgreementLimit(noise_only, SelectionRules{});
  if (shift) j.shift = FitStartStateShift(early, before, 2, j.noise_limit);
  return j;
}

// Redraws of the clean seed-8 record's noise on its exact motion: the departures' RMS is between
// half the predicted one-sigma spread's and twice it (twelve draws: departures 0.0015-0.013,
// predictions 0.0042-0.0125, ratio 1.04; probed along every principal axis of the estimate's
// covariance the predictions were 0.008-0.027, ratio 0.52).
TEST(FitTriggerStateUncertainty, TheEstimatesSpreadBoundsTheStartsDepartures) {
  const ConfigVariants config = ConfigVariants::Load(kSource + "/tests/truth/flexible_pm_b.toml");
  const MeasurementParams& m = config.declared().measurement.value();
  ASSERT_TRUE(m.trigger_state_from_record);
  const MeasuredRecord exact = ExactRecord("clean", 8, m);
  double departures = 0.0, predicted = 0.0;
  constexpr int kDraws = 12;
  for (int d = 0; d < kDraws; ++d) {
    const StartJudgement j = JudgeStart(config, m, WithNoise(exact, m, d));
    std::printf("draw %d: departure %.4f, predicted %.4f\n", d, j.departure, j.sensitivity);
    departures += j.departure * j.departure / kDraws;
    predicted += j.sensitivity * j.sensitivity / kDraws;
  }
  const double ratio = std::sqrt(departures / predicted);
  std::printf("departures' RMS / predicted RMS: %.2f\n", ratio);
  EXPECT_GT(ratio, 0.5);
  EXPECT_LT(ratio, 2.0);
}

// The generator's own record of the clean seed 8 (its noise, not redrawn) departs at the
// start far beyond the redraws' bulk: 0.046, 7.4 times the predicted spread (0.0062), and the
// fit took it for a DE sensor 16 mm off its station. Such tails are the redraws' too (two of
// eight more, redrawn by hand: 0.034 and 0.026). A shift of the state at the trigger of
// plausible size along every axis of the estimate's covariance takes it within the record's
// noise (3.9 standard deviations over 11 directions, 0.0038 against 0.0048; the two redraws:
// 3.1 and 3.0; drawn back along its ray to the least of it that stays within the noise, as the
// fit did, 3.7 and 0.0045; the least shift within the noise, as it does now, 2.4 and 0.0047).
// The clean seed 102 departs by 0.036: the maximum a posteriori shift, 6.1 standard deviations
// (5.8 drawn back along its ray), was beyond the plausible 5.2 and the fit named a disc's polar
// inertia; the least shift within the noise (the discrepancy principle on the same Jacobian)
// is 1.2. A TDB 60 um off its centre (seed 3) departs too, and
// no plausible shift takes its start there (166 standard deviations leave 0.032).
TEST(FitTriggerStateUncertainty, ACleanStartIsWithinTheEstimatesReachAnOffsetTdbIsNot) {
  const ConfigVariants config = ConfigVariants::Load(kSource + "/tests/truth/flexible_pm_b.toml");
  const MeasurementParams& m = config.declared().measurement.value();
  for (const std::uint64_t seed : {8, 102}) {
    const StartJudgement clean = JudgeStart(config, m, NoisyRecord("clean", seed, m), true);
    std::printf(
        "clean seed %d: departure %.4f, predicted %.4f; shifted by %.2f sigma (plausible %.2f "
        "over %.1f directions): %.4f, noise limit %.4f\n",
        static_cast<int>(seed), clean.departure, clean.sensitivity, clean.shift.sigmas,
        clean.shift.plausible_sigmas, clean.shift.directions, clean.shift.rms_after,
        clean.noise_limit);
    EXPECT_GT(clean.departure, 2.0 * clean.sensitivity) << seed;
    ASSERT_TRUE(clean.shift.fitted) << seed;
    EXPECT_LE(clean.shift.sigmas, clean.shift.plausible_sigmas) << seed;
    EXPECT_LE(clean.shift.rms_after, clean.noise_limit) << seed;
  }

  const StartJudgement offset = JudgeStart(config, m, NoisyRecord("tdb_misalignment", 3, m), true);
  std::printf(
      "TDB offset, seed 3: departure %.4f; shifted by %.2f sigma (plausible %.2f): "
      "%.4f, noise limit %.4f\n",
      offset.departure, offset.shift.sigmas, offset.shift.plausible_sigmas, offset.shift.rms_after,
      offset.noise_limit);
  EXPECT_GT(offset.departure, 2.0 * offset.sensitivity);
  ASSERT_TRUE(offset.shift.fitted);
  EXPECT_TRUE(offset.shift.sigmas > offset.shift.plausible_sigmas ||
              offset.shift.rms_after > offset.noise_limit);
}

// After an agreeing start, a magnet-biased rotor comes to rest where its first impacts leave
// it: the clean seed 6's rests 21 um higher on its DE race than the declared model's, and the
// whole record departs (0.048 against a limit of 0.028; the fit then sold a TDB bearing's
// damping as the cause). What the record leaves open of the state at the trigger decides that:
// draws of the state from its estimate's uncertainty (DrawJitter, trigger_state = "record")
// reach the record: the eighth takes the whole record's residual (at this test's step, 0.046)
// to under half, 0.022. A TDB 60 um off its centre (seed 3, 0.159) moves where every draw
// rests: none of eight comes near.
TEST(FitTriggerStateUncertainty, TheEstimatesDrawsReachWhereACleanRotorRestsNotAnOffsetTdb) {
  const ConfigVariants config = ConfigVariants::Load(kSource + "/tests/truth/flexible_pm_b.toml");
  const MeasurementParams& m = config.declared().measurement.value();
  RecordRunOptions run;
  run.step_s = 5e-6;
  run.rotor_cache = std::make_shared<ReducedRotorCache>();
  const ModelParams& declared = config.declared().params;
  const auto draws = [&](const MeasuredRecord& record, const char* name) {
    const RecordCost whole(declared, m, record, run, 3000, CostScope::kWhole);
    const double before = OverallRms(whole, whole.Residual(declared).squaredNorm());
    const JitterDraws d = DrawJitter(whole, whole, 0.5 * before, 8, 2);
    std::printf("%s: whole record %.4f; first draw under half of it: %d of %d (%.4f)\n", name,
                before, d.first_within, d.draws, d.within_rms);
    EXPECT_TRUE(d.ran && d.from_estimate) << name;
    return d;
  };
  const JitterDraws clean = draws(NoisyRecord("clean", 6, m), "clean seed 6");
  EXPECT_GT(clean.first_within, 0);
  const JitterDraws offset = draws(NoisyRecord("tdb_misalignment", 3, m), "TDB offset seed 3");
  EXPECT_EQ(offset.first_within, 0);
  EXPECT_EQ(offset.draws, 8);
}

}  // namespace
}  // namespace ambdrop::fit_trigger_state_uncertainty_test
