#include "tools/cli/scenario_command.hpp"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>

#include "controller_if/boundary/controller_watchdog.hpp"
#include "controller_if/boundary/scenario_faults.hpp"
#include "controller_if/controller/current_profile.hpp"
#include "controller_if/controller/internal_controller_link.hpp"
#include "controller_if/controller/profile_controller_link.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/state_dump.hpp"
#include "controller_if/loop/step_driver.hpp"
#include "io/config/config_loader.hpp"
#include "io/files/json_writer.hpp"
#include "io/files/timeseries_csv.hpp"
#include "tools/cli/exit_codes.hpp"
#include "tools/cli/junit_report.hpp"
#include "tools/cli/long_run_note.hpp"
#include "tools/cli/scenario_outcome.hpp"
#include "tools/cli/settled_start_refusal.hpp"
#include "tools/record/run_record_writer.hpp"
#include "tools/record/trajectory_hasher.hpp"
#include "tools/validation/run_summary.hpp"
#include "tools/validation/tdb_summary_json.hpp"

namespace ambdrop {
namespace {

namespace fs = std::filesystem;

const char* StatusOf(HilStop stop) {
  switch (stop) {
    case HilStop::kWatchdog:
      return "watchdog_stop";
    case HilStop::kDiverged:
      return "diverged";
    default:
      return "ok";
  }
}

}  // namespace

int RunScenarioCommand(const SimOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  LoadedConfig config;
  std::optional<Model> model;
  std::int64_t substeps = 0;
  try {
    config = LoadConfig(options.scenario_path, options.overrides);
    if (!config.scenario) {
      throw ConfigError(options.scenario_path +
                        ": not a scenario: it has no [scenario] table (see configs/scenarios/)");
    }
    // Without a controller the AMBs follow their current profiles, applied at every step as
    // `ambdrop sim` applies them.
    if (config.params.controller.kind == ControllerKind::kNone) {
      config.params.controller.rate_Hz = 1.0 / config.params.simulation.step_s;
    }
    model.emplace(BuildModel(config.params));
    substeps = ControllerSubsteps(*model);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitConfig;
  }
  if (RefusesSettledStart(*model, options.scenario_path, "scenario")) return kExitConfig;
  NoteLongRun(*model, false);
  const ScenarioParams& scenario = *config.scenario;
  const double dt = model->params.simulation.step_s;
  const double period_s = static_cast<double>(substeps) * dt;

  const fs::path out_dir(options.out_dir);
  std::optional<TimeseriesCsvWriter> csv;
  std::unique_ptr<RunRecordWriter> recorder;
  try {
    fs::create_directories(out_dir);
    WriteTextFile(out_dir / "effective_config.toml", config.effective_toml);
    csv.emplace(out_dir / "timeseries.csv", *model);
    if (!options.record_path.empty()) {
      RecordHeaderInfo header;
      header.source = "sim";
      header.controller = model->params.controller.kind == ControllerKind::kNone
                              ? "profile+scenario"
                              : "internal+scenario";
      header.config_toml = config.effective_toml;
      header.sensor_every_steps = substeps;
      header.output_every_steps = OutputEverySteps(*model);
      header.total_steps = model->total_steps;
      recorder = std::make_unique<RunRecordWriter>(options.record_path, *model, header);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }

  const bool profile_driven = model->params.controller.kind == ControllerKind::kNone;
  std::unique_ptr<ControllerLink> controller;
  if (profile_driven) {
    controller = std::make_unique<ProfileControllerLink>(*model);
  } else {
    controller = std::make_unique<InternalControllerLink>(*model, period_s);
  }
  ScenarioLink link(controller.get(), *model, scenario);
  ScenarioTrigger trigger(*model, scenario);
  // A rig's own scheduled trigger (allowed only when the scenario has no power events).
  std::optional<ScheduledTrigger> rig_trigger;
  std::vector<TriggerSource*> triggers{&trigger};
  if (model->trigger_step >= 0) {
    // At the steps `ambdrop sim` uses: times formed as the session forms them.
    const double restore_s = model->restore_step >= 0 ? model->restore_step * dt : -1.0;
    rig_trigger.emplace(model->trigger_step * dt, ScheduledFailure(*model), restore_s,
                        ScheduledRestore(*model));
    triggers.push_back(&*rig_trigger);
  }
  const ControlInput profile_start = ProfileStartInput(*model);
  HilOptions hil;
  if (profile_driven) hil.initial_input = &profile_start;
  hil.watchdog_timeout_s = scenario.watchdog_timeout_s;
  hil.silence_action = ParseSilenceAction(scenario.silence_action);
  TrajectoryHasher hasher(model->params.sensors.size(), recorder.get());
  hil.recorder = &hasher;
  auto outputs = std::make_unique<HilSession::OutputRing>();
  HilSession session(*model, &link, triggers, hil, outputs.get());
  RunSummary summary(model->params);
  ScenarioOutcome outcome(*model);
  Observation o;
  // A write error is held, not thrown through the session: the run finishes and its summary
  // says what failed.
  std::string output_error;
  const auto drain = [&] {
    while (outputs->TryPop(&o)) {
      summary.Add(o);
      outcome.Add(o);
      if (!output_error.empty()) continue;
      try {
        csv->Write(o);
      } catch (const std::exception& e) {
        output_error = e.what();
      }
    }
  };
  // The virtual clock: period n starts at n periods; the session runs on this thread.
  const std::int64_t period_ns = std::llround(period_s * 1e9);
  session.Start(0);
  for (std::int64_t n = 1; session.Period(n * period_ns); ++n) drain();
  drain();
  try {
    csv->Close();
  } catch (const std::exception& e) {
    if (output_error.empty()) output_error = e.what();
  }
  if (recorder) {
    try {
      recorder->Finish(StatusOf(session.stop()), session.state().step_index);
    } catch (const std::exception& e) {
      if (output_error.empty()) output_error = e.what();
    }
  }

  const char* status = StatusOf(session.stop());
  const std::vector<ScenarioOutcome::Check> checks =
      outcome.Evaluate(scenario.expect, status, session);
  bool all_pass = true;
  for (const auto& c : checks) all_pass = all_pass && c.pass;
  if (!options.junit_path.empty()) {
    // As `hil --junit` writes it: the run's own checks, then each expectation.
    std::vector<JunitCase> cases;
    cases.push_back({"sim", "run_completed", session.stop() != HilStop::kDiverged,
                     fmt::format("the run stopped: {}", status)});
    cases.push_back({"sim", "outputs_written", output_error.empty(), output_error});
    for (const ScenarioOutcome::Check& c : checks) {
      cases.push_back({"sim.scenario", c.name, c.pass,
                       fmt::format("expected {}, got {}", c.expected, c.actual)});
    }
    try {
      WriteJunit(
          options.junit_path, "ambdrop sim --scenario " + options.scenario_path, cases,
          std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
    } catch (const std::exception& e) {
      if (output_error.empty()) output_error = std::string("--junit: ") + e.what();
    }
  }

  JsonWriter json;
  json.BeginObject();
  json.Key("config").String(options.scenario_path);
  json.Key("name").String(model->params.name);
  // A run whose outputs failed is not ok, even if its physics was.
  json.Key("status").String(session.stop() != HilStop::kDiverged &&
                                    session.stop() != HilStop::kWatchdog && !output_error.empty()
                                ? "output_error"
                                : status);
  json.Key("output_error");
  if (output_error.empty()) {
    json.Null();
  } else {
    json.String(output_error);
  }
  json.Key("steps").Integer(session.state().step_index);
  json.Key("power_events").Integer(session.counters().power_events);
  json.Key("watchdog_silence_episodes").Integer(session.watchdog().silence_episodes());
  json.Key("currents_swallowed").Integer(link.messages_swallowed());
  json.Key("trajectory_hash").String(hasher.Hex());
  json.Key("scenario").BeginObject();
  json.Key("description").String(scenario.description);
  json.Key("relevitated").Bool(outcome.relevitated());
  json.Key("pass").Bool(all_pass);
  json.Key("checks");
  WriteScenarioChecks(json, checks);
  json.EndObject();
  WriteTdbSummaries(json, summary);
  json.EndObject();
  try {
    WriteTextFile(out_dir / "summary.json", json.str());
  } catch (const std::exception& e) {
    if (output_error.empty()) output_error = e.what();
  }

  if (!options.quiet) {
    fmt::print("{}: {}\n  {}\n", options.scenario_path, status, scenario.description);
    for (const auto& c : checks) {
      fmt::print("  {:<4} {:<28} expected {:<14} got {}\n", c.pass ? "ok" : "FAIL", c.name,
                 c.expected, c.actual);
    }
  }
  if (session.stop() == HilStop::kDiverged) {
    fmt::print(stderr, "error: the simulation diverged: {}\n",
               DescribeFailure(*model, session.step_status(), session.state()));
  }
  if (!output_error.empty()) {
    fmt::print(stderr, "error: {}\n", output_error);
    return kExitError;
  }
  if (!all_pass) {
    fmt::print(stderr, "error: {}: an expected outcome did not happen\n", options.scenario_path);
    return kExitExpectationFailed;
  }
  return kExitOk;
}

}  // namespace ambdrop
