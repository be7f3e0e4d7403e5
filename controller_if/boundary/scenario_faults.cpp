#include "controller_if/boundary/scenario_faults.hpp"

#include <algorithm>

namespace ambdrop {
namespace {

PowerEvent EventFor(const ScenarioEvent& e, bool restore) {
  PowerEvent p;
  p.restore = restore;
  p.amb_mask = e.amb < 0 ? ~0u : (1u << e.amb);
  p.axis_x = e.axis != 1;
  p.axis_y = e.axis != 0;
  // Only a failure of everything takes the drive down with it.
  p.motor = e.amb < 0 && e.axis < 0;
  return p;
}

}  // namespace

ScenarioTrigger::ScenarioTrigger(const Model&, const ScenarioParams& scenario) {
  for (const ScenarioEvent& e : scenario.events) {
    switch (e.kind) {
      case ScenarioEventKind::kPowerFail:
        events_.push_back({e.time_s, EventFor(e, false)});
        break;
      case ScenarioEventKind::kPowerRestore:
        events_.push_back({e.time_s, EventFor(e, true)});
        break;
      case ScenarioEventKind::kTriggerGlitch:
        events_.push_back({e.time_s, EventFor(e, false)});
        events_.push_back({e.time_s + e.duration_s, EventFor(e, true)});
        break;
      default:
        break;
    }
  }
  std::stable_sort(events_.begin(), events_.end(),
                   [](const Timed& a, const Timed& b) { return a.time_s < b.time_s; });
}

bool ScenarioTrigger::Poll(double time_s, PowerEvent* out) noexcept {
  if (next_ >= events_.size() || events_[next_].time_s > time_s) return false;
  *out = events_[next_++].event;
  return true;
}

ScenarioLink::ScenarioLink(ControllerLink* inner, const Model& model,
                           const ScenarioParams& scenario)
    : inner_(inner),
      ambs_(static_cast<int>(model.params.ambs.size())),
      sensors_(static_cast<int>(model.params.sensors.size())) {
  for (const ScenarioEvent& e : scenario.events) {
    if (e.kind == ScenarioEventKind::kControllerSilence ||
        e.kind == ScenarioEventKind::kStuckCurrent || e.kind == ScenarioEventKind::kSensorDropout) {
      faults_.push_back(e);
    }
  }
  stuck_value_A_.resize(faults_.size());
  stuck_captured_.assign(faults_.size(), false);
  const ControlInput initial = StaticLoadInput(model);
  for (int a = 0; a < ambs_; ++a) last_delivered_A_[a] = initial.amb[a].current_A;
}

bool ScenarioLink::PollCurrents(CurrentsMessage* out) noexcept {
  // A stuck axis keeps what was flowing when its fault began.
  for (std::size_t f = 0; f < faults_.size(); ++f) {
    if (faults_[f].kind == ScenarioEventKind::kStuckCurrent && !stuck_captured_[f] &&
        Active(faults_[f], time_s_)) {
      stuck_value_A_[f] = last_delivered_A_;
      stuck_captured_[f] = true;
    }
  }
  if (!inner_->PollCurrents(out)) return false;
  for (const ScenarioEvent& e : faults_) {
    if (e.kind == ScenarioEventKind::kControllerSilence && Active(e, time_s_)) {
      ++swallowed_;
      return false;
    }
  }
  for (std::size_t f = 0; f < faults_.size(); ++f) {
    const ScenarioEvent& e = faults_[f];
    if (e.kind != ScenarioEventKind::kStuckCurrent || !Active(e, time_s_)) continue;
    for (int a = 0; a < ambs_; ++a) {
      if (e.amb >= 0 && e.amb != a) continue;
      for (int axis = 0; axis < 2; ++axis) {
        if (e.axis < 0 || e.axis == axis) out->current_A[a][axis] = stuck_value_A_[f][a][axis];
      }
    }
  }
  last_delivered_A_ = out->current_A;
  return true;
}

void ScenarioLink::SendSensors(const SensorReadings& readings, std::int64_t step,
                               double time_s) noexcept {
  time_s_ = time_s;
  scratch_ = readings;
  for (const ScenarioEvent& e : faults_) {
    if (e.kind != ScenarioEventKind::kSensorDropout || !Active(e, time_s)) continue;
    for (int s = 0; s < sensors_; ++s) {
      if (e.sensor >= 0 && e.sensor != s) continue;
      for (int axis = 0; axis < 2; ++axis) {
        if (e.axis < 0 || e.axis == axis) scratch_.reading_m[s][axis] = e.value_m;
      }
    }
  }
  inner_->SendSensors(scratch_, step, time_s);
}

}  // namespace ambdrop
