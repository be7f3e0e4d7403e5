#include "controller_if/offline_run.hpp"

#include <cmath>

#include "controller_if/current_profile.hpp"
#include "rt_core/amb_force.hpp"
#include "controller_if/state_dump.hpp"

namespace ambdrop {
namespace {

// Scheduled full power failure: before the trigger every AMB follows its current profile;
// after it the motor is off and each AMB's force fades with its flux decay (or vanishes),
// its currents frozen at their values at the trigger.
ControlInput InputAt(const Model& model, std::int64_t step) {
  const bool powered = model.trigger_step < 0 || step < model.trigger_step;
  ControlInput in = powered ? ControlInput::Powered() : ControlInput::PowerOff();
  const double dt = model.params.simulation.step_s;
  const double t = step * dt;
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    const AmbParams& amb = model.params.ambs[a];
    if (powered) {
      in.amb[a].current_A = CurrentAt(amb.current_profile, t);
    } else {
      const double trigger_s = model.trigger_step * dt;
      in.amb[a].current_A = CurrentAt(amb.current_profile, trigger_s);
      const double scale = FluxDecayForceScale(amb, t - trigger_s);
      in.amb[a].force_scale = {scale, scale};
    }
  }
  return in;
}

}  // namespace

OfflineRunResult RunOffline(const Model& model,
                            const std::function<void(const Observation&)>& on_output,
                            const std::function<void(double)>& on_progress) {
  Simulator sim(model);
  OfflineRunResult result;
  State state = sim.InitialState(InputAt(model, 0));
  const double dt = model.params.simulation.step_s;
  const std::int64_t output_every =
      std::max<std::int64_t>(1, std::llround(model.params.simulation.output_interval_s / dt));
  const std::int64_t progress_every = std::max<std::int64_t>(1, model.total_steps / 200);
  Observation obs;
  if (on_output) {
    sim.Observe(state, &obs);
    on_output(obs);
  }
  while (state.step_index < model.total_steps) {
    const ControlInput input = InputAt(model, state.step_index);
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
