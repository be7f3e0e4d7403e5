#include "controller_if/loop/replay_run.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "controller_if/loop/state_dump.hpp"

namespace ambdrop {

ReplayResult ReplayRun(const Model& model, const RecordedRun& run,
                       const std::function<void(const Observation&)>& on_output,
                       const std::function<void(const RecordedSensors&)>& on_sensors,
                       const std::function<void(double)>& on_progress, RunRecorder* observer) {
  const double dt = model.params.simulation.step_s;
  Simulator sim(model);
  std::optional<SensorEmulator> sensors;
  if (run.sensor_every_steps > 0) {
    sensors.emplace(model.params.sensors, static_cast<double>(run.sensor_every_steps) * dt);
  }
  PowerState power(model);
  ControlInput input;
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    input.amb[a].current_A = run.start.loop_current_A[a];
  }
  ReplayResult result;
  State state = sim.InitialState(run.start.equilibrium_input);
  const std::int64_t output_every =
      std::max<std::int64_t>(1, std::llround(model.params.simulation.output_interval_s / dt));
  const std::int64_t end = run.end_step;
  const std::int64_t progress_every = std::max<std::int64_t>(1, end / 200);
  Observation obs;
  RecordedSensors sample;
  auto send_sensors = [&] {
    if (!sensors || state.step_index % run.sensor_every_steps != 0) return;
    sim.Observe(state, &obs);
    sample.step = state.step_index;
    sample.time_s = obs.time_s;
    sensors->Sample(obs, &sample.readings);
    if (on_sensors) on_sensors(sample);
    if (observer != nullptr) observer->OnSensors(sample);
  };
  const auto output = [&] {
    sim.Observe(state, &obs);
    if (on_output) on_output(obs);
    if (observer != nullptr) observer->OnState(state, obs);
  };
  if (on_output || observer != nullptr) output();
  std::size_t next_input = 0;
  std::size_t next_power = 0;
  while (state.step_index < end) {
    const std::int64_t k = state.step_index;
    send_sensors();
    // Events recorded for steps already passed cannot come from a live run; skip them.
    while (next_power < run.power.size() && run.power[next_power].step < k) ++next_power;
    while (next_input < run.inputs.size() && run.inputs[next_input].step < k) ++next_input;
    for (; next_power < run.power.size() && run.power[next_power].step == k; ++next_power) {
      power.Apply(run.power[next_power].event, k, input);
    }
    for (; next_input < run.inputs.size() && run.inputs[next_input].step == k; ++next_input) {
      const RecordedInput& in = run.inputs[next_input];
      switch (in.kind) {
        case RecordedInputKind::kCurrents:
          for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
            input.amb[a].current_A = in.current_A[a];
          }
          break;
        case RecordedInputKind::kWatchdogZero:
          for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
            input.amb[a].current_A = {0.0, 0.0};
          }
          break;
        case RecordedInputKind::kWatchdogStop:
          result.watchdog_stop = true;
          break;
      }
    }
    if (result.watchdog_stop) break;
    power.Fill(k, &input);
    const StepStatus status = sim.Step(&state, input);
    if (status != StepStatus::kOk) {
      result.status = status;
      result.failure_message = DescribeFailure(model, status, state);
      break;
    }
    if ((on_output || observer != nullptr) && state.step_index % output_every == 0) output();
    if (on_progress && state.step_index % progress_every == 0) {
      on_progress(static_cast<double>(state.step_index) / static_cast<double>(end));
    }
  }
  if (result.status == StepStatus::kOk && !result.watchdog_stop) send_sensors();
  result.steps = state.step_index;
  result.final_state = state;
  return result;
}

}  // namespace ambdrop
