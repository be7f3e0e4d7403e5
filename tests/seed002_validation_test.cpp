// Chen, Liu, Yuliane, Kuan (ITRI) 2019 (seed 002), Sec. IV: the 32 kg flexible rotor of
// configs/chen_itri_flexible.toml dropped at 18 000, 14 000 and 10 000 rpm onto its two
// discrete-ball TDBs, 0.2 s after the drop:
//  - "the orbit and the rotor responses are less than critical clearance of 2e-4 m" (the
//    paper's maxima are 1.0-1.2e-4 m), at every speed;
//  - with the support Ks = 5e8 N/m, Cs = 27 900 N s/m (Fig. 19) the contact forces after 0.1 s
//    are lower than without (Fig. 12), at 18 000 rpm;
//  - peak contact forces 2.3e4 / 2.35e4 N (front / rear) at 18 000 rpm, 2.25e4 / 2.15e4 N at
//    14 000 (the text says 15 000 once) and 2.1e4 / 1.9e4 N at 10 000, each within 25 %, and
//    falling with the speed. ambdrop does not reproduce these (see kPeakReason): skipped.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include "controller_if/offline_run.hpp"
#include "rt_core/model.hpp"
#include "test_configs.hpp"

namespace ambdrop {
namespace {

struct Drop {
  double peak_N[2] = {0.0, 0.0};       ///< front, rear: largest contact (normal) force
  double late_peak_N[2] = {0.0, 0.0};  ///< the same from 0.1 s after the drop on
  double max_displacement_m = 0.0;     ///< largest journal radius at either TDB
};

Drop RunDrop(double rpm, bool support) {
  const std::string speed = std::to_string(rpm * std::numbers::pi / 30.0);
  const std::string on = support ? "true" : "false";
  const ModelParams p = testing::LoadTestConfig(
      "chen_itri_flexible.toml",
      {"simulation.spin_speed_rad_s=" + speed, "simulation.duration_s=0.21",
       "simulation.output_interval_s=2e-6", "tdb.front.ball_bearing_tdb.support.enabled=" + on,
       "tdb.rear.ball_bearing_tdb.support.enabled=" + on});
  const Model model = BuildModel(p);
  Drop d;
  const OfflineRunResult r = RunOffline(model, [&](const Observation& o) {
    if (o.time_s < p.trigger.time_s) return;
    for (int i = 0; i < 2; ++i) {
      const double fn = o.tdb[i].normal_force_N;
      d.peak_N[i] = std::max(d.peak_N[i], fn);
      if (o.time_s >= p.trigger.time_s + 0.1) d.late_peak_N[i] = std::max(d.late_peak_N[i], fn);
      d.max_displacement_m = std::max(
          d.max_displacement_m, std::hypot(o.tdb_journal_xy_m[i][0], o.tdb_journal_xy_m[i][1]));
    }
  });
  EXPECT_EQ(r.status, StepStatus::kOk) << r.failure_message;
  std::printf(
      "%6.0f rpm%s: peak contact force front %8.0f N rear %8.0f N; after 0.1 s %8.0f / "
      "%8.0f N; max displacement %.3g m\n",
      rpm, support ? " + Ks, Cs" : "          ", d.peak_N[0], d.peak_N[1], d.late_peak_N[0],
      d.late_peak_N[1], d.max_displacement_m);
  return d;
}

class Seed002 : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    for (int i = 0; i < 3; ++i) drops_[i] = RunDrop(kRpm[i], false);
    supported_ = RunDrop(18000.0, true);
  }
  static constexpr double kRpm[3] = {18000.0, 14000.0, 10000.0};
  static Drop drops_[3];
  static Drop supported_;
};
Drop Seed002::drops_[3];
Drop Seed002::supported_;

TEST_F(Seed002, DisplacementStaysBelowTheCriticalClearance) {
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE(kRpm[i]);
    EXPECT_GT(drops_[i].max_displacement_m, 1e-4);  // it does reach the race (0.1 mm gap)
    EXPECT_LT(drops_[i].max_displacement_m, 2e-4);
  }
  EXPECT_LT(supported_.max_displacement_m, 2e-4);
}

TEST_F(Seed002, SupportLowersTheContactForcesAfterAFifthOfTheRun) {
  // Fig. 19 vs Fig. 12: "after 0.1 sec contact forces decrease".
  const double without = std::max(drops_[0].late_peak_N[0], drops_[0].late_peak_N[1]);
  const double with = std::max(supported_.late_peak_N[0], supported_.late_peak_N[1]);
  ASSERT_GT(with, 0.0);  // the rotor still runs on its TDBs
  EXPECT_LT(with, without);
}

bool SkipKnownFailure() {
  const char* run = std::getenv("AMBDROP_RUN_KNOWN_FAILURES");
  return run == nullptr || std::string(run) != "1";
}
// ambdrop, 0.2 s after the drop: peaks ~3.0e3 / 2.3e3 N at 18 000 rpm, ~2.9e3 / 1.6e3 N at
// 14 000, ~3.7e3 / 3.1e3 N at 10 000: an order of magnitude below the paper, with no trend on
// the speed. A 0.1 mm fall of 16 kg per TDB brings 0.016 J; stored in the ~1e8-1e9 N/m of
// balls and line contact that is ~2-3e3 N, and the 1.25 um eccentricity adds only 142 N at
// 18 000 rpm. The paper's 2.3e4 N needs a violent whirl (or a stiffer/heavier set-up) that its
// text does not specify; we do not tune unpublished parameters to reach it.
constexpr const char* kPeakReason =
    "known failure, issue 5: ambdrop's peak contact forces are ~3e3 N, not the paper's "
    "~2.3e4 N, with no speed trend (the drop energy bounds them; see the comment). Set "
    "AMBDROP_RUN_KNOWN_FAILURES=1 to run it.";

TEST_F(Seed002, PeakContactForcesMatchThePaper) {
  if (SkipKnownFailure()) GTEST_SKIP() << kPeakReason;
  const double published[3][2] = {{2.3e4, 2.35e4}, {2.25e4, 2.15e4}, {2.1e4, 1.9e4}};
  for (int i = 0; i < 3; ++i) {
    for (int t = 0; t < 2; ++t) {
      SCOPED_TRACE(std::to_string(kRpm[i]) + (t == 0 ? " rpm front" : " rpm rear"));
      EXPECT_NEAR(drops_[i].peak_N[t] / published[i][t], 1.0, 0.25);
    }
  }
  for (int t = 0; t < 2; ++t) {
    EXPECT_GT(drops_[0].peak_N[t], drops_[1].peak_N[t]);
    EXPECT_GT(drops_[1].peak_N[t], drops_[2].peak_N[t]);
  }
}

}  // namespace
}  // namespace ambdrop
