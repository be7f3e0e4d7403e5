#include "tools/fit/held_current.hpp"

#include <algorithm>

namespace ambdrop {

double HeldCurrentAtTrigger(const MeasuredRecord& r, int column, double trigger_s,
                            bool decay_seen) {
  const std::vector<double>& ts = r.time_s;
  const std::vector<double>& v = r.values[static_cast<std::size_t>(column)];
  // A sample at the trigger's own time (to a rounding error of its time) counts as after it.
  const double slack = 1e-6 * r.SampleInterval();
  const auto after = std::lower_bound(ts.begin(), ts.end(), trigger_s - slack);
  const std::size_t first = static_cast<std::size_t>(after - ts.begin());
  if (decay_seen && first + 1 < ts.size() && ts[first + 1] > ts[first]) {
    const double slope = (v[first + 1] - v[first]) / (ts[first + 1] - ts[first]);
    return v[first] - slope * std::max(0.0, ts[first] - trigger_s);
  }
  if (first == 0) return v.front();
  return v[first - 1];
}

}  // namespace ambdrop
