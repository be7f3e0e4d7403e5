#pragma once
#include <array>

#include "rt_core/limits.hpp"

namespace ambdrop {

/// What the controller side hands the physics for one step (zero-order hold over the step).
struct ControlInput {
  bool power_on = true;  ///< false after the shutdown trigger: AMB forces removed
  /// Control currents (x, y) per AMB, used by the linearised-currents force law.
  std::array<std::array<double, 2>, kMaxAmbs> current_A{};
};

}  // namespace ambdrop
