#include "tools/record/trajectory_hasher.hpp"

#include <fmt/format.h>

#include <span>

namespace ambdrop {

void TrajectoryHasher::Mix(const void* data, std::size_t size) noexcept {
  hash_ =
      Fnv1a64(std::span<const std::uint8_t>(static_cast<const std::uint8_t*>(data), size), hash_);
}

void TrajectoryHasher::OnStart(const RecordedStart& start) noexcept {
  if (next_ != nullptr) next_->OnStart(start);
}

void TrajectoryHasher::OnInput(const RecordedInput& input) noexcept {
  if (next_ != nullptr) next_->OnInput(input);
}

void TrajectoryHasher::OnPower(const RecordedPower& power) noexcept {
  if (next_ != nullptr) next_->OnPower(power);
}

void TrajectoryHasher::OnSensors(const RecordedSensors& sensors) noexcept {
  if (next_ != nullptr) next_->OnSensors(sensors);
  if (sensors.step > last_sensor_step_) return;
  Mix(&sensors.step, sizeof sensors.step);
  // Only the rig's own sensors: the unused slots of the fixed-size arrays are not results.
  for (std::size_t s = 0; s < sensor_count_ && s < kMaxSensors; ++s) {
    Mix(sensors.readings.reading_m[s].data(), sizeof sensors.readings.reading_m[s]);
    Mix(sensors.readings.counts[s].data(), sizeof sensors.readings.counts[s]);
  }
  ++sensor_samples_;
}

void TrajectoryHasher::OnState(const State& state, const Observation& observation) noexcept {
  Mix(&state.step_index, sizeof state.step_index);
  Mix(state.y.data(), sizeof(double) * static_cast<std::size_t>(state.y.size()));
  ++states_;
  if (next_ != nullptr) next_->OnState(state, observation);
}

std::string TrajectoryHasher::Hex() const {
  return fmt::format("{:016x}", hash_);
}

}  // namespace ambdrop
