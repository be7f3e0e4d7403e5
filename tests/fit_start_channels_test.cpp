// The drop's start sensor by sensor (JudgeStartChannels, tools/fit/start_channels.cpp), on the
// independent generator's 4-DOF rig (tools/truth, no code shared with ambdrop) through its
// translation (tests/truth/rigid_fourdof_c.toml). One sensor's gain or the acquisition chain's
// lag moves one or a few of the start's 17 channels: their one RMS stays within its limit, and
// only each displacement channel held to its own noise and its own widest jitter draw shows
// the sensor. Clean records of the same rig must show nothing there: their rotors jitter when
// the power fails as the model's draws do.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "generator_record.hpp"
#include "io/config/config_variants.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/effect_selection_internal.hpp"
#include "tools/fit/record_cost.hpp"
#include "tools/fit/reduced_rotor_cache.hpp"
#include "tools/fit/start_channels.hpp"

namespace ambdrop::fit_start_channels_test {
namespace {

const std::string kSource = AMBDROP_SOURCE_DIR;

struct Judged {
  StartChannels channels;
  double start_rms = 0.0;    // the start's one RMS over every channel
  double start_limit = 0.0;  // and its limit (the part's, JudgePart)
  std::vector<std::string> columns;
};

// The generator's record of `effect` at `seed`, judged on the declared model's start.
Judged JudgeRecord(const std::string& effect, int seed) {
  const ConfigVariants config =
      ConfigVariants::Load(kSource + "/tests/truth/rigid_fourdof_c.toml", {});
  const ModelParams& declared = config.declared().params;
  const MeasurementParams m = config.declared().measurement.value();
  const MeasuredRecord record =
      testing::GeneratorRecord("rigid_fourdof_c", effect, static_cast<std::uint64_t>(seed), m);

  RecordRunOptions options;
  options.step_s = 5e-6;  // the step the fit chooses for this rig's records
  options.rotor_cache = std::make_shared<ReducedRotorCache>();
  const RecordCost start(declared, m, record, options, 3000, CostScope::kEarly);
  const Eigen::VectorXd before = start.Residual(declared);
  SelectionRules rules;
  rules.threads = 2;
  Judged j;
  j.channels = JudgeStartChannels(config, start, before, rules);
  const Selection::Part part = JudgePart(config, start, before, start.NoiseFloor(), rules, {});
  j.start_rms = part.rms_before;
  j.start_limit = part.limit;
  for (const MeasurementChannel& ch : m.channels) j.columns.push_back(ch.column);
  for (std::size_t c = 0; c < j.channels.rms.size(); ++c) {
    if (j.channels.rms[c] > 0.0) {
      std::printf("%s %d %-12s %.5f limit %.5f (noise %.5f, widest start move %.5f)%s\n",
                  effect.c_str(), seed, j.columns[c].c_str(), j.channels.rms[c],
                  j.channels.limit[c], j.channels.noise[c], j.channels.start[c],
                  j.channels.departing[c] ? " departs" : "");
    }
  }
  return j;
}

bool Departs(const Judged& j, const std::string& column) {
  for (std::size_t c = 0; c < j.columns.size(); ++c) {
    if (j.columns[c] == column) return j.channels.departing.at(c);
  }
  ADD_FAILURE() << "no column " << column;
  return false;
}

int DepartingCount(const Judged& j) {
  int n = 0;
  for (const bool d : j.channels.departing) n += d ? 1 : 0;
  return n;
}

TEST(FitStartChannels, CleanRecordsDepartOnNoSensor) {
  // Seed 12 is the clean record (of seeds 3-18) whose sensors came closest to their limits.
  for (const int seed : {12, 202}) {
    const Judged j = JudgeRecord("clean", seed);
    ASSERT_FALSE(j.channels.limit.empty()) << "the start's jitter is drawn on this rig";
    EXPECT_EQ(DepartingCount(j), 0) << "clean seed " << seed;
  }
}

TEST(FitStartChannels, OneSensorsGainDepartsOnItsOwnChannelWhereTheStartAgrees) {
  // Seed 10: the NDE sensor's y gain 0.877; seed 210: the DE sensor's y gain 1.198.
  const Judged nde = JudgeRecord("sensor_gain_axis", 10);
  EXPECT_LE(nde.start_rms, nde.start_limit) << "the start as a whole hides it";
  EXPECT_TRUE(Departs(nde, "y_nde_um"));
  EXPECT_EQ(DepartingCount(nde), 1);
  const Judged de = JudgeRecord("sensor_gain_axis", 210);
  EXPECT_TRUE(Departs(de, "y_de_um"));
  EXPECT_EQ(DepartingCount(de), 1);
}

TEST(FitStartChannels, TheAcquisitionChainsLagDepartsOnTheFallingSensors) {
  // Seed 12: 0.16 ms of delay and a 0.33 ms low-pass on every sensor. The y sensors read the
  // fall; the coil currents, speeds and impact forces are not the sensors' and stay within.
  const Judged j = JudgeRecord("chain_lag", 12);
  EXPECT_LE(j.start_rms, j.start_limit) << "the start as a whole hides it";
  EXPECT_TRUE(Departs(j, "y_de_um"));
  for (std::size_t c = 0; c < j.columns.size(); ++c) {
    if (j.columns[c].find("_um") == std::string::npos) {
      EXPECT_FALSE(j.channels.departing[c]) << j.columns[c];
    }
  }
}

}  // namespace
}  // namespace ambdrop::fit_start_channels_test
