// ambdrop command line: argument wiring only; the work is in the *_command files.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "tools/cli/exit_codes.hpp"
#include "tools/cli/fit_command.hpp"
#include "tools/cli/hil_command.hpp"
#include "tools/cli/keys_command.hpp"
#include "tools/cli/measure_command.hpp"
#include "tools/cli/modes_command.hpp"
#include "tools/cli/replay_command.hpp"
#include "tools/cli/sim_command.hpp"
#include "tools/cli/validate_command.hpp"

#ifndef AMBDROP_VERSION
#define AMBDROP_VERSION "unknown"
#endif

namespace {

// Repeatable `--set key=value`. One value per occurrence: otherwise CLI11 would let a vector
// option swallow the following positional (`--set a=1 CONFIG`).
CLI::Option* AddSetOption(CLI::App* command, std::vector<std::string>* overrides) {
  return command
      ->add_option("--set", *overrides,
                   "Override a config value, e.g. --set simulation.duration_s=0.3 (TOML value "
                   "syntax; repeatable, applied in order)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
}

// CLI11 reads "nan" and "inf" into a double, and its Range and PositiveNumber let NaN through
// (every comparison with it is false): each number flag is checked finite first.
const CLI::Validator kFinite(
    [](std::string& text) {
      char* end = nullptr;
      const double value = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !std::isfinite(value)) {
        return "expected a finite number, found " + text;
      }
      return std::string();
    },
    "FINITE");

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ambdrop: rotor-drop / active-magnetic-bearing emulator"};
  app.set_version_flag("--version", std::string("ambdrop ") + AMBDROP_VERSION);
  app.require_subcommand(1);

  ambdrop::SimOptions sim;
  CLI::App* sim_command = app.add_subcommand(
      "sim", "Simulate a rotor drop offline; write timeseries.csv and summary.json");
  CLI::Option* sim_config = sim_command->add_option("CONFIG", sim.config_path, "TOML config file");
  CLI::Option* sim_scenario =
      sim_command
          ->add_option("--scenario", sim.scenario_path,
                       "Run a scripted shutdown: a scenario file (a rig config with a [scenario] "
                       "table; configs/scenarios/); exits 4 if an expected outcome fails")
          ->type_name("FILE");
  sim_config->excludes(sim_scenario);
  sim_command->callback([sim_config, sim_scenario] {
    if (sim_config->count() == 0 && sim_scenario->count() == 0) {
      throw CLI::RequiredError("CONFIG or --scenario");
    }
  });
  sim_command->add_option("--out", sim.out_dir, "Output directory")
      ->type_name("DIR")
      ->capture_default_str();
  AddSetOption(sim_command, &sim.overrides);
  sim_command->add_flag("--quiet,-q", sim.quiet, "No summary on stdout and no progress bar");
  sim_command->add_flag("--amb-currents", sim.amb_currents,
                        "timeseries.csv: every AMB's commanded and coil currents per axis "
                        "(amb_<name>_x_command_A, ..., amb_<name>_y_coil_A) as the last columns");
  sim_command
      ->add_option("--junit", sim.junit_path,
                   "With --scenario: write the run's checks and the scenario's expectations as "
                   "JUnit XML")
      ->type_name("FILE")
      ->needs(sim_scenario);
  sim_command
      ->add_option("--record", sim.record_path,
                   "Record the run (inputs, power events, sensor samples, state) into an LCM "
                   "event log for `ambdrop replay`")
      ->type_name("FILE.lcm");

