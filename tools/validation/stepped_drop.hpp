#pragma once
// A drop stepped by hand and observed at every step, for the light catcher-bearing rigs
// (seeds 003, 004) whose impacts last a few steps: an output interval would miss their peaks.
// Powered until the trigger (ControlInput::Powered: motor on, AMBs at full force with zero
// control currents, which is all their equivalent-stiffness laws need), everything off from it
// on; no controller or current profile is run.
#include <functional>
#include <string>

#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop {

struct SteppedDrop {
  StepStatus status = StepStatus::kOk;
  State final_state;
  std::string failure_message;  ///< with a state dump when status != kOk
};

/// Steps `model` until `after_trigger_s` past its trigger step (or the first failed step);
/// `on_step` sees every state from the trigger step on.
SteppedDrop RunSteppedDrop(const Model& model, double after_trigger_s,
                           const std::function<void(const Observation&)>& on_step);

}  // namespace ambdrop
