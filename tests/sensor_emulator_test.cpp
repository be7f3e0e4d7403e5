// Sensor emulation: each error model against its definition, and noise that repeats on any
// platform (xoshiro256** reference value, fixed seeds).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "controller_if/boundary/portable_random.hpp"
#include "controller_if/boundary/sensor_emulator.hpp"

namespace ambdrop::sensor_emulator_test {
namespace {

Observation At(double x, double y, double angle = 0.0) {
  Observation o;
  o.sensor_xy_m[0] = {x, y};
  o.spin_angle_rad = angle;
  return o;
}

TEST(PortableRandom, MatchesTheXoshiroReference) {
  // xoshiro256** from state {1, 2, 3, 4}: first output rotl(2 * 5, 7) * 9 = 11520, second 0.
  PortableRandom r = PortableRandom::FromState(1, 2, 3, 4);
  EXPECT_EQ(r.Next(), 11520u);
  EXPECT_EQ(r.Next(), 0u);
  EXPECT_EQ(r.Next(), 1509978240u);
}

TEST(SensorEmulator, GainOffsetAndQuantisation) {
  SensorParams p;
  p.gain = 1.02;
  p.offset_m = 3e-6;
  p.quantisation_m = 1e-6;
  SensorEmulator s({p}, 5e-5);
  SensorReadings r;
  s.Sample(At(10.2e-6, -4.6e-6), &r);
  EXPECT_NEAR(r.reading_m[0][0], 13e-6, 1e-18);  // 1.02 * 10.2 + 3 = 13.404 → 13 um
  EXPECT_NEAR(r.reading_m[0][1], -2e-6, 1e-18);  // 1.02 * -4.6 + 3 = -1.692 → -2 um
}

// A probe whose x gain drifted (issue 23 item 4): the x reading scales by the gain error, the y
// reading and everything downstream of it stay bit for bit those of the healthy sensor.
TEST(SensorEmulator, OneAxisGainOrOffsetLeavesTheOtherAxisAlone) {
  SensorParams healthy;
  healthy.gain = 1.02;
  healthy.offset_m = 3e-6;
  healthy.lag = {true, 2 * 5e-5, 800.0};  // the error passes through the same lag as the signal
  SensorParams drifted = healthy;
  drifted.gain_x = 1.02 * 1.1;
  SensorParams shifted = healthy;
  shifted.offset_y_m = 3e-6 + 5e-6;
  SensorEmulator a({healthy}, 5e-5), b({drifted}, 5e-5), c({shifted}, 5e-5);
  SensorReadings ra, rb, rc;
  for (int k = 0; k < 50; ++k) {
    // Offset-free motion, so that the x reading of the drifted probe is 1.1x the healthy one
    // once the offsets are taken out.
    const double x = 20e-6 * std::sin(0.3 * k), y = -15e-6 * std::cos(0.2 * k);
    a.Sample(At(x, y), &ra);
    b.Sample(At(x, y), &rb);
    c.Sample(At(x, y), &rc);
    EXPECT_EQ(rb.reading_m[0][1], ra.reading_m[0][1]) << "sample " << k;
    EXPECT_EQ(rc.reading_m[0][0], ra.reading_m[0][0]) << "sample " << k;
    // The lag is linear, and a constant offset passes it unchanged.
    EXPECT_NEAR(rb.reading_m[0][0] - 3e-6, 1.1 * (ra.reading_m[0][0] - 3e-6), 1e-17);
    EXPECT_NEAR(rc.reading_m[0][1] - ra.reading_m[0][1], 5e-6, 1e-17);
  }
  // Per-axis values equal to the common ones change nothing.
  SensorParams explicit_axes = healthy;
  explicit_axes.gain_x = explicit_axes.gain_y = healthy.gain;
  explicit_axes.offset_x_m = explicit_axes.offset_y_m = healthy.offset_m;
  SensorEmulator d({explicit_axes}, 5e-5), e({healthy}, 5e-5);
  SensorReadings rd, re;
  d.Sample(At(7e-6, -2e-6), &rd);
  e.Sample(At(7e-6, -2e-6), &re);
  EXPECT_EQ(rd.reading_m[0][0], re.reading_m[0][0]);
  EXPECT_EQ(rd.reading_m[0][1], re.reading_m[0][1]);
}

TEST(SensorEmulator, DelayIsWholeSamples) {
  SensorParams p;
  p.lag = {true, 3 * 5e-5, 0.0};
  SensorEmulator s({p}, 5e-5);
  SensorReadings r;
  for (int k = 0; k < 10; ++k) {
    s.Sample(At(k * 1e-6, 0.0), &r);
    EXPECT_NEAR(r.reading_m[0][0], std::max(0, k - 3) * 1e-6, 1e-18) << "sample " << k;
  }
}

// A delay that is not a whole number of samples reads between the samples: on a ramp, linear
// interpolation is exact, so the reading is the ramp 2.4 samples late; a constant passes as is.
TEST(SensorEmulator, DelayBetweenSamplesReadsBetweenThem) {
  SensorParams p;
  p.lag = {true, 2.4 * 5e-5, 0.0};
  SensorEmulator s({p}, 5e-5);
  SensorReadings r;
  s.Sample(At(1e-6, 2e-6), &r);
  EXPECT_DOUBLE_EQ(r.reading_m[0][1], 2e-6);
  for (int k = 1; k < 12; ++k) {
    s.Sample(At((1 + k) * 1e-6, 2e-6), &r);
    EXPECT_NEAR(r.reading_m[0][0], (1 + std::max(0.0, k - 2.4)) * 1e-6, 1e-18) << "sample " << k;
    EXPECT_DOUBLE_EQ(r.reading_m[0][1], 2e-6);
  }
}

TEST(SensorEmulator, LowPassStepResponse) {
  SensorParams p;
  p.lag = {true, 0.0, 500.0};
  const double dt = 5e-5;
  SensorEmulator s({p}, dt);
  SensorReadings r;
  s.Sample(At(0.0, 0.0), &r);
  const double tau = 1.0 / (2 * std::numbers::pi * 500.0);
  // Between samples the input is taken as linear: a ramp from 0 to 1 um over the first period,
  // then held. The continuous filter's exact answer to it, for t >= dt:
  // y = 1 - (tau/dt) (e^(dt/tau) - 1) e^(-t/tau).
  for (int k = 1; k <= 3 * static_cast<int>(std::round(tau / dt)); ++k) {
    s.Sample(At(1e-6, 0.0), &r);
    const double t = k * dt;
    const double exact = 1 - tau / dt * std::expm1(dt / tau) * std::exp(-t / tau);
    EXPECT_NEAR(r.reading_m[0][0] / 1e-6, exact, 1e-12) << "sample " << k;
  }
}

TEST(SensorEmulator, LowPassAtTheSamplingRateFollowsTheContinuousFilter) {
  // An acquisition chain's low-pass near its sampling period (tau 80 us sampled at 10 kHz), a
  // 1 kHz signal: the continuous filter's steady state is |H| = 1/sqrt(1 + (w tau)^2) = 0.89
  // with phase -atan(w tau). Ten samples a period leave 2.8 % of the amplitude from the
  // straight lines between them; backward Euler at this period was 11 % off (0.79 amplitude).
  SensorParams p;
  const double tau = 80e-6;
  p.lag = {true, 0.0, 1.0 / (2 * std::numbers::pi * tau)};
  const double dt = 1e-4;
  SensorEmulator s({p}, dt);
  SensorReadings r;
  const double w = 2 * std::numbers::pi * 1000.0;
  const double gain = 1.0 / std::hypot(1.0, w * tau);
  const double phase = -std::atan(w * tau);
  double worst = 0.0;
  for (int k = 0; k < 400; ++k) {
    s.Sample(At(1e-6 * std::sin(w * k * dt), 0.0), &r);
    if (k < 200) continue;  // the start's transient has died (e^(-200 dt/tau) ~ 0)
    worst =
        std::max(worst, std::abs(r.reading_m[0][0] / 1e-6 - gain * std::sin(w * k * dt + phase)));
  }
  EXPECT_LT(worst, 0.03);
}

TEST(SensorEmulator, RunoutTurnsWithTheRotor) {
  SensorParams p;
  p.runout = {true, 2e-6, 0.3, 0.0, 0.0};
  SensorEmulator s({p}, 5e-5);
  SensorReadings r;
  for (double angle : {0.0, 1.0, 2.5}) {
    s.Sample(At(0.0, 0.0, angle), &r);
    // One mark on the surface: the x sensor sees it at cos, the y sensor a quarter turn later.
    EXPECT_NEAR(r.reading_m[0][0], 2e-6 * std::cos(angle + 0.3), 1e-18);
    EXPECT_NEAR(r.reading_m[0][1], 2e-6 * std::sin(angle + 0.3), 1e-18);
  }
}

TEST(SensorEmulator, NoiseHasItsStatisticsAndRepeats) {
  SensorParams p;
  p.noise = {true, 1e-6, 7};
  SensorEmulator a({p}, 5e-5), b({p}, 5e-5);
  SensorReadings ra, rb;
  double sum = 0, sum2 = 0;
  const int n = 100000;
  for (int k = 0; k < n; ++k) {
    a.Sample(At(0.0, 0.0), &ra);
    b.Sample(At(0.0, 0.0), &rb);
    ASSERT_EQ(ra.reading_m[0][0], rb.reading_m[0][0]);
    sum += ra.reading_m[0][0];
    sum2 += ra.reading_m[0][0] * ra.reading_m[0][0];
  }
  EXPECT_NEAR(sum / n, 0.0, 2e-8);
  EXPECT_NEAR(std::sqrt(sum2 / n) / 1e-6, 1.0, 0.01);
  // x and y draw from different streams.
  EXPECT_NE(ra.reading_m[0][0], ra.reading_m[0][1]);
}

TEST(SensorEmulator, NoiseThroughABandwidthKeepsItsSigmaAndCorrelatesAsTheLowPass) {
  // White noise through a first-order low-pass at fc, sampled every T, is AR(1) with lag-k
  // correlation exp(-2 pi fc T k) and the variance of the draws (the stationary law kept).
  SensorParams p;
  p.noise = {true, 1e-6, 7, 2000.0};
  const double period = 5e-5;
  SensorEmulator s({p}, period);
  SensorReadings r;
  const int n = 200000;
  std::vector<double> v(n);
  for (int k = 0; k < n; ++k) {
    s.Sample(At(0.0, 0.0), &r);
    v[k] = r.reading_m[0][0];
  }
  const auto correlation = [&](int lag) {
    double c = 0.0, var = 0.0;
    for (int k = 0; k + lag < n; ++k) c += v[k] * v[k + lag];
    for (const double x : v) var += x * x;
    return c / var * n / (n - lag);
  };
  double var = 0.0;
  for (const double x : v) var += x * x;
  EXPECT_NEAR(std::sqrt(var / n) / 1e-6, 1.0, 0.02);
  for (const int lag : {1, 2, 5}) {
    EXPECT_NEAR(correlation(lag), std::exp(-2.0 * std::numbers::pi * 2000.0 * period * lag), 0.01)
        << "lag " << lag;
  }
  // White (bandwidth 0) is uncorrelated from sample to sample, as before.
  p.noise.bandwidth_Hz = 0.0;
  SensorEmulator w({p}, period);
  for (int k = 0; k < n; ++k) {
    w.Sample(At(0.0, 0.0), &r);
    v[k] = r.reading_m[0][0];
  }
  EXPECT_NEAR(correlation(1), 0.0, 0.01);
}

TEST(SensorEmulator, AdcCounts) {
  SensorParams p;
  p.output = SensorOutput::kCounts;
  p.counts_per_m = 1e7;  // 0.1 um per count
  p.counts_offset = 32768;
  SensorEmulator s({p}, 5e-5);
  SensorReadings r;
  s.Sample(At(12.34e-6, -1e-6), &r);
  EXPECT_EQ(r.counts[0][0], 32768 + 123);
  EXPECT_EQ(r.counts[0][1], 32768 - 10);
}

}  // namespace
}  // namespace ambdrop::sensor_emulator_test
