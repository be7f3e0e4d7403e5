#include "tools/cli/scenario_outcome.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace ambdrop {
namespace {

std::string YesNo(bool b) {
  return b ? "true" : "false";
}

}  // namespace

ScenarioOutcome::ScenarioOutcome(const Model& model)
    : model_(model),
      touched_(model.params.tdbs.size(), false),
      final_excursion_m_(model.params.tdbs.size(), 0.0) {}

void ScenarioOutcome::Add(const Observation& o) {
  last_time_s_ = o.time_s;
  for (std::size_t t = 0; t < touched_.size(); ++t) {
    const bool contact = o.tdb[t].normal_force_N > 0.0;
    if (contact) {
      touched_[t] = true;
      if (!first_contact_s_) first_contact_s_ = o.time_s;
      last_contact_s_ = o.time_s;
    }
    // penetration = excursion - clearance (negative while free).
    final_excursion_m_[t] = o.tdb[t].penetration_m + model_.params.tdbs[t].clearance_m;
  }
}

bool ScenarioOutcome::relevitated() const {
  if (last_contact_s_ >= 0.0 && last_contact_s_ > last_time_s_ - kQuietWindow_s) return false;
  for (std::size_t t = 0; t < final_excursion_m_.size(); ++t) {
    if (final_excursion_m_[t] > kCentredFraction * model_.params.tdbs[t].clearance_m) {
      return false;
    }
  }
  return true;
}

std::vector<ScenarioOutcome::Check> ScenarioOutcome::Evaluate(const ScenarioExpect& x,
                                                              const char* status,
                                                              const HilSession& session) const {
  std::vector<Check> checks;
  const auto index_of = [&](const std::string& name) {
    for (std::size_t t = 0; t < model_.params.tdbs.size(); ++t) {
      if (model_.params.tdbs[t].name == name) return t;
    }
    return model_.params.tdbs.size();  // not reached: names are checked when read
  };
  if (x.status) checks.push_back({"status", *x.status, status, *x.status == status});
  if (x.watchdog_silence_episodes) {
    const auto n = session.watchdog().silence_episodes();
    checks.push_back({"watchdog_silence_episodes", std::to_string(*x.watchdog_silence_episodes),
                      std::to_string(n), n == *x.watchdog_silence_episodes});
  }
  if (x.power_events) {
    const auto n = session.counters().power_events;
    checks.push_back(
        {"power_events", std::to_string(*x.power_events), std::to_string(n), n == *x.power_events});
  }
  const bool any = std::find(touched_.begin(), touched_.end(), true) != touched_.end();
  if (x.contact) checks.push_back({"contact", YesNo(*x.contact), YesNo(any), *x.contact == any});
  for (const std::string& name : x.contact_at) {
    const bool t = touched_[index_of(name)];
    checks.push_back({"contact_at " + name, "true", YesNo(t), t});
  }
  for (const std::string& name : x.no_contact_at) {
    const bool t = touched_[index_of(name)];
    checks.push_back({"no_contact_at " + name, "true", YesNo(!t), !t});
  }
  if (x.first_contact_after_s) {
    const std::string actual =
        first_contact_s_ ? fmt::format("{:.6f} s", *first_contact_s_) : "no contact";
    checks.push_back({"first_contact_after_s", fmt::format("> {:.6f} s", *x.first_contact_after_s),
                      actual, !first_contact_s_ || *first_contact_s_ > *x.first_contact_after_s});
  }
  if (x.relevitated) {
    const bool r = relevitated();
    checks.push_back({"relevitated", YesNo(*x.relevitated), YesNo(r), r == *x.relevitated});
  }
  return checks;
}

void WriteScenarioChecks(JsonWriter& json, const std::vector<ScenarioOutcome::Check>& checks) {
  json.BeginArray();
  for (const ScenarioOutcome::Check& c : checks) {
    json.BeginObject();
    json.Key("check").String(c.name);
    json.Key("expected").String(c.expected);
    json.Key("actual").String(c.actual);
    json.Key("pass").Bool(c.pass);
    json.EndObject();
  }
  json.EndArray();
}

}  // namespace ambdrop
