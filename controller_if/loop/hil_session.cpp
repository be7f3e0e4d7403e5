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
                       OutputRing* outputs, const HilRunState* resume)
    : model_(model),
      link_(link),
      triggers_(std::move(triggers)),
      outputs_(outputs),
      substeps_(ControllerSubsteps(model)),
      recorder_(options.recorder),
      run_(resume != nullptr
               ? HilRunState(*resume)
               : HilRunState(model, substeps_, std::llround(options.watchdog_timeout_s * 1e9),
                             options.silence_action)) {
  initial_input_ =
      options.initial_input != nullptr ? *options.initial_input : StaticLoadInput(model);
  if (resume != nullptr) return;  // its input and currents go on
  run_.driver.SetInput(initial_input_);
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    run_.latest.current_A[a] = initial_input_.amb[a].current_A;
  }
}

void HilSession::OnSensors(StepDriver& driver, std::int64_t step) noexcept {
  if (!run_.send) return;  // a skipped period's sample: taken (the sensors count it), not sent
  const Observation& obs = driver.observation();
  link_->ObserveState(obs);
  link_->SendSensors(driver.readings(), step, obs.time_s);
  ++run_.counters.sensor_samples_sent;
  if (recorder_ != nullptr) {
    recorder_->OnSensors(RecordedSensors{step, obs.time_s, driver.readings()});
  }
}

void HilSession::OnOutput(StepDriver& driver) noexcept {
  if (run_.counters.power_events == 0) {
    const Observation& o = driver.observation();
    for (std::size_t t = 0; t < model_.params.tdbs.size(); ++t) {
      const double clearance = model_.params.tdbs[t].clearance_m;
      run_.counters.levitated_fraction = std::max(run_.counters.levitated_fraction,
                                                  (clearance + o.tdb[t].penetration_m) / clearance);
    }
  }
  if (outputs_ != nullptr && !outputs_->TryPush(driver.observation())) {
    ++run_.counters.observations_dropped;
  }
  if (recorder_ != nullptr) recorder_->OnState(driver.state(), driver.observation());
}

void HilSession::Start(std::int64_t now_ns) noexcept {
  run_.watchdog.Start(now_ns);
  if (recorder_ != nullptr) {
    RecordedStart start;
    start.equilibrium_input = initial_input_;
    start.loop_current_A = run_.latest.current_A;
    recorder_->OnStart(start);
  }
  run_.driver.Start(run_.driver.sim().InitialState(initial_input_));
  run_.driver.SampleNow(*this);
  run_.driver.Observe();
  OnOutput(run_.driver);
}

void HilSession::PowerEvents(StepDriver& driver, std::int64_t step) noexcept {
  if (!run_.period_start) return;
  // Power events first: an axis that loses power keeps the current that was flowing then.
  PowerEvent event;
  const double time_s = driver.sim().Time(driver.state());
  for (TriggerSource* trigger : triggers_) {
    while (trigger->Poll(time_s, &event)) {
      driver.ApplyPower(event);
      if (run_.counters.power_events == 0) run_.counters.first_power_event_step = step;
      ++run_.counters.power_events;
      if (recorder_ != nullptr) recorder_->OnPower(RecordedPower{step, event});
    }
  }
}

bool HilSession::Command(StepDriver& driver, std::int64_t) noexcept {
  if (!run_.period_start) return true;
  run_.period_start = false;
  // Recorded after the power events: a replay applies them in this order.
  if (run_.pending_record_valid && recorder_ != nullptr) recorder_->OnInput(run_.pending_record);
  run_.pending_record_valid = false;
  for (std::size_t a = 0; a < model_.params.ambs.size(); ++a) {
    driver.command()[a] = run_.latest.current_A[a];
  }
  return true;
}

bool HilSession::AdvancePeriod(bool send) noexcept {
  run_.period_start = true;
  run_.send = send;
  for (std::int64_t k = 0; k < substeps_; ++k) {
    if (!run_.driver.Step(*this)) {
      run_.stop = HilStop::kDiverged;
      run_.step_status = run_.driver.status();
      run_.send = true;
      return false;
    }
  }
  // The period's closing sample now, not at the next period's first step: the controller has
  // the rest of the period to answer it.
  run_.driver.SampleNow(*this);
  run_.send = true;
  return true;
}

bool HilSession::CatchUpPeriod() noexcept {
  if (!AdvancePeriod(false)) return false;
  ++run_.counters.catch_up_periods;
  if (run_.driver.state().step_index >= model_.total_steps) {
    run_.stop = HilStop::kDuration;
    return false;
  }
  return true;
}

bool HilSession::Period(std::int64_t now_ns, std::int64_t missed_before) noexcept {
  if (run_.stop != HilStop::kRunning) return false;
  ++run_.counters.periods;

  // Inputs: the controller's newest currents, then power events.
  CurrentsMessage message;
  bool received = false;
  while (link_->PollCurrents(&message)) {
    run_.latest = message;
    received = true;
    ++run_.counters.currents_received;
    run_.watchdog.Feed(now_ns);
  }
  if (!received && run_.counters.currents_received > 0) ++run_.counters.periods_without_currents;
  RecordedInput& record = run_.pending_record;
  record = RecordedInput{};
  record.step = run_.driver.state().step_index;
  if (received) {
    run_.watchdog_zeroed = false;
    record.receive_ns = run_.latest.receive_ns;
    record.sequence = run_.latest.sequence;
    record.current_A = run_.latest.current_A;
  }
  switch (run_.watchdog.Check(now_ns)) {
    case WatchdogVerdict::kNormal:
    case WatchdogVerdict::kHold:
      break;
    case WatchdogVerdict::kZero:
      run_.latest.current_A = {};
      ++run_.counters.watchdog_zero_periods;
      if (!run_.watchdog_zeroed) {
        run_.watchdog_zeroed = true;
        received = true;
        record.kind = RecordedInputKind::kWatchdogZero;
        record.current_A = {};
      }
      break;
    case WatchdogVerdict::kStop:
      run_.stop = HilStop::kWatchdog;
      if (recorder_ != nullptr) {
        record.kind = RecordedInputKind::kWatchdogStop;
        recorder_->OnInput(record);
      }
      return false;
  }
  if (run_.watchdog.silent() && run_.watchdog.action() == SilenceAction::kHold) {
    ++run_.counters.watchdog_hold_periods;
  }
  run_.pending_record_valid = received;
  // Skipped periods, with the newest currents: they answer the last sample sent, and a real
  // rotor would have felt them from the first skipped period on.
  for (std::int64_t m = 0; m < missed_before; ++m) {
    if (!CatchUpPeriod()) return false;
  }
  // Physics over the period, the controller's currents held; its closing sample is sent.
  if (!AdvancePeriod(true)) return false;
  if (run_.driver.state().step_index >= model_.total_steps) {
    run_.stop = HilStop::kDuration;
    return false;
  }
  return true;
}

}  // namespace ambdrop
