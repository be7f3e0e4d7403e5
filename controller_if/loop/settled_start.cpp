#include "controller_if/loop/settled_start.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/state_dump.hpp"

namespace ambdrop {

std::int64_t SettleSteps(const Model& model) {
  const double dt = model.params.simulation.step_s;
  const std::int64_t substeps = ControllerSubsteps(model);
  const auto periods = static_cast<std::int64_t>(
      std::llround(model.params.simulation.settle_s / (static_cast<double>(substeps) * dt)));
  return periods * substeps;
}

SettleResult SettleClosedLoop(const Model& model, Simulator& sim, State* state,
                              ReferenceController* controller, SensorEmulator* sensors,
                              ControlInput* input) {
  SettleResult result;
  const std::int64_t steps = SettleSteps(model);
  if (steps <= 0) return result;
  const double dt = model.params.simulation.step_s;
  const std::int64_t substeps = ControllerSubsteps(model);
  // The readings one revolution (or 10 ms) before the end, to tell how steady the start is.
  const double spin = model.params.simulation.spin_speed_rad_s;
  const double window_s = spin > 0.0 ? 2.0 * std::numbers::pi / spin : 10e-3;
  const std::int64_t mark =
      steps - std::clamp<std::int64_t>(
                  substeps * std::llround(window_s / (static_cast<double>(substeps) * dt)),
                  substeps, steps);
  Observation obs, at_mark;
  SensorReadings readings;
  for (std::int64_t k = 0; k < steps; ++k) {
    if (k % substeps == 0) {
      sim.Observe(*state, &obs);
      sensors->Sample(obs, &readings);
      if (k == mark) at_mark = obs;
      controller->Update(readings, input);
    }
    controller->Advance(input);
    result.clearance.Watch(model, state->y);
    const StepStatus status = sim.Step(state, *input);
    if (status != StepStatus::kOk) {
      result.status = status;
      result.failure =
          "while settling (simulation.settle_s): " + DescribeFailure(model, status, *state);
      result.steps = k + 1;
      return result;
    }
  }
  // The clock restarts at the run's t = 0: schedules (trigger, events, profiles) count from it.
  state->step_index = 0;
  sim.Observe(*state, &obs);
  for (std::size_t s = 0; s < model.params.sensors.size(); ++s) {
    for (int axis = 0; axis < 2; ++axis) {
      result.last_change_m = std::max(
          result.last_change_m, std::abs(obs.sensor_xy_m[s][axis] - at_mark.sensor_xy_m[s][axis]));
    }
  }
  result.steps = steps;
  return result;
}

}  // namespace ambdrop
