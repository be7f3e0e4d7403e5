#pragma once
// The two properties every TDB model's step is held to, on a rig's own drop (powered until its
// trigger step, unpowered after): the step allocates nothing through the drop and its contacts,
// and repeated runs, and a state copied mid-run, go on bit for bit.
#include "rt_core/model.hpp"

namespace ambdrop::testing {

/// Steps `steps` times from the initial state under a MallocGuard: the steps all ran, a TDB
/// carried a normal force (the window held contacts), and nothing was allocated.
void ExpectDropAllocatesNothing(const Model& model, int steps = 20000);

/// Two simulators over `steps` steps agree bit for bit at every step; a copy of the state then
/// goes on `after_copy` steps exactly as the original.
void ExpectDropBitIdentical(const Model& model, int steps = 20000, int after_copy = 1000);

}  // namespace ambdrop::testing
