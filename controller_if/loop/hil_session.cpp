#include "controller_if/loop/hil_session.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace ambdrop {

std::int64_t ControllerSubsteps(const Model& model) {
  const double dt = model.params.simulation.step_s;
  const double ratio = 1.0 / (model.params.controller.rate_Hz * dt);
  const std::int64_t n = std::llround(ratio);
  if (n < 1 || std::abs(ratio - static_cast<double>(n)) > 1e-6 * ratio) {
    // %g: std::to_string's %f printed a 0.1 us step as 0.000000 s.
    char text[200];
    std::snprintf(text, sizeof text,
                  "controller.rate_Hz = %.6g: the controller period must be a whole number of "
                  "physics steps (simulation.step_s = %.6g s); it is %.6g steps",
                  model.params.controller.rate_Hz, dt, ratio);
    throw std::invalid_argument(text);
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
                                                 model.params.simulation.step_s))),
      recorder_(options.recorder) {
  initial_input_ =
      options.initial_input != nullptr ? *options.initial_input : StaticLoadInput(model);
  input_ = initial_input_;
  state_ = sim_.InitialState(input_);
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    latest_.current_A[a] = input_.amb[a].current_A;
  }
}

void HilSession::SendSensors() noexcept {
  sim_.Observe(state_, &obs_);
  sensors_.Sample(obs_, &readings_);
  link_->ObserveState(obs_);
  link_->SendSensors(readings_, state_.step_index, obs_.time_s);
  ++counters_.sensor_samples_sent;
  if (recorder_ != nullptr) {
    recorder_->OnSensors(RecordedSensors{state_.step_index, obs_.time_s, readings_});
  }
}

void HilSession::PushObservation() noexcept {
  if (outputs_ != nullptr && !outputs_->TryPush(obs_)) ++counters_.observations_dropped;
  if (recorder_ != nullptr) recorder_->OnState(state_, obs_);
}

void HilSession::Start(std::int64_t now_ns) noexcept {
  watchdog_.Start(now_ns);
  if (recorder_ != nullptr) {
    RecordedStart start;
    start.equilibrium_input = initial_input_;
    start.loop_current_A = latest_.current_A;
    recorder_->OnStart(start);
  }
  SendSensors();
  PushObservation();
}

void HilSession::PrepareInput(std::int64_t step, double time_s) noexcept {
  // Power events first: an axis that loses power keeps the current that was flowing then.
  PowerEvent event;
  for (TriggerSource* trigger : triggers_) {
    while (trigger->Poll(time_s, &event)) {
      power_.Apply(event, step, input_);
      if (counters_.power_events == 0) counters_.first_power_event_step = step;
      ++counters_.power_events;
      if (recorder_ != nullptr) recorder_->OnPower(RecordedPower{step, event});
    }
  }
  // Recorded after the power events: a replay applies them in this order.
  if (pending_record_valid_ && recorder_ != nullptr) recorder_->OnInput(pending_record_);
  pending_record_valid_ = false;
  for (std::size_t a = 0; a < model_.params.ambs.size(); ++a) {
    input_.amb[a].current_A = latest_.current_A[a];
  }
  power_.Fill(step, &input_);
}

bool HilSession::AdvancePhysics() noexcept {
  for (std::int64_t k = 0; k < substeps_; ++k) {
    const StepStatus status = sim_.Step(&state_, input_);
    if (status != StepStatus::kOk) {
      stop_ = HilStop::kDiverged;
      step_status_ = status;
      return false;
    }
    if ((outputs_ != nullptr || recorder_ != nullptr) && state_.step_index % output_every_ == 0) {
      sim_.Observe(state_, &obs_);
      PushObservation();
    }
  }
  return true;
}

bool HilSession::CatchUpPeriod() noexcept {
  PrepareInput(state_.step_index, sim_.Time(state_));
  if (!AdvancePhysics()) return false;
  ++counters_.catch_up_periods;
  // Sampled, not sent (see Period).
  sim_.Observe(state_, &obs_);
  sensors_.Sample(obs_, &readings_);
  if (state_.step_index >= model_.total_steps) {
    stop_ = HilStop::kDuration;
    return false;
  }
  return true;
}

bool HilSession::Period(std::int64_t now_ns, std::int64_t missed_before) noexcept {
  if (stop_ != HilStop::kRunning) return false;
  ++counters_.periods;

  // Inputs: the controller's newest currents, then power events.
  CurrentsMessage message;
  bool received = false;
  while (link_->PollCurrents(&message)) {
    latest_ = message;
    received = true;
    ++counters_.currents_received;
    watchdog_.Feed(now_ns);
  }
  RecordedInput& record = pending_record_;
  record = RecordedInput{};
  record.step = state_.step_index;
  if (received) {
    watchdog_zeroed_ = false;
    record.receive_ns = latest_.receive_ns;
    record.sequence = latest_.sequence;
    record.current_A = latest_.current_A;
  }
  switch (watchdog_.Check(now_ns)) {
    case WatchdogVerdict::kNormal:
    case WatchdogVerdict::kHold:
      break;
    case WatchdogVerdict::kZero:
      latest_.current_A = {};
      ++counters_.watchdog_zero_periods;
      if (!watchdog_zeroed_) {
        watchdog_zeroed_ = true;
        received = true;
        record.kind = RecordedInputKind::kWatchdogZero;
        record.current_A = {};
      }
      break;
    case WatchdogVerdict::kStop:
      stop_ = HilStop::kWatchdog;
      if (recorder_ != nullptr) {
        record.kind = RecordedInputKind::kWatchdogStop;
        recorder_->OnInput(record);
      }
      return false;
  }
  if (watchdog_.silent() && watchdog_.action() == SilenceAction::kHold) {
    ++counters_.watchdog_hold_periods;
  }
  pending_record_valid_ = received;
  // Skipped periods, with the newest currents: they answer the last sample sent, and a real
  // rotor would have felt them from the first skipped period on.
  for (std::int64_t m = 0; m < missed_before; ++m) {
    if (!CatchUpPeriod()) return false;
  }
  PrepareInput(state_.step_index, sim_.Time(state_));

  // Physics over the period, the input held.
  if (!AdvancePhysics()) return false;
  SendSensors();
  if (state_.step_index >= model_.total_steps) {
    stop_ = HilStop::kDuration;
    return false;
  }
  return true;
}

}  // namespace ambdrop
