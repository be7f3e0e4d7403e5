// The fit's levitated part (CostScope::kLevitated): each displacement's and current's mean, 1X
// and 2X before the trigger, from the model's own closed loop, against a noise floor read from
// the record's own neighbouring frequencies (tools/fit/synchronous_blocks.hpp).
//  - That floor is what the blocks carry from noise, white or not: checked on synthetic signals
//    against the spread of the blocks themselves over many draws (the white-noise formula is
//    off by the noise's colour; the neighbours are not).
//  - On records of the independent generator (tools/truth, no code shared with ambdrop): the
//    clean records' levitated parts are within their limits (the rigid rig's, and the 4-DOF
//    rig's, whose levitated time is half as long), the rigid rig's record of a static unbalance
//    far beyond it, and the truth's own keys take it back within. The part weighs
//    each block by its own noise, so its floor is 1 (times the chi-square headroom).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "drop_run.hpp"
#include "effects.hpp"
#include "generator_record.hpp"
#include "io/config/config_variants.hpp"
#include "io/files/measured_record_si.hpp"
#include "noise.hpp"
#include "record_files.hpp"
#include "rig.hpp"
#include "scratch_directory.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/record_cost.hpp"
#include "tools/fit/reduced_rotor_cache.hpp"
#include "tools/fit/synchronous_blocks.hpp"

