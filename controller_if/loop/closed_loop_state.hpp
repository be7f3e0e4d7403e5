#pragma once
// All the mutable state of a run: the step driver's (the physics state, the power state and its
// power-loss law, the sensors' noise generators and delay lines, the input) and the in-process
// controller's (integrators, derivative filters, its delay line and amplifier loop). A plain
// value: a copy taken mid-run goes on bit for bit (tests/step_driver_test.cpp). What a run
// reads from outside (a profile, a record, a link) is not in it.
#include <cstdint>
#include <optional>

#include "controller_if/controller/pid_controller.hpp"
#include "controller_if/loop/step_driver.hpp"

namespace ambdrop {

struct ClosedLoopState {
  /// `controlled`: the in-process controller runs, every `substeps` steps.
  ClosedLoopState(const Model& model, std::int64_t substeps, bool controlled)
      : driver(model, controlled ? substeps : 0) {
    if (controlled) {
      controller.emplace(model, static_cast<double>(substeps) * model.params.simulation.step_s,
                         model.params.simulation.step_s);
    }
  }
  StepDriver driver;
  std::optional<ReferenceController> controller;  ///< empty: the currents come from elsewhere
};

}  // namespace ambdrop
