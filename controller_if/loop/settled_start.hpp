#pragma once
// The opt-in settled start (simulation.settle_s): before the run's t = 0 the in-process closed
// loop runs, powered, without trigger or output, so that the controller's filters, integrators
// and delay, the sensors' delay lines and the rotor's synchronous orbit are steady when the run
// starts, as on a rig that has levitated for a while before its record begins. The default
// (settle_s = 0) keeps the levitated equilibrium start, so references do not move.
#include <array>
#include <cstdint>
#include <string>

#include "controller_if/boundary/sensor_emulator.hpp"
#include "controller_if/controller/pid_controller.hpp"
#include "rt_core/control_input.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "rt_core/tdb_clearance_watch.hpp"

namespace ambdrop {

struct SettleResult {
  StepStatus status = StepStatus::kOk;
  std::string failure;     ///< with a state dump when status != kOk
  std::int64_t steps = 0;  ///< physics steps settled (a whole number of controller periods)
  /// Largest change of the rotor's displacement at any sensor plane over the last spin
  /// revolution of the settling (or its last 10 ms without spin): how steady the start is (a
  /// synchronous orbit repeats each revolution); 0 when nothing settled.
  double last_change_m = 0.0;
  /// How close the journal came to each TDB while settling.
  TdbClearanceWatch clearance;
};

/// Steps of simulation.settle_s, rounded to whole controller periods.
std::int64_t SettleSteps(const Model& model);

/// Runs the closed loop for SettleSteps(model) steps from `state`, the `controller` and the
/// `sensors` (which keep their state: the run goes on with them) and `input` (the controller's
/// currents; on return those it commands at the run's start). Then the state's clock is set
/// back to step 0; the spin angle runs on. Does nothing for settle_s = 0.
SettleResult SettleClosedLoop(const Model& model, Simulator& sim, State* state,
                              ReferenceController* controller, SensorEmulator* sensors,
                              ControlInput* input);

}  // namespace ambdrop
