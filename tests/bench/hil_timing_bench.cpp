// Timing of the HIL emulator at its controller rate (20 kHz for the seed-000 PID rig): one
// HilSession on the MonotonicClock, the seed-000 rig levitated by a controller stand-in over the
// chosen link, the power failing halfway so the touchdown impacts are in the sample. Prints one
// Markdown row of the README table (tools/bench/hil_timing_table.sh runs every configuration).
// Not a test: nothing is asserted.
//
//   build/tests/hil_timing_bench [SECONDS=10] [--link=can|lcm|internal] [--lcm-url=URL]
//       [--sched=other|fifo] [--priority=80] [--cpu=1] [--spin-us=0] [--load] [--header]
//       [--malformed-every=N]
//   build/tests/hil_timing_bench [SECONDS] --compute-only [--header]
//
// What the columns keep apart:
// - compute: the emulator's own work per period (wake-up to return: currents in, 10 RK4
//   sub-steps at 5 us, sensor emulation, sample out), what its code costs;
// - lateness: wake-up time minus deadline, what the host (kernel, hypervisor) adds;
// - overruns/min: periods whose work ended after the next deadline (both of the above);
// - round trip: controller sends currents -> the sample computed with them arrives back at the
//   controller (transport both ways + waiting for the period + compute); "next period" is the
//   share of answers applied in the period right after the sample they answer (lockstep).
// --compute-only runs the periods back to back without sleeping, the controller answered in
// between (untimed) through the CAN double: the compute figure without any scheduling effect
// except preemption.
// --malformed-every=N (CAN or LCM): after every N answers the controller stand-in also sends a
// malformed currents message (a frame of the currents id too short for its signals; a packet
// whose bytes are no amb_currents_t), so N = 10 puts 10 % of faults at the controller rate
// (issue 18 item 3). The emulator's link drops and counts each; the row and stderr say how
// many were sent and counted, beside the deadlines.
// --load: a thread pinned to the other CPU streams through 32 MB (cache and memory bandwidth
// pressure plus a busy core). --link=lcm uses udpm: run it inside a private network namespace
// (the script does), or pass --lcm-url=memq:// for the in-process bus.
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "controller_if/controller/internal_controller_link.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/periodic_loop.hpp"
#include "controller_if/loop/rt_clock.hpp"
#include "controller_if/loop/rt_system.hpp"
#include "controller_if/loop/timing_stats.hpp"
#include "hil_bench_links.hpp"
#include "io/config/config_can.hpp"
#include "io/config/config_loader.hpp"
#include "test_configs.hpp"

