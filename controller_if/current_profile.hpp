#pragma once
#include <array>
#include <vector>

#include "rt_core/amb_params.hpp"

namespace ambdrop {

/// Control currents (x, y) of one AMB at time t from its profile: linear between samples, held
/// beyond the ends, zero for an empty profile. Allocation-free (binary search).
std::array<double, 2> CurrentAt(const std::vector<CurrentSample>& profile, double time_s) noexcept;

}  // namespace ambdrop
