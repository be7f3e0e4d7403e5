#include "tools/cli/sim_command.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/offline_run.hpp"
#include "controller_if/loop/step_driver.hpp"
#include "io/config/config_loader.hpp"
#include "io/files/json_writer.hpp"
#include "io/files/timeseries_csv.hpp"
#include "rt_core/model.hpp"
#include "tools/cli/cli_registry.hpp"
#include "tools/cli/command_config.hpp"
#include "tools/cli/exit_codes.hpp"
#include "tools/cli/long_run_note.hpp"
#include "tools/cli/progress_bar.hpp"
#include "tools/cli/scenario_command.hpp"
#include "tools/record/run_record_writer.hpp"
#include "tools/record/trajectory_hasher.hpp"
#include "tools/validation/run_summary.hpp"
#include "tools/validation/tdb_summary_json.hpp"

namespace ambdrop {
namespace {

namespace fs = std::filesystem;

/// What the run produced besides the observations.
struct RunStatistics {
  std::string config_path;
  std::string name;
  StepStatus status = StepStatus::kOk;
  std::string failure_message;
  std::int64_t steps = 0;
  double step_s = 0.0;
  double wall_time_s = 0.0;
  std::optional<double> trigger_time_s;
  double final_spin_speed_rad_s = 0.0;
  std::string trajectory_hash;
  std::string output_error;  ///< a file the run could not write (empty: none)
  double settle_s = 0.0;     ///< simulation.settle_s as run (whole controller periods)
  double settle_last_change_m = 0.0;

