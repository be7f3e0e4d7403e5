#pragma once
#include <string>
#include <vector>

#include "tools/cli/hil_checks.hpp"

namespace ambdrop {

struct HilCommandOptions {
  std::string config_path;
  /// `--scenario FILE`: a scenario (a rig config with a [scenario] table) in place of CONFIG:
  /// its power events, faults and expectations apply to whatever controller runs.
  std::string scenario_path;
  /// `--junit FILE`: the run's checks (and the scenario's expectations) as JUnit XML.
  std::string junit_path;
  /// `--describe FILE`: write the plant description (tools/cli/plant_description.hpp) and exit.
  std::string describe_path;
  std::string out_dir = "out";
  std::vector<std::string> overrides;
  std::string controller = "internal";  ///< internal | lcm[:URL] | can:IFACE
  std::string trigger;                  ///< at:SECONDS | gpio:CHIP:LINE | can | lcm; "": config
  bool virtual_clock = false;           ///< run as fast as possible on simulated time
  int rt_priority = 0;                  ///< SCHED_FIFO priority; 0: normal scheduling
  int cpu = -1;                         ///< pin the loop thread; -1: any
  bool enforce_rt = false;              ///< a refused real-time request is an error
  /// LCM's receive and publish threads SCHED_FIFO one below the loop, off its CPU.
  bool lcm_io_fifo = false;
  double watchdog_timeout_s = 5e-3;
  std::string silence_action = "hold";  ///< hold | zero | stop
  bool quiet = false;
  std::string record_path;  ///< "": no record; else an LCM event log for `ambdrop replay`
  /// With virtual_clock: after each sample sent, wait (up to lockstep_timeout_s of wall time)
  /// for the external controller's answer, so a controller slower than real time (a firmware
  /// build on the host, an emulated CPU) still closes the loop sample by sample.
  bool lockstep = false;
  double lockstep_timeout_s = 1.0;
  /// With --controller lcm: simulated time between the states published live on AMBDROP_STATE
  /// (power events go out on AMBDROP_POWER as they happen); 0: none.
  double state_interval_s = 0.01;
  /// The checks every run is held to (tools/cli/hil_checks.hpp): `--check-*`.
  HilCheckBounds check_bounds;
  // The command line over the config's [realtime] table: a flag given overrides its key.
  double spin_us = -1.0;  ///< --spin-us: poll the clock before each deadline (us); < 0: config
  bool rt_priority_given = false;  ///< --rt-priority was given (it may be 0: SCHED_OTHER)
  bool cpu_given = false;          ///< --cpu was given
};

/// `ambdrop hil`: runs the emulator against a controller in real time (or on a virtual clock):
/// currents in, emulated sensor readings out, power events from the trigger. Writes
/// timeseries.csv, summary.json (with the loop's timing statistics) and effective_config.toml.
int RunHilCommand(const HilCommandOptions& options);

}  // namespace ambdrop