  ambdrop::ReplayOptions replay;
  CLI::App* replay_command = app.add_subcommand(
      "replay", "Re-run a recorded run offline from its inputs and compare with the record");
  replay_command->add_option("RECORD", replay.record_path, "LCM event log from --record")
      ->required();
  replay_command->add_option("--config", replay.config_path,
                             "Replay with this config instead of the recorded one (reports the "
                             "differences)");
  replay_command->add_flag("--strict", replay.strict,
                           "Exit 4 unless every recorded sensor sample is reproduced within "
                           "--tolerance-m (by value: -0 equals 0)");
  replay_command
      ->add_option("--tolerance-m", replay.tolerance_m,
                   "Tolerance of --strict (m); default 0 for an ambdrop record, half the frame "
                   "map's coarsest sensor count for a candump log")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->type_name("M");
  replay_command
      ->add_option("--align", replay.align,
                   "How a candump log's frames are placed at steps: time (receive times, a live "
                   "run) or sequence (the k-th sensor frame is the k-th exchange: a lock-step "
                   "capture)")
      ->check(CLI::IsMember({"time", "sequence"}))
      ->capture_default_str();
  replay_command->add_option("--out", replay.out_dir, "Output directory")
      ->type_name("DIR")
      ->capture_default_str();
  AddSetOption(replay_command, &replay.overrides);
  replay_command->add_flag("--quiet,-q", replay.quiet, "No report on stdout");
  CLI::Option* export_profile =
      replay_command
          ->add_option("--export-profile", replay.export_profile_path,
                       "Instead of replaying, write the recorded coil currents as a rig config "
                       "driven by current profiles ([controller] kind = \"none\"), for "
                       "`ambdrop sim` or a scenario's base")
          ->type_name("FILE.toml");
  replay_command
      ->add_option("--profile-points", replay.profile.max_points,
                   "At most this many points per AMB profile")
      ->check(CLI::Range(2, 1024))
      ->needs(export_profile)
      ->capture_default_str();
  replay_command
      ->add_option("--profile-from", replay.profile.from_s,
                   "Export from this record time (s); the profile starts there at 0 s")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->needs(export_profile)
      ->capture_default_str();
  replay_command
      ->add_option("--profile-to", replay.profile.to_s, "Export up to this record time (s)")
      ->check(kFinite & CLI::PositiveNumber)
      ->needs(export_profile);

  ambdrop::ValidateOptions validate;
  CLI::App* validate_command = app.add_subcommand(
      "validate", "Run every seed paper's case and compare with its published numbers");
  validate_command->add_option("--out", validate.out_dir, "Output directory (validate.json)")
      ->type_name("DIR")
      ->capture_default_str();
  validate_command->add_option("--configs", validate.configs_dir, "The seed rigs' config folder")
      ->type_name("DIR")
      ->capture_default_str();
  validate_command->add_option("--case", validate.cases, "Run only this case (repeatable)")
      ->type_name("NAME");
  validate_command->add_flag("--allow-known-failures", validate.allow_known_failures,
                             "Checks marked as known failures (open issues) do not fail the exit "
                             "code; they are still reported");
  validate_command->add_flag("--quiet,-q", validate.quiet, "No table on stdout");

  ambdrop::ModesOptions modes;
  double speed_rpm = 0.0;
  CLI::App* modes_command = app.add_subcommand(
      "modes", "Natural frequencies: free-free, supported at speed, reduced model at speed");
  modes_command->add_option("CONFIG", modes.config_path, "TOML config file")->required();
  CLI::Option* speed_option =
      modes_command
          ->add_option("--speed-rpm", speed_rpm,
                       "Spin speed in rpm (default: the config's simulation.spin_speed_rad_s)")
          ->type_name("R")
          ->check(kFinite & CLI::Range(-1e7, 1e7));
  modes_command->add_option("--count", modes.count, "Frequencies per list at most")
      ->type_name("N")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  AddSetOption(modes_command, &modes.overrides);
  modes_command->add_option("--out", modes.out_dir, "Output directory")
      ->type_name("DIR")
      ->capture_default_str();

