#pragma once
#include <optional>
#include <string>
#include <vector>

#include "controller_if/loop/hil_session.hpp"
#include "io/files/json_writer.hpp"
#include "rt_core/model.hpp"
#include "rt_core/scenario_params.hpp"

namespace ambdrop {

/// Watches a scenario run's observations and checks its [scenario.expect] afterwards.
class ScenarioOutcome {
 public:
  explicit ScenarioOutcome(const Model& model);
  void Add(const Observation& observation);

  struct Check {
    std::string name;
    std::string expected;
    std::string actual;
    bool pass = false;
  };
  /// One check per expectation the scenario states.
  std::vector<Check> Evaluate(const ScenarioExpect& expect, const char* status,
                              const HilSession& session) const;

  /// No contact in the last 20 ms and every journal within a fifth of its clearance.
  bool relevitated() const;

 private:
  static constexpr double kQuietWindow_s = 0.02;
  static constexpr double kCentredFraction = 0.2;

  const Model& model_;
  std::vector<bool> touched_;
  std::optional<double> first_contact_s_;
  double last_contact_s_ = -1.0;
  double last_time_s_ = 0.0;
  std::vector<double> final_excursion_m_;
};

void WriteScenarioChecks(JsonWriter& json, const std::vector<ScenarioOutcome::Check>& checks);

}  // namespace ambdrop
