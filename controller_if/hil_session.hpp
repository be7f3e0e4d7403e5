#pragma once
#include <cstdint>
#include <vector>

#include "controller_if/controller_link.hpp"
#include "controller_if/controller_watchdog.hpp"
#include "controller_if/power_state.hpp"
#include "controller_if/sensor_emulator.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "rt_core/spsc_ring.hpp"

namespace ambdrop {

struct HilOptions {
  double watchdog_timeout_s = 5e-3;  ///< controller silence that trips the watchdog
  SilenceAction silence_action = SilenceAction::kHold;
};

/// Counters of a HIL run (read after it, or from another thread as a snapshot).
struct HilCounters {
  std::int64_t periods = 0;
  std::int64_t currents_received = 0;
  std::int64_t sensor_samples_sent = 0;
  std::int64_t power_events = 0;
  std::int64_t watchdog_hold_periods = 0;
  std::int64_t watchdog_zero_periods = 0;
  std::int64_t observations_dropped = 0;  ///< output ring full
};

enum class HilStop { kRunning, kDuration, kWatchdog, kDiverged };

/// One HIL run: each controller period it takes the controller's newest currents, applies
/// power events from the trigger sources, advances the physics by its whole number of steps
/// with the currents held, and sends the emulated sensor readings back. Period() is the
/// real-time body: noexcept, allocation-free. The same session runs on a real or a virtual
/// clock; with the in-process controller on a virtual clock it reproduces `ambdrop sim`.
class HilSession {
 public:
  using OutputRing = SpscRing<Observation, 8192>;

  HilSession(const Model& model, ControllerLink* link, std::vector<TriggerSource*> triggers,
             const HilOptions& options, OutputRing* outputs = nullptr);

  /// Sends the first sensor sample (before period 0) and starts the watchdog at `now_ns`.
  void Start(std::int64_t now_ns) noexcept;
  /// One controller period at clock time `now_ns`; false when the run must end (stop()).
  bool Period(std::int64_t now_ns) noexcept;

  HilStop stop() const noexcept { return stop_; }
  const State& state() const noexcept { return state_; }
  const HilCounters& counters() const noexcept { return counters_; }
  const ControllerWatchdog& watchdog() const noexcept { return watchdog_; }
  std::int64_t substeps() const noexcept { return substeps_; }
  double period_s() const noexcept { return substeps_ * model_.params.simulation.step_s; }

 private:
  void SendSensors() noexcept;

  const Model& model_;
  ControllerLink* link_;
  std::vector<TriggerSource*> triggers_;
  OutputRing* outputs_;
  Simulator sim_;
  SensorEmulator sensors_;
  PowerState power_;
  ControllerWatchdog watchdog_;
  std::int64_t substeps_;
  std::int64_t output_every_;
  State state_;
  ControlInput input_;
  CurrentsMessage latest_;
  Observation obs_;
  SensorReadings readings_;
  HilCounters counters_;
  HilStop stop_ = HilStop::kRunning;
};

/// Physics steps per controller period; throws if the period is not a whole number of steps.
std::int64_t ControllerSubsteps(const Model& model);

}  // namespace ambdrop
