#pragma once
// The one per-step order every run shares: `ambdrop sim` (offline), `replay`, `hil` and the
// scenario runs differ only in where their power events and currents come from and what they do
// with the sensor samples and output rows. They are hooks around this driver, so a live run, its
// replay and its HIL twin on a virtual clock take the same steps bit for bit (docs/equations.md,
// "One step").
#include <array>
#include <cstdint>
#include <optional>

#include "controller_if/boundary/power_state.hpp"
#include "controller_if/boundary/sensor_emulator.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop {

/// Physics steps between output rows: simulation.output_interval_s rounded, at least one.
std::int64_t OutputEverySteps(const Model& model) noexcept;

/// What a run plugs into the driver. Every hook is optional (the defaults do nothing); a run
/// derives from this and hides the ones it needs. Called from the real-time step: noexcept, and
/// they must not allocate.
class StepDriver;
struct StepHooks {
  /// The step is about to begin: a run may still move the state (a fit's start estimate).
  void BeginStep(StepDriver&, std::int64_t /*step*/) noexcept {}
  /// A sensor sample of the state at `step`, a multiple of the sensor period, taken before the
  /// step's power events (or earlier by SampleNow, once that step's physics is done).
  void OnSensors(StepDriver&, std::int64_t /*step*/) noexcept {}
  /// Power events due at `step`: StepDriver::ApplyPower for each.
  void PowerEvents(StepDriver&, std::int64_t /*step*/) noexcept {}
  /// The commanded currents from `step` on, into StepDriver::command(); false ends the run
  /// before the step (a recorded watchdog stop).
  bool Command(StepDriver&, std::int64_t /*step*/) noexcept { return true; }
  /// The step's input is complete (the power state has overridden the unpowered axes); a run
  /// that drives axes by a record after the trigger overrides them here (mutable_input()).
  /// False ends the run before the step (a fit that has predicted its last row).
  bool BeforeStep(StepDriver&) noexcept { return true; }
  /// After a step that lands on the output cadence: StepDriver::observation() is its state's.
  void OnOutput(StepDriver&) noexcept {}
};

using AxisCurrents = std::array<std::array<double, 2>, kMaxAmbs>;

/// Owns the simulator, the state, the power state, the sensor emulator and the input, and runs
/// one step in this order:
///   1. on a sensor period's boundary, the sensor sample of the state (unless SampleNow took it
///      already: a HIL period sends it the moment its physics is done);
///   2. the power events due at the step (an axis that loses power keeps the current that was
///      flowing: the previous step's input);
///   3. the command (the controller's newest currents, a profile's, a record's) becomes the
///      input's currents;
///   4. the power state overrides the unpowered axes' currents and force scales (PowerState::Fill);
///   5. the physics step;
///   6. on the output cadence, an observation of the new state.
class StepDriver {
 public:
  /// `sensor_every_steps` > 0: the sensors are sampled every that many steps (a controller's
  /// period); 0: never.
  StepDriver(const Model& model, std::int64_t sensor_every_steps);

  /// Starts from `state` with the input of SetInput (and the power events applied since).
  void Start(const State& state) noexcept {
    state_ = state;
    sampled_step_ = -1;
  }

  /// The sensor sample of the current state now, if its step is on the sensor period and it was
  /// not taken yet; the step then does not take it again.
  template <class Hooks>
  void SampleNow(Hooks& hooks) noexcept {
    const std::int64_t k = state_.step_index;
    if (!sensors_ || k % sensor_every_ != 0 || sampled_step_ == k) return;
    sampled_step_ = k;
    sim_.Observe(state_, &obs_);
    sensors_->Sample(obs_, &readings_);
    hooks.OnSensors(*this, k);
  }

