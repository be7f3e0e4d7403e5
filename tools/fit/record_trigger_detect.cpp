#include "tools/fit/record_trigger_detect.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace ambdrop {
namespace {

// One channel's levitated level and how far from it a row must be to count.
struct Levitated {
  const std::vector<double>* values = nullptr;
  double mean = 0.0;
  double band = 0.0;  // within it, a row may still be levitated
  double far = 0.0;   // beyond it, the row is not
};

Levitated LevelOf(const std::vector<double>& v, std::size_t quiet, bool scaled_by_mean) {
  Levitated l;
  l.values = &v;
  for (std::size_t j = 0; j < quiet; ++j) l.mean += v[j];
  l.mean /= static_cast<double>(quiet);
  double var = 0.0;
  for (std::size_t j = 0; j < quiet; ++j) var += (v[j] - l.mean) * (v[j] - l.mean);
  double sigma = std::sqrt(var / static_cast<double>(quiet));
  // A noise-free or coarsely quantised channel may read one value throughout: a floor far below
  // anything the failure moves keeps "no change" from meaning "any change".
  double reach = 0.0;
  for (const double x : v) reach = std::max(reach, std::abs(x - l.mean));
  sigma = std::max(sigma, 1e-9 * reach);
  l.band = 3.0 * sigma;
  // A coil current's or command's level is a scale of its own (a slow drift of an integral
  // action is not a failure); a displacement's level is a place, not a scale.
  l.far = std::max(8.0 * sigma, scaled_by_mean ? 0.2 * std::abs(l.mean) : 0.0);
  return l;
}

}  // namespace

double RecordTriggerTime(const MeasurementParams& m, const MeasuredRecord& r) {
  if (m.trigger_time_s) return *m.trigger_time_s;
  const std::size_t rows = r.time_s.size();
  const std::size_t quiet = std::max<std::size_t>(rows / 10, 2);
  std::vector<Levitated> channels;
  for (const MeasurementChannel& ch : m.channels) {
    const bool electrical = ch.quantity == MeasuredQuantity::kCurrent ||
                            ch.quantity == MeasuredQuantity::kControllerCommand;
    if (!electrical && ch.quantity != MeasuredQuantity::kDisplacement) continue;
    channels.push_back(LevelOf(r.values[r.Column(ch.column)], quiet, electrical));
  }
  if (channels.empty()) {
    throw std::runtime_error(
        "measurement.trigger = \"detect\" needs a current, controller_command or displacement "
        "channel; give trigger_time_s");
  }
  const auto far = [&](std::size_t j) {
    return std::any_of(channels.begin(), channels.end(), [j](const Levitated& l) {
      return std::abs((*l.values)[j] - l.mean) > l.far;
    });
  };
  const auto within = [&](std::size_t j) {
    return std::all_of(channels.begin(), channels.end(), [j](const Levitated& l) {
      return std::abs((*l.values)[j] - l.mean) <= l.band;
    });
  };
  // A glitch is not a failure: far for half a millisecond (four rows at least) on end.
  const double dt = r.SampleInterval();
  const std::size_t sustained =
      std::max<std::size_t>(4, static_cast<std::size_t>(std::ceil(0.5e-3 / dt)));
  std::size_t run = 0, first_far = rows;
  for (std::size_t j = quiet; j < rows; ++j) {
    run = far(j) ? run + 1 : 0;
    if (run == sustained) {
      first_far = j + 1 - sustained;
      break;
    }
  }
  if (first_far >= rows) {
    throw std::runtime_error(
        "measurement.trigger = \"detect\": no current, command or displacement leaves its "
        "levitated level (the record's first tenth) for good; give trigger_time_s");
  }
  std::size_t j = first_far;
  while (j > quiet && !within(j)) --j;
  // The power went between row j (still levitated) and row j + 1: the middle of the interval
  // is the unbiased estimate, wrong by half a sample at most where either end may be a whole
  // one (a sampler that reads after the cut puts it on row j + 1, one before it on row j).
  return 0.5 * (r.time_s[j] + r.time_s[j + 1]);
}

}  // namespace ambdrop
