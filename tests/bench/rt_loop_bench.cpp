// Timing of the real-time loop on this machine: a PeriodicLoop on the MonotonicClock at 20 kHz
// (by default) with a synthetic compute load, under normal scheduling and under SCHED_FIFO (via
// RequestRealtime). Prints wake-up lateness and compute time p50/p99/p99.9/max and overruns per
// minute, as Markdown table rows for the README. Not a test: nothing is asserted.
//
//   build/tests/rt_loop_bench [SECONDS=10] [--rate-hz=20000] [--load-us=10] [--physics]
//                             [--priority=80] [--cpu=1] [--configs=other,slack,fifo]
//                             [--spin-us=0]
//
// --load-us: a fixed amount of arithmetic calibrated to take that long (0: none).
// --physics: instead, the seed-000 rig's physics: period / 5 us RK4 steps per period.
// --spin-us: MonotonicClock's spin: poll the clock for the last US before each deadline.
// Configs: "other" = SCHED_OTHER with the default 50 us timer slack; "slack" = SCHED_OTHER with
// 1 ns slack; "fifo" = SCHED_FIFO at --priority, pinned to --cpu, mlockall, 1 ns slack.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "controller_if/loop/periodic_loop.hpp"
#include "controller_if/loop/rt_clock.hpp"
#include "controller_if/loop/rt_system.hpp"
#include "controller_if/loop/timing_stats.hpp"
#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"
#include "test_configs.hpp"

namespace ambdrop {
namespace {

struct Options {
  double seconds = 10.0;
  double rate_hz = 20'000.0;
  double load_us = 10.0;
  double spin_us = 0.0;
  bool physics = false;
  int priority = 80;
  int cpu = 1;
  std::vector<std::string> configs = {"other", "slack", "fifo"};
};

[[noreturn]] void Usage(const char* problem) {
  std::fprintf(stderr,
               "%s\nusage: rt_loop_bench [SECONDS] [--rate-hz=HZ] [--load-us=US] [--physics] "
               "[--priority=P] [--cpu=C] [--configs=other,slack,fifo] [--spin-us=US]\n",
               problem);
  std::exit(64);
}

double ParseNumber(std::string_view text, const char* what) {
  char* end = nullptr;
  const std::string s(text);
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0') Usage((std::string("bad number for ") + what).c_str());
  return v;
}

Options Parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    const auto value = [&](std::string_view key) -> std::optional<std::string_view> {
      if (arg.substr(0, key.size()) == key) return arg.substr(key.size());
      return std::nullopt;
    };
    if (auto v = value("--rate-hz=")) {
      o.rate_hz = ParseNumber(*v, "--rate-hz");
    } else if (auto v = value("--load-us=")) {
      o.load_us = ParseNumber(*v, "--load-us");
    } else if (auto v = value("--spin-us=")) {
      o.spin_us = ParseNumber(*v, "--spin-us");
    } else if (arg == "--physics") {
      o.physics = true;
    } else if (auto v = value("--priority=")) {
      o.priority = static_cast<int>(ParseNumber(*v, "--priority"));
    } else if (auto v = value("--cpu=")) {
      o.cpu = static_cast<int>(ParseNumber(*v, "--cpu"));
    } else if (auto v = value("--configs=")) {
      o.configs.clear();
      std::string_view rest = *v;
      while (!rest.empty()) {
        const auto comma = rest.find(',');
        o.configs.emplace_back(rest.substr(0, comma));
        rest = comma == std::string_view::npos ? "" : rest.substr(comma + 1);
      }
    } else if (arg == "--help" || arg == "-h") {
      Usage("Timing of the real-time loop.");
    } else if (!arg.empty() && arg[0] != '-') {
      o.seconds = ParseNumber(arg, "SECONDS");
    } else {
      Usage(("unknown argument " + std::string(arg)).c_str());
    }
  }
  if (o.seconds <= 0 || o.rate_hz <= 0 || o.load_us < 0 || o.spin_us < 0)
    Usage("values must be positive");
  for (const std::string& c : o.configs) {
    if (c != "other" && c != "slack" && c != "fifo") Usage(("unknown config " + c).c_str());
  }
  return o;
}

// ---------------------------------------------------------------------------------------------
// Synthetic load: a dependent chain of floating-point operations, so the time per iteration is
// fixed by latency, not by how well the CPU overlaps independent work.

volatile double g_sink = 0.0;

void Work(std::int64_t iterations) noexcept {
  double x = 1.0;
  for (std::int64_t i = 0; i < iterations; ++i) x = x * 1.0000001 + 1e-9;
  g_sink = x;
}

// Iterations per microsecond: the fastest of several trials (the slower ones were preempted).
double CalibrateWork() {
  MonotonicClock clock;
  constexpr std::int64_t kTrial = 2'000'000;
  std::int64_t best_ns = INT64_MAX;
  for (int trial = 0; trial < 7; ++trial) {
    const std::int64_t t0 = clock.Now();
    Work(kTrial);
    best_ns = std::min(best_ns, clock.Now() - t0);
  }
  return static_cast<double>(kTrial) / (static_cast<double>(best_ns) / 1e3);
}

// ---------------------------------------------------------------------------------------------

struct ConfigResult {
  std::string name;
  RtGrant grant;
  LoopResult loop;
  TimingSummary lateness;
  TimingSummary compute;
};

