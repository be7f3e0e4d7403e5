#include "tools/record/sensor_diff.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstring>

namespace ambdrop {

SensorDiff::SensorDiff(const std::vector<RecordedSensors>& recorded,
                       std::vector<std::string> sensor_names, double tolerance_m)
    : recorded_(recorded),
      names_(std::move(sensor_names)),
      tolerance_m_(tolerance_m),
      max_abs_m_(2 * names_.size(), 0.0) {}

void SensorDiff::Add(const RecordedSensors& replayed) {
  while (next_ < recorded_.size() && recorded_[next_].step < replayed.step) ++next_;
  if (next_ >= recorded_.size() || recorded_[next_].step != replayed.step) return;
  const RecordedSensors& rec = recorded_[next_++];
  ++compared_;
  bool differs = false;
  bool beyond = false;
  for (std::size_t s = 0; s < names_.size(); ++s) {
    for (int axis = 0; axis < 2; ++axis) {
      const double a = rec.readings.reading_m[s][axis];
      const double b = replayed.readings.reading_m[s][axis];
      if (std::memcmp(&a, &b, sizeof a) == 0) continue;
      // By value: -0 and 0 are one reading; two NaNs (a sensor that reads nothing) agree.
      const bool both_nan = std::isnan(a) && std::isnan(b);
      if (!both_nan && !(std::abs(a - b) <= tolerance_m_)) beyond = true;
      differs = true;
      const double d = std::abs(a - b);
      double& m = max_abs_m_[2 * s + axis];
      if (!(d <= m)) m = d;  // NaN differences count as the largest
      if (first_.step < 0) first_ = {rec.step, static_cast<int>(s), axis, a, b};
    }
  }
  if (differs) ++differing_;
  if (beyond) ++beyond_tolerance_;
}

std::string SensorDiff::Describe(double step_s) const {
  if (identical()) return fmt::format("identical, bit for bit ({} sensor samples)", compared_);
  std::string text;
  if (differing_ > 0) {
    const char* axis = first_.axis == 0 ? "x" : "y";
    text = fmt::format(
        "{} of {} sensor samples differ; first at step {} (t = {:.6f} s), sensor {} {}: "
        "recorded {:.9g} m, replayed {:.9g} m (difference {:.3g} m)",
        differing_, compared_, first_.step, first_.step * step_s, names_[first_.sensor], axis,
        first_.recorded_m, first_.replayed_m, first_.replayed_m - first_.recorded_m);
    for (std::size_t c = 0; c < max_abs_m_.size(); ++c) {
      if (max_abs_m_[c] != 0.0) {
        text += fmt::format("\n  max |difference| {} {}: {:.3g} m", names_[c / 2],
                            c % 2 == 0 ? "x" : "y", max_abs_m_[c]);
      }
    }
  }
  if (missing() > 0) {
    text += fmt::format("{}{} recorded samples were not reproduced (the replay ended earlier)",
                        text.empty() ? "" : "\n  ", missing());
  }
  return text;
}

void SensorDiff::WriteJson(JsonWriter& json, double step_s) const {
  json.Key("identical").Bool(identical());
  json.Key("samples_compared").Integer(compared_);
  json.Key("samples_differing").Integer(differing_);
  json.Key("samples_missing").Integer(missing());
  json.Key("tolerance_m").Number(tolerance_m_);
  json.Key("samples_beyond_tolerance").Integer(beyond_tolerance_);
  json.Key("within_tolerance").Bool(within_tolerance());
  if (differing_ > 0) {
    json.Key("first_difference").BeginObject();
    json.Key("step").Integer(first_.step);
    json.Key("time_s").Number(first_.step * step_s);
    json.Key("sensor").String(names_[first_.sensor]);
    json.Key("axis").String(first_.axis == 0 ? "x" : "y");
    json.Key("recorded_m").Number(first_.recorded_m);
    json.Key("replayed_m").Number(first_.replayed_m);
    json.EndObject();
    json.Key("max_abs_difference_m").BeginObject();
    for (std::size_t c = 0; c < max_abs_m_.size(); ++c) {
      json.Key(names_[c / 2] + (c % 2 == 0 ? ".x" : ".y")).Number(max_abs_m_[c]);
    }
    json.EndObject();
  }
}

}  // namespace ambdrop
