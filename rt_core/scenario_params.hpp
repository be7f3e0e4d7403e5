#pragma once
// A scripted shutdown (the [scenario] table of a scenario file, io/config/config_scenario.hpp):
// timed events on the power, the sensors, the currents and the controller link, and the outcome the
// scenario expects. Plain data; controller_if/boundary/scenario_faults.hpp carries the events out.
#include <optional>
#include <string>
#include <vector>

namespace ambdrop {

enum class ScenarioEventKind {
  kPowerFail,          ///< the named AMB axes (default: all, and the motor) lose power
  kPowerRestore,       ///< they get it back
  kTriggerGlitch,      ///< a false trigger: power fails, and returns after duration_s
  kSensorDropout,      ///< a sensor axis reads value_m for duration_s (signal lost)
  kStuckCurrent,       ///< an AMB axis keeps the current it had, whatever the controller says
  kControllerSilence,  ///< no currents arrive for duration_s
};

struct ScenarioEvent {
  ScenarioEventKind kind = ScenarioEventKind::kPowerFail;
  double time_s = 0.0;
  double duration_s = 0.0;  ///< glitch, dropout, stuck current, silence
  int amb = -1;             ///< AMB index (model order); -1: all
  int sensor = -1;          ///< sensor index; -1: all
  int axis = -1;            ///< 0 = x, 1 = y, -1: both
  double value_m = 0.0;     ///< what a dropped-out sensor reads, m
  std::string location;     ///< "file:line" of the event, for messages
};

/// What the scenario says must come out; every field is optional.
struct ScenarioExpect {
  std::optional<std::string> status;  ///< ok | watchdog_stop | diverged
  std::optional<int> watchdog_silence_episodes;
  std::optional<int> power_events;
  std::optional<bool> contact;          ///< any touchdown bearing touched
  std::vector<std::string> contact_at;  ///< these TDBs touched
  std::vector<std::string> no_contact_at;
  std::optional<double> first_contact_after_s;  ///< no contact anywhere before this time
  /// At the end the rotor is levitated again: no contact in the last 20 ms and every journal
  /// within a fifth of its clearance of the TDB centre.
  std::optional<bool> relevitated;
};

struct ScenarioParams {
  std::string description;
  double watchdog_timeout_s = 5e-3;
  std::string silence_action = "hold";  ///< hold | zero | stop
  std::vector<ScenarioEvent> events;
  ScenarioExpect expect;
};

}  // namespace ambdrop
