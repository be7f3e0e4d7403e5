#include "tools/fit/held_current.hpp"

#include <algorithm>
#include <cmath>

#include "rt_core/power_loss_drive.hpp"
#include "tools/fit/noise_floor.hpp"

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

double HeldCurrentWindowSeconds(const MeasuredRecord& r) {
  return std::min(2e-3, 40.0 * r.SampleInterval());
}

double HeldCurrentByLaw(const MeasuredRecord& r, int column, double trigger_s, const AmbParams& amb,
                        double* sd_A) {
  if (sd_A != nullptr) *sd_A = 0.0;
  const double reading = HeldCurrentAtTrigger(r, column, trigger_s, true);
  const std::vector<double>& ts = r.time_s;
  const std::vector<double>& v = r.values[static_cast<std::size_t>(column)];
  const double slack = 1e-6 * r.SampleInterval();
  const double window = HeldCurrentWindowSeconds(r);
  const auto first = std::lower_bound(ts.begin(), ts.end(), trigger_s - slack) - ts.begin();
  const auto law = [&](double c0, double t) {
    return ReportedCoilCurrent(PowerLossDrive(amb, c0, std::max(0.0, t)));
  };
  double c0 = reading;
  const double h = 1e-6 + 1e-6 * std::abs(reading);
  for (int iteration = 0; iteration < 4; ++iteration) {
    double jtj = 0.0, jte = 0.0;
    for (auto j = static_cast<std::size_t>(first); j < ts.size(); ++j) {
      const double t = ts[j] - trigger_s;
      if (t > window + slack) break;
      const double predicted = law(c0, t);
      const double slope = (law(c0 + h, t) - law(c0 - h, t)) / (2.0 * h);
      jtj += slope * slope;
      jte += slope * (v[j] - predicted);
    }
    if (!(jtj > 0.0)) return reading;  // the law's current does not depend on c0
    const double step = jte / jtj;
    c0 += step;
    if (!std::isfinite(c0)) return reading;
    if (std::abs(step) <= 1e-12 * (1.0 + std::abs(c0))) break;
  }
  if (sd_A != nullptr) {
    // From the samples' noise (their second differences: a law's smooth fall has almost
    // none), not from the fit's residual: a law that does not fit would otherwise widen its
    // own agreement limit and hide itself.
    double jtj = 0.0;
    std::size_t count = 0;
    for (auto j = static_cast<std::size_t>(first); j < ts.size(); ++j) {
      const double t = ts[j] - trigger_s;
      if (t > window + slack) break;
      const double slope = (law(c0 + h, t) - law(c0 - h, t)) / (2.0 * h);
      jtj += slope * slope;
      ++count;
    }
    const auto from = static_cast<std::size_t>(first);
    const double noise = NoiseSigma(v, from, from + count);
    if (jtj > 0.0) *sd_A = noise / std::sqrt(jtj);
  }
  return c0;
}

}  // namespace ambdrop
