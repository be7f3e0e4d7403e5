#include "controller_if/controller/current_profile.hpp"

#include <algorithm>
#include <cmath>
#include <queue>

namespace ambdrop {

std::array<double, 2> CurrentAt(const std::vector<CurrentSample>& p, double t) noexcept {
  if (p.empty()) return {0.0, 0.0};
  if (t <= p.front().time_s) return {p.front().current_x_A, p.front().current_y_A};
  if (t >= p.back().time_s) return {p.back().current_x_A, p.back().current_y_A};
  const auto hi = std::upper_bound(p.begin(), p.end(), t,
                                   [](double v, const CurrentSample& s) { return v < s.time_s; });
  const auto lo = hi - 1;
  const double w = (t - lo->time_s) / (hi->time_s - lo->time_s);
  return {lo->current_x_A + w * (hi->current_x_A - lo->current_x_A),
          lo->current_y_A + w * (hi->current_y_A - lo->current_y_A)};
}

namespace {

struct Segment {
  std::size_t first = 0;
  std::size_t last = 0;
  std::size_t worst = 0;  // the sample farthest from the chord first..last
  double error_A = 0.0;
  bool operator<(const Segment& o) const {
    // Ties go to the earlier segment, so the choice does not depend on the heap's layout.
    return error_A < o.error_A || (error_A == o.error_A && first > o.first);
  }
};

Segment Measure(const CurrentSeries& s, std::size_t first, std::size_t last) {
  Segment seg{first, last, first, 0.0};
  const double t0 = s.time_s[first];
  const double span = s.time_s[last] - t0;
  for (std::size_t j = first + 1; j < last; ++j) {
    const double w = (s.time_s[j] - t0) / span;
    for (int a = 0; a < s.ambs; ++a) {
      for (int axis = 0; axis < 2; ++axis) {
        const double lo = s.current_A[first][a][axis];
        const double hi = s.current_A[last][a][axis];
        const double e = std::abs(s.current_A[j][a][axis] - (lo + w * (hi - lo)));
        if (e > seg.error_A) {
          seg.error_A = e;
          seg.worst = j;
        }
      }
    }
  }
  return seg;
}

}  // namespace

// Rounding leaves ~1e-16 A on a straight line; no amplifier resolves a nanoampere.
constexpr double kExactEnough_A = 1e-9;

ProfileDecimation DecimateCurrents(const CurrentSeries& series, std::size_t max_points) {
  ProfileDecimation result;
  const std::size_t n = series.time_s.size();
  if (n == 0) return result;
  result.kept.push_back(0);
  if (n == 1) return result;
  result.kept.push_back(n - 1);
  std::priority_queue<Segment> open;
  open.push(Measure(series, 0, n - 1));
  while (result.kept.size() < std::max<std::size_t>(max_points, 2) && !open.empty() &&
         open.top().error_A > kExactEnough_A) {
    const Segment seg = open.top();
    open.pop();
    result.kept.push_back(seg.worst);
    open.push(Measure(series, seg.first, seg.worst));
    open.push(Measure(series, seg.worst, seg.last));
  }
  std::sort(result.kept.begin(), result.kept.end());
  result.max_error_A = open.empty() ? 0.0 : open.top().error_A;
  return result;
}

ControlInput ProfileStartInput(const Model& model) {
  ControlInput input;
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    input.amb[a].current_A = CurrentAt(model.params.ambs[a].current_profile, 0.0);
  }
  return input;
}

}  // namespace ambdrop