namespace ambdrop::fit_levitated_part_test {
namespace {

const std::string kSource = AMBDROP_SOURCE_DIR;
constexpr double kSpin = 1256.6370614359173;  // 12000 rpm
constexpr double kRate = 20000.0;
constexpr std::size_t kRows = 2000;  // 0.1 s: 20 turns

std::vector<double> Times() {
  std::vector<double> t(kRows);
  for (std::size_t i = 0; i < kRows; ++i) t[i] = static_cast<double>(i) / kRate;
  return t;
}

double Project(const std::vector<double>& k, const std::vector<double>& v) {
  double sum = 0.0;
  for (std::size_t i = 0; i < k.size(); ++i) sum += k[i] * v[i];
  return sum;
}

// Over many draws of a noise (white, or low-passed as a controller's jitter is), with a mean,
// a drift, 1X and 2X on top: the blocks' own variance across draws, against the mean of the
// estimates each draw makes of it.
struct Spread {
  std::vector<double> measured;   // variance of each block over the draws
  std::vector<double> estimated;  // mean of SynchronousBlockNoise over the draws
  std::vector<double> white;      // the noise's sigma from second differences, as if white
};

Spread BlockSpread(double pole) {
  const std::vector<double> t = Times();
  const std::vector<std::vector<double>> k = SynchronousBlockCoefficients(t, 0, kRows, kSpin);
  constexpr int kDraws = 400;
  std::vector<double> sum(5, 0.0), sum_sq(5, 0.0), estimate(5, 0.0), white(5, 0.0);
  for (int d = 0; d < kDraws; ++d) {
    ambdrop_truth::GaussianNoise noise(1234, static_cast<std::uint64_t>(d));
    std::vector<double> v(kRows);
    std::vector<double> alone(kRows);
    double state = 0.0;
    for (std::size_t i = 0; i < kRows; ++i) {
      state = pole * state + noise.Normal();
      alone[i] = 1e-3 * state;
      v[i] = 0.3 + 0.05 * t[i] + 0.2 * std::cos(kSpin * t[i] + 0.4) +
             0.05 * std::sin(2.0 * kSpin * t[i]) + alone[i];
    }
    double second_sq = 0.0;
    for (std::size_t i = 1; i + 1 < kRows; ++i) {
      second_sq += std::pow(alone[i + 1] - 2.0 * alone[i] + alone[i - 1], 2);
    }
    const double sigma_sq = second_sq / (6.0 * static_cast<double>(kRows - 2));
    const std::vector<double> e = SynchronousBlockNoise(t, v, 0, kRows, kSpin);
    EXPECT_EQ(e.size(), 5u);
    for (std::size_t b = 0; b < 5; ++b) {
      const double x = Project(k[b], v);
      sum[b] += x;
      sum_sq[b] += x * x;
      estimate[b] += e[b] / kDraws;
      double coefficients_sq = 0.0;
      for (const double c : k[b]) coefficients_sq += c * c;
      white[b] += sigma_sq * coefficients_sq / kDraws;
    }
  }
  Spread s;
  for (std::size_t b = 0; b < 5; ++b) {
    const double mean = sum[b] / kDraws;
    s.measured.push_back(sum_sq[b] / kDraws - mean * mean);
  }
  s.estimated = estimate;
  s.white = white;
  return s;
}

// Measured: white, the estimates within 13 % of the blocks' spread (400 draws leave about 7 %
// on a variance); low-passed (pole 0.95, as a rotor's jitter lies below 1X), within 6 %, where
// the white-noise formula from second differences misses by 160 to 1000 times.
TEST(SynchronousBlocks, TheNeighboursCarryWhatTheBlocksCarryFromNoise) {
  for (const double pole : {0.0, 0.95}) {
    const Spread s = BlockSpread(pole);
    for (std::size_t b = 0; b < 5; ++b) {
      std::printf("pole %.2f block %zu: spread %.3e, estimated %.3e, white formula %.3e\n", pole, b,
                  s.measured[b], s.estimated[b], s.white[b]);
      EXPECT_NEAR(s.estimated[b] / s.measured[b], 1.0, 0.25) << "block " << b;
    }
    // The white-noise formula, which the other parts use, holds for white noise only: the
    // reason for the neighbours.
    const double white_off = s.measured[1] / s.white[1];
    if (pole > 0.0) {
      EXPECT_GT(white_off, 3.0);
    } else {
      EXPECT_NEAR(white_off, 1.0, 0.25);
    }
  }
}

TEST(SynchronousBlocks, TooFewTurnsOrRowsGiveNoEstimate) {
  const std::vector<double> t = Times();
  const std::vector<double> v(kRows, 1.0);
  EXPECT_TRUE(SynchronousBlockNoise(t, v, 0, 40, kSpin).empty());    // 40 rows
  EXPECT_TRUE(SynchronousBlockNoise(t, v, 0, 500, kSpin).empty());   // 5 turns
  EXPECT_EQ(SynchronousBlockNoise(t, v, 0, 700, kSpin).size(), 5u);  // 7 turns
}

struct Levitated {
  double declared = 0.0;  // relative RMS of the declared model
  double truth = 0.0;     // of the truth's own keys
  double floor = 0.0;     // the noise floor with its chi-square headroom, as SelectEffects sets it
};

// `step_s`: the step the fit chooses for the rig's records (fit.json "step").
Levitated LevitatedPart(const std::string& effect, std::uint64_t seed,
                        const std::string& rig = "rigid_rotor_a", double step_s = 1e-5) {
  const std::string toml = kSource + "/tests/truth/" + rig + ".toml";
  const ConfigVariants declared = ConfigVariants::Load(toml);
  const MeasurementParams& m = declared.declared().measurement.value();
  ambdrop_truth::Truth truth;
  const MeasuredRecord record = testing::GeneratorRecord(rig, effect, seed, m, &truth);
  std::vector<std::string> lines;
  for (const auto& [key, value] : truth.ambdrop_keys) lines.push_back(key + "=" + value);
  const ConfigVariants true_keys = ConfigVariants::Load(toml, lines);
  RecordRunOptions run;
  run.step_s = step_s;
  run.rotor_cache = std::make_shared<ReducedRotorCache>();
  const RecordCost cost(declared.declared().params, m, record, run, 3000, CostScope::kLevitated);
  EXPECT_GT(cost.size(), 0u);
  EXPECT_NEAR(cost.NoiseFloor(), 1.0, 1e-9);  // each block in units of its own noise
  Levitated out;
  out.declared = OverallRms(cost, cost.Residual(declared.declared().params).squaredNorm());
  out.truth = OverallRms(cost, cost.Residual(true_keys.declared().params).squaredNorm());
  out.floor = cost.NoiseFloor() * std::sqrt(1.0 + 3.0 * std::sqrt(2.0 / cost.size()));
  std::printf("%s %s seed %llu: levitated %.3g declared, %.3g with the truth's keys; floor %.3g\n",
              rig.c_str(), effect.c_str(), static_cast<unsigned long long>(seed), out.declared,
              out.truth, out.floor);
  return out;
}

// In units of the blocks' noise, measured on seeds 401 and 406 of the rigid battery: clean 1.06
// against a floor of 1.29; the unbalance (6.1e-6 kg m) 16.9 declared, 1.15 with the truth's keys.
TEST(FitLevitatedPart, ACleanRecordAgreesWhileLevitated) {
  const Levitated clean = LevitatedPart("clean", 401);
  EXPECT_LT(clean.declared, 1.25 * clean.floor);
}

// The 4-DOF truth rig's levitated time is half the rigid rig's (0.05 s, 7.5 turns). Its clean
// seed 2 departed there at 5.2 (limit 1.62): its DE x current's mean was weighed by a noise read
// from two neighbouring frequencies, 21 times low by chance, and the fit "explained" the record
// with a sensor offset. From four neighbours, as the 1X and 2X blocks: within the limit.
TEST(FitLevitatedPart, TheFourDofRigsCleanRecordsAgreeWhileLevitated) {
  for (const std::uint64_t seed : {1u, 2u}) {
    const Levitated clean = LevitatedPart("clean", seed, "rigid_fourdof_c", 5e-6);
    EXPECT_LT(clean.declared, 1.25 * clean.floor) << "seed " << seed;
  }
}

TEST(FitLevitatedPart, AStaticUnbalanceDepartsWhileLevitatedAndItsTruthAgrees) {
  const Levitated unbalance = LevitatedPart("static_unbalance", 406);
  EXPECT_GT(unbalance.declared, 5.0 * unbalance.floor);
  EXPECT_LT(unbalance.truth, 1.25 * unbalance.floor);
}

}  // namespace
}  // namespace ambdrop::fit_levitated_part_test
