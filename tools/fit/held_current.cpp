#include "tools/fit/held_current.hpp"

#include <algorithm>

namespace ambdrop {

double HeldCurrentAtTrigger(const MeasuredRecord& r, int column, double trigger_s) {
  const std::vector<double>& ts = r.time_s;
  const std::vector<double>& v = r.values[static_cast<std::size_t>(column)];
  // A sample at the trigger's own time (to a rounding error of its time) may be taken after
  // the cut, already inside the decay: only samples clearly before it count.
  const double slack = 1e-6 * r.SampleInterval();
  const auto after = std::lower_bound(ts.begin(), ts.end(), trigger_s - slack);
  if (after == ts.begin()) return v.front();
  return v[static_cast<std::size_t>(after - ts.begin()) - 1];
}

}  // namespace ambdrop
