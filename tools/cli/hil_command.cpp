#include "tools/cli/hil_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <thread>

#include "controller_if/boundary/scenario_faults.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/periodic_loop.hpp"
#include "controller_if/loop/recorder_tee.hpp"
#include "controller_if/loop/rt_clock.hpp"
#include "controller_if/loop/rt_system.hpp"
#include "controller_if/loop/step_driver.hpp"
#include "io/config/config_loader.hpp"
#include "io/files/json_writer.hpp"
#include "io/files/timeseries_csv.hpp"
#include "tools/cli/cli_registry.hpp"
#include "tools/cli/exit_codes.hpp"
#include "tools/cli/hil_checks.hpp"
#include "tools/cli/junit_report.hpp"
#include "tools/cli/long_run_note.hpp"
#include "tools/cli/plant_description.hpp"
#include "tools/cli/scenario_outcome.hpp"
#include "tools/cli/settled_start_refusal.hpp"
#include "tools/hil/hil_links.hpp"
#include "tools/hil/lcm_live_state.hpp"
#include "tools/record/run_record_writer.hpp"
#include "tools/validation/run_summary.hpp"
#include "tools/validation/tdb_summary_json.hpp"

namespace ambdrop {
namespace {

namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
extern "C" void OnSignal(int) {
  g_stop.store(true);
}

const char* StopName(HilStop stop) {
  switch (stop) {
    case HilStop::kRunning:
      return "interrupted";
    case HilStop::kDuration:
      return "ok";
    case HilStop::kWatchdog:
      return "watchdog_stop";
    case HilStop::kDiverged:
      return "diverged";
  }
  return "unknown";
}

void WriteStats(JsonWriter& json, const char* key, const TimingStats& stats) {
  json.Key(key).BeginObject();
  json.Key("count").Integer(stats.count());
  json.Key("p50_us").Number(static_cast<double>(stats.Quantile(0.5)) / 1e3);
  json.Key("p99_us").Number(static_cast<double>(stats.Quantile(0.99)) / 1e3);
  json.Key("p999_us").Number(static_cast<double>(stats.Quantile(0.999)) / 1e3);
  json.Key("max_us").Number(static_cast<double>(stats.max_ns()) / 1e3);
  json.EndObject();
}

}  // namespace

int RunHilCommand(const HilCommandOptions& given) {
  // A scenario is a rig config with a [scenario] table: it stands where CONFIG would.
  HilCommandOptions options = given;
  if (!options.scenario_path.empty()) options.config_path = options.scenario_path;
  const auto wall_start = std::chrono::steady_clock::now();
  LoadedConfig config;
  std::optional<Model> model;
  try {
    config = LoadConfig(options.config_path, options.overrides);
    if (!options.scenario_path.empty() && !config.scenario) {
      throw ConfigError(options.scenario_path +
                        ": not a scenario: it has no [scenario] table (see configs/scenarios/)");
    }
    model.emplace(BuildModel(config.params));
    // A config error (the controller period in whole steps), not one of the links' below.
    ControllerSubsteps(*model);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitConfig;
  }

  if (!options.describe_path.empty()) {
    try {
      WriteTextFile(options.describe_path, PlantDescriptionJson(*model, options.config_path));
    } catch (const std::exception& e) {
      fmt::print(stderr, "error: --describe: {}\n", e.what());
      return kExitError;
    }
    return kExitOk;
  }
  if (RefusesSettledStart(*model, options.config_path, "hil")) return kExitConfig;
  // The controller link and trigger sources (tools/hil/hil_links.hpp).
  HilLinks links;
  std::int64_t substeps = 0;
  try {
    substeps = ControllerSubsteps(*model);
    links = MakeHilLinks(config, *model, options.controller, options.trigger);
  } catch (const ConfigError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitConfig;
  } catch (const CanBusError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  } catch (const GpioError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitUsage;
  }
  // The plant description on LCM: at the start and on request (AMBDROP_PLANT_REQUEST).
  if (links.lcm) {
    links.lcm->PublishPlantDescription(PlantDescriptionJson(*model, options.config_path),
                                       kPlantDescriptionVersion);
  }
  HilOptions hil;
  hil.watchdog_timeout_s = options.watchdog_timeout_s;
  try {
    hil.silence_action = ParseSilenceAction(options.silence_action);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: --silence: {}\n", e.what());
    return kExitUsage;
  }
  // The scenario's faults sit between the emulator and whatever controller runs, and its power
  // events join the trigger sources; its watchdog settings are part of what it tests.
  const ScenarioParams* scenario = config.scenario ? &*config.scenario : nullptr;
  std::optional<ScenarioLink> scenario_link;
  std::optional<ScenarioTrigger> scenario_trigger;
  std::optional<ScenarioOutcome> outcome;
  ControllerLink* link = links.link.get();
  std::vector<TriggerSource*> triggers = links.triggers;
  if (scenario != nullptr) {
    scenario_link.emplace(links.link.get(), *model, *scenario);
    scenario_trigger.emplace(*model, *scenario);
    outcome.emplace(*model);
    link = &*scenario_link;
    triggers.push_back(&*scenario_trigger);
    hil.watchdog_timeout_s = scenario->watchdog_timeout_s;
    try {
      hil.silence_action = ParseSilenceAction(scenario->silence_action);
    } catch (const std::exception& e) {
      fmt::print(stderr, "error: {}: scenario.silence_action: {}\n", options.scenario_path,
                 e.what());
      return kExitConfig;
    }
  }

  NoteLongRun(*model, !options.virtual_clock);

  const fs::path out_dir(options.out_dir);
  fs::create_directories(out_dir);
  WriteTextFile(out_dir / "effective_config.toml", config.effective_toml);
  TimeseriesCsvWriter csv(out_dir / "timeseries.csv", *model);
  RunSummary summary(model->params);
  HilChecks checks;

  std::unique_ptr<RunRecordWriter> recorder;
  if (!options.record_path.empty()) {
    RecordHeaderInfo header;
    header.source = "hil";
    header.controller = options.controller;
    header.config_toml = config.effective_toml;
    header.sensor_every_steps = ControllerSubsteps(*model);
    header.output_every_steps = OutputEverySteps(*model);
    header.total_steps = model->total_steps;
    RecordWriterOptions record_options;
    // Live: wall-clock stamps, and a full ring drops (counted in the footer) rather than
    // stalling the loop. Virtual clock: simulated time, and the run waits for the writer.
    record_options.wall_clock = !options.virtual_clock;
    record_options.wait_when_full = options.virtual_clock;
    try {
      recorder =
          std::make_unique<RunRecordWriter>(options.record_path, *model, header, record_options);
    } catch (const std::exception& e) {
      fmt::print(stderr, "error: --record: {}\n", e.what());
      return kExitError;
    }
    hil.recorder = recorder.get();
  }
  // The run live on LCM beside the sensor readings (tools/hil/lcm_live_state.hpp).
  std::unique_ptr<LcmLiveState> live;
  std::unique_ptr<RecorderTee> tee;
  {
    const HilCheckBounds& b = options.check_bounds;
    for (const double bound : {b.levitated_fraction, b.answered_fraction, b.max_tdb_load_N,
                               b.max_penetration_m, b.max_race_speed_rad_s}) {
      if (std::isnan(bound)) {
        fmt::print(stderr, "error: a --check-* bound is NaN: give a number\n");
        return kExitUsage;
      }
    }
  }
  if (!(options.state_interval_s >= 0.0 && std::isfinite(options.state_interval_s))) {
    fmt::print(stderr, "error: --state-interval-s {}: expected a finite time >= 0 s\n",
               options.state_interval_s);
    return kExitUsage;
  }
  if (links.lcm && options.state_interval_s > 0.0) {
    try {
      live = std::make_unique<LcmLiveState>(links.lcm.get(), *model, options.state_interval_s);
    } catch (const std::exception& e) {
      fmt::print(stderr, "error: --state-interval-s: {}\n", e.what());
      return kExitUsage;
    }
    tee = std::make_unique<RecorderTee>(recorder.get(), live.get());
    hil.recorder = tee.get();
  }

  auto outputs = std::make_unique<HilSession::OutputRing>();
  HilSession session(*model, link, triggers, hil, outputs.get());

  // The writer drains observations off the real-time thread. A write error is held (an
  // exception here would terminate the process) and the ring still drained, so the loop runs on.
  std::atomic<bool> loop_done{false};
  std::string output_error;  // the writer's until it is joined
  std::thread writer([&] {
    Observation o;
    for (;;) {
      bool any = false;
      while (outputs->TryPop(&o)) {
        summary.Add(o);
        checks.Add(o);
        if (outcome) outcome->Add(o);
        any = true;
        if (!output_error.empty()) continue;
        try {
          csv.Write(o);
        } catch (const std::exception& e) {
          output_error = e.what();
        }
      }
      if (!any) {
        if (loop_done.load()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
    }
  });

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  LoopResult result;
  std::optional<PeriodicLoop> loop;
  RtGrant grant;
  // Real-time settings: the config's [realtime] table, the command line on top. A monotonic run
  // always asks for 1 ns timer slack (the default 50 us slack alone would make every wake-up
  // late by most of a 20 kHz period) and mlockall; refusals are warnings unless enforced.
  RtRequest rt_request;
  rt_request.priority = options.rt_priority_given ? options.rt_priority : config.realtime.priority;
  rt_request.cpu = options.cpu_given ? options.cpu : config.realtime.cpu;
  rt_request.lock_memory = true;
  rt_request.enforce = options.enforce_rt || config.realtime.enforce;
  rt_request.timer_slack_ns = 1;
  const std::int64_t spin_ns = options.spin_us >= 0.0 ? std::llround(options.spin_us * 1e3)
                                                      : std::llround(config.realtime.spin_s * 1e9);
  const std::int64_t period_ns = std::llround(substeps * model->params.simulation.step_s * 1e9);
  std::string throttling_warning;  // advice, not a refusal: never an error
  std::int64_t lockstep_timeouts = 0;
  std::thread rt([&] {
    try {
      if (!options.virtual_clock) {
        LinuxRtSystem system;
        grant = RequestRealtime(system, rt_request);
        if (options.lcm_io_fifo && grant.fifo && links.lcm) {
          // Just below the loop: the LCM threads carry its sensor samples and the answers.
          const std::string refused = links.lcm->RaiseIoThreads(std::max(1, grant.priority - 1),
                                                                grant.pinned ? grant.cpu : -1);
          if (!refused.empty()) grant.warnings.push_back("LCM I/O threads: " + refused);
        }
        const auto throttling = ReadRtThrottling();
        if (grant.fifo && throttling) {
          throttling_warning = RtThrottlingWarning(spin_ns, period_ns, *throttling);
        }
      }
    } catch (const std::exception& e) {
      grant.warnings.push_back(std::string("fatal: ") + e.what());
      g_stop.store(true);
    }
    MonotonicClock monotonic(spin_ns);
    VirtualClock virtual_clock;
    Clock* clock = options.virtual_clock ? static_cast<Clock*>(&virtual_clock) : &monotonic;
    loop.emplace(clock, period_ns);
    session.Start(clock->Now());
    const auto lockstep_timeout =
        std::chrono::nanoseconds(std::llround(options.lockstep_timeout_s * 1e9));
    if (options.lockstep && !link->AwaitAnswer(lockstep_timeout)) ++lockstep_timeouts;
    LoopRunOptions run;
    run.stop = &g_stop;
    // Periods the loop skipped after an overrun still advance the physics (HilSession::Period),
    // so simulated time keeps up with wall time.
    result = loop->Run(
        [&](const LoopTick& tick) {
          const bool more = session.Period(tick.wake_ns, tick.missed_before);
          if (more && options.lockstep && !link->AwaitAnswer(lockstep_timeout)) {
            ++lockstep_timeouts;
          }
          return more;
        },
        run);
  });
  rt.join();
  links.Stop();
  loop_done.store(true);
  writer.join();
  try {
    csv.Close();
  } catch (const std::exception& e) {
    if (output_error.empty()) output_error = e.what();
  }
  if (recorder) {
    try {
      recorder->Finish(StopName(session.stop()), session.state().step_index);
    } catch (const std::exception& e) {
      if (output_error.empty()) output_error = std::string("--record: ") + e.what();
    }
  }

  for (const std::string& w : grant.warnings) fmt::print(stderr, "warning: {}\n", w);
  if (!throttling_warning.empty()) fmt::print(stderr, "warning: {}\n", throttling_warning);
  if (rt_request.enforce && !grant.complete()) return kExitError;

  JsonWriter json;
  json.BeginObject();
  json.Key("config").String(options.config_path);
  // A run whose outputs failed is not ok, even if the loop was.
  // Controller messages refused (not decodable, out of range, a current not finite or beyond
  // its bound) make a run not ok: the loop went on with the last good currents, not with what
  // the controller sent, so this is not the run that was asked for. They do not stop it (the
  // watchdog catches a controller that sends nothing usable); the "lcm" block counts each kind.
  const std::uint64_t rejected = links.RejectedControllerMessages();
  const HilCounters& counters = session.counters();
  std::optional<double> first_power_event_s;
  if (counters.first_power_event_step >= 0) {
    first_power_event_s =
        static_cast<double>(counters.first_power_event_step) * model->params.simulation.step_s;
  }
  HilRunFacts facts;
  facts.first_power_event_s = first_power_event_s;
  facts.levitated_fraction = counters.levitated_fraction;
  facts.external = options.controller != "internal";
  const HilLinks::Answers answers =
      links.ControllerAnswers(counters.currents_received, counters.sensor_samples_sent);
  facts.answers = answers.answers;
  // A scenario's swallowed currents were answers all the same (LCM counts them on arrival).
  if (scenario_link && !links.lcm) facts.answers += scenario_link->messages_swallowed();
  facts.samples_sent = answers.samples;
  const std::string check_failures = checks.Failures(facts, options.check_bounds);
  // The scenario's expectations, judged on the run's own stop (a scenario may expect the
  // watchdog to stop it).
  std::vector<ScenarioOutcome::Check> expectations;
  if (outcome)
    expectations = outcome->Evaluate(scenario->expect, StopName(session.stop()), session);
  const bool expectations_pass =
      std::all_of(expectations.begin(), expectations.end(), [](const auto& c) { return c.pass; });
  std::string status = StopName(session.stop());
  if (session.stop() == HilStop::kDuration || !expectations.empty()) {
    if (!output_error.empty()) {
      status = "output_error";
    } else if (rejected > 0) {
      status = "controller_messages_rejected";
    } else if (!check_failures.empty()) {
      status = "check_failed";
    } else if (!expectations_pass) {
      status = "expectation_failed";
    } else if (!expectations.empty()) {
      status = "ok";  // the scenario expected how the run stopped
    }
  }
  json.Key("status").String(status);
  // The checks every HIL run is held to (tools/cli/hil_checks.hpp).
  json.Key("checks").BeginObject();
  json.Key("passed").Bool(check_failures.empty());
  json.Key("failures").String(check_failures);
  json.Key("first_contact_s");
  if (checks.first_contact_s()) {
    json.Number(*checks.first_contact_s());
  } else {
    json.Null();
  }
  json.Key("first_power_event_s");
  if (first_power_event_s) {
    json.Number(*first_power_event_s);
  } else {
    json.Null();
  }
  // The figures the checks judged, beside their bounds (null: no bound).
  const auto bound = [&json](const char* key, double value) {
    json.Key(key);
    if (std::isfinite(value)) {
      json.Number(value);
    } else {
      json.Null();
    }
  };
  json.Key("levitated_fraction").Number(facts.levitated_fraction);
  json.Key("answers").Integer(facts.answers);
  json.Key("samples_sent").Integer(facts.samples_sent);
  json.Key("periods_without_currents").Integer(counters.periods_without_currents);
  json.Key("peak_tdb_load_N").Number(checks.peak_tdb_load_N());
  json.Key("max_penetration_m").Number(checks.max_penetration_m());
  json.Key("max_race_speed_rad_s").Number(checks.max_race_speed_rad_s());
  json.Key("bounds").BeginObject();
  bound("levitated_fraction", options.check_bounds.levitated_fraction);
  bound("answered_fraction", facts.external ? options.check_bounds.answered_fraction
                                            : std::numeric_limits<double>::infinity());
  bound("max_tdb_load_N", options.check_bounds.max_tdb_load_N);
  bound("max_penetration_m", options.check_bounds.max_penetration_m);
  bound("max_race_speed_rad_s", options.check_bounds.max_race_speed_rad_s);
  json.EndObject();
  json.EndObject();
  json.Key("output_error");
  if (output_error.empty()) {
    json.Null();
  } else {
    json.String(output_error);
  }
  json.Key("controller").String(options.controller);
  json.Key("clock").String(options.virtual_clock ? "virtual" : "monotonic");
  json.Key("sched_fifo").Bool(grant.fifo);
  json.Key("periods").Integer(result.periods);
  json.Key("overruns").Integer(result.overruns);
  json.Key("missed_periods").Integer(result.missed_periods);
  json.Key("catch_up_periods").Integer(session.counters().catch_up_periods);
  json.Key("spin_us").Number(static_cast<double>(spin_ns) / 1e3);
  json.Key("lockstep").Bool(options.lockstep);
  json.Key("lockstep_timeouts").Integer(lockstep_timeouts);
  json.Key("currents_received").Integer(session.counters().currents_received);
  json.Key("sensor_samples_sent").Integer(session.counters().sensor_samples_sent);
  json.Key("power_events").Integer(session.counters().power_events);
  json.Key("watchdog_silence_episodes").Integer(session.watchdog().silence_episodes());
  json.Key("observations_dropped").Integer(session.counters().observations_dropped);
  links.WriteSummary(json);  // CAN and GPIO counters, when used
  if (recorder) {
    json.Key("record").BeginObject();
    json.Key("path").String(options.record_path);
    json.Key("events_written").Integer(recorder->events_written());
    json.Key("events_dropped").Integer(recorder->dropped());
    json.EndObject();
  }
  WriteStats(json, "wakeup_lateness", loop->lateness());
  WriteStats(json, "compute_per_period", loop->compute());
  if (scenario != nullptr) {
    json.Key("scenario").BeginObject();
    json.Key("path").String(options.scenario_path);
    json.Key("description").String(scenario->description);
    json.Key("relevitated").Bool(outcome->relevitated());
    json.Key("currents_swallowed").Integer(scenario_link->messages_swallowed());
    json.Key("pass").Bool(expectations_pass);
    json.Key("checks");
    WriteScenarioChecks(json, expectations);
    json.EndObject();
  }
  WriteTdbSummaries(json, summary);
  json.EndObject();
  if (!options.junit_path.empty()) {
    // One test case per check a CI job cares about: the run's own, then each expectation.
    std::vector<JunitCase> cases;
    cases.push_back({"hil", "run_completed", status != "interrupted" && status != "diverged",
                     fmt::format("the run stopped: {}", StopName(session.stop()))});
    cases.push_back({"hil", "outputs_written", output_error.empty(), output_error});
    cases.push_back({"hil", "controller_messages_accepted", rejected == 0,
                     fmt::format("{} controller messages refused", rejected)});
    cases.push_back({"hil", "checks", check_failures.empty(), check_failures});
    for (const ScenarioOutcome::Check& c : expectations) {
      cases.push_back({"hil.scenario", c.name, c.pass,
                       fmt::format("expected {}, got {}", c.expected, c.actual)});
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    try {
      WriteJunit(options.junit_path,
                 fmt::format("ambdrop hil {} ({})", options.config_path, options.controller), cases,
                 seconds);
    } catch (const std::exception& e) {
      if (output_error.empty()) output_error = std::string("--junit: ") + e.what();
    }
  }
  try {
    WriteTextFile(out_dir / "summary.json", json.str());
  } catch (const std::exception& e) {
    if (output_error.empty()) output_error = e.what();
  }
  if (!options.quiet) {
    fmt::print(
        "{}: {}, {} periods, {} overruns; lateness p50/p99/max {:.1f}/{:.1f}/{:.1f} us; "
        "compute p50/p99/max {:.1f}/{:.1f}/{:.1f} us\n",
        model->params.name, StopName(session.stop()), result.periods, result.overruns,
        static_cast<double>(loop->lateness().Quantile(0.5)) / 1e3,
        static_cast<double>(loop->lateness().Quantile(0.99)) / 1e3,
        static_cast<double>(loop->lateness().max_ns()) / 1e3,
        static_cast<double>(loop->compute().Quantile(0.5)) / 1e3,
        static_cast<double>(loop->compute().Quantile(0.99)) / 1e3,
        static_cast<double>(loop->compute().max_ns()) / 1e3);
  }
  if (!output_error.empty()) fmt::print(stderr, "error: {}\n", output_error);
  if (rejected > 0) {
    fmt::print(stderr,
               "error: {} controller messages were refused (malformed, or a current not finite "
               "or beyond its bound): see the \"lcm\" block of {}\n",
               rejected, (out_dir / "summary.json").string());
  }
  if (!check_failures.empty()) fmt::print(stderr, "error: check failed: {}\n", check_failures);
  if (!options.quiet) {
    for (const auto& c : expectations) {
      fmt::print("  {:<4} {:<28} expected {:<14} got {}\n", c.pass ? "ok" : "FAIL", c.name,
                 c.expected, c.actual);
    }
  }
  if (!expectations_pass) {
    fmt::print(stderr, "error: {}: an expected outcome did not happen\n", options.scenario_path);
  }
  if (session.stop() == HilStop::kDiverged) return kExitRunFailed;
  if (!output_error.empty() || rejected > 0) return kExitError;
  return check_failures.empty() && expectations_pass ? kExitOk : kExitExpectationFailed;
}

RegisteredCommand AddHilCommand(CLI::App& app) {
  auto options = std::make_shared<HilCommandOptions>();
  CLI::App* hil_command = app.add_subcommand(
      "hil", "Run the emulator against a controller in real time: currents in, sensors out");
  CLI::Option* hil_config =
      hil_command->add_option("CONFIG", options->config_path, "TOML config file");
  CLI::Option* hil_scenario =
      hil_command
          ->add_option("--scenario", options->scenario_path,
                       "A scenario file in place of CONFIG: its power events, faults and "
                       "expectations apply to whatever controller runs; exits 4 if one fails")
          ->type_name("FILE");
  hil_config->excludes(hil_scenario);
  hil_command
      ->add_option("--junit", options->junit_path,
                   "Write the run's checks and the scenario's expectations as JUnit XML")
      ->type_name("FILE");
  hil_command
      ->add_option("--describe", options->describe_path,
                   "Write the plant description (index order, units, rates, per AMB the static "
                   "load, ki, ks, bias and limits; the reference controller in A/m) as JSON, and "
                   "exit without running")
      ->type_name("FILE");
  hil_command->callback([hil_config, hil_scenario] {
    if (hil_config->count() == 0 && hil_scenario->count() == 0) {
      throw CLI::RequiredError("CONFIG or --scenario");
    }
  });
  hil_command->add_option("--controller", options->controller, "internal | lcm[:URL] | can:IFACE")
      ->capture_default_str();
  hil_command->add_option("--trigger", options->trigger,
                          "at:SECONDS | gpio:CHIP:LINE | can | lcm (default: the config's "
                          "[trigger] schedule)");
  hil_command
      ->add_option("--state-interval-s", options->state_interval_s,
                   "With --controller lcm: simulated time between the emulator states published "
                   "live on AMBDROP_STATE, s (power events go out on AMBDROP_POWER when they "
                   "happen; 0: no live state)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e6));
  // The checks' bounds (tools/cli/hil_checks.hpp).
  HilCheckBounds& b = options->check_bounds;
  hil_command
      ->add_option("--check-levitated-fraction", b.levitated_fraction,
                   "Before the first power event every journal stays within this fraction of its "
                   "TDB's radial clearance")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e6));
  hil_command
      ->add_option("--check-answered-fraction", b.answered_fraction,
                   "An outside controller answers at least this fraction of the sensor samples "
                   "sent (currents messages per sample; 0: no check)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  hil_command
      ->add_option("--check-max-tdb-load-N", b.max_tdb_load_N,
                   "Largest TDB normal force allowed, N (default: no bound)")
      ->check(CLI::Range(0.0, 1e12));
  hil_command
      ->add_option("--check-max-penetration-m", b.max_penetration_m,
                   "Largest journal excursion beyond its clearance allowed, m (default: no bound)")
      ->check(CLI::Range(-1.0, 1.0));
  hil_command
      ->add_option("--check-max-race-speed-rad-s", b.max_race_speed_rad_s,
                   "Largest inner-race spin speed allowed, rad/s (default: no bound)")
      ->check(CLI::Range(0.0, 1e9));
  hil_command->add_flag("--virtual-clock", options->virtual_clock,
                        "Run on simulated time, as fast as possible (offline, tests)");
  // The real-time flags override the config's [realtime] table; the callbacks note which were
  // given (an explicit --rt-priority 0 overrides a config priority too).
  hil_command
      ->add_option_function<int>(
          "--rt-priority",
          [options](int priority) {
            options->rt_priority = priority;
            options->rt_priority_given = true;
          },
          "SCHED_FIFO priority of the loop thread (0: normal scheduling; default: "
          "realtime.priority)")
      ->type_name("P")
      ->check(CLI::Range(0, 99));
  hil_command
      ->add_option_function<int>(
          "--cpu",
          [options](int cpu) {
            options->cpu = cpu;
            options->cpu_given = true;
          },
          "Pin the loop thread to this CPU (-1: any; default: realtime.cpu)")
      ->type_name("N")
      ->check(CLI::Range(-1, 1023));
  hil_command
      ->add_option("--spin-us", options->spin_us,
                   "Poll the clock for the last US microseconds before each deadline instead of "
                   "sleeping (default: realtime.spin_s); with SCHED_FIFO a spin near the period "
                   "trips the kernel's RT throttling")
      ->type_name("US")
      ->check(kFinite & CLI::Range(0.0, 10000.0));
  hil_command->add_flag(
      "--lcm-io-fifo", options->lcm_io_fifo,
      "With --controller lcm and SCHED_FIFO: run LCM's receive and publish threads, and udpm's "
      "reading thread, SCHED_FIFO one priority below the loop, off its CPU, so a busy host does "
      "not hold the controller's "
      "answers back (at 20 kHz they then fall under the kernel's RT throttling: slower)");
  hil_command->add_flag("--enforce-rt", options->enforce_rt,
                        "Fail if real-time scheduling, CPU pinning or memory locking is refused "
                        "(also realtime.enforce)");
  hil_command
      ->add_option("--watchdog-s", options->watchdog_timeout_s,
                   "Controller silence that trips the watchdog (s)")
      ->check(kFinite & CLI::Range(0.0, 1e6))
      ->capture_default_str();
  hil_command
      ->add_option("--silence", options->silence_action, "Watchdog action: hold | zero | stop")
      ->capture_default_str();
  hil_command->add_option("--out", options->out_dir, "Output directory")->capture_default_str();
  AddSetOption(hil_command, &options->overrides);
  hil_command->add_flag("--quiet,-q", options->quiet, "No summary on stdout");
  CLI::Option* lockstep =
      hil_command->add_flag("--lockstep", options->lockstep,
                            "With --virtual-clock: after each sample sent, wait for the external "
                            "controller's answer (a controller slower than real time closes the "
                            "loop sample by sample)");
  hil_command
      ->add_option("--lockstep-timeout-s", options->lockstep_timeout_s,
                   "Longest wait for an answer in --lockstep (wall time, s)")
      ->check(kFinite & CLI::Range(0.0, 1e6))
      ->capture_default_str();
  lockstep->needs(hil_command->get_option("--virtual-clock"));
  hil_command
      ->add_option("--record", options->record_path,
                   "Record the run (currents in with their receive time, power events, sensor "
                   "samples out, state) into an LCM event log for `ambdrop replay`")
      ->type_name("FILE.lcm");
  return {hil_command, [options] { return RunHilCommand(*options); }};
}

}  // namespace ambdrop
