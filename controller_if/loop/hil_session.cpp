#include "controller_if/loop/hil_session.hpp"

#include <algorithm>
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
      driver_(model, ControllerSubsteps(model)),
      watchdog_(std::llround(options.watchdog_timeout_s * 1e9), options.silence_action),
      substeps_(ControllerSubsteps(model)),
      recorder_(options.recorder) {
  initial_input_ =
      options.initial_input != nullptr ? *options.initial_input : StaticLoadInput(model);
  driver_.SetInput(initial_input_);
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    latest_.current_A[a] = initial_input_.amb[a].current_A;
  }
}

void HilSession::OnSensors(StepDriver& driver, std::int64_t step) noexcept {
  if (!send_) return;  // a skipped period's sample: taken (the sensors count it), not sent
  const Observation& obs = driver.observation();
  link_->ObserveState(obs);
  link_->SendSensors(driver.readings(), step, obs.time_s);
  ++counters_.sensor_samples_sent;
  if (recorder_ != nullptr) {
    recorder_->OnSensors(RecordedSensors{step, obs.time_s, driver.readings()});
  }
}

void HilSession::OnOutput(StepDriver& driver) noexcept {
  if (counters_.power_events == 0) {
    const Observation& o = driver.observation();
    for (std::size_t t = 0; t < model_.params.tdbs.size(); ++t) {
      const double clearance = model_.params.tdbs[t].clearance_m;
      counters_.levitated_fraction =
          std::max(counters_.levitated_fraction, (clearance + o.tdb[t].penetration_m) / clearance);
    }
  }
  if (outputs_ != nullptr && !outputs_->TryPush(driver.observation())) {
    ++counters_.observations_dropped;
  }
  if (recorder_ != nullptr) recorder_->OnState(driver.state(), driver.observation());
}

void HilSession::Start(std::int64_t now_ns) noexcept {
  watchdog_.Start(now_ns);
  if (recorder_ != nullptr) {
    RecordedStart start;
    start.equilibrium_input = initial_input_;
    start.loop_current_A = latest_.current_A;
    recorder_->OnStart(start);
  }
  driver_.Start(driver_.sim().InitialState(initial_input_));
  driver_.SampleNow(*this);
  driver_.Observe();
  OnOutput(driver_);
}

void HilSession::PowerEvents(StepDriver& driver, std::int64_t step) noexcept {
  if (!period_start_) return;
  // Power events first: an axis that loses power keeps the current that was flowing then.
  PowerEvent event;
  const double time_s = driver.sim().Time(driver.state());
  for (TriggerSource* trigger : triggers_) {
    while (trigger->Poll(time_s, &event)) {
      driver.ApplyPower(event);
      if (counters_.power_events == 0) counters_.first_power_event_step = step;
      ++counters_.power_events;
      if (recorder_ != nullptr) recorder_->OnPower(RecordedPower{step, event});
    }
  }
}

bool HilSession::Command(StepDriver& driver, std::int64_t) noexcept {
  if (!period_start_) return true;
  period_start_ = false;
  // Recorded after the power events: a replay applies them in this order.
  if (pending_record_valid_ && recorder_ != nullptr) recorder_->OnInput(pending_record_);
  pending_record_valid_ = false;
  for (std::size_t a = 0; a < model_.params.ambs.size(); ++a) {
    driver.command()[a] = latest_.current_A[a];
  }
  return true;
}

bool HilSession::AdvancePeriod(bool send) noexcept {
  period_start_ = true;
  send_ = send;
  for (std::int64_t k = 0; k < substeps_; ++k) {
    if (!driver_.Step(*this)) {
      stop_ = HilStop::kDiverged;
      step_status_ = driver_.status();
      send_ = true;
      return false;
    }
  }
  // The period's closing sample now, not at the next period's first step: the controller has
  // the rest of the period to answer it.
  driver_.SampleNow(*this);
  send_ = true;
  return true;
}

bool HilSession::CatchUpPeriod() noexcept {
  if (!AdvancePeriod(false)) return false;
  ++counters_.catch_up_periods;
  if (driver_.state().step_index >= model_.total_steps) {
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
  if (!received && counters_.currents_received > 0) ++counters_.periods_without_currents;
  RecordedInput& record = pending_record_;
  record = RecordedInput{};
  record.step = driver_.state().step_index;
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
  // Physics over the period, the controller's currents held; its closing sample is sent.
  if (!AdvancePeriod(true)) return false;
  if (driver_.state().step_index >= model_.total_steps) {
    stop_ = HilStop::kDuration;
    return false;
  }
  return true;
}

}  // namespace ambdrop
