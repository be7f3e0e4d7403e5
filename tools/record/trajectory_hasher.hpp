#pragma once
// A run's fingerprint for determinism checks: every bit of the state at each output step and of
// every sensor sample, hashed as the run goes (FNV-1a 64). It covers the physics and what the
// controller saw, not the layout of summary.json or timeseries.csv, so that new summary fields or
// CSV columns leave it alone while any change of a result bit changes it.
#include <cstdint>
#include <string>

#include "controller_if/loop/run_record.hpp"
#include "io/files/event_log.hpp"

namespace ambdrop {

/// A RunRecorder that hashes states and sensor samples, then hands every event on to `next`
/// (which may be null). Allocation-free and noexcept, as the real-time thread requires.
class TrajectoryHasher final : public RunRecorder {
 public:
  explicit TrajectoryHasher(std::size_t sensor_count, RunRecorder* next = nullptr) noexcept
      : sensor_count_(sensor_count), next_(next) {}

  void OnStart(const RecordedStart& start) noexcept override;
  void OnInput(const RecordedInput& input) noexcept override;
  void OnPower(const RecordedPower& power) noexcept override;
  void OnSensors(const RecordedSensors& sensors) noexcept override;
  void OnState(const State& state, const Observation& observation) noexcept override;

  /// Sensor samples after `step` are left out of the hash. A replay samples once more at its end
  /// step, where a HIL session samples and an offline run does not: bounded by the record's last
  /// sample, a replay's hash covers what the live run sent, and equals the live run's.
  void HashSensorsUpTo(std::int64_t step) noexcept { last_sensor_step_ = step; }

  std::uint64_t value() const noexcept { return hash_; }
  /// 16 lower-case hex digits.
  std::string Hex() const;
  std::int64_t states() const noexcept { return states_; }
  std::int64_t sensor_samples() const noexcept { return sensor_samples_; }

 private:
  void Mix(const void* data, std::size_t size) noexcept;

  std::size_t sensor_count_;
  RunRecorder* next_;
  std::uint64_t hash_ = kFnv1a64Basis;
  std::int64_t states_ = 0;
  std::int64_t sensor_samples_ = 0;
  std::int64_t last_sensor_step_ = INT64_MAX;
};

}  // namespace ambdrop
