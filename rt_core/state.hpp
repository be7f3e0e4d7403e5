#pragma once
#include <cstdint>

#include "rt_core/eigen_types.hpp"

namespace ambdrop {

/// Faults the step records instead of throwing (read by the caller after each step).
struct FaultCounters {
  std::int64_t non_finite_state = 0;
  std::int64_t excursion_beyond_bound = 0;
};

/// All mutable state of a run. Copying it copies the run.
/// y = [q (n), q' (n), spin speed (rad/s), spin angle (rad), TDB internal states ...]
struct State {
  StateVector y;
  std::int64_t step_index = 0;
  bool power_on = true;  ///< the motor drove the rotor (no full power failure) in the last step
  FaultCounters faults;
};

}  // namespace ambdrop
