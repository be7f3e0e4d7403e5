#pragma once
#include "tools/cli/sim_command.hpp"

namespace ambdrop {

/// `ambdrop sim --scenario FILE`: runs a scripted shutdown (io/config/config_scenario.hpp) offline:
/// the in-process reference controller behind the scenario's faults, its power events, the HIL
/// watchdog, on the virtual clock. Writes what `ambdrop sim` writes (summary.json gains a
/// "scenario" object with each expectation checked) and, with --record, a run record. Exits
/// kExitExpectationFailed when an expectation fails.
int RunScenarioCommand(const SimOptions& options);

}  // namespace ambdrop