RtRequest RequestFor(const std::string& config, const Options& o) {
  RtRequest r;
  r.timer_slack_ns = config == "other" ? 0 : 1;  // 0: leave the 50 us default
  if (config == "fifo") {
    r.priority = o.priority;
    r.cpu = o.cpu;
    r.lock_memory = true;
  }
  return r;
}

ConfigResult RunConfig(const std::string& config, const Options& o, std::int64_t work_per_period,
                       const Model* model) {
  ConfigResult out;
  out.name = config;
  // Scheduling, affinity and slack are per thread: a fresh thread per config keeps them apart.
  std::thread runner([&] {
    LinuxRtSystem system;
    out.grant = RequestRealtime(system, RequestFor(config, o));
    for (const std::string& w : out.grant.warnings)
      std::fprintf(stderr, "warning: %s\n", w.c_str());

    std::unique_ptr<Simulator> sim;
    State state;
    std::int64_t steps_per_period = 0;
    ControlInput input = ControlInput::Powered();
    if (model != nullptr) {
      sim = std::make_unique<Simulator>(*model);
      state = sim->InitialState();
      steps_per_period = std::max<std::int64_t>(
          1, std::llround(1.0 / o.rate_hz / model->params.simulation.step_s));
    }
    const State initial = state;

    MonotonicClock clock(std::llround(o.spin_us * 1e3));
    const auto period_ns = static_cast<std::int64_t>(std::llround(1e9 / o.rate_hz));
    PeriodicLoop loop(&clock, period_ns);
    LoopRunOptions run;
    run.max_periods = static_cast<std::int64_t>(o.seconds * o.rate_hz);
    out.loop = loop.Run(
        [&](const LoopTick&) noexcept {
          if (sim) {
            for (std::int64_t i = 0; i < steps_per_period; ++i) {
              if (sim->Step(&state, input) != StepStatus::kOk) state = initial;
            }
          } else {
            Work(work_per_period);
          }
        },
        run);
    out.lateness = loop.lateness().Summarize();
    out.compute = loop.compute().Summarize();
    if (out.grant.memory_locked) (void)system.UnlockMemory();
  });
  runner.join();
  return out;
}

double Us(std::int64_t ns) {
  return static_cast<double>(ns) / 1e3;
}

}  // namespace
}  // namespace ambdrop

int main(int argc, char** argv) {
  using namespace ambdrop;
  const Options o = Parse(argc, argv);

  std::unique_ptr<Model> model;
  std::int64_t work_per_period = 0;
  std::string load;
  if (o.physics) {
    model =
        std::make_unique<Model>(BuildModel(testing::LoadTestConfig("jarroux2019_industrial.toml")));
    load = "seed-000 physics, " +
           std::to_string(std::llround(1.0 / o.rate_hz / model->params.simulation.step_s)) +
           " steps/period";
  } else {
    const double per_us = CalibrateWork();
    work_per_period = static_cast<std::int64_t>(o.load_us * per_us);
    char text[96];
    std::snprintf(text, sizeof(text), "synthetic %.1f us (%lld iterations)", o.load_us,
                  static_cast<long long>(work_per_period));
    load = text;
  }
  std::printf("rt_loop_bench: %.0f Hz for %.1f s per config, load: %s, spin %.1f us, %u CPUs\n",
              o.rate_hz, o.seconds, load.c_str(), o.spin_us, std::thread::hardware_concurrency());

  std::vector<ConfigResult> results;
  for (const std::string& c : o.configs) {
    std::fprintf(stderr, "running %s ...\n", c.c_str());
    results.push_back(RunConfig(c, o, work_per_period, model.get()));
  }

  std::printf(
      "\n| scheduling | lateness p50 / p99 / p99.9 / max (us) | compute p50 / p99 / p99.9 / max "
      "(us) | overruns/min | missed periods |\n| --- | --- | --- | --- | --- |\n");
  for (const ConfigResult& r : results) {
    std::string name;
    if (r.name == "other") name = "SCHED_OTHER, 50 us slack";
    if (r.name == "slack") name = "SCHED_OTHER, 1 ns slack";
    if (r.name == "fifo") {
      name = r.grant.fifo ? "SCHED_FIFO " + std::to_string(r.grant.priority) : "FIFO refused";
      if (r.grant.pinned) name += ", CPU " + std::to_string(r.grant.cpu);
      if (r.grant.memory_locked) name += ", mlockall";
    }
    const double minutes = static_cast<double>(r.loop.end_ns - r.loop.first_deadline_ns) / 60e9;
    std::printf("| %s | %.1f / %.1f / %.1f / %.1f | %.1f / %.1f / %.1f / %.1f | %.1f | %lld |\n",
                name.c_str(), Us(r.lateness.p50_ns), Us(r.lateness.p99_ns), Us(r.lateness.p999_ns),
                Us(r.lateness.max_ns), Us(r.compute.p50_ns), Us(r.compute.p99_ns),
                Us(r.compute.p999_ns), Us(r.compute.max_ns),
                minutes > 0 ? static_cast<double>(r.loop.overruns) / minutes : 0.0,
                static_cast<long long>(r.loop.missed_periods));
  }
  std::printf(
      "\nQuantiles are histogram bucket upper edges (<= 6.25 %% above the exact value); "
      "max is exact.\n");
  return 0;
}