  ambdrop::KeysOptions keys;
  CLI::App* keys_command = app.add_subcommand(
      "keys", "Every number of a config: its --set path, value, unit, class and fit range");
  keys_command->add_option("CONFIG", keys.config_path, "TOML config file")->required();
  AddSetOption(keys_command, &keys.overrides);
  keys_command->add_option("--class", keys.key_class, "Only keys of this class")
      ->type_name("CLASS")
      ->check(CLI::IsMember({"physical", "measurement", "solver", "run", "interface"}));
  keys_command->add_flag("--json", keys.json, "JSON on stdout instead of the table");

  ambdrop::HilCommandOptions hil;
  CLI::App* hil_command = app.add_subcommand(
      "hil", "Run the emulator against a controller in real time: currents in, sensors out");
  CLI::Option* hil_config = hil_command->add_option("CONFIG", hil.config_path, "TOML config file");
  CLI::Option* hil_scenario =
      hil_command
          ->add_option("--scenario", hil.scenario_path,
                       "A scenario file in place of CONFIG: its power events, faults and "
                       "expectations apply to whatever controller runs; exits 4 if one fails")
          ->type_name("FILE");
  hil_config->excludes(hil_scenario);
  hil_command
      ->add_option("--junit", hil.junit_path,
                   "Write the run's checks and the scenario's expectations as JUnit XML")
      ->type_name("FILE");
  hil_command
      ->add_option("--describe", hil.describe_path,
                   "Write the plant description (index order, units, rates, per AMB the static "
                   "load, ki, ks, bias and limits; the reference controller in A/m) as JSON, and "
                   "exit without running")
      ->type_name("FILE");
  hil_command->callback([hil_config, hil_scenario] {
    if (hil_config->count() == 0 && hil_scenario->count() == 0) {
      throw CLI::RequiredError("CONFIG or --scenario");
    }
  });
  hil_command->add_option("--controller", hil.controller, "internal | lcm[:URL] | can:IFACE")
      ->capture_default_str();
  hil_command->add_option("--trigger", hil.trigger,
                          "at:SECONDS | gpio:CHIP:LINE | can | lcm (default: the config's "
                          "[trigger] schedule)");
  hil_command->add_flag("--virtual-clock", hil.virtual_clock,
                        "Run on simulated time, as fast as possible (offline, tests)");
  // The real-time flags override the config's [realtime] table; the callbacks note which were
  // given (an explicit --rt-priority 0 overrides a config priority too).
  hil_command
      ->add_option_function<int>(
          "--rt-priority",
          [&hil](int priority) {
            hil.rt_priority = priority;
            hil.rt_priority_given = true;
          },
          "SCHED_FIFO priority of the loop thread (0: normal scheduling; default: "
          "realtime.priority)")
      ->type_name("P")
      ->check(CLI::Range(0, 99));
  hil_command
      ->add_option_function<int>(
          "--cpu",
          [&hil](int cpu) {
            hil.cpu = cpu;
            hil.cpu_given = true;
          },
          "Pin the loop thread to this CPU (-1: any; default: realtime.cpu)")
      ->type_name("N")
      ->check(CLI::Range(-1, 1023));
  hil_command
      ->add_option("--spin-us", hil.spin_us,
                   "Poll the clock for the last US microseconds before each deadline instead of "
                   "sleeping (default: realtime.spin_s); with SCHED_FIFO a spin near the period "
                   "trips the kernel's RT throttling")
      ->type_name("US")
      ->check(kFinite & CLI::Range(0.0, 10000.0));
  hil_command->add_flag(
      "--lcm-io-fifo", hil.lcm_io_fifo,
      "With --controller lcm and SCHED_FIFO: run LCM's receive and publish threads SCHED_FIFO one "
      "priority below the loop, off its CPU, so a busy host does not hold the controller's "
      "answers back (at 20 kHz they then fall under the kernel's RT throttling: slower)");
  hil_command->add_flag("--enforce-rt", hil.enforce_rt,
                        "Fail if real-time scheduling, CPU pinning or memory locking is refused "
                        "(also realtime.enforce)");
  hil_command
      ->add_option("--watchdog-s", hil.watchdog_timeout_s,
                   "Controller silence that trips the watchdog (s)")
      ->check(kFinite & CLI::Range(0.0, 1e6))
      ->capture_default_str();
  hil_command->add_option("--silence", hil.silence_action, "Watchdog action: hold | zero | stop")
      ->capture_default_str();
  hil_command->add_option("--out", hil.out_dir, "Output directory")->capture_default_str();
  AddSetOption(hil_command, &hil.overrides);
  hil_command->add_flag("--quiet,-q", hil.quiet, "No summary on stdout");
  CLI::Option* lockstep =
      hil_command->add_flag("--lockstep", hil.lockstep,
                            "With --virtual-clock: after each sample sent, wait for the external "
                            "controller's answer (a controller slower than real time closes the "
                            "loop sample by sample)");
  hil_command
      ->add_option("--lockstep-timeout-s", hil.lockstep_timeout_s,
                   "Longest wait for an answer in --lockstep (wall time, s)")
      ->check(kFinite & CLI::Range(0.0, 1e6))
      ->capture_default_str();
  lockstep->needs(hil_command->get_option("--virtual-clock"));
  hil_command
      ->add_option("--record", hil.record_path,
                   "Record the run (currents in with their receive time, power events, sensor "
                   "samples out, state) into an LCM event log for `ambdrop replay`")
      ->type_name("FILE.lcm");

