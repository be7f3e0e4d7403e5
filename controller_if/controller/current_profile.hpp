#pragma once
#include <array>
#include <vector>

#include "rt_core/amb_params.hpp"
#include "rt_core/control_input.hpp"
#include "rt_core/model.hpp"

namespace ambdrop {

/// Control currents (x, y) of one AMB at time t from its profile: linear between samples, held
/// beyond the ends, zero for an empty profile. Allocation-free (binary search).
std::array<double, 2> CurrentAt(const std::vector<CurrentSample>& profile, double time_s) noexcept;

/// Currents of every AMB sampled at a series of times (a recording's inputs).
struct CurrentSeries {
  std::vector<double> time_s;                                          ///< increasing
  std::vector<std::array<std::array<double, 2>, kMaxAmbs>> current_A;  ///< per time: per AMB x, y
  int ambs = 0;
};

/// The samples of `series` to keep so that linear interpolation between them follows all of
/// it as closely as `max_points` points allow: greedy refinement (the sample farthest from the
/// interpolation so far is added next, error measured over every AMB and axis), stopping early
/// once the interpolation is exact (within 1 nA). Keeps both ends. `max_error_A` is what remains.
struct ProfileDecimation {
  std::vector<std::size_t> kept;  ///< indices into the series, increasing
  double max_error_A = 0.0;
};
ProfileDecimation DecimateCurrents(const CurrentSeries& series, std::size_t max_points);

/// Every AMB's profile currents at time 0: what a rig without a controller starts on.
ControlInput ProfileStartInput(const Model& model);

}  // namespace ambdrop
