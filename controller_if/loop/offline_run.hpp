#pragma once
#include <cstdint>
#include <functional>
#include <string>

#include "controller_if/loop/run_record.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop {

struct OfflineRunResult {
  StepStatus status = StepStatus::kOk;
  std::int64_t steps = 0;
  State final_state;
  std::string failure_message;  ///< with a state dump when status != kOk
  /// The settled start (simulation.settle_s): steps run before t = 0, and the largest change of
  /// the rotor at a sensor plane over its last revolution (SettleResult). 0 without one.
  std::int64_t settle_steps = 0;
  double settle_last_change_m = 0.0;
};

/// Called at every output row with the state's observation and the AMB currents applied from
/// the row's time on (over the step that starts there; at the last row, the commands of the step
/// before and the coil currents at that time).
using OfflineOutput = std::function<void(const Observation&, const AmbCurrents&)>;

/// Runs a model offline on the virtual clock: scheduled trigger, AMB currents from the
/// configured profiles, an observation every output interval (and at t = 0) passed to
/// `on_output`. Stops early, with a message and a state dump, if the simulation diverges.
/// `recorder` (optional) receives every input change, power event, sensor sample and state.
OfflineRunResult RunOffline(const Model& model,
                            const std::function<void(const Observation&)>& on_output,
                            const std::function<void(double fraction_done)>& on_progress = {},
                            RunRecorder* recorder = nullptr);
/// The same, with the AMB currents of each output row.
OfflineRunResult RunOfflineWithCurrents(
    const Model& model, const OfflineOutput& on_output,
    const std::function<void(double fraction_done)>& on_progress = {},
    RunRecorder* recorder = nullptr);

}  // namespace ambdrop
