#include "tools/hil/lcm_live_state.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace ambdrop {
namespace {

std::int64_t WallClockUs() noexcept {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

LcmLiveState::LcmLiveState(LcmEndpoint* endpoint, const Model& model, double interval_s)
    : endpoint_(endpoint), model_(model) {
  const double step_s = model.params.simulation.step_s;
  if (!(std::isfinite(interval_s) && interval_s > 0.0 && interval_s / step_s < 1e15)) {
    throw std::invalid_argument("the live state interval must be a finite time > 0 s");
  }
  every_steps_ = std::max<std::int64_t>(1, std::llround(interval_s / step_s));
  for (std::size_t a = 0; a < model.params.ambs.size() && a < kMaxAmbs; ++a) {
    powered_axes_[a] = kAxisX | kAxisY;
  }
}

void LcmLiveState::OnPower(const RecordedPower& power) noexcept {
  const PowerEvent& e = power.event;
  const std::uint8_t axes =
      static_cast<std::uint8_t>((e.axis_x ? kAxisX : 0) | (e.axis_y ? kAxisY : 0));
  HilPowerEvent out;
  out.utime_us = WallClockUs();
  out.sequence = events_++;
  out.step_index = power.step;
  out.time_s = static_cast<double>(power.step) * model_.params.simulation.step_s;
  out.power_on = e.restore;
  out.motor = e.motor;
  out.axis_mask = axes;
  for (std::size_t a = 0; a < model_.params.ambs.size() && a < kMaxAmbs; ++a) {
    if ((e.amb_mask & (1u << a)) == 0) continue;
    out.amb_mask = static_cast<std::uint8_t>(out.amb_mask | (1u << a));
    powered_axes_[a] = e.restore ? static_cast<std::uint8_t>(powered_axes_[a] | axes)
                                 : static_cast<std::uint8_t>(powered_axes_[a] & ~axes);
  }
  out.powered_axes = powered_axes_;
  if (endpoint_->TryPushPowerEvent(out)) ++power_pushed_;
  // The state after the event goes out at once: the next one handed over (the state at the
  // event's own step was taken before the event applied).
  after_event_ = true;
}

void LcmLiveState::OnState(const State& state, const Observation& observation) noexcept {
  if (state.step_index < next_step_ && !after_event_) return;
  after_event_ = false;
  // Back on the interval's grid (multiples of it from step 0) after a state off it.
  next_step_ = (state.step_index / every_steps_ + 1) * every_steps_;
  HilEmulatorState s;
  s.utime_us = WallClockUs();
  s.step_index = state.step_index;
  s.time_s = observation.time_s;
  s.power_on = state.power_on;
  s.powered_axes = powered_axes_;
  s.spin_speed_rad_s = observation.spin_speed_rad_s;
  s.spin_angle_rad = observation.spin_angle_rad;
  s.mode_count = std::min(model_.modes(), kMaxModes);
  for (int i = 0; i < s.mode_count; ++i) {
    s.q[i] = state.y[i];
    s.q_dot[i] = state.y[model_.modes() + i];
  }
  s.tdb_count = std::min(static_cast<int>(model_.params.tdbs.size()), kMaxTdbs);
  for (int t = 0; t < s.tdb_count; ++t) {
    const TdbForce& f = observation.tdb[t];
    s.tdb[t].normal_force_N = f.normal_force_N;
    s.tdb[t].tangential_force_N = f.tangential_force_N;
    s.tdb[t].penetration_m = f.penetration_m;
    s.tdb[t].race_speed_rad_s = f.tdb_spin_rad_s;
    s.tdb[t].journal_xy_m = observation.tdb_journal_xy_m[t];
  }
  s.fault_count = state.faults.non_finite_state + state.faults.excursion_beyond_bound;
  if (endpoint_->TryPushState(s)) ++states_pushed_;
}

}  // namespace ambdrop
