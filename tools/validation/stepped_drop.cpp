#include "tools/validation/stepped_drop.hpp"

#include <cmath>
#include <cstdint>

#include "controller_if/loop/state_dump.hpp"

namespace ambdrop {

SteppedDrop RunSteppedDrop(const Model& model, double after_trigger_s,
                           const std::function<void(const Observation&)>& on_step) {
  Simulator sim(model);
  SteppedDrop d;
  d.final_state = sim.InitialState();
  State& s = d.final_state;
  Observation obs;
  const std::int64_t end =
      model.trigger_step +
      static_cast<std::int64_t>(std::llround(after_trigger_s / model.params.simulation.step_s));
  while (s.step_index < end) {
    const ControlInput in =
        s.step_index < model.trigger_step ? ControlInput::Powered() : ControlInput::PowerOff();
    d.status = sim.Step(&s, in);
    if (d.status != StepStatus::kOk) {
      d.failure_message = DescribeFailure(model, d.status, s);
      break;
    }
    if (s.step_index < model.trigger_step) continue;
    sim.Observe(s, &obs);
    on_step(obs);
  }
  return d;
}

}  // namespace ambdrop
