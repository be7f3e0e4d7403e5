#pragma once
#include <cstdint>
#include <functional>
#include <string>

#include "controller_if/loop/run_record.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop {

struct ReplayResult {
  StepStatus status = StepStatus::kOk;
  bool watchdog_stop = false;  ///< the record says the run stopped on controller silence
  std::int64_t steps = 0;
  State final_state;
  std::string failure_message;  ///< with a state dump when status != kOk
};

/// Re-runs a recorded run offline, as fast as the machine allows: the recorded inputs and power
/// events applied at their recorded steps, in the order the live run applied them (power events,
/// then currents, then the power state), sensor samples every sensor_every_steps, an observation
/// every output interval. With the config the run was recorded with, every output is
/// bit-identical to the live run's. `observer` (optional) receives the state at every output
/// step and every sensor sample, as a live run's recorder does (the inputs and power events come
/// from the record, so it is not told of them).
ReplayResult ReplayRun(const Model& model, const RecordedRun& run,
                       const std::function<void(const Observation&)>& on_output,
                       const std::function<void(const RecordedSensors&)>& on_sensors,
                       const std::function<void(double fraction_done)>& on_progress = {},
                       RunRecorder* observer = nullptr);

}  // namespace ambdrop
