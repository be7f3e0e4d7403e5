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
#include "controller_if/loop/closed_loop_state.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/settled_start.hpp"
#include "controller_if/loop/state_dump.hpp"
#include "controller_if/loop/step_driver.hpp"
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

namespace {

// `ambdrop sim`'s sources around the step driver: the scheduled trigger and restore, the
// in-process controller (on its sensor samples) or the configured current profiles, output rows
// with the currents applied over the step that starts at them, and the recorder.
struct OfflineHooks : StepHooks {
  const Model& model;
  bool internal;
  std::int64_t substeps;
  ReferenceController* controller;
  RunRecorder* recorder;
  const OfflineOutput& on_output;
  PowerEvent failure;
  PowerEvent restore;
  ControlInput controller_out;
  // The currents last recorded: a profile's are recorded only when they change.
  AxisCurrents recorded_A{};
  // An output row waits for the currents applied from its time on, known at the next step.
  Observation row;
  bool row_pending = false;

  OfflineHooks(const Model& m, bool in, std::int64_t sub, ReferenceController* c, RunRecorder* r,
               const OfflineOutput& out)
      : model(m),
        internal(in),
        substeps(sub),
        controller(c),
        recorder(r),
        on_output(out),
        failure(ScheduledFailure(m)),
        restore(ScheduledRestore(m)) {}

  void ApplyPower(StepDriver& d, const PowerEvent& event, std::int64_t k) noexcept {
    d.ApplyPower(event);
    if (recorder != nullptr) recorder->OnPower(RecordedPower{k, event});
  }
  void OnSensors(StepDriver& d, std::int64_t k) noexcept {
    if (!internal) return;
    if (recorder != nullptr) {
      recorder->OnSensors(RecordedSensors{k, d.observation().time_s, d.readings()});
    }
  }
  void PowerEvents(StepDriver& d, std::int64_t k) noexcept {
    if (k == model.trigger_step && k > 0) ApplyPower(d, failure, k);
    if (k == model.restore_step) ApplyPower(d, restore, k);
  }
  // The controller (on its own supply) keeps running; an unpowered axis's amplifier is off, so
  // the power state overrides its current with the one it had when power failed.
  bool Command(StepDriver& d, std::int64_t k) noexcept {
    if (internal) {
      const bool sample = k % substeps == 0;
      if (!sample && !controller->advances_amplifier()) return true;
      if (sample) controller->Update(d.readings(), &controller_out);
      controller->Advance(&controller_out);
      for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
        d.command()[a] = controller_out.amb[a].current_A;
      }
    } else {
      const double dt = model.params.simulation.step_s;
      for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
        d.command()[a] = CurrentAt(model.params.ambs[a].current_profile, k * dt);
      }
    }
    RecordCurrents(d, k);
    return true;
  }
  void RecordCurrents(const StepDriver& d, std::int64_t k) noexcept {
    if (recorder == nullptr) return;
    RecordedInput in;
    in.step = k;
    in.receive_ns = std::llround(static_cast<double>(k) * model.params.simulation.step_s * 1e9);
    for (std::size_t a = 0; a < model.params.ambs.size(); ++a) in.current_A[a] = d.command()[a];
    // Bitwise, so that a change of sign of a zero is recorded too.
    if (k > 0 && std::memcmp(&in.current_A, &recorded_A, sizeof recorded_A) == 0) return;
    recorded_A = in.current_A;
    recorder->OnInput(in);
  }
  bool BeforeStep(StepDriver& d) noexcept {
    EmitRow(d);
    return true;
  }
  void OnOutput(StepDriver& d) noexcept { Output(d.state(), d.observation()); }
  void Output(const State& state, const Observation& o) noexcept {
    row = o;
    row_pending = static_cast<bool>(on_output);
    if (recorder != nullptr) recorder->OnState(state, row);
  }
  void EmitRow(const StepDriver& d) {
    if (!row_pending) return;
    row_pending = false;
    on_output(row, RowCurrents(model, d.command(), d.input()));
  }
};

}  // namespace

OfflineRunResult RunOfflineWithCurrents(const Model& model, const OfflineOutput& on_output,
                                        const std::function<void(double)>& on_progress,
                                        RunRecorder* recorder) {
  const std::int64_t substeps =
      model.params.controller.kind == ControllerKind::kNone ? 1 : ControllerSubsteps(model);
  const bool internal = model.params.controller.kind == ControllerKind::kInternalPid;
  ClosedLoopState run(model, substeps, internal);
  StepDriver& driver = run.driver;
  std::optional<ReferenceController>& controller = run.controller;
  ControlInput input;
  if (internal) {
    controller->Initial(&input);
  } else {
    input = ProfileStartInput(model);
  }
  OfflineRunResult result;
  // The opt-in settled start: the closed loop runs before t = 0
  // (controller_if/loop/settled_start.hpp), on the run's own sensors.
  std::optional<State> settled;
  if (internal && model.params.simulation.settle_s > 0.0) {
    State s = driver.sim().InitialState(StaticLoadInput(model));
    const SettleResult r =
        SettleClosedLoop(model, driver.sim(), &s, &*controller, driver.sensors(), &input);
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
  OfflineHooks hooks(model, internal, substeps, controller ? &*controller : nullptr, recorder,
                     on_output);
  driver.SetInput(input);
  RecordedStart start;
  start.loop_current_A = driver.command();
  hooks.recorded_A = start.loop_current_A;
  if (model.trigger_step == 0) hooks.ApplyPower(driver, hooks.failure, 0);
  driver.FillInput(0);

  // A controller-driven rotor starts levitated on the currents that carry its static load.
  start.equilibrium_input = internal ? StaticLoadInput(model) : driver.input();
  const State initial = settled ? *settled : driver.sim().InitialState(start.equilibrium_input);
  if (recorder != nullptr) recorder->OnStart(start);
  if (on_output || recorder != nullptr) {
    Observation first;
    driver.sim().Observe(initial, &first);
    hooks.Output(initial, first);
  }
  driver.Start(initial);
  const std::int64_t progress_every = std::max<std::int64_t>(1, model.total_steps / 200);
  while (driver.state().step_index < model.total_steps) {
    if (!driver.Step(hooks)) {
      result.status = driver.status();
      result.failure_message = DescribeFailure(model, driver.status(), driver.state());
      break;
    }
    const std::int64_t k = driver.state().step_index;
    if (on_progress && k % progress_every == 0) {
      on_progress(static_cast<double>(k) / static_cast<double>(model.total_steps));
    }
  }
  // The last row: no step follows; its coil currents are those of the power state at its time.
  if (hooks.row_pending) {
    driver.FillInput(driver.state().step_index);
    hooks.EmitRow(driver);
  }
  result.steps = driver.state().step_index;
  result.final_state = driver.state();
  return result;
}

}  // namespace ambdrop
