#pragma once
// How close a run's journal came to touching each TDB: a run that never came close repeats,
// bit for bit, with any TDB that leaves it as free (tools/fit/levitated_prefix_cache.hpp).
// Watched between steps, outside the step: it reads the state and allocates nothing.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "rt_core/model.hpp"
#include "rt_core/state.hpp"

namespace ambdrop {

struct TdbClearanceWatch {
  /// Per TDB: the journal's largest reach from the machine axis, its distance plus twice its
  /// speed times the step (where the RK4 stages between the steps may take it).
  std::array<double, kMaxTdbs> journal_reach_m{};
  /// Per TDB: its smallest free radius (TouchdownBearing::FreeRadius_m).
  std::array<double, kMaxTdbs> free_radius_m = Unbounded();

  void Watch(const Model& m, const StateVector& y) noexcept {
    const int n = m.modes();
    const double dt = m.params.simulation.step_s;
    for (std::size_t i = 0; i < m.tdbs.size(); ++i) {
      const StationShape& shape = m.tdb_shapes[i];
      const double x = shape.row(0).dot(y.head(n)), yy = shape.row(1).dot(y.head(n));
      const double vx = shape.row(0).dot(y.segment(n, n)), vy = shape.row(1).dot(y.segment(n, n));
      // (sqrt, not hypot: glibc's hypot was 4 % of a fit; no overflow at these magnitudes)
      journal_reach_m[i] = std::max(
          journal_reach_m[i], std::sqrt(x * x + yy * yy) + 2.0 * dt * std::sqrt(vx * vx + vy * vy));
      free_radius_m[i] =
          std::min(free_radius_m[i], m.tdbs[i]->FreeRadius_m(y.data() + m.tdb_state_offset[i]));
    }
  }
  /// Both watches' extremes.
  void Merge(const TdbClearanceWatch& other) noexcept {
    for (int i = 0; i < kMaxTdbs; ++i) {
      journal_reach_m[i] = std::max(journal_reach_m[i], other.journal_reach_m[i]);
      free_radius_m[i] = std::min(free_radius_m[i], other.free_radius_m[i]);
    }
  }

 private:
  static std::array<double, kMaxTdbs> Unbounded() noexcept {
    std::array<double, kMaxTdbs> a;
    a.fill(std::numeric_limits<double>::infinity());
    return a;
  }
};

}  // namespace ambdrop
