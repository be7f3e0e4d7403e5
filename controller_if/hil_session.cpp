#include "controller_if/hil_session.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace ambdrop {

std::int64_t ControllerSubsteps(const Model& model) {
  const double dt = model.params.simulation.step_s;
  const double ratio = 1.0 / (model.params.controller.rate_Hz * dt);
  const std::int64_t n = std::llround(ratio);
  if (n < 1 || std::abs(ratio - static_cast<double>(n)) > 1e-6 * ratio) {
    throw std::invalid_argument(
        "controller.rate_Hz = " + std::to_string(model.params.controller.rate_Hz) +
        ": the controller period must be a whole number of physics "
        "steps (" +
        std::to_string(dt) + " s)");
  }
  return n;
}

HilSession::HilSession(const Model& model, ControllerLink* link,
                       std::vector<TriggerSource*> triggers, const HilOptions& options,
                       OutputRing* outputs)
    : model_(model),
      link_(link),
      triggers_(std::move(triggers)),
      outputs_(outputs),
      sim_(model),
      sensors_(model.params.sensors,
               static_cast<double>(ControllerSubsteps(model)) * model.params.simulation.step_s),
      power_(model),
      watchdog_(std::llround(options.watchdog_timeout_s * 1e9), options.silence_action),
      substeps_(ControllerSubsteps(model)),
      output_every_(
          std::max<std::int64_t>(1, std::llround(model.params.simulation.output_interval_s /
                                                 model.params.simulation.step_s))) {
  // Levitated on the currents that carry the static load, as `ambdrop sim` starts; they stay
  // applied until the controller's first currents arrive.
  input_ = StaticLoadInput(model);
  state_ = sim_.InitialState(input_);
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    latest_.current_A[a] = input_.amb[a].current_A;
  }
}

void HilSession::SendSensors() noexcept {
  sim_.Observe(state_, &obs_);
  sensors_.Sample(obs_, &readings_);
  link_->SendSensors(readings_, state_.step_index, obs_.time_s);
  ++counters_.sensor_samples_sent;
}

void HilSession::Start(std::int64_t now_ns) noexcept {
  watchdog_.Start(now_ns);
  SendSensors();
  if (outputs_ != nullptr && !outputs_->TryPush(obs_)) ++counters_.observations_dropped;
}

bool HilSession::Period(std::int64_t now_ns) noexcept {
  if (stop_ != HilStop::kRunning) return false;
  ++counters_.periods;
  const std::int64_t step = state_.step_index;
  const double time_s = sim_.Time(state_);

  // Inputs: the controller's newest currents, then power events.
  CurrentsMessage message;
  while (link_->PollCurrents(&message)) {
    latest_ = message;
    ++counters_.currents_received;
    watchdog_.Feed(now_ns);
  }
  switch (watchdog_.Check(now_ns)) {
    case WatchdogVerdict::kNormal:
    case WatchdogVerdict::kHold:
      break;
    case WatchdogVerdict::kZero:
      latest_.current_A = {};
      ++counters_.watchdog_zero_periods;
      break;
    case WatchdogVerdict::kStop:
      stop_ = HilStop::kWatchdog;
      return false;
  }
  if (watchdog_.silent() && watchdog_.action() == SilenceAction::kHold) {
    ++counters_.watchdog_hold_periods;
  }
  // Power events first: an axis that loses power keeps the current that was flowing then.
  PowerEvent event;
  for (TriggerSource* trigger : triggers_) {
    while (trigger->Poll(time_s, &event)) {
      power_.Apply(event, step, input_);
      ++counters_.power_events;
    }
  }
  for (std::size_t a = 0; a < model_.params.ambs.size(); ++a) {
    input_.amb[a].current_A = latest_.current_A[a];
  }
  power_.Fill(step, &input_);

  // Physics over the period, the input held.
  for (std::int64_t k = 0; k < substeps_; ++k) {
    if (sim_.Step(&state_, input_) != StepStatus::kOk) {
      stop_ = HilStop::kDiverged;
      return false;
    }
    if (outputs_ != nullptr && state_.step_index % output_every_ == 0) {
      sim_.Observe(state_, &obs_);
      if (!outputs_->TryPush(obs_)) ++counters_.observations_dropped;
    }
  }
  SendSensors();
  if (state_.step_index >= model_.total_steps) {
    stop_ = HilStop::kDuration;
    return false;
  }
  return true;
}

}  // namespace ambdrop
