#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "controller_if/boundary/portable_random.hpp"
#include "rt_core/limits.hpp"
#include "rt_core/model_params.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop {

/// One sample of every sensor as the controller receives it.
struct SensorReadings {
  std::array<std::array<double, 2>, kMaxSensors> reading_m{};     ///< (x, y), metres
  std::array<std::array<std::int64_t, 2>, kMaxSensors> counts{};  ///< when output = counts
};

/// Turns the rotor's true displacement at each sensor plane into what the sensor electronics
/// deliver, sample by sample at the controller rate (SensorParams says the model). All state
/// (delay lines, filter states, noise generators) lives in the object: copy it to copy the run.
/// Sample() is allocation-free.
class SensorEmulator {
 public:
  SensorEmulator(const std::vector<SensorParams>& sensors, double sample_period_s);
  void Sample(const Observation& observation, SensorReadings* out) noexcept;

 private:
  struct Channel {
    std::array<double, kMaxSensorDelaySamples> delay_line{};
    int delay_samples = 0;        ///< whole samples of the delay
    double delay_fraction = 0.0;  ///< and its fraction of one more, in [0, 1)
    int head = 0;
    double filtered = 0.0;
    double last_input = 0.0;  ///< the low-pass's input one sample ago
    bool primed = false;
    PortableRandom noise;
    double coloured = 0.0;  ///< the noise's AR(1) state, in units of std_dev_m
    bool primed_noise = false;
  };
  std::vector<SensorParams> params_;
  std::vector<std::array<Channel, 2>> channels_;
  /// A sensor's first-order low-pass, y_k = e y_(k-1) + b0 x_k + b1 x_(k-1) (off: 0, 1, 0).
  struct Filter {
    double e = 0.0;
    double b0 = 1.0;
    double b1 = 0.0;
  };
  std::array<Filter, kMaxSensors> filter_{};
  /// A sensor's noise colour: n_k = a n_(k-1) + r w_k, r = sqrt(1 - a^2) (white: 0, 1).
  struct NoiseColour {
    double a = 0.0;
    double r = 1.0;
  };
  std::array<NoiseColour, kMaxSensors> colour_{};
};

}  // namespace ambdrop