  double simulated_time_s() const { return static_cast<double>(steps) * step_s; }
  double realtime_factor() const {
    return wall_time_s > 0.0 ? simulated_time_s() / wall_time_s
                             : std::numeric_limits<double>::quiet_NaN();
  }
};

const char* StatusName(StepStatus status) {
  switch (status) {
    case StepStatus::kOk:
      return "ok";
    case StepStatus::kNonFinite:
      return "non_finite";
    case StepStatus::kExcursionBound:
      return "excursion_bound";
  }
  return "unknown";
}

std::string SummaryJson(const RunStatistics& run, const RunSummary& summary) {
  JsonWriter json;
  json.BeginObject();
  json.Key("config").String(run.config_path);
  json.Key("name").String(run.name);
  // A run whose outputs failed is not ok, even if its physics was.
  json.Key("status").String(run.status == StepStatus::kOk && !run.output_error.empty()
                                ? "output_error"
                                : StatusName(run.status));
  json.Key("output_error");
  if (run.output_error.empty()) {
    json.Null();
  } else {
    json.String(run.output_error);
  }
  json.Key("failure_message");
  if (run.status == StepStatus::kOk) {
    json.Null();
  } else {
    json.String(run.failure_message);
  }
  json.Key("steps").Integer(run.steps);
  json.Key("step_s").Number(run.step_s);
  json.Key("simulated_time_s").Number(run.simulated_time_s());
  json.Key("wall_time_s").Number(run.wall_time_s);
  json.Key("realtime_factor").Number(run.realtime_factor());
  json.Key("trigger_time_s").Number(run.trigger_time_s);
  // Where the run started: the levitated equilibrium, or the closed loop's own steady state
  // after settle_s (the rotor's largest change at a sensor plane over the last revolution).
  json.Key("start").BeginObject(true);
  json.Key("kind").String(run.settle_s > 0.0 ? "settled" : "equilibrium");
  if (run.settle_s > 0.0) {
    json.Key("settle_s").Number(run.settle_s);
    json.Key("last_revolution_change_m").Number(run.settle_last_change_m);
  }
  json.EndObject();
  json.Key("final_spin_speed_rad_s").Number(run.final_spin_speed_rad_s);
  json.Key("observations").Integer(summary.observations());
  json.Key("trajectory_hash").String(run.trajectory_hash);
  WriteTdbSummaries(json, summary);
  json.EndObject();
  return json.str();
}

std::string OrDash(std::optional<double> value) {
  return value ? fmt::format("{:.6g}", *value) : std::string("-");
}

void PrintSummaryTable(const RunStatistics& run, const RunSummary& summary, const fs::path& out_dir,
                       std::int64_t rows) {
  fmt::print("{}: {}, {} steps, {:.6g} s simulated in {:.3g} s ({:.3g}x real time)\n",
             run.name.empty() ? run.config_path : run.name, StatusName(run.status), run.steps,
             run.simulated_time_s(), run.wall_time_s, run.realtime_factor());
  fmt::print("final spin speed {:.6g} rad/s ({:.6g} rpm)\n", run.final_spin_speed_rad_s,
             run.final_spin_speed_rad_s * 60.0 / (2.0 * std::numbers::pi));
  if (!summary.tdbs().empty()) {
    fmt::print("{:<10} {:>14} {:>14} {:>18} {:>14}\n", "TDB", "peak Fn [N]", "max |e|/c",
               "first contact [s]", "spin-up [s]");
    for (const TdbSummary& tdb : summary.tdbs()) {
      fmt::print("{:<10} {:>14.6g} {:>14.6g} {:>18} {:>14}\n", tdb.name, tdb.peak_normal_force_N,
                 tdb.max_excursion_over_clearance, OrDash(tdb.first_contact_time_s),
                 OrDash(tdb.spinup_time_s));
    }
  }
  fmt::print("wrote {} ({} rows) and {}\n", (out_dir / "timeseries.csv").string(), rows,
             (out_dir / "summary.json").string());
}

}  // namespace

int RunSimCommand(const SimOptions& options) {
  if (!options.scenario_path.empty()) {
    if (options.amb_currents) {
      fmt::print(stderr, "error: --amb-currents is not available with --scenario (yet)\n");
      return kExitUsage;
    }
    return RunScenarioCommand(options);
  }
  const std::optional<LoadedConfig> loaded =
      LoadCommandConfig(options.config_path, options.overrides);
  if (!loaded) return kExitConfig;
  const LoadedConfig& config = *loaded;
  const std::optional<Model> model = BuildCommandModel(options.config_path, config.params);
  if (!model) return kExitConfig;

  NoteLongRun(*model, false);

  const fs::path out_dir(options.out_dir);
  std::optional<TimeseriesCsvWriter> csv;
  try {
    fs::create_directories(out_dir);
    WriteTextFile(out_dir / "effective_config.toml", config.effective_toml);
    csv.emplace(out_dir / "timeseries.csv", *model, options.amb_currents);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }

  std::unique_ptr<RunRecordWriter> recorder;
  if (!options.record_path.empty() && model->params.simulation.settle_s > 0.0) {
    // A replay starts from the record's levitated equilibrium: it has no settled state to
    // start from (nor the sensors' noise state), so it could not reproduce the run.
    fmt::print(stderr,
               "error: --record with simulation.settle_s = {} s: a record does not carry the "
               "settled start yet; record without it (settle_s = 0)\n",
               model->params.simulation.settle_s);
    return kExitUsage;
  }
  if (!options.record_path.empty()) {
    const bool internal = model->params.controller.kind == ControllerKind::kInternalPid;
    RecordHeaderInfo header;
    header.source = "sim";
    header.controller = internal ? "internal" : "profile";
    header.config_toml = config.effective_toml;
    header.sensor_every_steps = internal ? ControllerSubsteps(*model) : 0;
    header.output_every_steps = OutputEverySteps(*model);
    header.total_steps = model->total_steps;
    try {
      recorder = std::make_unique<RunRecordWriter>(options.record_path, *model, header);
    } catch (const std::exception& e) {
      fmt::print(stderr, "error: --record: {}\n", e.what());
      return kExitError;
    }
  }

  RunSummary summary(model->params);
  ProgressBar progress(!options.quiet && ProgressBar::IsTerminal(2));
  // RunOffline cannot be stopped from a callback, so an output error is held until it returns
  // rather than thrown through the simulator.
  std::string output_error;
  const auto on_output = [&](const Observation& observation, const AmbCurrents& currents) {
    summary.Add(observation);
    if (!output_error.empty()) return;
    try {
      csv->Write(observation, currents);
    } catch (const std::exception& e) {
      output_error = e.what();
    }
  };
  const auto on_progress = [&](double fraction) { progress.Update(fraction); };

  const auto start = std::chrono::steady_clock::now();
  TrajectoryHasher hasher(model->params.sensors.size(), recorder.get());
  const OfflineRunResult result = RunOfflineWithCurrents(*model, on_output, on_progress, &hasher);
  const auto stop = std::chrono::steady_clock::now();
  progress.Finish();

  RunStatistics run;
  run.config_path = options.config_path;
  run.name = model->params.name;
  run.status = result.status;
  run.failure_message = result.failure_message;
  run.steps = result.steps;
  run.step_s = model->params.simulation.step_s;
  run.wall_time_s = std::chrono::duration<double>(stop - start).count();
  run.trajectory_hash = hasher.Hex();
  run.settle_s = static_cast<double>(result.settle_steps) * run.step_s;
  run.settle_last_change_m = result.settle_last_change_m;
  if (model->params.trigger.enabled) run.trigger_time_s = model->params.trigger.time_s;
  // The final state is exact even when the duration is not a multiple of the output interval;
  // the last observation is the fallback should a failed run leave no state.
  const int spin_index = model->spin_index();
  if (result.final_state.y.size() > spin_index) {
    run.final_spin_speed_rad_s = result.final_state.y[spin_index];
  } else {
    run.final_spin_speed_rad_s =
        summary.last_spin_speed_rad_s().value_or(std::numeric_limits<double>::quiet_NaN());
  }

  try {
    csv->Close();
  } catch (const std::exception& e) {
    if (output_error.empty()) output_error = e.what();
  }
  if (recorder) {
    try {
      recorder->Finish(result.status == StepStatus::kOk ? "ok" : "diverged", result.steps);
    } catch (const std::exception& e) {
      if (output_error.empty()) output_error = e.what();
    }
  }
  run.output_error = output_error;
  try {
    WriteTextFile(out_dir / "summary.json", SummaryJson(run, summary));
  } catch (const std::exception& e) {
    if (output_error.empty()) output_error = e.what();
  }

  if (!options.quiet) PrintSummaryTable(run, summary, out_dir, csv->rows());
  std::fflush(stdout);
  if (!output_error.empty()) fmt::print(stderr, "error: {}\n", output_error);
  if (result.status != StepStatus::kOk) {
    // The message may end with its own newline (state dumps do); print exactly one.
    std::string_view message = result.failure_message;
    while (!message.empty() && message.back() == '\n') message.remove_suffix(1);
    fmt::print(stderr, "error: simulation failed ({}): {}\n", StatusName(result.status), message);
    return kExitRunFailed;
  }
  return output_error.empty() ? kExitOk : kExitError;
}

RegisteredCommand AddSimCommand(CLI::App& app) {
  auto options = std::make_shared<SimOptions>();
  CLI::App* sim_command = app.add_subcommand(
      "sim", "Simulate a rotor drop offline; write timeseries.csv and summary.json");
  CLI::Option* sim_config =
      sim_command->add_option("CONFIG", options->config_path, "TOML config file");
  CLI::Option* sim_scenario =
      sim_command
          ->add_option("--scenario", options->scenario_path,
                       "Run a scripted shutdown: a scenario file (a rig config with a [scenario] "
                       "table; configs/scenarios/); exits 4 if an expected outcome fails")
          ->type_name("FILE");
  sim_config->excludes(sim_scenario);
  sim_command->callback([sim_config, sim_scenario] {
    if (sim_config->count() == 0 && sim_scenario->count() == 0) {
      throw CLI::RequiredError("CONFIG or --scenario");
    }
  });
  sim_command->add_option("--out", options->out_dir, "Output directory")
      ->type_name("DIR")
      ->capture_default_str();
  AddSetOption(sim_command, &options->overrides);
  sim_command->add_flag("--quiet,-q", options->quiet, "No summary on stdout and no progress bar");
  sim_command->add_flag("--amb-currents", options->amb_currents,
                        "timeseries.csv: every AMB's commanded and coil currents per axis "
                        "(amb_<name>_x_command_A, ..., amb_<name>_y_coil_A) as the last columns");
  sim_command
      ->add_option("--junit", options->junit_path,
                   "With --scenario: write the run's checks and the scenario's expectations as "
                   "JUnit XML")
      ->type_name("FILE")
      ->needs(sim_scenario);
  sim_command
      ->add_option("--record", options->record_path,
                   "Record the run (inputs, power events, sensor samples, state) into an LCM "
                   "event log for `ambdrop replay`")
      ->type_name("FILE.lcm");
  return {sim_command, [options] { return RunSimCommand(*options); }};
}

}  // namespace ambdrop
