#pragma once
#include <string>

#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop {

/// A readable account of a failed step: what went wrong, when, and the state it left
/// (modal coordinates, spin, journal positions, TDB states), so the run can be diagnosed.
std::string DescribeFailure(const Model& model, StepStatus status, const State& state);

}  // namespace ambdrop
