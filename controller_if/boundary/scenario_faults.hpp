#pragma once
// Carries out a scenario's events (rt_core/scenario_params.hpp) around a controller link:
// ScenarioTrigger turns the power events into PowerEvents at their times; ScenarioLink sits
// between the session and the controller and makes the link misbehave as scripted (silence,
// stuck currents, sensor dropouts). Both are real-time safe: allocation-free and noexcept after
// construction, so a scenario can also run against a live controller.
#include <array>
#include <vector>

#include "controller_if/loop/controller_link.hpp"
#include "rt_core/model.hpp"
#include "rt_core/scenario_params.hpp"

namespace ambdrop {

/// The scenario's power_fail, power_restore and trigger_glitch events, in time order.
class ScenarioTrigger final : public TriggerSource {
 public:
  ScenarioTrigger(const Model& model, const ScenarioParams& scenario);
  bool Poll(double time_s, PowerEvent* out) noexcept override;
  std::size_t pending() const noexcept { return events_.size() - next_; }

 private:
  struct Timed {
    double time_s;
    PowerEvent event;
  };
  std::vector<Timed> events_;
  std::size_t next_ = 0;
};

/// A controller link with the scenario's faults: during controller_silence no currents get
/// through; during stuck_current an AMB axis keeps the current it had when the fault began;
/// during sensor_dropout a sensor axis reads value_m. Time is the run time of the last sensor
/// sample sent (the session sends one at the end of every period).
class ScenarioLink final : public ControllerLink {
 public:
  ScenarioLink(ControllerLink* inner, const Model& model, const ScenarioParams& scenario);
  bool PollCurrents(CurrentsMessage* out) noexcept override;
  void SendSensors(const SensorReadings& readings, std::int64_t step,
                   double time_s) noexcept override;
  // An outside controller's lock step and status channel pass through the faults unchanged.
  bool AwaitAnswer(std::chrono::nanoseconds timeout) noexcept override {
    return inner_->AwaitAnswer(timeout);
  }
  void ObserveState(const Observation& observation) noexcept override {
    inner_->ObserveState(observation);
  }

  std::int64_t messages_swallowed() const noexcept { return swallowed_; }

 private:
  static bool Active(const ScenarioEvent& e, double time_s) noexcept {
    return time_s >= e.time_s && time_s < e.time_s + e.duration_s;
  }

  ControllerLink* inner_;
  int ambs_;
  int sensors_;
  std::vector<ScenarioEvent> faults_;
  std::vector<std::array<std::array<double, 2>, kMaxAmbs>> stuck_value_A_;  // per fault
  std::vector<bool> stuck_captured_;
  std::array<std::array<double, 2>, kMaxAmbs> last_delivered_A_{};
  double time_s_ = 0.0;
  std::int64_t swallowed_ = 0;
  SensorReadings scratch_;
};

}  // namespace ambdrop
