#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "controller_if/loop/run_record.hpp"
#include "io/files/json_writer.hpp"

namespace ambdrop {

/// Compares replayed sensor samples with the recorded ones, step by step, bit for bit: the
/// first difference (step, sensor, axis, values) and the largest one per channel. Beside the
/// bits, by value within `tolerance_m` (-0 equals 0, NaN equals NaN): what `replay --strict`
/// holds a record to (a candump log carries readings in the frame map's counts).
class SensorDiff {
 public:
  SensorDiff(const std::vector<RecordedSensors>& recorded, std::vector<std::string> sensor_names,
             double tolerance_m = 0.0);

  /// A replayed sample; samples at steps the record has none for are not compared.
  void Add(const RecordedSensors& replayed);

  bool identical() const noexcept { return differing_ == 0 && missing() == 0; }
  /// Every recorded sample reproduced, each reading within the tolerance by value.
  bool within_tolerance() const noexcept { return beyond_tolerance_ == 0 && missing() == 0; }
  std::int64_t beyond_tolerance() const noexcept { return beyond_tolerance_; }
  double tolerance_m() const noexcept { return tolerance_m_; }
  std::int64_t compared() const noexcept { return compared_; }
  std::int64_t differing() const noexcept { return differing_; }
  /// Step of the first differing sample; -1 if none differs.
  std::int64_t first_difference_step() const noexcept { return first_.step; }
  /// Recorded samples the replay never produced (it stopped earlier).
  std::int64_t missing() const noexcept {
    return static_cast<std::int64_t>(recorded_.size()) - compared_;
  }
  /// One line for people: "identical (N samples)" or the first difference and the largest.
  std::string Describe(double step_s) const;
  void WriteJson(JsonWriter& json, double step_s) const;

 private:
  struct Difference {
    std::int64_t step = -1;
    int sensor = 0;
    int axis = 0;
    double recorded_m = 0.0;
    double replayed_m = 0.0;
  };
  const std::vector<RecordedSensors>& recorded_;
  std::vector<std::string> names_;
  std::size_t next_ = 0;
  std::int64_t compared_ = 0;
  std::int64_t differing_ = 0;
  double tolerance_m_ = 0.0;
  std::int64_t beyond_tolerance_ = 0;
  Difference first_;
  std::vector<double> max_abs_m_;  // per sensor*2 + axis
};

}  // namespace ambdrop
