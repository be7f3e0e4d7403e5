// `trigger = "detect"` on records of the independent generator (tools/truth, no code shared with
// ambdrop), whose controllers answer their sensors' noise so that the levitated currents jitter
// by more than a cut current moves: the failure is found where the record shows it, never
// before it, and within half a sample where the power loss shows at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "generator_record.hpp"
#include "io/config/config_variants.hpp"
#include "tools/fit/record_trigger_detect.hpp"

namespace ambdrop::truth_trigger_detect_test {
namespace {

struct Detected {
  double truth_s = 0.0;
  double found_s = 0.0;
  double sample_s = 0.0;
};

// The rig's record of `effect` at `seed`, read through its translation with only the channels
// of `quantities` and the trigger time left for the detector.
Detected Detect(const std::string& rig, const std::string& effect, int seed,
                const std::vector<MeasuredQuantity>& quantities) {
  const ConfigVariants config =
      ConfigVariants::Load(std::string(AMBDROP_SOURCE_DIR) + "/tests/truth/" + rig + ".toml", {});
  MeasurementParams m = config.declared().measurement.value();
  const MeasuredRecord record =
      testing::GeneratorRecord(rig, effect, static_cast<std::uint64_t>(seed), m);
  Detected d;
  d.truth_s = m.trigger_time_s.value();
  d.sample_s = record.SampleInterval();
  std::vector<MeasurementChannel> kept;
  for (const MeasurementChannel& ch : m.channels) {
    if (std::find(quantities.begin(), quantities.end(), ch.quantity) != quantities.end()) {
      kept.push_back(ch);
    }
  }
  m.channels = kept;
  m.trigger_time_s.reset();
  m.detect_trigger = true;
  d.found_s = RecordTriggerTime(m, record);
  std::printf("%s %s %d: trigger %.6f s, found %.6f s (%+.2f samples)\n", rig.c_str(),
              effect.c_str(), seed, d.truth_s, d.found_s, (d.found_s - d.truth_s) / d.sample_s);
  return d;
}

using Q = MeasuredQuantity;

TEST(TruthTriggerDetect, CutCurrentsAreFoundWithinHalfASampleThoughTheirJitterIsLarger) {
  // rigid_rotor_a loses its currents at once; its PID's levitated currents jitter by about
  // 60 mA, a fifth of the control current that carries the weight.
  for (const int seed : {1, 2, 7}) {
    const Detected d = Detect("rigid_rotor_a", "clean", seed,
                              {Q::kDisplacement, Q::kCurrent, Q::kTdbSpeed, Q::kRotorSpeed});
    EXPECT_LE(std::abs(d.found_s - d.truth_s), 0.5 * d.sample_s + 1e-12) << seed;
  }
}

TEST(TruthTriggerDetect, DisplacementsAloneFindTheFallNeverBeforeTheCut) {
  // Without currents, the fall shows once the rotor has left its noise band: g t^2 / 2 beyond
  // 3 sigma of the levitated readings (about 1 um here: within a millisecond).
  const Detected d = Detect("rigid_rotor_a", "clean", 1, {Q::kDisplacement});
  EXPECT_GE(d.found_s, d.truth_s - 0.5 * d.sample_s);
  EXPECT_LE(d.found_s, d.truth_s + 1e-3);
}

TEST(TruthTriggerDetect, AFadingForceIsFoundOnceItsFallLeavesTheNoise) {
  // rigid_rotor_e's currents fade with tau = 2 ms and its force as exp(-2t/tau): the rotor falls
  // as g t^3 / (3 tau) at first, past a few um of band within about 2 ms.
  const Detected d = Detect("rigid_rotor_e", "clean", 1, {Q::kDisplacement, Q::kCurrent});
  EXPECT_GE(d.found_s, d.truth_s - 0.5 * d.sample_s);
  EXPECT_LE(d.found_s, d.truth_s + 2e-3);
}

TEST(TruthTriggerDetect, AHeldCurrentIsFoundWhereItStopsJittering) {
  // rigid_hc_g's power loss holds every coil current for 0.4 ms, then lets the force fall: the
  // rotor and the levels show nothing until the hold ends (the level rule alone found it
  // 1.26 ms late). The held currents lose their levitated jitter at once: their second
  // differences fall to the current channels' own noise, about 0.3 of the jitter's here.
  for (const int seed : {1, 2}) {
    const Detected d = Detect("rigid_hc_g", "clean", seed, {Q::kDisplacement, Q::kCurrent});
    EXPECT_LE(std::abs(d.found_s - d.truth_s), 1.5 * d.sample_s + 1e-12) << seed;
  }
  // Without currents only the fall shows: after the hold.
  const Detected late = Detect("rigid_hc_g", "clean", 1, {Q::kDisplacement});
  EXPECT_GT(late.found_s, late.truth_s + 0.4e-3);
}

TEST(TruthTriggerDetect, FadingAndRampingCurrentsStopJitteringAtTheFailure) {
  // rigid_rotor_e's currents fade with tau = 2 ms, rigid_fourdof_f's ramp down at 400 A/s:
  // smooth from the failure on, both are dated by the jitter they lose, not by their fall.
  for (const std::string rig : {"rigid_rotor_e", "rigid_fourdof_f"}) {
    const Detected d = Detect(rig, "clean", 1, {Q::kDisplacement, Q::kCurrent});
    EXPECT_LE(std::abs(d.found_s - d.truth_s), 1.5 * d.sample_s + 1e-12) << rig;
  }
}

}  // namespace
}  // namespace ambdrop::truth_trigger_detect_test
