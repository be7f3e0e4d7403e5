#include "controller_if/loop/step_driver.hpp"

#include <algorithm>
#include <cmath>

namespace ambdrop {

std::int64_t OutputEverySteps(const Model& model) noexcept {
  return std::max<std::int64_t>(
      1, std::llround(model.params.simulation.output_interval_s / model.params.simulation.step_s));
}

StepDriver::StepDriver(const Model& model, std::int64_t sensor_every_steps)
    : model_(model),
      sim_(model),
      power_(model),
      sensor_every_(sensor_every_steps),
      output_every_(OutputEverySteps(model)) {
  if (sensor_every_ > 0) {
    sensors_.emplace(model.params.sensors,
                     static_cast<double>(sensor_every_) * model.params.simulation.step_s);
  }
}

void StepDriver::FillInput(std::int64_t step) noexcept {
  for (std::size_t a = 0; a < model_.params.ambs.size(); ++a) input_.amb[a].current_A = command_[a];
  power_.Fill(step, &input_);
}

}  // namespace ambdrop