namespace ambdrop::bench {
namespace {

struct Options {
  double seconds = 10.0;
  std::string link = "can";
  std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0";
  std::string sched = "other";
  int priority = 80;
  int cpu = 1;
  double spin_us = 0.0;
  bool load = false;
  bool compute_only = false;
  bool header = false;
  int malformed_every = 0;
};

[[noreturn]] void Usage(const std::string& problem) {
  std::fprintf(stderr,
               "%s\nusage: hil_timing_bench [SECONDS] [--link=can|lcm|internal] [--lcm-url=URL] "
               "[--sched=other|fifo] [--priority=P] [--cpu=C] [--spin-us=US] [--load] "
               "[--compute-only] [--header] [--malformed-every=N]\n",
               problem.c_str());
  std::exit(64);
}

double ParseNumber(std::string_view text, const char* what) {
  const std::string s(text);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0') Usage(std::string("bad number for ") + what);
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
    if (auto v = value("--link=")) {
      o.link = *v;
    } else if (auto v = value("--lcm-url=")) {
      o.lcm_url = *v;
    } else if (auto v = value("--sched=")) {
      o.sched = *v;
    } else if (auto v = value("--priority=")) {
      o.priority = static_cast<int>(ParseNumber(*v, "--priority"));
    } else if (auto v = value("--cpu=")) {
      o.cpu = static_cast<int>(ParseNumber(*v, "--cpu"));
    } else if (auto v = value("--spin-us=")) {
      o.spin_us = ParseNumber(*v, "--spin-us");
    } else if (auto v = value("--malformed-every=")) {
      o.malformed_every = static_cast<int>(ParseNumber(*v, "--malformed-every"));
      if (o.malformed_every < 1) Usage("--malformed-every must be at least 1");
    } else if (arg == "--load") {
      o.load = true;
    } else if (arg == "--compute-only") {
      o.compute_only = true;
    } else if (arg == "--header") {
      o.header = true;
    } else if (arg == "--help" || arg == "-h") {
      Usage("Timing of the HIL emulator.");
    } else if (!arg.empty() && arg[0] != '-') {
      o.seconds = ParseNumber(arg, "SECONDS");
    } else {
      Usage("unknown argument " + std::string(arg));
    }
  }
  if (o.seconds <= 0 || o.spin_us < 0) Usage("values must be positive");
  if (o.link != "can" && o.link != "lcm" && o.link != "internal") Usage("unknown link " + o.link);
  if (o.sched != "other" && o.sched != "fifo") Usage("unknown scheduling " + o.sched);
  return o;
}

// ---------------------------------------------------------------------------------------------
// Load on the other CPU: streams through a buffer larger than the caches, so it competes for
// memory bandwidth and the shared cache as well as keeping its core busy.

class Load {
 public:
  explicit Load(int cpu) {
    thread_ = std::thread([this, cpu] {
      cpu_set_t set;
      CPU_ZERO(&set);
      CPU_SET(cpu, &set);
      (void)pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
      std::vector<std::uint64_t> buffer(4 << 20);  // 32 MB
      std::uint64_t x = 1;
      while (!stop_.load(std::memory_order_relaxed)) {
        for (std::size_t i = 0; i < buffer.size(); i += 8) buffer[i] = x += buffer[i] + i;
      }
      sink_ = x;
    });
  }
  ~Load() {
    stop_ = true;
    thread_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
  volatile std::uint64_t sink_ = 0;
};

// ---------------------------------------------------------------------------------------------

double Us(std::int64_t ns) {
  return static_cast<double>(ns) / 1e3;
}

std::string Quantiles(const TimingStats& s) {
  char text[96];
  std::snprintf(text, sizeof(text), "%.1f / %.1f / %.1f / %.1f", Us(s.Quantile(0.5)),
                Us(s.Quantile(0.99)), Us(s.Quantile(0.999)), Us(s.max_ns()));
  return s.count() > 0 ? text : "–";
}

struct Rig {
  Model model;
  std::int64_t substeps;
  double period_s;
  std::int64_t period_ns;
  FrameMap frame_map;
};

Rig MakeRig(double seconds) {
  // Levitated for the first half, then the drop: the impacts cost the most compute.
  const std::vector<std::string> overrides = {
      "simulation.duration_s=" + std::to_string(seconds + 1.0),
      "trigger.time_s=" + std::to_string(seconds / 2)};
  LoadedConfig config =
      LoadConfig(testing::ConfigPath("jarroux2019_industrial_pid.toml"), overrides);
  Model model = BuildModel(config.params);
  const std::int64_t substeps = ControllerSubsteps(model);
  const double period_s = static_cast<double>(substeps) * model.params.simulation.step_s;
  const CanNames names = CanNamesOf(model.params);
  CanConfig can = LoadCanConfigFromString(CanTableFor(model), "hil_timing_bench", &names);
  return Rig{std::move(model), substeps, period_s, std::llround(period_s * 1e9),
             std::move(can.frame_map)};
}

CanSocketOptions FdSocket() {
  CanSocketOptions options;
  options.fd_frames = true;  // without it an endpoint never sees FD frames, as CAN_RAW
  return options;
}

void PrintHeader() {
  std::printf(
      "| link | scheduling | other CPU | compute p50 / p99 / p99.9 / max (us) | lateness p50 / "
      "p99 / p99.9 / max (us) | overruns/min | round trip p50 / p99 / p99.9 / max (us) | next "
      "period |\n| --- | --- | --- | --- | --- | --- | --- | --- |\n");
}

// --compute-only: periods back to back; the controller stand-in answers between them, untimed.
void RunComputeOnly(const Options& o, Rig& rig) {
  VirtualCanBus bus;
  CanBusDouble emulator_end(bus, FdSocket());
  CanBusDouble controller_end(bus, FdSocket());
  const std::int64_t periods = std::llround(o.seconds / rig.period_s);
  ExchangeLog log(static_cast<std::size_t>(periods) + 8);
  BenchCanLink can_link(&emulator_end, &rig.frame_map);
  CanControllerStandIn controller(rig.model, rig.period_s, &controller_end, &log, rig.substeps);
  // The schedule's trigger, as `ambdrop hil` would use without --trigger.
  ScheduledTrigger trigger(rig.model.params.trigger.time_s, ScheduledFailure(rig.model));
  HilSession dropping(rig.model, &can_link, {&trigger}, HilOptions{});
  LinuxRtSystem system;
  (void)RequestRealtime(system, RtRequest{0, o.cpu, false, false, 1});
  TimingStats compute;
  MonotonicClock clock;
  dropping.Start(clock.Now());
  for (std::int64_t k = 0; k < periods; ++k) {
    controller.Serve(std::chrono::nanoseconds(0));
    const std::int64_t t0 = clock.Now();
    const bool go_on = dropping.Period(t0);
    compute.Record(clock.Now() - t0);
    if (!go_on) break;
  }
  std::printf("| CAN double, back to back | no sleeping, CPU %d | idle | %s | – | – | – | – |\n",
              o.cpu, Quantiles(compute).c_str());
  std::fprintf(stderr, "compute-only: %lld periods, stop %d, %lld power events\n",
               static_cast<long long>(compute.count()), static_cast<int>(dropping.stop()),
               static_cast<long long>(dropping.counters().power_events));
}

struct RoundTrips {
  TimingStats round_trip;  ///< currents sent -> their sample received
  std::int64_t next_period = 0;
  std::int64_t answered = 0;
};

RoundTrips Analyse(const ExchangeLog& log) {
  RoundTrips r;
  for (std::size_t k = 0; k < log.consumed_seq.size(); ++k) {
    const std::int64_t seq = log.consumed_seq[k];
    if (seq < 0 || static_cast<std::size_t>(seq) >= log.send_ns.size()) continue;
    if (log.recv_ns[k] < 0 || log.send_ns[static_cast<std::size_t>(seq)] < 0) continue;
    r.round_trip.Record(log.recv_ns[k] - log.send_ns[static_cast<std::size_t>(seq)]);
    ++r.answered;
    if (log.answers_sample[static_cast<std::size_t>(seq)] == static_cast<std::int64_t>(k) - 1) {
      ++r.next_period;
    }
  }
  return r;
}

void RunRealTime(const Options& o, Rig& rig) {
  const std::int64_t periods = std::llround(o.seconds / rig.period_s);
  ExchangeLog log(static_cast<std::size_t>(periods) + 64);
  const int other_cpu = o.cpu == 0 ? 1 : 0;
  std::optional<Load> load;
  if (o.load) load.emplace(other_cpu);

  // Links.
  VirtualCanBus bus;
  std::unique_ptr<CanBusDouble> emulator_end, controller_end;
  std::unique_ptr<BenchCanLink> can_link;
  std::unique_ptr<CanControllerStandIn> can_controller;
  std::unique_ptr<LcmEndpoint> endpoint;
  std::unique_ptr<lcm::LCM> controller_lcm;
  std::unique_ptr<BenchLcmLink> lcm_link;
  std::unique_ptr<LcmControllerStandIn> lcm_controller;
  std::unique_ptr<InternalControllerLink> internal_link;
  ControllerLink* inner = nullptr;
  const bool memq = o.lcm_url.rfind("memq", 0) == 0;
  if (o.link == "can") {
    emulator_end = std::make_unique<CanBusDouble>(bus, FdSocket());
    controller_end = std::make_unique<CanBusDouble>(bus, FdSocket());
    can_link = std::make_unique<BenchCanLink>(emulator_end.get(), &rig.frame_map);
    can_controller = std::make_unique<CanControllerStandIn>(
        rig.model, rig.period_s, controller_end.get(), &log, rig.substeps, o.malformed_every);
    inner = can_link.get();
  } else if (o.link == "lcm") {
    LcmEndpointOptions lcm_options;
    lcm_options.url = o.lcm_url;
    endpoint = std::make_unique<LcmEndpoint>(lcm_options);
    lcm::LCM* controller_side = &endpoint->lcm();
    if (!memq) {
      controller_lcm = std::make_unique<lcm::LCM>(o.lcm_url);
      if (!controller_lcm->good()) Usage("LCM refused " + o.lcm_url + " (no multicast route?)");
      controller_side = controller_lcm.get();
    }
    lcm_controller = std::make_unique<LcmControllerStandIn>(
        rig.model, rig.period_s, controller_side, &log, rig.substeps, o.malformed_every);
    endpoint->Start();
    lcm_link = std::make_unique<BenchLcmLink>(endpoint.get(),
                                              static_cast<int>(rig.model.params.sensors.size()));
    inner = lcm_link.get();
  } else {
    internal_link = std::make_unique<InternalControllerLink>(rig.model, rig.period_s);
    inner = internal_link.get();
  }
  TimedLink link(inner, &log, rig.substeps);
  ScheduledTrigger trigger(rig.model.params.trigger.time_s, ScheduledFailure(rig.model));
  HilSession session(rig.model, &link, {&trigger}, HilOptions{});

  // The controller stand-in runs on the other CPU, with the emulator's scheduling one priority
  // below it: the bench measures the emulator, not a starved stand-in.
  std::atomic<bool> stop{false};
  std::thread controller_thread;
  if (can_controller || controller_lcm) {
    controller_thread = std::thread([&] {
      LinuxRtSystem system;
      RtRequest request{o.sched == "fifo" ? o.priority - 1 : 0, other_cpu, false, false, 1};
      const RtGrant g = RequestRealtime(system, request);
      for (const std::string& w : g.warnings) std::fprintf(stderr, "controller: %s\n", w.c_str());
      while (!stop.load(std::memory_order_relaxed)) {
        if (can_controller) {
          can_controller->Serve(std::chrono::milliseconds(5));
        } else {
          (void)controller_lcm->handleTimeout(5);
        }
      }
    });
  }

  // The emulator's loop, set up as `ambdrop hil` does.
  RtGrant grant;
  LoopResult result;
  TimingStats lateness, compute;
  std::thread rt([&] {
    LinuxRtSystem system;
    RtRequest request{o.sched == "fifo" ? o.priority : 0, o.cpu, true, false, 1};
    grant = RequestRealtime(system, request);
    MonotonicClock clock(std::llround(o.spin_us * 1e3));
    PeriodicLoop loop(&clock, rig.period_ns);
    session.Start(clock.Now());
    LoopRunOptions run;
    run.max_periods = periods;
    result = loop.Run(
        [&](const LoopTick& tick) noexcept {
          link.SetWake(tick.wake_ns);
          return session.Period(tick.wake_ns, tick.missed_before);
        },
        run);
    lateness = loop.lateness();
    compute = loop.compute();
    if (grant.memory_locked) (void)system.UnlockMemory();
  });
  rt.join();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the last answers arrive
  stop = true;
  if (controller_thread.joinable()) controller_thread.join();
  if (endpoint) endpoint->Stop();
  load.reset();

  for (const std::string& w : grant.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  std::string link_name = o.link == "can"   ? "CAN double (FD)"
                          : o.link == "lcm" ? "LCM "
                                            : "in-process PID";
  if (o.link == "lcm") link_name += memq ? "memq" : "udpm (loopback)";
  // Faults sent by the stand-in and counted by the emulator's link.
  std::uint64_t sent = 0, counted = 0;
  if (can_controller) {
    sent = can_controller->malformed_sent();
    counted = can_link->counters().malformed;
  } else if (lcm_controller) {
    sent = lcm_controller->malformed_sent();
    const LcmEndpointCounters c = endpoint->counters();
    counted =
        c.malformed_decode + c.malformed_range + c.malformed_non_finite + c.malformed_current_bound;
  }
  if (o.malformed_every > 0) {
    link_name += ", " + std::to_string(100.0 / o.malformed_every).substr(0, 4) +
                 " % malformed: " + std::to_string(sent) + " sent, " + std::to_string(counted) +
                 " counted";
  }
  // A rotor that crashed ends the run early: the row covers fewer periods than asked.
  if (session.stop() == HilStop::kDiverged) {
    link_name += ", diverged after " + std::to_string(result.periods) + " periods";
  }
  std::string sched = "SCHED_OTHER";
  if (grant.fifo) sched = "SCHED_FIFO " + std::to_string(grant.priority);
  if (o.sched == "fifo" && !grant.fifo) sched = "FIFO refused: SCHED_OTHER";
  if (grant.pinned) sched += ", CPU " + std::to_string(grant.cpu);
  if (grant.memory_locked) sched += ", mlockall";
  if (o.spin_us > 0) sched += ", spin " + std::to_string(std::llround(o.spin_us)) + " us";
  const double minutes = static_cast<double>(result.end_ns - result.first_deadline_ns) / 60e9;
  const RoundTrips trips = Analyse(log);
  char next[32] = "–";
  if (trips.answered > 0) {
    std::snprintf(
        next, sizeof(next), "%.1f %%",
        100.0 * static_cast<double>(trips.next_period) / static_cast<double>(trips.answered));
  }
  std::printf("| %s | %s | %s | %s | %s | %.1f | %s | %s |\n", link_name.c_str(), sched.c_str(),
              o.load ? "loaded" : "idle", Quantiles(compute).c_str(), Quantiles(lateness).c_str(),
              minutes > 0 ? static_cast<double>(result.overruns) / minutes : 0.0,
              Quantiles(trips.round_trip).c_str(), next);
  std::fprintf(stderr,
               "%lld periods, %lld overruns, %lld missed (caught up %lld), %lld currents "
               "received, %lld round trips, stop %d\n",
               static_cast<long long>(result.periods), static_cast<long long>(result.overruns),
               static_cast<long long>(result.missed_periods),
               static_cast<long long>(session.counters().catch_up_periods),
               static_cast<long long>(session.counters().currents_received),
               static_cast<long long>(trips.answered), static_cast<int>(session.stop()));
}

}  // namespace
}  // namespace ambdrop::bench

int main(int argc, char** argv) {
  using namespace ambdrop::bench;
  const Options o = Parse(argc, argv);
  Rig rig = MakeRig(o.seconds);
  if (o.header) PrintHeader();
  std::fflush(stdout);
  if (o.compute_only) {
    RunComputeOnly(o, rig);
  } else {
    RunRealTime(o, rig);
  }
  return 0;
}