  ambdrop::MeasureCommandOptions measure;
  CLI::App* measure_command = app.add_subcommand(
      "measure",
      "Make a measured-like record (CSV) from a truth rig: sensor readings, coil currents, TDB "
      "loads and speeds, with noise, for testing `fit`");
  measure_command->add_option("TRUTH_CONFIG", measure.config_path, "TOML config of the truth rig")
      ->required();
  measure_command->add_option("--out", measure.out_path, "The record to write")
      ->type_name("FILE.csv")
      ->required();
  AddSetOption(measure_command, &measure.overrides);
  measure_command
      ->add_option("--rate-Hz", measure.rate_Hz,
                   "Sample rate, a whole number of physics steps per sample (default: the "
                   "config's controller.rate_Hz)")
      ->type_name("R")
      ->check(kFinite & CLI::PositiveNumber);
  measure_command
      ->add_option("--channels", measure.channels,
                   "Comma list of channel groups: displacement, current, tdb_normal_force, "
                   "tdb_speed, rotor_speed, controller_command, tdb_support_force")
      ->type_name("LIST")
      ->capture_default_str();
  measure_command
      ->add_option("--measurement-toml", measure.measurement_toml_path,
                   "Also write the [measurement] table that maps the record's columns, for an "
                   "analysed config")
      ->type_name("FILE");
  measure_command
      ->add_option("--current-noise-A", measure.current_noise_A,
                   "Standard deviation of the noise added to the currents (A)")
      ->type_name("S")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->capture_default_str();
  measure_command
      ->add_option("--force-noise-N", measure.force_noise_N,
                   "Standard deviation of the noise added to the TDB normal forces (N)")
      ->type_name("S")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->capture_default_str();
  measure_command
      ->add_option("--speed-noise-rad-s", measure.speed_noise_rad_s,
                   "Standard deviation of the noise added to the TDB and rotor speeds (rad/s)")
      ->type_name("S")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->capture_default_str();
  measure_command
      ->add_option("--seed", measure.seed,
                   "Seed of the added noise (the sensors' noise keeps the config's seeds)")
      ->type_name("N")
      ->capture_default_str();
  measure_command
      ->add_option("--from-s", measure.from_s,
                   "Leave out the rows before this run time (t stays run time)")
      ->type_name("T0")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->capture_default_str();
  measure_command->add_flag("--quiet,-q", measure.quiet,
                            "No summary on stdout and no progress bar");