  /// One step in the order above; false when the run ends here (diverged: status(); or a hook
  /// stopped it before the step: stopped()).
  template <class Hooks>
  bool Step(Hooks& hooks) noexcept {
    const std::int64_t k = state_.step_index;
    hooks.BeginStep(*this, k);
    SampleNow(hooks);
    hooks.PowerEvents(*this, k);
    if (!hooks.Command(*this, k)) {
      stopped_ = true;
      return false;
    }
    FillInput(k);
    if (!hooks.BeforeStep(*this)) {
      stopped_ = true;
      return false;
    }
    status_ = sim_.Step(&state_, input_);
    if (status_ != StepStatus::kOk) return false;
    if (state_.step_index % output_every_ == 0) {
      sim_.Observe(state_, &obs_);
      hooks.OnOutput(*this);
    }
    return true;
  }

  /// A power event at the current step (from StepHooks::PowerEvents or before Start).
  void ApplyPower(const PowerEvent& event) noexcept {
    power_.Apply(event, state_.step_index, input_);
  }
  /// The input's currents from the command, then the power state's override at `step`.
  void FillInput(std::int64_t step) noexcept;

  /// The state's observation into observation() (for rows outside the output cadence).
  const Observation& Observe() noexcept {
    sim_.Observe(state_, &obs_);
    return obs_;
  }

  /// Before Start: the input (its currents also the command) that power events set before the
  /// first step act on (ApplyPower, FillInput).
  void SetInput(const ControlInput& input) noexcept {
    input_ = input;
    for (std::size_t a = 0; a < model_.params.ambs.size(); ++a)
      command_[a] = input_.amb[a].current_A;
  }

  /// What a run carries from one step to the next, but its power state: a fit that has run a
  /// model's levitated time once resumes other models of the same levitated behaviour from it
  /// (tools/fit/levitated_prefix_cache.hpp). Taken before any power event.
  struct Snapshot {
    std::optional<SensorEmulator> sensors;
    State state;
    ControlInput input;
    AxisCurrents command{};
    Observation obs;
    SensorReadings readings;
    std::int64_t sampled_step = -1;
  };
  Snapshot TakeSnapshot() const {
    return {sensors_, state_, input_, command_, obs_, readings_, sampled_step_};
  }
  /// Resumes from `s`, whose sensors must be this driver's (their parameters equal).
  void Restore(const Snapshot& s) {
    sensors_ = s.sensors;
    state_ = s.state;
    input_ = s.input;
    command_ = s.command;
    obs_ = s.obs;
    readings_ = s.readings;
    sampled_step_ = s.sampled_step;
    status_ = StepStatus::kOk;
    stopped_ = false;
  }

  const Model& model() const noexcept { return model_; }
  /// For a pre-run of the same physics and sensors (the settled start, settled_start.hpp).
  Simulator& sim() noexcept { return sim_; }
  const Simulator& sim() const noexcept { return sim_; }
  SensorEmulator* sensors() noexcept { return sensors_ ? &*sensors_ : nullptr; }
  const State& state() const noexcept { return state_; }
  /// For BeginStep: a run that moves its state between steps (before the step's sample).
  State& mutable_state() noexcept { return state_; }
  const ControlInput& input() const noexcept { return input_; }
  /// For BeforeStep: a run that overrides axes after the power state's fill.
  ControlInput& mutable_input() noexcept { return input_; }
  AxisCurrents& command() noexcept { return command_; }
  const AxisCurrents& command() const noexcept { return command_; }
  const PowerState& power() const noexcept { return power_; }
  const Observation& observation() const noexcept { return obs_; }
  const SensorReadings& readings() const noexcept { return readings_; }
  std::int64_t output_every() const noexcept { return output_every_; }
  std::int64_t sensor_every() const noexcept { return sensor_every_; }
  StepStatus status() const noexcept { return status_; }
  bool stopped() const noexcept { return stopped_; }

 private:
  const Model& model_;
  Simulator sim_;
  PowerState power_;
  std::optional<SensorEmulator> sensors_;
  std::int64_t sensor_every_;
  std::int64_t output_every_;
  State state_;
  ControlInput input_;
  AxisCurrents command_{};
  Observation obs_;
  SensorReadings readings_;
  std::int64_t sampled_step_ = -1;  // the step whose sample was taken
  StepStatus status_ = StepStatus::kOk;
  bool stopped_ = false;
};

}  // namespace ambdrop
