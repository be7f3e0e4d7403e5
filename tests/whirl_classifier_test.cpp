// The whirl classifier (Jarroux 2016, seed 001, Sec. 3: rocking motion vs backward whirl) on
// synthetic orbits with known answers: forward and backward circles at a known whirl frequency,
// a pendulum-like swing at the bottom of the race, a levitated orbit, and RunSummary's use of
// the second half of the time after the trigger.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "tools/fit/whirl_classifier.hpp"
#include "tools/validation/run_summary.hpp"

namespace ambdrop::whirl_classifier_test {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kClearance = 0.25e-3;
constexpr double kSpin = 600.0;  // rad/s

// Circle of radius r at whirl speed w (rad/s, > 0 anticlockwise), sampled at 20 kHz for T s.
std::vector<OrbitSample> Circle(double r, double w, double duration_s, double spin = kSpin) {
  std::vector<OrbitSample> orbit;
  for (int i = 0; i * 5e-5 <= duration_s; ++i) {
    const double t = i * 5e-5;
    orbit.push_back({t, r * std::cos(w * t + 0.3), r * std::sin(w * t + 0.3), spin});
  }
  return orbit;
}

// Pendulum at the bottom of the race: angle -pi/2 + a sin(2 pi f t).
std::vector<OrbitSample> Rocking(double amplitude_rad, double f_Hz, double duration_s) {
  std::vector<OrbitSample> orbit;
  for (int i = 0; i * 5e-5 <= duration_s; ++i) {
    const double t = i * 5e-5;
    const double a = -kPi / 2 + amplitude_rad * std::sin(2 * kPi * f_Hz * t);
    orbit.push_back({t, kClearance * std::cos(a), kClearance * std::sin(a), kSpin});
  }
  return orbit;
}

TEST(WhirlClassifier, ForwardCircle) {
  // 150 Hz whirl with the spin: ratio 2 pi 150 / 600 = 1.5708.
  const WhirlClassification c = ClassifyWhirl(Circle(kClearance, 2 * kPi * 150, 0.2), kClearance);
  EXPECT_EQ(c.kind, WhirlKind::kForwardWhirl);
  EXPECT_STREQ(WhirlName(c.kind), "forward_whirl");
  EXPECT_NEAR(c.frequency_Hz, 150.0, 1e-6);
  EXPECT_NEAR(c.frequency_ratio, 2 * kPi * 150 / kSpin, 1e-8);
  EXPECT_NEAR(c.revolutions, 30.0, 1e-6);
}

TEST(WhirlClassifier, BackwardCircle) {
  // 400 Hz against the spin; a backward whirl faster than the sampling's Nyquist would alias,
  // 400 Hz at 20 kHz is 50 samples a turn.
  const WhirlClassification c =
      ClassifyWhirl(Circle(1.1 * kClearance, -2 * kPi * 400, 0.1), kClearance);
  EXPECT_EQ(c.kind, WhirlKind::kBackwardWhirl);
  EXPECT_STREQ(WhirlName(c.kind), "backward_whirl");
  EXPECT_NEAR(c.frequency_ratio, -2 * kPi * 400 / kSpin, 1e-8);
  // A negative spin turns the meaning round: the same orbit is then a forward whirl.
  EXPECT_EQ(ClassifyWhirl(Circle(kClearance, -2 * kPi * 400, 0.1, -kSpin), kClearance).kind,
            WhirlKind::kForwardWhirl);
}

TEST(WhirlClassifier, PendulumAtTheBottomIsRocking) {
  // +-60 degrees at 12 Hz: never goes round; swing frequency 12 Hz.
  const WhirlClassification c = ClassifyWhirl(Rocking(kPi / 3, 12.0, 0.5), kClearance);
  EXPECT_EQ(c.kind, WhirlKind::kRocking);
  EXPECT_STREQ(WhirlName(c.kind), "rocking");
  EXPECT_NEAR(c.frequency_Hz, 12.0, 1.0 / 0.5);  // one half-cycle resolution over 0.5 s
  EXPECT_NEAR(c.frequency_ratio, 2 * kPi * c.frequency_Hz / kSpin, 1e-12);
  EXPECT_LT(std::abs(c.revolutions), 0.5);
  // A swing of +-170 degrees still does not go round.
  EXPECT_EQ(ClassifyWhirl(Rocking(170.0 / 180.0 * kPi, 5.0, 0.5), kClearance).kind,
            WhirlKind::kRocking);
}

TEST(WhirlClassifier, NotOnTheRaceOrTooShortIsNone) {
  // A levitated unbalance orbit, 10 um, well inside the clearance.
  EXPECT_EQ(ClassifyWhirl(Circle(10e-6, 2 * kPi * 100, 0.2), kClearance).kind, WhirlKind::kNone);
  EXPECT_EQ(ClassifyWhirl(std::vector<OrbitSample>(2), kClearance).kind, WhirlKind::kNone);
  EXPECT_STREQ(WhirlName(WhirlKind::kNone), "none");
}

TEST(WhirlClassifier, LessThanOneTurnIsNotAWhirl) {
  // 0.8 turn over the window: rocking (the journal did not go round).
  const WhirlClassification c = ClassifyWhirl(Circle(kClearance, 2 * kPi * 4.0, 0.2), kClearance);
  EXPECT_EQ(c.kind, WhirlKind::kRocking);
  EXPECT_NEAR(c.revolutions, 0.8, 1e-3);
}

TEST(RunSummaryWhirl, ClassifiesTheSecondHalfAfterTheTrigger) {
  ModelParams p;
  p.trigger.enabled = true;
  p.trigger.time_s = 0.1;
  TdbParams t;
  t.name = std::string(1, 'a');  // not = "a": GCC 12 false -Wrestrict
  t.clearance_m = kClearance;
  t.journal_radius_m = 0.06;
  p.tdbs.push_back(t);
  RunSummary summary(p);
  EXPECT_EQ(summary.Whirl(0).kind, WhirlKind::kNone);  // nothing yet
  // Levitated before the trigger, forward whirl until 0.5 s, then backward whirl at 100 Hz.
  Observation o;
  for (int i = 0; i <= 18000; ++i) {
    o.time_s = i * 5e-5;
    o.spin_speed_rad_s = kSpin;
    const double t_s = o.time_s;
    double r = kClearance, w = 2 * kPi * 50;
    if (t_s < 0.1) r = 5e-6;
    if (t_s >= 0.5) w = -2 * kPi * 100;
    o.tdb_journal_xy_m[0][0] = r * std::cos(w * t_s);
    o.tdb_journal_xy_m[0][1] = r * std::sin(w * t_s);
    summary.Add(o);
  }
  const WhirlClassification c = summary.Whirl(0);
  EXPECT_EQ(c.kind, WhirlKind::kBackwardWhirl);
  EXPECT_NEAR(c.frequency_Hz, -100.0, 0.5);
}

}  // namespace
}  // namespace ambdrop::whirl_classifier_test
