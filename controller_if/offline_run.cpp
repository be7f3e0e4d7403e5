#include "controller_if/offline_run.hpp"

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "controller_if/current_profile.hpp"
#include "controller_if/hil_session.hpp"
#include "controller_if/pid_controller.hpp"
#include "controller_if/power_state.hpp"
#include "controller_if/sensor_emulator.hpp"
#include "controller_if/state_dump.hpp"

namespace ambdrop {
OfflineRunResult RunOffline(const Model& model,
                            const std::function<void(const Observation&)>& on_output,
                            const std::function<void(double)>& on_progress) {
  const double dt = model.params.simulation.step_s;
  const std::int64_t substeps =
      model.params.controller.kind == ControllerKind::kNone ? 1 : ControllerSubsteps(model);
  const bool internal = model.params.controller.kind == ControllerKind::kInternalPid;
  Simulator sim(model);
  SensorEmulator sensors(model.params.sensors, static_cast<double>(substeps) * dt);
  std::optional<ReferenceController> controller;
  ControlInput input;
  if (internal) {
    controller.emplace(model, static_cast<double>(substeps) * dt);
    controller->Initial(&input);
  } else {
    for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
      input.amb[a].current_A = CurrentAt(model.params.ambs[a].current_profile, 0.0);
    }
  }
  PowerState power(model);
  const PowerEvent failure = ScheduledFailure(model);
  const PowerEvent restore = ScheduledRestore(model);
  if (model.trigger_step == 0) power.Apply(failure, 0, input);
  power.Fill(0, &input);

  OfflineRunResult result;
  // A controller-driven rotor starts levitated on the currents that carry its static load.
  State state = sim.InitialState(internal ? StaticLoadInput(model) : input);
  const std::int64_t output_every =
      std::max<std::int64_t>(1, std::llround(model.params.simulation.output_interval_s / dt));
  const std::int64_t progress_every = std::max<std::int64_t>(1, model.total_steps / 200);
  Observation obs;
  SensorReadings readings;
  if (on_output) {
    sim.Observe(state, &obs);
    on_output(obs);
  }
  while (state.step_index < model.total_steps) {
    const std::int64_t k = state.step_index;
    if (k == model.trigger_step && k > 0) power.Apply(failure, k, input);
    if (k == model.restore_step) power.Apply(restore, k, input);
    // The controller (on its own supply) keeps running; an unpowered axis's amplifier is off,
    // so PowerState overrides its current with the one it had when power failed.
    if (internal) {
      if (k % substeps == 0) {
        sim.Observe(state, &obs);
        sensors.Sample(obs, &readings);
        controller->Update(readings, &input);
      }
    } else {
      for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
        input.amb[a].current_A = CurrentAt(model.params.ambs[a].current_profile, k * dt);
      }
    }
    power.Fill(k, &input);
    const StepStatus status = sim.Step(&state, input);
    if (status != StepStatus::kOk) {
      result.status = status;
      result.failure_message = DescribeFailure(model, status, state);
      break;
    }
    if (on_output && state.step_index % output_every == 0) {
      sim.Observe(state, &obs);
      on_output(obs);
    }
    if (on_progress && state.step_index % progress_every == 0) {
      on_progress(static_cast<double>(state.step_index) / static_cast<double>(model.total_steps));
    }
  }
  result.steps = state.step_index;
  result.final_state = state;
  return result;
}

}  // namespace ambdrop
