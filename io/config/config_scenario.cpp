#include "io/config/config_scenario.hpp"

#include <string>
#include <vector>

#include "io/config/config_loader.hpp"

namespace ambdrop {
namespace {

using config_detail::NodeLocation;
using config_detail::NonNegative;
using config_detail::NumberRule;
using config_detail::Positive;
using config_detail::TableReader;

template <typename Component>
int IndexOf(const TableReader& table, std::string_view key, const std::vector<Component>& list,
            std::string_view noun) {
  if (!table.Has(key)) return -1;
  const std::string name = table.String(key);
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (list[i].name == name) return static_cast<int>(i);
  }
  std::string names;
  for (const Component& c : list) names += (names.empty() ? "\"" : ", \"") + c.name + "\"";
  table.Reject(
      key, std::string("the name of one of the rig's ") + std::string(noun) + " (" + names + ")");
  return -1;  // not reached: Reject throws
}

std::vector<std::string> TdbNames(const TableReader& table, std::string_view key,
                                  const ModelParams& params) {
  std::vector<std::string> out;
  const toml::array* array = table.OptionalArray(key, "an array of TDB names");
  if (array == nullptr) return out;
  for (const toml::node& node : *array) {
    bool known = false;
    if (node.is_string()) {
      for (const TdbParams& t : params.tdbs) known = known || t.name == node.as_string()->get();
    }
    if (!known) table.Reject(key, "an array of the rig's TDB names");
    out.push_back(node.as_string()->get());
  }
  return out;
}

ScenarioEvent ReadEvent(const TableReader& t, const ModelParams& params) {
  t.AllowOnly({"kind", "time_s", "duration_s", "amb", "axis", "sensor", "value_m"});
  ScenarioEvent e;
  e.location = NodeLocation(t.table(), t.source_name());
  const std::string kind = t.Choice("kind",
                                    {"power_fail", "power_restore", "trigger_glitch",
                                     "sensor_dropout", "stuck_current", "controller_silence"},
                                    std::nullopt);
  e.time_s = t.Number("time_s", NonNegative());
  const bool timed = kind == "trigger_glitch" || kind == "sensor_dropout" ||
                     kind == "stuck_current" || kind == "controller_silence";
  if (timed) {
    e.duration_s = t.Number("duration_s", Positive());
  } else if (t.Has("duration_s")) {
    t.Reject("duration_s", "no duration for " + kind + " (use a later event, or trigger_glitch)");
  }
  const bool amb_event = kind == "power_fail" || kind == "power_restore" ||
                         kind == "trigger_glitch" || kind == "stuck_current";
  if (amb_event) {
    e.amb = IndexOf(t, "amb", params.ambs, "AMBs");
  } else if (t.Has("amb")) {
    t.Reject("amb", "no AMB for " + kind);
  }
  if (kind == "sensor_dropout") {
    e.sensor = IndexOf(t, "sensor", params.sensors, "sensors");
    e.value_m = t.Number("value_m", config_detail::AnyNumber(), 0.0);
  } else {
    if (t.Has("sensor")) t.Reject("sensor", "no sensor for " + kind);
    if (t.Has("value_m")) t.Reject("value_m", "no value_m for " + kind);
  }
  if (kind == "controller_silence") {
    if (t.Has("axis")) t.Reject("axis", "no axis for controller_silence");
  } else {
    const std::string axis = t.Choice("axis", {"x", "y", "both"}, "both");
    e.axis = axis == "x" ? 0 : axis == "y" ? 1 : -1;
  }
  if (kind == "power_fail") e.kind = ScenarioEventKind::kPowerFail;
  if (kind == "power_restore") e.kind = ScenarioEventKind::kPowerRestore;
  if (kind == "trigger_glitch") e.kind = ScenarioEventKind::kTriggerGlitch;
  if (kind == "sensor_dropout") e.kind = ScenarioEventKind::kSensorDropout;
  if (kind == "stuck_current") e.kind = ScenarioEventKind::kStuckCurrent;
  if (kind == "controller_silence") e.kind = ScenarioEventKind::kControllerSilence;
  return e;
}

ScenarioExpect ReadExpect(const TableReader& t, const ModelParams& params) {
  t.AllowOnly({"status", "watchdog_silence_episodes", "power_events", "contact", "contact_at",
               "no_contact_at", "first_contact_after_s", "relevitated"});
  ScenarioExpect x;
  if (t.Has("status")) x.status = t.Choice("status", {"ok", "watchdog_stop", "diverged"}, "ok");
  if (t.Has("watchdog_silence_episodes")) {
    x.watchdog_silence_episodes = t.Integer("watchdog_silence_episodes", 0, 1000000, 0);
  }
  if (t.Has("power_events")) x.power_events = t.Integer("power_events", 0, 1000000, 0);
  if (t.Has("contact")) x.contact = t.Bool("contact", false);
  x.contact_at = TdbNames(t, "contact_at", params);
  x.no_contact_at = TdbNames(t, "no_contact_at", params);
  if (t.Has("first_contact_after_s")) {
    x.first_contact_after_s = t.Number("first_contact_after_s", NonNegative());
  }
  if (t.Has("relevitated")) x.relevitated = t.Bool("relevitated", false);
  return x;
}

}  // namespace

ScenarioParams ReadScenario(const TableReader& table, const ModelParams& params) {
  table.AllowOnly({"description", "watchdog_timeout_s", "silence_action", "event", "expect"});
  ScenarioParams s;
  s.description = table.String("description", "");
  // Bounded as hil's --watchdog-s is: it becomes nanoseconds through llround.
  s.watchdog_timeout_s = table.Number("watchdog_timeout_s",
                                      NumberRule{.lower = 0.0,
                                                 .lower_inclusive = false,
                                                 .upper = 1e6,
                                                 .what = "a positive number of at most 1e6"},
                                      5e-3);
  s.silence_action = table.Choice("silence_action", {"hold", "zero", "stop"}, "hold");
  bool power_events = false;
  for (const TableReader& event : table.TableArray("event")) {
    s.events.push_back(ReadEvent(event, params));
    const ScenarioEventKind k = s.events.back().kind;
    power_events = power_events || k == ScenarioEventKind::kPowerFail ||
                   k == ScenarioEventKind::kPowerRestore || k == ScenarioEventKind::kTriggerGlitch;
  }
  if (power_events && params.trigger.enabled) {
    throw ConfigError(table.source_name() + ": [" + table.path() +
                      "] has power events, and the rig's [trigger] is enabled too: set "
                      "trigger.enabled = false so that the scenario alone drives the power");
  }
  if (const auto expect = table.OptionalTable("expect")) s.expect = ReadExpect(*expect, params);
  return s;
}

}  // namespace ambdrop
