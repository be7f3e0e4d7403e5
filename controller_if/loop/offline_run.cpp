#include "controller_if/loop/offline_run.hpp"

#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>

#include "controller_if/boundary/power_state.hpp"
#include "controller_if/boundary/sensor_emulator.hpp"
#include "controller_if/controller/current_profile.hpp"
#include "controller_if/controller/pid_controller.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/settled_start.hpp"
#include "controller_if/loop/state_dump.hpp"
#include "rt_core/amb_force.hpp"
#include "rt_core/power_loss_drive.hpp"

namespace ambdrop {
namespace {

/// The row's currents: `command_A` as commanded, the coils' from the input the step applies
/// (its force scale is the square of the uniform laws' current fraction, ReportedCoilCurrent).
AmbCurrents RowCurrents(const Model& model,
                        const std::array<std::array<double, 2>, kMaxAmbs>& command_A,
                        const ControlInput& input) noexcept {
  AmbCurrents c;
  c.command_A = command_A;
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      const AmbDrive& drive = input.amb[a];
      c.coil_A[a][axis] = ReportedCoilCurrent(
          UnpoweredDrive{LimitedCurrent(model.params.ambs[a], drive.current_A[axis]),
                         drive.force_scale[axis], drive.bias_scale[axis]});
    }
  }
  return c;
}

}  // namespace

OfflineRunResult RunOffline(const Model& model,
                            const std::function<void(const Observation&)>& on_output,
                            const std::function<void(double)>& on_progress, RunRecorder* recorder) {
  OfflineOutput with_currents;
  if (on_output) {
    with_currents = [&on_output](const Observation& o, const AmbCurrents&) { on_output(o); };
  }
  return RunOfflineWithCurrents(model, with_currents, on_progress, recorder);
}

OfflineRunResult RunOfflineWithCurrents(const Model& model, const OfflineOutput& on_output,
                                        const std::function<void(double)>& on_progress,
                                        RunRecorder* recorder) {
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
    input = ProfileStartInput(model);
  }
  OfflineRunResult result;
  // The opt-in settled start: the closed loop runs before t = 0
  // (controller_if/loop/settled_start.hpp).
  std::optional<State> settled;
  if (internal && model.params.simulation.settle_s > 0.0) {
    State s = sim.InitialState(StaticLoadInput(model));
    const SettleResult r = SettleClosedLoop(model, sim, &s, &*controller, &sensors, &input);
    result.settle_steps = r.steps;
    result.settle_last_change_m = r.last_change_m;
    if (r.status != StepStatus::kOk) {
      result.status = r.status;
      result.failure_message = r.failure;
      result.final_state = s;
      return result;
    }
    settled = s;
  }
  PowerState power(model);
  const PowerEvent failure = ScheduledFailure(model);
  const PowerEvent restore = ScheduledRestore(model);
  const auto apply_power = [&](const PowerEvent& event, std::int64_t k) {
    power.Apply(event, k, input);
    if (recorder != nullptr) recorder->OnPower(RecordedPower{k, event});
  };
  RecordedStart start;
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    start.loop_current_A[a] = input.amb[a].current_A;
  }
  // What the controller or the profile commands; PowerState overrides an unpowered axis's
  // current in `input`, so the command is kept apart.
  std::array<std::array<double, 2>, kMaxAmbs> command_A = start.loop_current_A;
  if (model.trigger_step == 0) apply_power(failure, 0);
  power.Fill(0, &input);

  // A controller-driven rotor starts levitated on the currents that carry its static load.
  start.equilibrium_input = internal ? StaticLoadInput(model) : input;
  State state = settled ? *settled : sim.InitialState(start.equilibrium_input);
  if (recorder != nullptr) recorder->OnStart(start);
  // The currents last recorded: a profile's are recorded only when they change.
  std::array<std::array<double, 2>, kMaxAmbs> recorded_A = start.loop_current_A;
  const auto record_currents = [&](std::int64_t k) {
    if (recorder == nullptr) return;
    RecordedInput in;
    in.step = k;
    in.receive_ns = std::llround(static_cast<double>(k) * dt * 1e9);
    for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
      in.current_A[a] = input.amb[a].current_A;
    }
    // Bitwise, so that a change of sign of a zero is recorded too.
    if (k > 0 && std::memcmp(&in.current_A, &recorded_A, sizeof recorded_A) == 0) return;
    recorded_A = in.current_A;
    recorder->OnInput(in);
  };
  const std::int64_t output_every =
      std::max<std::int64_t>(1, std::llround(model.params.simulation.output_interval_s / dt));
  const std::int64_t progress_every = std::max<std::int64_t>(1, model.total_steps / 200);
  Observation obs;
  SensorReadings readings;
  // An output row waits for the currents applied from its time on, known at the next step.
  Observation row;
  bool row_pending = false;
  const auto emit_row = [&] {
    if (!row_pending) return;
    row_pending = false;
    on_output(row, RowCurrents(model, command_A, input));
  };
  if (on_output || recorder != nullptr) {
    sim.Observe(state, &row);
    row_pending = static_cast<bool>(on_output);
    if (recorder != nullptr) recorder->OnState(state, row);
  }
  while (state.step_index < model.total_steps) {
    const std::int64_t k = state.step_index;
    if (k == model.trigger_step && k > 0) apply_power(failure, k);
    if (k == model.restore_step) apply_power(restore, k);
    // The controller (on its own supply) keeps running; an unpowered axis's amplifier is off,
    // so PowerState overrides its current with the one it had when power failed.
    if (internal) {
      if (k % substeps == 0) {
        sim.Observe(state, &obs);
        sensors.Sample(obs, &readings);
        if (recorder != nullptr) recorder->OnSensors(RecordedSensors{k, obs.time_s, readings});
        controller->Update(readings, &input);
        for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
          command_A[a] = input.amb[a].current_A;
        }
        record_currents(k);
      }
    } else {
      for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
        input.amb[a].current_A = CurrentAt(model.params.ambs[a].current_profile, k * dt);
        command_A[a] = input.amb[a].current_A;
      }
      record_currents(k);
    }
    power.Fill(k, &input);
    emit_row();
    const StepStatus status = sim.Step(&state, input);
    if (status != StepStatus::kOk) {
      result.status = status;
      result.failure_message = DescribeFailure(model, status, state);
      break;
    }
    if ((on_output || recorder != nullptr) && state.step_index % output_every == 0) {
      sim.Observe(state, &row);
      row_pending = static_cast<bool>(on_output);
      if (recorder != nullptr) recorder->OnState(state, row);
    }
    if (on_progress && state.step_index % progress_every == 0) {
      on_progress(static_cast<double>(state.step_index) / static_cast<double>(model.total_steps));
    }
  }
  // The last row: no step follows; its coil currents are those of the power state at its time.
  if (row_pending) {
    power.Fill(state.step_index, &input);
    emit_row();
  }
  result.steps = state.step_index;
  result.final_state = state;
  return result;
}

}  // namespace ambdrop
