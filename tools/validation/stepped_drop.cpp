#include "tools/validation/stepped_drop.hpp"

#include <cmath>
#include <cstdint>

#include "controller_if/loop/state_dump.hpp"
#include "controller_if/loop/step_driver.hpp"

namespace ambdrop {
namespace {

// The seed rigs' drop: the whole input powered, then off, at the trigger step (no power state,
// controller or profile), set after the driver's fill.
struct SteppedHooks : StepHooks {
  std::int64_t trigger_step = 0;
  bool BeforeStep(StepDriver& d) noexcept {
    d.mutable_input() =
        d.state().step_index < trigger_step ? ControlInput::Powered() : ControlInput::PowerOff();
    return true;
  }
};

}  // namespace

SteppedDrop RunSteppedDrop(const Model& model, double after_trigger_s,
                           const std::function<void(const Observation&)>& on_step) {
  StepDriver driver(model, 0);
  SteppedHooks hooks;
  hooks.trigger_step = model.trigger_step;
  driver.Start(driver.sim().InitialState());
  SteppedDrop d;
  const std::int64_t end =
      model.trigger_step +
      static_cast<std::int64_t>(std::llround(after_trigger_s / model.params.simulation.step_s));
  while (driver.state().step_index < end) {
    if (!driver.Step(hooks)) {
      d.status = driver.status();
      d.failure_message = DescribeFailure(model, d.status, driver.state());
      break;
    }
    if (driver.state().step_index < model.trigger_step) continue;
    on_step(driver.Observe());
  }
  d.final_state = driver.state();
  return d;
}

}  // namespace ambdrop
