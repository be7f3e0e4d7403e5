#pragma once
// `ambdrop hil --controller lcm`: the run as a monitor or the controller sees it live on LCM,
// besides the sensor readings: AMBDROP_STATE (emulator_state_t) every state interval and
// AMBDROP_POWER (power_event_t) the moment a power event applies, whatever its source.
#include <array>
#include <cstdint>

#include "controller_if/loop/run_record.hpp"
#include "io/lcm/lcm_transport.hpp"
#include "rt_core/model.hpp"

namespace ambdrop {

/// A RunRecorder (the session hands it every state at the output cadence and every power event
/// at its step) that pushes into the endpoint's publish rings. Real-time safe: noexcept,
/// allocation-free; a full ring drops and the endpoint counts it.
class LcmLiveState final : public RunRecorder {
 public:
  /// `interval_s`: simulated time between published states (> 0), on a grid of its multiples
  /// from the start, no finer than the config's output interval (states arrive at that
  /// cadence); after a power event the next state goes out at once, off the grid.
  LcmLiveState(LcmEndpoint* endpoint, const Model& model, double interval_s);

  void OnStart(const RecordedStart&) noexcept override {}
  void OnInput(const RecordedInput&) noexcept override {}
  void OnPower(const RecordedPower& power) noexcept override;
  void OnSensors(const RecordedSensors&) noexcept override {}
  void OnState(const State& state, const Observation& observation) noexcept override;

  std::int64_t states_pushed() const noexcept { return states_pushed_; }
  std::int64_t power_events_pushed() const noexcept { return power_pushed_; }

 private:
  LcmEndpoint* endpoint_;
  const Model& model_;
  std::int64_t every_steps_;
  std::int64_t next_step_ = 0;  // the first state goes out at once
  bool after_event_ = false;    // a power event applied: the next state goes out
  std::array<std::uint8_t, kMaxAmbs> powered_axes_{};
  std::int64_t events_ = 0;
  std::int64_t states_pushed_ = 0;
  std::int64_t power_pushed_ = 0;
};

}  // namespace ambdrop
