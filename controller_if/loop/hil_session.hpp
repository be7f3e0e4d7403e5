#pragma once
#include <cstdint>
#include <vector>

#include "controller_if/boundary/controller_watchdog.hpp"
#include "controller_if/boundary/power_state.hpp"
#include "controller_if/boundary/sensor_emulator.hpp"
#include "controller_if/loop/controller_link.hpp"
#include "controller_if/loop/run_record.hpp"
#include "controller_if/loop/step_driver.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "rt_core/spsc_ring.hpp"

namespace ambdrop {

struct HilOptions {
  double watchdog_timeout_s = 5e-3;  ///< controller silence that trips the watchdog
  SilenceAction silence_action = SilenceAction::kHold;
  RunRecorder* recorder = nullptr;  ///< receives every input, power event, sample and state
  /// The currents the rotor starts levitated on (at their powered equilibrium) and that stay
  /// applied until the controller's first currents arrive; null: those that carry the static
  /// load. A profile-driven rig starts on its profile's first currents, as `ambdrop sim` does.
  const ControlInput* initial_input = nullptr;
};

/// Counters of a HIL run (read after it, or from another thread as a snapshot).
struct HilCounters {
  std::int64_t periods = 0;
  std::int64_t currents_received = 0;
  std::int64_t sensor_samples_sent = 0;
  std::int64_t power_events = 0;
  std::int64_t first_power_event_step = -1;  ///< step the first power event applied at; -1: none
  std::int64_t watchdog_hold_periods = 0;
  std::int64_t watchdog_zero_periods = 0;
  std::int64_t observations_dropped = 0;  ///< output ring full
  /// Periods the physics advanced without a controller exchange, to catch up after the loop
  /// missed deadlines (see Period).
  std::int64_t catch_up_periods = 0;
  /// Periods, after the controller's first currents message, that ended with no new one: its
  /// answer came late (after the period it was due in) or not at all.
  std::int64_t periods_without_currents = 0;
  /// Largest journal excursion towards contact before the first power event, as a fraction of
  /// its TDB's radial clearance ((clearance + penetration) / clearance, over the output states):
  /// how well the controller levitated the rotor.
  double levitated_fraction = 0.0;
};

enum class HilStop { kRunning, kDuration, kWatchdog, kDiverged };

/// Everything a HIL session changes as it runs: the step driver (physics, power state, sensors,
/// input), the watchdog, the controller's newest currents, the counters and the period's flags.
/// The link, the trigger sources, the output ring and the recorder it talks to are not in it. A
/// session resumed from another's run state over copies of its link and triggers goes on bit
/// for bit (tests/hil_session_test.cpp).
struct HilRunState {
  HilRunState(const Model& model, std::int64_t substeps, std::int64_t watchdog_timeout_ns,
              SilenceAction silence_action)
      : driver(model, substeps), watchdog(watchdog_timeout_ns, silence_action) {}
  StepDriver driver;
  ControllerWatchdog watchdog;
  CurrentsMessage latest;
  HilCounters counters;
  bool period_start = false;     ///< the next step is a period's first: events and currents are due
  bool send = true;              ///< the period's closing sample goes to the controller
  bool watchdog_zeroed = false;  ///< the zero currents of this silence are recorded
  RecordedInput pending_record;  ///< this period's input, recorded once the power events are
  bool pending_record_valid = false;
  HilStop stop = HilStop::kRunning;
  StepStatus step_status = StepStatus::kOk;
};

/// One HIL run: each controller period it takes the controller's newest currents, applies
/// power events from the trigger sources, advances the physics by its whole number of steps
/// with the currents held, and sends the emulated sensor readings back. Period() is the
/// real-time body: noexcept, allocation-free. The same session runs on a real or a virtual
/// clock; with the in-process controller on a virtual clock it reproduces `ambdrop sim`.
class HilSession {
 public:
  using OutputRing = SpscRing<Observation, 8192>;

  /// `resume`: another session's run state (same model and options) to go on from, instead of
  /// a new run; its link and triggers must be in the same state (copies of them).
  HilSession(const Model& model, ControllerLink* link, std::vector<TriggerSource*> triggers,
             const HilOptions& options, OutputRing* outputs = nullptr,
             const HilRunState* resume = nullptr);

  /// Sends the first sensor sample (before period 0) and starts the watchdog at `now_ns`.
  void Start(std::int64_t now_ns) noexcept;
  /// One controller period at clock time `now_ns`; false when the run must end (stop()).
  /// `missed_before` (LoopTick::missed_before): periods the loop skipped just before this one.
  /// The physics advances through each of them before this one, so simulated time keeps up with
  /// wall time and the controller next sees a rotor where the elapsed time puts it: power events
  /// fire at their period, the newest currents are held, and the sensor emulator takes its sample
  /// (its delay line and filter count samples) but nothing is sent. Only this period's sample
  /// goes out: the skipped ones are stale by now, and a burst of them would arrive at the
  /// controller together and upset its sample-by-sample timing (derivative terms, CAN bus load).
  bool Period(std::int64_t now_ns, std::int64_t missed_before = 0) noexcept;

  /// The run so far: a session made with it as `resume` goes on from there.
  const HilRunState& run_state() const noexcept { return run_; }

  HilStop stop() const noexcept { return run_.stop; }
  /// What the step reported when the run diverged (kOk otherwise); see DescribeFailure.
  StepStatus step_status() const noexcept { return run_.step_status; }
  const State& state() const noexcept { return run_.driver.state(); }
  const HilCounters& counters() const noexcept { return run_.counters; }
  const ControllerWatchdog& watchdog() const noexcept { return run_.watchdog; }
  std::int64_t substeps() const noexcept { return substeps_; }
  double period_s() const noexcept { return substeps_ * model_.params.simulation.step_s; }

 private:
  friend class StepDriver;
  // The step driver's hooks (step_driver.hpp): the trigger sources' power events and the
  // controller's newest currents at a period's first step, the sample sent at its end.
  void OnSensors(StepDriver& driver, std::int64_t step) noexcept;
  void PowerEvents(StepDriver& driver, std::int64_t step) noexcept;
  bool Command(StepDriver& driver, std::int64_t step) noexcept;
  void BeginStep(StepDriver&, std::int64_t) noexcept {}
  bool BeforeStep(StepDriver&) noexcept { return true; }
  void OnOutput(StepDriver&) noexcept;

  // The physics over one period, the controller's currents held; false (stop_ set) if it
  // diverged. `send`: the sample at its end goes to the controller (not for a skipped period).
  bool AdvancePeriod(bool send) noexcept;
  // One skipped period (see Period); false when the run must end.
  bool CatchUpPeriod() noexcept;

  const Model& model_;
  ControllerLink* link_;
  std::vector<TriggerSource*> triggers_;
  OutputRing* outputs_;
  std::int64_t substeps_;
  ControlInput initial_input_;
  RunRecorder* recorder_;
  HilRunState run_;
};

/// Physics steps per controller period; throws if the period is not a whole number of steps.
std::int64_t ControllerSubsteps(const Model& model);

}  // namespace ambdrop
