#include "controller_if/current_profile.hpp"

#include <algorithm>

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

}  // namespace ambdrop
