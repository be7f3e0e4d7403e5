#include "controller_if/boundary/sensor_emulator.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>

namespace ambdrop {

SensorEmulator::SensorEmulator(const std::vector<SensorParams>& sensors, double period_s)
    : params_(sensors), channels_(sensors.size()) {
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    const SensorParams& p = sensors[i];
    // In samples as a double first: llround is undefined beyond int64, int beyond 2^31.
    const double samples = p.lag.enabled ? p.lag.delay_s / period_s : 0.0;
    if (!(samples >= 0.0 && samples <= kMaxSensorDelaySamples - 2)) {
      char text[256];
      std::snprintf(text, sizeof text,
                    "sensor.%s.lag.delay_s = %.6g s is %.6g samples of %.6g s, at most %d",
                    p.name.c_str(), p.lag.delay_s, samples, period_s, kMaxSensorDelaySamples - 2);
      throw std::invalid_argument(text);
    }
    // A delay between samples reads between them (linear interpolation): a chain's delay is a
    // time, not a count of this controller's samples (69 us at 8 kHz once became 125 us).
    const int delay = static_cast<int>(std::floor(samples));
    const double fraction = samples - delay;
    // The electronics' first-order low-pass tau y' = x - y is continuous: its exact response to
    // an input linear between two samples (first-order hold),
    //   y_k = e y_(k-1) + b0 x_k + b1 x_(k-1),  e = exp(-T/tau),
    //   b0 = 1 - (tau/T)(1 - e),  b1 = (tau/T)(1 - e) - e.
    // Backward Euler at the sampling period, used before, is right only for T << tau; a chain's
    // 40-120 us at 8-10 kHz is not: at 1 kHz it passed 0.79 of the amplitude where the filter
    // passes 0.89, and the impacts' kHz content sets the drop's start.
    filter_[i] = {0.0, 1.0, 0.0};
    if (p.lag.enabled && p.lag.cutoff_Hz > 0.0) {
      const double tau = 1.0 / (2.0 * std::numbers::pi * p.lag.cutoff_Hz);
      const double r = tau / period_s;
      const double e = std::exp(-period_s / tau);
      // 1 - e by expm1: exact to the last bit where T << tau makes it tiny.
      const double one_minus_e = -std::expm1(-period_s / tau);
      filter_[i] = {e, 1.0 - r * one_minus_e, r * one_minus_e - e};
    }
    // A first-order low-pass of white noise sampled every T is AR(1) with a = exp(-2 pi fc T);
    // r keeps its variance that of the white draw (the stationary law from the first sample).
    if (p.noise.bandwidth_Hz > 0.0) {
      const double a = std::exp(-2.0 * std::numbers::pi * p.noise.bandwidth_Hz * period_s);
      colour_[i] = {a, std::sqrt(-std::expm1(2.0 * std::log(a)))};
    }
    for (int axis = 0; axis < 2; ++axis) {
      Channel& c = channels_[i][axis];
      c.delay_samples = delay;
      c.delay_fraction = fraction;
      // One independent stream per sensor axis from the sensor's seed.
      c.noise = PortableRandom(p.noise.seed * 2 + static_cast<std::uint64_t>(axis));
    }
  }
}

void SensorEmulator::Sample(const Observation& obs, SensorReadings* out) noexcept {
  const double phi = obs.spin_angle_rad;
  for (std::size_t i = 0; i < params_.size(); ++i) {
    const SensorParams& p = params_[i];
    // Runout is one pattern on the surface: the y sensor sees it a quarter turn later.
    double runout[2] = {0.0, 0.0};
    if (p.runout.enabled) {
      const double a1 = p.runout.amplitude_1x_m, a2 = p.runout.amplitude_2x_m;
      runout[0] = a1 * std::cos(phi + p.runout.phase_1x_rad) +
                  a2 * std::cos(2.0 * phi + p.runout.phase_2x_rad);
      runout[1] = a1 * std::sin(phi + p.runout.phase_1x_rad) -
                  a2 * std::cos(2.0 * phi + p.runout.phase_2x_rad);
    }
    for (int axis = 0; axis < 2; ++axis) {
      Channel& c = channels_[i][axis];
      double v =
          p.AxisGain(axis) * (obs.sensor_xy_m[i][axis] + runout[axis]) + p.AxisOffset_m(axis);
      // Transport delay.
      if (c.delay_samples > 0 || c.delay_fraction > 0.0) {
        if (!c.primed) c.delay_line.fill(v);
        c.delay_line[c.head] = v;
        const int tail =
            (c.head - c.delay_samples + kMaxSensorDelaySamples) % kMaxSensorDelaySamples;
        const int before = (tail - 1 + kMaxSensorDelaySamples) % kMaxSensorDelaySamples;
        c.head = (c.head + 1) % kMaxSensorDelaySamples;
        v = c.delay_fraction > 0.0 ? (1.0 - c.delay_fraction) * c.delay_line[tail] +
                                         c.delay_fraction * c.delay_line[before]
                                   : c.delay_line[tail];
      }
      // Electronics low-pass; primed at rest on the first sample.
      if (!c.primed) {
        c.filtered = v;
        c.last_input = v;
      }
      const Filter& f = filter_[i];
      c.filtered = f.e * c.filtered + f.b0 * v + f.b1 * c.last_input;
      c.last_input = v;
      c.primed = true;
      v = c.filtered;
      if (p.noise.enabled) {
        const double w = c.noise.StandardNormalApprox();
        if (p.noise.bandwidth_Hz > 0.0) {
          const NoiseColour& k = colour_[i];
          c.coloured = c.primed_noise ? k.a * c.coloured + k.r * w : w;
          c.primed_noise = true;
          v += p.noise.std_dev_m * c.coloured;
        } else {
          v += p.noise.std_dev_m * w;
        }
      }
      if (p.quantisation_m > 0.0) v = p.quantisation_m * std::nearbyint(v / p.quantisation_m);
      out->reading_m[i][axis] = v;
      out->counts[i][axis] =
          p.output == SensorOutput::kCounts
              ? static_cast<std::int64_t>(std::llround(v * p.counts_per_m + p.counts_offset))
              : 0;
    }
  }
}

}  // namespace ambdrop
