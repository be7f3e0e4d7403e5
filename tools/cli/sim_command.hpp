#pragma once
#include <string>
#include <vector>

namespace ambdrop {

struct SimOptions {
  std::string config_path;
  std::string out_dir = "out";
  std::vector<std::string> overrides;  ///< "dotted.key=value", applied in order
  bool quiet = false;                  ///< no summary on stdout, no progress bar
  std::string record_path;             ///< "": no record; else an LCM event log of the run
  std::string scenario_path;  ///< a scenario file (its own rig config): see scenario_command
  /// timeseries.csv gets every AMB's commanded and coil currents as its last columns (off by
  /// default: replay, hil and scenario runs do not write them yet, and their files are compared
  /// byte for byte with sim's).
  bool amb_currents = false;
  /// With scenario_path: the run's checks and the scenario's expectations as JUnit XML.
  std::string junit_path;
};

/// `ambdrop sim`: loads the config, runs it offline and writes into options.out_dir
///   timeseries.csv         every observation, exact to the bit
///   summary.json           drop metrics per TDB and run statistics
///   effective_config.toml  the config after the overrides, to rerun or diff the case
/// and, with record_path, a run record for `ambdrop replay`.
/// Returns an ExitCode (exit_codes.hpp); errors are reported on stderr.
int RunSimCommand(const SimOptions& options);

}  // namespace ambdrop
