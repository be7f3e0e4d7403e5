#include "tools/hil_command.hpp"

#include <fmt/format.h>

#include <atomic>
#include <csignal>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <thread>

#include "controller_if/hil_session.hpp"
#include "controller_if/internal_controller_link.hpp"
#include "controller_if/periodic_loop.hpp"
#include "controller_if/rt_clock.hpp"
#include "controller_if/rt_system.hpp"
#include "io/config_loader.hpp"
#include "io/json_writer.hpp"
#include "io/timeseries_csv.hpp"
#include "tools/exit_codes.hpp"
#include "tools/lcm_controller_link.hpp"
#include "tools/run_summary.hpp"
#include "tools/tdb_summary_json.hpp"

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

int RunHilCommand(const HilCommandOptions& options) {
  LoadedConfig config;
  std::optional<Model> model;
  try {
    config = LoadConfig(options.config_path, options.overrides);
    model.emplace(BuildModel(config.params));
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitConfig;
  }

  std::unique_ptr<LcmEndpoint> lcm;
  LcmControllerLink* lcm_trigger = nullptr;
  std::unique_ptr<ControllerLink> link;
  std::vector<std::unique_ptr<TriggerSource>> triggers;
  std::int64_t substeps = 0;
  try {
    substeps = ControllerSubsteps(*model);
    const double period_s = substeps * model->params.simulation.step_s;
    if (options.controller == "internal") {
      link = std::make_unique<InternalControllerLink>(*model, period_s);
    } else if (options.controller == "lcm" || options.controller.rfind("lcm:", 0) == 0) {
      LcmEndpointOptions lcm_options;
      if (options.controller.size() > 4) lcm_options.url = options.controller.substr(4);
      lcm = std::make_unique<LcmEndpoint>(lcm_options);
      lcm->Start();
      auto lcm_link = std::make_unique<LcmControllerLink>(
          lcm.get(), static_cast<int>(model->params.sensors.size()));
      lcm_trigger = lcm_link.get();
      link = std::move(lcm_link);
    } else {
      throw std::invalid_argument("--controller " + options.controller +
                                  ": expected internal or lcm[:URL] (can: see the README)");
    }
    if (options.trigger.empty()) {
      if (model->params.trigger.enabled) {
        triggers.push_back(std::make_unique<ScheduledTrigger>(
            model->params.trigger.time_s, ScheduledFailure(*model),
            model->params.trigger.restore_time_s, ScheduledRestore(*model)));
      }
    } else if (options.trigger == "lcm") {
      if (lcm_trigger == nullptr)
        throw std::invalid_argument("--trigger lcm needs --controller lcm");
    } else if (options.trigger.rfind("at:", 0) == 0) {
      const double at = std::stod(options.trigger.substr(3));
      triggers.push_back(std::make_unique<ScheduledTrigger>(at, ScheduledFailure(*model)));
    } else {
      throw std::invalid_argument("--trigger " + options.trigger +
                                  ": expected at:SECONDS or lcm (gpio and can: see the README)");
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitUsage;
  }
  HilOptions hil;
  hil.watchdog_timeout_s = options.watchdog_timeout_s;
  try {
    hil.silence_action = ParseSilenceAction(options.silence_action);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: --silence: {}\n", e.what());
    return kExitUsage;
  }

  const fs::path out_dir(options.out_dir);
  fs::create_directories(out_dir);
  WriteTextFile(out_dir / "effective_config.toml", config.effective_toml);
  TimeseriesCsvWriter csv(out_dir / "timeseries.csv", *model);
  RunSummary summary(model->params);

  std::vector<TriggerSource*> trigger_ptrs;
  for (auto& t : triggers) trigger_ptrs.push_back(t.get());
  if (lcm_trigger != nullptr) trigger_ptrs.push_back(lcm_trigger);  // LCM trigger messages
  auto outputs = std::make_unique<HilSession::OutputRing>();
  HilSession session(*model, link.get(), trigger_ptrs, hil, outputs.get());

  // The writer drains observations off the real-time thread.
  std::atomic<bool> loop_done{false};
  std::thread writer([&] {
    Observation o;
    for (;;) {
      bool any = false;
      while (outputs->TryPop(&o)) {
        summary.Add(o);
        csv.Write(o);
        any = true;
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
  std::thread rt([&] {
    try {
      if (!options.virtual_clock && (options.rt_priority > 0 || options.cpu >= 0)) {
        LinuxRtSystem system;
        grant = RequestRealtime(
            system, RtRequest{options.rt_priority, options.cpu, true, options.enforce_rt});
      }
    } catch (const std::exception& e) {
      grant.warnings.push_back(std::string("fatal: ") + e.what());
      g_stop.store(true);
    }
    MonotonicClock monotonic;
    VirtualClock virtual_clock;
    Clock* clock = options.virtual_clock ? static_cast<Clock*>(&virtual_clock) : &monotonic;
    loop.emplace(clock, std::llround(substeps * model->params.simulation.step_s * 1e9));
    session.Start(clock->Now());
    LoopRunOptions run;
    run.stop = &g_stop;
    result = loop->Run([&](const LoopTick& tick) { return session.Period(tick.wake_ns); }, run);
  });
  rt.join();
  if (lcm) lcm->Stop();
  loop_done.store(true);
  writer.join();
  csv.Close();

  for (const std::string& w : grant.warnings) fmt::print(stderr, "warning: {}\n", w);
  if (options.enforce_rt && !grant.complete()) return kExitError;

  JsonWriter json;
  json.BeginObject();
  json.Key("config").String(options.config_path);
  json.Key("status").String(StopName(session.stop()));
  json.Key("controller").String(options.controller);
  json.Key("clock").String(options.virtual_clock ? "virtual" : "monotonic");
  json.Key("sched_fifo").Bool(grant.fifo);
  json.Key("periods").Integer(result.periods);
  json.Key("overruns").Integer(result.overruns);
  json.Key("missed_periods").Integer(result.missed_periods);
  json.Key("currents_received").Integer(session.counters().currents_received);
  json.Key("sensor_samples_sent").Integer(session.counters().sensor_samples_sent);
  json.Key("power_events").Integer(session.counters().power_events);
  json.Key("watchdog_silence_episodes").Integer(session.watchdog().silence_episodes());
  json.Key("observations_dropped").Integer(session.counters().observations_dropped);
  WriteStats(json, "wakeup_lateness", loop->lateness());
  WriteStats(json, "compute_per_period", loop->compute());
  WriteTdbSummaries(json, summary);
  json.EndObject();
  WriteTextFile(out_dir / "summary.json", json.str());
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
  if (session.stop() == HilStop::kDiverged) return kExitRunFailed;
  return kExitOk;
}

}  // namespace ambdrop
