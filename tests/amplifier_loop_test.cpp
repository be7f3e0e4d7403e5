// The amplifier current loop against the step responses of its continuous first- and
// second-order forms at the controller's samples, and its slew limit.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "controller_if/controller/amplifier_loop.hpp"

namespace ambdrop::amplifier_loop_test {
namespace {

constexpr double kT = 5e-5;

TEST(AmplifierLoop, FirstOrderStepIsOneMinusExp) {
  AmplifierParams p;
  p.enabled = true;
  p.bandwidth_Hz = 1500.0;
  AmplifierLoop loop(p, kT, 0.0);
  for (int k = 1; k <= 100; ++k) {
    const double t = k * kT;  // the end of the k-th period
    EXPECT_NEAR(loop.Update(1.0), 1.0 - std::exp(-t * 2 * std::numbers::pi * p.bandwidth_Hz), 1e-14)
        << k;
  }
}

TEST(AmplifierLoop, SecondOrderStepMatchesTheUnderdampedResponse) {
  AmplifierParams p;
  p.enabled = true;
  p.order = 2;
  p.bandwidth_Hz = 1500.0;
  p.damping_ratio = 0.5;
  AmplifierLoop loop(p, kT, 0.0);
  const double w = 2 * std::numbers::pi * p.bandwidth_Hz, z = p.damping_ratio;
  const double wd = w * std::sqrt(1 - z * z);
  for (int k = 1; k <= 100; ++k) {
    const double t = k * kT;
    // Ogata, "Modern Control Engineering", 5th ed., Eq. (5-21).
    const double expected =
        1 - std::exp(-z * w * t) * (std::cos(wd * t) + z / std::sqrt(1 - z * z) * std::sin(wd * t));
    EXPECT_NEAR(loop.Update(1.0), expected, 1e-13) << k;
  }
}

TEST(AmplifierLoop, SlewLimitBoundsTheCurrentRate) {
  AmplifierParams p;
  p.enabled = true;
  p.bandwidth_Hz = 1500.0;
  p.slew_rate_A_per_s = 1000.0;  // 0.05 A per period
  AmplifierLoop loop(p, kT, 0.0);
  double previous = 0.0;
  for (int k = 1; k <= 400; ++k) {
    const double command = k < 200 ? 1.0 : -1.0;
    const double i = loop.Update(command);
    EXPECT_LE(std::abs(i - previous), p.slew_rate_A_per_s * kT * (1 + 1e-12)) << k;
    if (k <= 5) {
      EXPECT_NEAR(i, k * p.slew_rate_A_per_s * kT, 1e-15);  // on the limit: a ramp
    }
    previous = i;
  }
  EXPECT_NEAR(previous, -1.0, 1e-6);  // the loop still reaches the command
}

}  // namespace
}  // namespace ambdrop::amplifier_loop_test