  ambdrop::FitOptions fit;
  CLI::App* fit_command = app.add_subcommand(
      "fit",
      "Hold the model against a measured record: residuals, the missing effect, its parameters, "
      "and the error before and after");
  fit_command->add_option("CONFIG", fit.config_path, "The declared model, with [measurement]")
      ->required();
  CLI::Option* measured_option =
      fit_command
          ->add_option("--measured", fit.measured_paths,
                       "The measured record: CSV, or an ambdrop run record (.lcm); several "
                       "records of one rig: each fitted, and what they share")
          ->type_name("FILE...");
  CLI::Option* spin_up_option =
      fit_command
          ->add_option("--spin-up-times", fit.spin_up_times,
                       "Instead of a record: measured TDB spin-up times after the trigger, "
                       "e.g. de=0.11,nde=0.129; which single parameter change explains them")
          ->type_name("TDB=S,...");
  measured_option->excludes(spin_up_option);
  fit_command->add_option("--out", fit.out_dir, "Output directory (fit.json, report.md, plots)")
      ->type_name("DIR")
      ->capture_default_str();
  AddSetOption(fit_command, &fit.overrides);
  fit_command
      ->add_option("--lead-s", fit.lead_s,
                   "Simulate from this long before the trigger, from the measured state")
      ->check(kFinite & CLI::PositiveNumber)
      ->capture_default_str();
  fit_command->add_option("--threads", fit.threads, "Candidates fitted in parallel")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  fit_command
      ->add_option("--max-runs", fit.max_runs_per_start,
                   "Model runs per start of each candidate's search")
      ->check(CLI::Range(4, 10000))
      ->capture_default_str();
  fit_command
      ->add_option("--tolerance", fit.tolerance,
                   "A relative RMS residual within which model and record agree anyway, added "
                   "in quadrature to the limit the record's noise and the model's sensitivity "
                   "set (0: the record alone decides)")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->capture_default_str();
  fit_command->add_flag("--declared-step", fit.declared_step,
                        "Run every model at the config's step (default: up to 4x coarser "
                        "where that moves the prediction by under 0.2 of the record's noise)");
  fit_command->add_flag("--quiet,-q", fit.quiet, "No summary on stdout");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version arrive as "errors" with exit code 0.
    if (e.get_exit_code() == 0) return app.exit(e);
    // CLI11 reports `ambdrop frobnicate` as a missing subcommand; name the word it rejected.
    if (app.get_subcommands().empty() && argc > 1 && argv[1][0] != '-') {
      fmt::print(stderr, "error: unknown subcommand '{}'\n\n{}", argv[1], app.help());
      return ambdrop::kExitUsage;
    }
    // A usage error: say what was wrong and show the help of the command that was meant
    // (App::help() answers for the selected subcommand, if any).
    fmt::print(stderr, "error: {}\n\n{}", e.what(), app.help());
    return ambdrop::kExitUsage;
  }

  try {
    if (sim_command->parsed()) return ambdrop::RunSimCommand(sim);
    if (hil_command->parsed()) return ambdrop::RunHilCommand(hil);
    if (replay_command->parsed()) return ambdrop::RunReplayCommand(replay);
    if (validate_command->parsed()) return ambdrop::RunValidateCommand(validate);
    if (measure_command->parsed()) return ambdrop::RunMeasureCommand(measure);
    if (fit_command->parsed()) return ambdrop::RunFitCommand(fit);
    if (keys_command->parsed()) return ambdrop::RunKeysCommand(keys);
    if (modes_command->parsed()) {
      if (speed_option->count() > 0) modes.speed_rpm = speed_rpm;
      return ambdrop::RunModesCommand(modes);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return ambdrop::kExitError;
  }
  // Unreachable while exactly one subcommand is required; kept as a safe default.
  fmt::print(stderr, "{}", app.help());
  return ambdrop::kExitUsage;
}
