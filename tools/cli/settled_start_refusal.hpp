#pragma once
// The runs whose loop (controller_if/loop/hil_session.hpp) starts from the levitated equilibrium
// refuse simulation.settle_s (only `sim` and `fit` run the settled start).
#include <string>

#include "rt_core/model.hpp"

namespace ambdrop {

/// True, with the error on stderr, if the model asks for a settled start that a `run_kind`
/// ("hil", "scenario") run cannot give.
bool RefusesSettledStart(const Model& model, const std::string& config_path, const char* run_kind);

}  // namespace ambdrop
