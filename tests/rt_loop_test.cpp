// The real-time loop: clocks, timing statistics, the periodic loop and real-time setup.
// Deterministic checks run on the VirtualClock; on the MonotonicClock only loose statistics,
// since this VM pauses for milliseconds and no hard deadline can be asserted.
#include <gtest/gtest.h>
#include <linux/capability.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "controller_if/loop/periodic_loop.hpp"
#include "controller_if/loop/rt_clock.hpp"
#include "controller_if/loop/rt_system.hpp"
#include "controller_if/loop/timing_stats.hpp"
#include "malloc_guard.hpp"

// Sanitizer builds compile the guard's malloc hooks out (AMBDROP_NO_MALLOC_HOOKS): their runtimes
// own malloc. The allocation checks are skipped there rather than passing vacuously.
#ifdef AMBDROP_NO_MALLOC_HOOKS
#define AMBDROP_SKIP_WITHOUT_MALLOC_HOOKS() GTEST_SKIP() << "no malloc hooks in sanitizer builds"
#else
#define AMBDROP_SKIP_WITHOUT_MALLOC_HOOKS() (void)0
#endif

namespace ambdrop::rt_loop_test {
namespace {

// ASan and TSan intercept mlockall and make it a no-op that returns 0 (locking their shadow
// memory would be absurd), so /proc shows nothing locked in those builds. GCC says so by
// __SANITIZE_*__, clang (14) only by __has_feature.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define AMBDROP_MLOCKALL_INTERCEPTED
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define AMBDROP_MLOCKALL_INTERCEPTED
#endif
#endif
#ifdef AMBDROP_MLOCKALL_INTERCEPTED
constexpr bool kMlockallIsReal = false;
#else
constexpr bool kMlockallIsReal = true;
#endif

constexpr std::int64_t kMs = 1'000'000;

// ---------------------------------------------------------------------------------------------
// Clocks

TEST(VirtualClock, SleepJumpsForwardAndNeverBack) {
  VirtualClock clock(1000);
  EXPECT_EQ(clock.Now(), 1000);
  clock.SleepUntil(5000);
  EXPECT_EQ(clock.Now(), 5000);
  clock.SleepUntil(3000);  // a passed deadline returns at once, time stays
  EXPECT_EQ(clock.Now(), 5000);
  clock.Advance(250);
  EXPECT_EQ(clock.Now(), 5250);
  clock.Advance(-100);  // ignored
  EXPECT_EQ(clock.Now(), 5250);
  EXPECT_EQ(clock.sleeps(), 2);
}

TEST(VirtualClock, LatenessHookDelaysWakeUp) {
  VirtualClock clock;
  std::vector<std::int64_t> seen;
  clock.SetLatenessHook([&](std::int64_t deadline) {
    seen.push_back(deadline);
    return deadline == 200 ? 37 : -5;  // negative lateness is ignored
  });
  clock.SleepUntil(100);
  EXPECT_EQ(clock.Now(), 100);
  clock.SleepUntil(200);
  EXPECT_EQ(clock.Now(), 237);
  EXPECT_EQ(seen, (std::vector<std::int64_t>{100, 200}));
}

TEST(MonotonicClock, NeverWakesBeforeTheDeadline) {
  MonotonicClock clock;
  std::int64_t previous = clock.Now();
  for (int i = 0; i < 20; ++i) {
    const std::int64_t deadline = clock.Now() + 500'000;  // 0.5 ms
    clock.SleepUntil(deadline);
    const std::int64_t now = clock.Now();
    EXPECT_GE(now, deadline);
    EXPECT_GE(now, previous);
    previous = now;
  }
  // A deadline in the past (even a negative one) returns without sleeping.
  clock.SleepUntil(clock.Now() - kMs);
  clock.SleepUntil(-5);
}

TEST(MonotonicClock, SpinningClockWakesOnTimeButNeverEarly) {
  MonotonicClock clock(300'000);  // poll for the last 0.3 ms
  EXPECT_EQ(clock.spin_ns(), 300'000);
  EXPECT_EQ(MonotonicClock(-5).spin_ns(), 0);
  PeriodicLoop loop(&clock, kMs);
  const LoopResult r = loop.Run([](const LoopTick&) {}, LoopRunOptions{.max_periods = 200});
  EXPECT_EQ(r.periods, 200);
  EXPECT_EQ(loop.lateness().clamped_negative(), 0);  // never before the deadline
  // Loose: polling usually wakes within microseconds, but the VM may pause at any time.
  EXPECT_LT(loop.lateness().Quantile(0.5), 5 * kMs);
}

extern "C" void NoteSignal(int) {}

TEST(MonotonicClock, SleepResumesAfterSignals) {
  // A handler without SA_RESTART makes clock_nanosleep return EINTR; the sleep must resume and
  // still end no earlier than its deadline.
  struct sigaction action {};
  action.sa_handler = NoteSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  struct sigaction previous {};
  ASSERT_EQ(sigaction(SIGUSR1, &action, &previous), 0);

  MonotonicClock clock;
  const std::int64_t deadline = clock.Now() + 200 * kMs;
  std::atomic<bool> started{false};
  std::atomic<std::int64_t> woke{0};
  std::thread sleeper([&] {
    started = true;
    clock.SleepUntil(deadline);
    woke = clock.Now();
  });
  while (!started) std::this_thread::yield();
  for (int i = 0; i < 5; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    pthread_kill(sleeper.native_handle(), SIGUSR1);
  }
  sleeper.join();
  sigaction(SIGUSR1, &previous, nullptr);
  EXPECT_GE(woke.load(), deadline);
}

// ---------------------------------------------------------------------------------------------
// TimingStats

TEST(TimingStats, BucketsTileTheInt64RangeWithBoundedWidth) {
  EXPECT_EQ(TimingStats::BucketLowerBound(0), 0);
  for (int i = 0; i < TimingStats::kBucketCount; ++i) {
    const std::int64_t lower = TimingStats::BucketLowerBound(i);
    const std::int64_t upper = TimingStats::BucketUpperBound(i);
    ASSERT_LE(lower, upper) << i;
    EXPECT_EQ(TimingStats::BucketIndex(lower), i);
    EXPECT_EQ(TimingStats::BucketIndex(upper), i);
    if (i + 1 < TimingStats::kBucketCount) {
      EXPECT_EQ(upper + 1, TimingStats::BucketLowerBound(i + 1)) << i;
    }
    // Width at most 1/16 of the lower edge: the quantile resolution the header promises.
    if (i >= TimingStats::kSubBuckets) {
      EXPECT_LE(upper - lower + 1, lower / 16) << i;
    }
  }
  EXPECT_EQ(TimingStats::BucketUpperBound(TimingStats::kBucketCount - 1),
            std::numeric_limits<std::int64_t>::max());
  for (std::int64_t v = 0; v < 16; ++v) EXPECT_EQ(TimingStats::BucketIndex(v), v);
}

TEST(TimingStats, EmptyAndConstant) {
  TimingStats stats;
  EXPECT_EQ(stats.Quantile(0.5), 0);
  EXPECT_EQ(stats.Summarize().count, 0);
  for (int i = 0; i < 1000; ++i) stats.Record(12'345);
  const TimingSummary s = stats.Summarize();
  // Clamping to [min, max] makes a constant exact although its bucket is ~700 ns wide.
  EXPECT_EQ(s.p50_ns, 12'345);
  EXPECT_EQ(s.p999_ns, 12'345);
  EXPECT_EQ(s.min_ns, 12'345);
  EXPECT_EQ(s.max_ns, 12'345);
  EXPECT_DOUBLE_EQ(s.mean_ns, 12'345.0);
}

TEST(TimingStats, SmallValuesAreExact) {
  TimingStats stats;
  for (int v = 0; v < 10; ++v) stats.Record(v);  // 0..9: nearest rank of q is ceil(10 q) - 1
  EXPECT_EQ(stats.Quantile(0.0), 0);
  EXPECT_EQ(stats.Quantile(0.1), 0);
  EXPECT_EQ(stats.Quantile(0.5), 4);
  EXPECT_EQ(stats.Quantile(0.51), 5);
  EXPECT_EQ(stats.Quantile(0.99), 9);
  EXPECT_EQ(stats.Quantile(1.0), 9);
}

TEST(TimingStats, NegativeValuesAreClampedAndCounted) {
  TimingStats stats;
  stats.Record(-40);
  stats.Record(10);
  EXPECT_EQ(stats.clamped_negative(), 1);
  EXPECT_EQ(stats.min_ns(), 0);
  EXPECT_EQ(stats.Quantile(0.5), 0);
}

// Exact nearest-rank quantile of a sorted sample.
std::int64_t ExactQuantile(const std::vector<std::int64_t>& sorted, double q) {
  const auto n = static_cast<std::int64_t>(sorted.size());
  // Integer ppm, as TimingStats does, so the reference itself does not misround.
  const std::int64_t q_ppm = std::llround(q * 1e6);
  const std::int64_t rank = std::max<std::int64_t>(1, (n * q_ppm + 999'999) / 1'000'000);
  return sorted[rank - 1];
}

void ExpectQuantilesWithinABucket(const std::vector<std::int64_t>& values) {
  TimingStats stats;
  for (std::int64_t v : values) stats.Record(v);
  std::vector<std::int64_t> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  for (double q : {0.0, 0.01, 0.25, 0.5, 0.9, 0.99, 0.999, 0.9999, 1.0}) {
    const std::int64_t exact = ExactQuantile(sorted, q);
    const std::int64_t got = stats.Quantile(q);
    EXPECT_EQ(TimingStats::BucketIndex(got), TimingStats::BucketIndex(exact))
        << "q=" << q << " exact=" << exact << " got=" << got;
    EXPECT_GE(got, exact) << "q=" << q;  // the upper edge: never optimistic
    EXPECT_LE(static_cast<double>(got - exact), static_cast<double>(exact) / 16.0 + 1.0);
  }
  EXPECT_EQ(stats.min_ns(), sorted.front());
  EXPECT_EQ(stats.max_ns(), sorted.back());
  EXPECT_EQ(stats.count(), static_cast<std::int64_t>(values.size()));
  const double mean =
      std::accumulate(sorted.begin(), sorted.end(), 0.0) / static_cast<double>(sorted.size());
  EXPECT_NEAR(stats.mean_ns(), mean, 1e-9 * mean);
}

TEST(TimingStats, UniformOneToHundredThousand) {
  std::vector<std::int64_t> values(100'000);
  std::iota(values.begin(), values.end(), 1);
  std::shuffle(values.begin(), values.end(), std::mt19937_64(7));
  ExpectQuantilesWithinABucket(values);
  // And the headline numbers by hand: p50 = 50 000, p99 = 99 000, p99.9 = 99 900.
  TimingStats stats;
  for (std::int64_t v : values) stats.Record(v);
  EXPECT_EQ(TimingStats::BucketIndex(stats.Quantile(0.5)), TimingStats::BucketIndex(50'000));
  EXPECT_EQ(TimingStats::BucketIndex(stats.Quantile(0.99)), TimingStats::BucketIndex(99'000));
  EXPECT_EQ(TimingStats::BucketIndex(stats.Quantile(0.999)), TimingStats::BucketIndex(99'900));
  EXPECT_EQ(stats.Quantile(1.0), 100'000);
}

TEST(TimingStats, HeavyTailedLateness) {
  // A lateness-like sample: log-normal around 20 us, plus rare multi-millisecond VM pauses.
  std::mt19937_64 rng(42);
  std::lognormal_distribution<double> body(std::log(20'000.0), 0.4);
  std::uniform_real_distribution<double> pause(3e5, 6e6);
  std::bernoulli_distribution rare(0.002);
  std::vector<std::int64_t> values;
  for (int i = 0; i < 200'000; ++i) {
    values.push_back(static_cast<std::int64_t>(rare(rng) ? pause(rng) : body(rng)));
  }
  ExpectQuantilesWithinABucket(values);
}

TEST(TimingStats, HugeValues) {
  ExpectQuantilesWithinABucket({1, 1'000'000'000'000, std::numeric_limits<std::int64_t>::max(),
                                std::numeric_limits<std::int64_t>::max() / 3});
}

TEST(TimingStats, MergeEqualsRecordingEverything) {
  TimingStats a, b, all;
  for (int i = 0; i < 1000; ++i) {
    const std::int64_t v = (i * 7919) % 50'000;
    ((i % 3 == 0) ? a : b).Record(v);
    all.Record(v);
  }
  a.Merge(b);
  EXPECT_EQ(a.count(), all.count());
  EXPECT_EQ(a.min_ns(), all.min_ns());
  EXPECT_EQ(a.max_ns(), all.max_ns());
  for (int i = 0; i < TimingStats::kBucketCount; ++i) {
    ASSERT_EQ(a.bucket_count(i), all.bucket_count(i));
  }
  TimingStats empty;
  empty.Merge(all);
  EXPECT_EQ(empty.min_ns(), all.min_ns());
  a.Reset();
  EXPECT_EQ(a.count(), 0);
  EXPECT_EQ(a.max_ns(), 0);
}

TEST(TimingStats, RecordingDoesNotAllocate) {
  AMBDROP_SKIP_WITHOUT_MALLOC_HOOKS();
  TimingStats stats;
  std::int64_t allocations = 0;
  {
    testing::MallocGuard guard;
    for (std::int64_t i = 0; i < 100'000; ++i) stats.Record(i * 37);
    const TimingSummary s = stats.Summarize();
    EXPECT_GT(s.p99_ns, 0);
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0);
}

// ---------------------------------------------------------------------------------------------
// PeriodicLoop on the VirtualClock: exact

TEST(PeriodicLoop, RejectsBadArguments) {
  VirtualClock clock;
  EXPECT_THROW(PeriodicLoop(&clock, 0), std::invalid_argument);
  EXPECT_THROW(PeriodicLoop(&clock, -5), std::invalid_argument);
  EXPECT_THROW(PeriodicLoop(nullptr, 5), std::invalid_argument);
}

TEST(PeriodicLoop, ExactAbsoluteDeadlines) {
  VirtualClock clock(1'000);
  PeriodicLoop loop(&clock, 50'000);  // 20 kHz
  std::vector<LoopTick> ticks;
  ticks.reserve(100);
  const LoopResult r =
      loop.Run([&](const LoopTick& t) { ticks.push_back(t); }, LoopRunOptions{.max_periods = 100});
  EXPECT_EQ(r.stop_reason, LoopStopReason::kPeriods);
  EXPECT_EQ(r.periods, 100);
  EXPECT_EQ(r.cycles, 100);
  EXPECT_EQ(r.overruns, 0);
  EXPECT_EQ(r.missed_periods, 0);
  EXPECT_EQ(r.first_deadline_ns, 51'000);  // one period after the start
  ASSERT_EQ(ticks.size(), 100u);
  for (std::int64_t k = 0; k < 100; ++k) {
    EXPECT_EQ(ticks[k].index, k);
    EXPECT_EQ(ticks[k].deadline_ns, 51'000 + k * 50'000);
    EXPECT_EQ(ticks[k].wake_ns, ticks[k].deadline_ns);
    EXPECT_EQ(ticks[k].missed_before, 0);
  }
  EXPECT_EQ(clock.Now(), 51'000 + 99 * 50'000);
  EXPECT_EQ(r.end_ns, clock.Now());
  EXPECT_EQ(loop.lateness().count(), 100);
  EXPECT_EQ(loop.lateness().max_ns(), 0);
  EXPECT_EQ(loop.compute().max_ns(), 0);
}

TEST(PeriodicLoop, ExplicitFirstDeadline) {
  VirtualClock clock(0);
  PeriodicLoop loop(&clock, 10);
  std::int64_t first = -1;
  const LoopResult r = loop.Run(
      [&](const LoopTick& t) {
        if (t.index == 0) first = t.deadline_ns;
      },
      LoopRunOptions{.max_periods = 3, .first_deadline_ns = 777});
  EXPECT_EQ(first, 777);
  EXPECT_EQ(r.end_ns, 797);
}

TEST(PeriodicLoop, ComputeTimeIsRecorded) {
  VirtualClock clock;
  PeriodicLoop loop(&clock, 1'000);
  const LoopResult r = loop.Run([&](const LoopTick& t) { clock.Advance(100 + t.index); },
                                LoopRunOptions{.max_periods = 500});
  EXPECT_EQ(r.overruns, 0);
  EXPECT_EQ(loop.compute().min_ns(), 100);
  EXPECT_EQ(loop.compute().max_ns(), 599);
  EXPECT_EQ(loop.lateness().max_ns(), 0);  // finishing early never delays the next wake-up
}

TEST(PeriodicLoop, OverrunSkipsToTheNextFutureDeadline) {
  VirtualClock clock(0);
  PeriodicLoop loop(&clock, 100);
  std::vector<LoopTick> ticks;
  ticks.reserve(32);
  const LoopResult r = loop.Run(
      [&](const LoopTick& t) {
        ticks.push_back(t);
        if (t.index == 3) clock.Advance(250);  // finishes 150 after the next deadline
      },
      LoopRunOptions{.max_periods = 10});
  // Deadlines 100, 200, ... Period 3 (deadline 400) ends at 650: deadlines 500 and 600 are
  // missed, 700 is the next future one.
  EXPECT_EQ(r.overruns, 1);
  EXPECT_EQ(r.missed_periods, 2);
  EXPECT_EQ(r.periods, 10);
  EXPECT_EQ(r.cycles, 8);
  ASSERT_EQ(ticks.size(), 8u);
  const std::int64_t indices[] = {0, 1, 2, 3, 6, 7, 8, 9};
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    EXPECT_EQ(ticks[i].index, indices[i]);
    EXPECT_EQ(ticks[i].deadline_ns, 100 * (indices[i] + 1));  // still on the original grid
    EXPECT_EQ(ticks[i].wake_ns, ticks[i].deadline_ns);
  }
  EXPECT_EQ(ticks[4].missed_before, 2);
  EXPECT_EQ(ticks[5].missed_before, 0);
  EXPECT_EQ(loop.compute().max_ns(), 250);
}

TEST(PeriodicLoop, FinishingExactlyOnTheNextDeadlineIsNotAnOverrun) {
  for (std::int64_t compute : {100, 200, 201}) {
    VirtualClock clock(0);
    PeriodicLoop loop(&clock, 100);
    std::vector<LoopTick> ticks;
    ticks.reserve(8);
    const LoopResult r = loop.Run(
        [&](const LoopTick& t) {
          ticks.push_back(t);
          if (t.index == 0) clock.Advance(compute);
        },
        LoopRunOptions{.max_periods = 4});
    SCOPED_TRACE(compute);
    if (compute == 100) {  // ends on deadline 200: runs it with zero lateness
      EXPECT_EQ(r.overruns, 0);
      EXPECT_EQ(r.missed_periods, 0);
      EXPECT_EQ(ticks[1].deadline_ns, 200);
    } else if (compute == 200) {  // ends on deadline 300: 200 missed, 300 run on time
      EXPECT_EQ(r.overruns, 1);
      EXPECT_EQ(r.missed_periods, 1);
      EXPECT_EQ(ticks[1].deadline_ns, 300);
    } else {  // ends at 301: 200 and 300 missed
      EXPECT_EQ(r.overruns, 1);
      EXPECT_EQ(r.missed_periods, 2);
      EXPECT_EQ(ticks[1].deadline_ns, 400);
    }
    EXPECT_EQ(ticks[1].wake_ns, ticks[1].deadline_ns);
    EXPECT_EQ(loop.lateness().max_ns(), 0);
    EXPECT_EQ(r.periods, 4);
    EXPECT_EQ(r.cycles + r.missed_periods, 4);
  }
}

TEST(PeriodicLoop, MissedPeriodsNeverRunPastTheEnd) {
  VirtualClock clock(0);
  PeriodicLoop loop(&clock, 100);
  const LoopResult r = loop.Run(
      [&](const LoopTick& t) {
        if (t.index == 3) clock.Advance(10'000);
      },
      LoopRunOptions{.max_periods = 5});
  EXPECT_EQ(r.periods, 5);
  EXPECT_EQ(r.cycles, 4);
  EXPECT_EQ(r.missed_periods, 1);
}

TEST(PeriodicLoop, InjectedLatenessIsMeasuredAndDoesNotDrift) {
  VirtualClock clock(0);
  clock.SetLatenessHook([](std::int64_t deadline) { return (deadline / 1'000) % 7 * 10; });
  PeriodicLoop loop(&clock, 1'000);
  std::vector<LoopTick> ticks;
  ticks.reserve(1000);
  const LoopResult r =
      loop.Run([&](const LoopTick& t) { ticks.push_back(t); }, LoopRunOptions{.max_periods = 700});
  EXPECT_EQ(r.overruns, 0);
  for (std::size_t k = 0; k < ticks.size(); ++k) {
    const std::int64_t deadline = 1'000 * static_cast<std::int64_t>(k + 1);
    ASSERT_EQ(ticks[k].deadline_ns, deadline);  // no drift although every wake-up was late
    ASSERT_EQ(ticks[k].wake_ns - deadline, (deadline / 1'000) % 7 * 10);
  }
  // Lateness 0, 10, ..., 60 ns, each 100 times: small values have exact buckets.
  EXPECT_EQ(loop.lateness().min_ns(), 0);
  EXPECT_EQ(loop.lateness().max_ns(), 60);
  EXPECT_EQ(loop.lateness().Quantile(0.5), 30);
  EXPECT_DOUBLE_EQ(loop.lateness().mean_ns(), 30.0);
}

TEST(PeriodicLoop, LateWakeUpPastTheNextDeadlineIsAnOverrun) {
  // A VM pause: the wake-up itself comes 2.5 periods late, the callback is instant.
  VirtualClock clock(0);
  clock.SetLatenessHook([](std::int64_t deadline) { return deadline == 300 ? 250 : 0; });
  PeriodicLoop loop(&clock, 100);
  const LoopResult r = loop.Run([](const LoopTick&) {}, LoopRunOptions{.max_periods = 10});
  EXPECT_EQ(r.overruns, 1);
  EXPECT_EQ(r.missed_periods, 2);  // 400 and 500 (the wake at 550 ends after both)
  EXPECT_EQ(loop.lateness().max_ns(), 250);
  EXPECT_EQ(loop.compute().max_ns(), 0);
}

TEST(PeriodicLoop, StopFlagAndCallbackStop) {
  VirtualClock clock(0);
  PeriodicLoop loop(&clock, 100);
  std::atomic<bool> stop{false};
  LoopResult r = loop.Run(
      [&](const LoopTick& t) {
        if (t.index == 10) stop = true;
      },
      LoopRunOptions{.stop = &stop});
  EXPECT_EQ(r.stop_reason, LoopStopReason::kStopFlag);
  EXPECT_EQ(r.cycles, 11);  // the flag is seen before the next sleep

  r = loop.Run([&](const LoopTick& t) { return t.index < 4; }, LoopRunOptions{});
  EXPECT_EQ(r.stop_reason, LoopStopReason::kCallback);
  EXPECT_EQ(r.cycles, 5);
  EXPECT_EQ(loop.lateness().count(), 5);  // stats restart with each run

  stop = true;  // already set: no period runs at all
  r = loop.Run([](const LoopTick&) {}, LoopRunOptions{.max_periods = 5, .stop = &stop});
  EXPECT_EQ(r.cycles, 0);
  EXPECT_EQ(r.stop_reason, LoopStopReason::kStopFlag);
}

TEST(PeriodicLoop, RunDoesNotAllocate) {
  AMBDROP_SKIP_WITHOUT_MALLOC_HOOKS();
  VirtualClock clock(0);
  PeriodicLoop loop(&clock, 50'000);
  std::array<double, 8> state{};
  std::int64_t allocations = 0;
  LoopResult r;
  {
    testing::MallocGuard guard;
    r = loop.Run(
        [&](const LoopTick& t) {
          state[t.index % 8] += 1.0;
          clock.Advance(t.index % 97 == 0 ? 120'000 : 20'000);  // with some overruns
        },
        LoopRunOptions{.max_periods = 20'000});
    allocations = guard.allocations();
  }
  EXPECT_GT(r.overruns, 0);
  EXPECT_EQ(allocations, 0);
}

// ---------------------------------------------------------------------------------------------
// PeriodicLoop on the MonotonicClock: loose statistics only

TEST(PeriodicLoopRealTime, TwoThousandPeriodsAtOneKilohertz) {
  MonotonicClock clock;
  PeriodicLoop loop(&clock, kMs);
  std::int64_t work = 0;
  const LoopResult r =
      loop.Run([&](const LoopTick& t) { work += t.index; }, LoopRunOptions{.max_periods = 2000});
  EXPECT_EQ(r.periods, 2000);
  EXPECT_EQ(r.cycles + r.missed_periods, 2000);
  EXPECT_EQ(loop.lateness().count(), r.cycles);
  // The loop cannot end before its last deadline; it can end late (VM pauses), so no upper bound.
  EXPECT_GE(r.end_ns - r.first_deadline_ns, 1999 * kMs);
  EXPECT_LT(loop.lateness().Quantile(0.5), 5 * kMs);
  const TimingSummary s = loop.lateness().Summarize();
  RecordProperty("lateness_p50_ns", std::to_string(s.p50_ns));
  RecordProperty("lateness_max_ns", std::to_string(s.max_ns));
  std::printf(
      "1 kHz, normal scheduling: lateness p50 %lld ns, p99 %lld ns, max %lld ns, "
      "overruns %lld\n",
      static_cast<long long>(s.p50_ns), static_cast<long long>(s.p99_ns),
      static_cast<long long>(s.max_ns), static_cast<long long>(r.overruns));
}

TEST(PeriodicLoopRealTime, StopFromAnotherThread) {
  MonotonicClock clock;
  PeriodicLoop loop(&clock, kMs);
  std::atomic<bool> stop{false};
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    stop = true;
  });
  const LoopResult r = loop.Run([](const LoopTick&) {}, LoopRunOptions{.stop = &stop});
  stopper.join();
  EXPECT_EQ(r.stop_reason, LoopStopReason::kStopFlag);
  EXPECT_GT(r.periods, 0);
}

// ---------------------------------------------------------------------------------------------
// RequestRealtime with the double

TEST(RtSystemDouble, FullGrantInOrder) {
  RtSystemDouble system(4);
  const RtGrant grant = RequestRealtime(system, RtRequest{80, 3, true, true});
  EXPECT_TRUE(grant.complete());
  EXPECT_TRUE(grant.memory_locked);
  EXPECT_TRUE(grant.fifo);
  EXPECT_EQ(grant.priority, 80);
  EXPECT_TRUE(grant.pinned);
  EXPECT_EQ(grant.cpu, 3);
  EXPECT_TRUE(grant.timer_slack_set);
  EXPECT_TRUE(system.memory_locked());
  EXPECT_EQ(system.fifo_priority(), 80);
  EXPECT_EQ(system.cpu(), 3);
  EXPECT_EQ(system.timer_slack_ns(), 1);
  using C = RtSystemDouble::Call;
  ASSERT_EQ(system.calls().size(), 4u);
  EXPECT_EQ(system.calls()[0].call, C::kLockMemory);
  EXPECT_EQ(system.calls()[1].call, C::kSetTimerSlack);
  EXPECT_EQ(system.calls()[2].call, C::kSetCpuAffinity);
  EXPECT_EQ(system.calls()[3].call, C::kSetFifoPriority);  // last: pinned before competing
  EXPECT_EQ(system.calls()[3].argument, 80);
}

TEST(RtSystemDouble, NothingRequestedNothingCalled) {
  RtSystemDouble system;
  RtRequest request;
  request.timer_slack_ns = 0;
  const RtGrant grant = RequestRealtime(system, request);
  EXPECT_TRUE(grant.complete());
  EXPECT_FALSE(grant.fifo || grant.pinned || grant.memory_locked || grant.timer_slack_set);
  EXPECT_TRUE(system.calls().empty());
  EXPECT_EQ(system.timer_slack_ns(), 50'000);
}

TEST(RtSystemDouble, EachRefusalIsAWarningAndTheRestIsGranted) {
  using C = RtSystemDouble::Call;
  for (C failing : {C::kLockMemory, C::kSetTimerSlack, C::kSetCpuAffinity, C::kSetFifoPriority}) {
    RtSystemDouble system(2);
    system.FailWith(failing, EPERM);
    const RtGrant grant = RequestRealtime(system, RtRequest{50, 1, true, false});
    SCOPED_TRACE(static_cast<int>(failing));
    ASSERT_EQ(grant.warnings.size(), 1u);
    EXPECT_NE(grant.warnings[0].find("EPERM"), std::string::npos) << grant.warnings[0];
    EXPECT_EQ(grant.memory_locked, failing != C::kLockMemory);
    EXPECT_EQ(system.memory_locked(), failing != C::kLockMemory);
    EXPECT_EQ(grant.timer_slack_set, failing != C::kSetTimerSlack);
    EXPECT_EQ(grant.pinned, failing != C::kSetCpuAffinity);
    EXPECT_EQ(system.cpu(), failing != C::kSetCpuAffinity ? 1 : -1);
    EXPECT_EQ(grant.fifo, failing != C::kSetFifoPriority);
    EXPECT_EQ(system.fifo_priority(), failing != C::kSetFifoPriority ? 50 : 0);
    EXPECT_EQ(system.calls().size(), 4u);  // every item tried after a refusal
  }
}

TEST(RtSystemDouble, WarningsExplainTheCause) {
  RtSystemDouble system(2);
  system.FailWith(RtSystemDouble::Call::kSetFifoPriority, EPERM);
  system.FailWith(RtSystemDouble::Call::kLockMemory, ENOMEM);
  const RtGrant grant = RequestRealtime(system, RtRequest{80, -1, true, false});
  ASSERT_EQ(grant.warnings.size(), 2u);
  EXPECT_NE(grant.warnings[0].find("mlockall"), std::string::npos);
  EXPECT_NE(grant.warnings[0].find("ENOMEM"), std::string::npos);
  EXPECT_NE(grant.warnings[0].find("ulimit -l"), std::string::npos);
  EXPECT_NE(grant.warnings[1].find("SCHED_FIFO priority 80"), std::string::npos);
  EXPECT_NE(grant.warnings[1].find("CAP_SYS_NICE"), std::string::npos);
  EXPECT_NE(grant.warnings[1].find("SCHED_OTHER"), std::string::npos);
}

TEST(RtSystemDouble, EnforcedRefusalThrowsNamingEveryItem) {
  RtSystemDouble system(2);
  system.FailWith(RtSystemDouble::Call::kSetFifoPriority, EPERM);
  try {
    (void)RequestRealtime(system, RtRequest{80, 5, false, true});  // CPU 5 of 2: EINVAL
    FAIL() << "expected a throw";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("enforced"), std::string::npos) << message;
    EXPECT_NE(message.find("SCHED_FIFO priority 80 refused: EPERM"), std::string::npos) << message;
    EXPECT_NE(message.find("pinning to CPU 5 refused: EINVAL"), std::string::npos) << message;
  }
  // The same request without enforce only warns.
  EXPECT_EQ(RequestRealtime(system, RtRequest{80, 5, false, false}).warnings.size(), 2u);
  // And once the cause is gone, enforce passes.
  system.FailWith(RtSystemDouble::Call::kSetFifoPriority, 0);
  EXPECT_NO_THROW((void)RequestRealtime(system, RtRequest{80, 1, false, true}));
  EXPECT_EQ(system.fifo_priority(), 80);
}

TEST(RtSystemDouble, ChecksArgumentsLikeLinux) {
  RtSystemDouble system(2);
  EXPECT_EQ(system.SetFifoPriority(0), EINVAL);
  EXPECT_EQ(system.SetFifoPriority(100), EINVAL);
  EXPECT_EQ(system.SetCpuAffinity(-1), EINVAL);
  EXPECT_EQ(system.SetCpuAffinity(2), EINVAL);
  EXPECT_EQ(system.SetTimerSlack(0), EINVAL);
  EXPECT_EQ(system.fifo_priority(), 0);  // failed calls change nothing
  EXPECT_EQ(system.cpu(), -1);
  EXPECT_EQ(system.SetFifoPriority(99), 0);
  EXPECT_EQ(system.SetCpuAffinity(1), 0);
  EXPECT_EQ(system.LockMemory(), 0);
  EXPECT_EQ(system.UnlockMemory(), 0);
  EXPECT_FALSE(system.memory_locked());
  EXPECT_EQ(system.calls().back().call, RtSystemDouble::Call::kUnlockMemory);
  EXPECT_EQ(system.calls()[0].result, EINVAL);
}

// ---------------------------------------------------------------------------------------------
// The real system, on throw-away threads (scheduling, affinity and slack are per thread)

// Runs `body` on a new thread and joins it, so per-thread settings die with the thread.
template <typename F>
void OnThrowAwayThread(F body) {
  std::thread t(body);
  t.join();
}

int AllowedCpuCount() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return 1;
  return CPU_COUNT(&set);
}

int FirstAllowedCpu() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return 0;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (CPU_ISSET(cpu, &set)) return cpu;
  }
  return 0;
}

TEST(LinuxRtSystem, RejectsTheSameArgumentsAsTheDouble) {
  OnThrowAwayThread([] {
    LinuxRtSystem real;
    RtSystemDouble fake(CPU_SETSIZE);
    for (int priority : {-1, 0, 100}) {
      EXPECT_EQ(real.SetFifoPriority(priority), EINVAL) << priority;
      EXPECT_EQ(fake.SetFifoPriority(priority), EINVAL) << priority;
    }
    for (int cpu : {-1, CPU_SETSIZE, 1 << 20}) {
      EXPECT_EQ(real.SetCpuAffinity(cpu), EINVAL) << cpu;
      EXPECT_EQ(fake.SetCpuAffinity(cpu), EINVAL) << cpu;
    }
    EXPECT_EQ(real.SetTimerSlack(0), EINVAL);
    EXPECT_EQ(fake.SetTimerSlack(0), EINVAL);
  });
}

TEST(LinuxRtSystem, RequestRealtimeOnAThread) {
  // As root (the dev VM) everything is granted; without privileges SCHED_FIFO and mlockall are
  // refused with EPERM and the request must say so in warnings rather than fail.
  const int cpu = FirstAllowedCpu();
  OnThrowAwayThread([&] {
    LinuxRtSystem system;
    const RtGrant grant = RequestRealtime(system, RtRequest{10, cpu, true, false});

    // 1 ns as asked; recent kernels zero the slack of SCHED_FIFO threads (it never applied to
    // them), so 0 once FIFO was granted.
    EXPECT_LE(prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0), 1);
    EXPECT_TRUE(grant.timer_slack_set);
    cpu_set_t set;
    CPU_ZERO(&set);
    ASSERT_EQ(pthread_getaffinity_np(pthread_self(), sizeof(set), &set), 0);
    EXPECT_TRUE(grant.pinned);
    EXPECT_EQ(CPU_COUNT(&set), 1);
    EXPECT_TRUE(CPU_ISSET(cpu, &set));

    int policy = 0;
    sched_param param{};
    ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &param), 0);
    if (grant.fifo) {
      EXPECT_EQ(policy, SCHED_FIFO);
      EXPECT_EQ(param.sched_priority, 10);
    } else {
      std::printf("SCHED_FIFO refused here (not root?): %s\n", grant.warnings.back().c_str());
      EXPECT_EQ(policy, SCHED_OTHER);
      EXPECT_FALSE(grant.complete());
      EXPECT_NE(grant.warnings.back().find("SCHED_FIFO"), std::string::npos);
    }

    if (grant.memory_locked) {
      // /proc/self/status VmLck counts locked memory: non-zero once mlockall succeeded.
      std::ifstream status("/proc/self/status");
      std::string line;
      long locked_kb = -1;
      while (std::getline(status, line)) {
        if (line.rfind("VmLck:", 0) == 0) locked_kb = std::stol(line.substr(6));
      }
      if (kMlockallIsReal) {
        EXPECT_GT(locked_kb, 0);
      }
      EXPECT_EQ(system.UnlockMemory(), 0);  // the rest of the test process runs unlocked
    } else {
      std::printf("mlockall refused here: %s\n", grant.warnings.front().c_str());
      EXPECT_NE(grant.warnings.front().find("mlockall"), std::string::npos);
    }

    // A short real-time loop on this thread works whatever was granted.
    MonotonicClock clock;
    PeriodicLoop loop(&clock, kMs);
    const LoopResult r = loop.Run([](const LoopTick&) {}, LoopRunOptions{.max_periods = 200});
    EXPECT_EQ(r.periods, 200);
    EXPECT_LT(loop.lateness().Quantile(0.5), 5 * kMs);
  });
  // The main thread kept normal scheduling.
  int policy = 0;
  sched_param param{};
  ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &param), 0);
  EXPECT_EQ(policy, SCHED_OTHER);
  EXPECT_GE(AllowedCpuCount(), 1);
}

// Clears CAP_SYS_NICE and CAP_IPC_LOCK from the calling thread's effective capabilities
// (capabilities are per thread in Linux), so root's thread looks like an unprivileged one.
// False if the capabilities could not be read or set.
bool DropRealtimeCapabilitiesOfThisThread() {
  __user_cap_header_struct header{};
  header.version = _LINUX_CAPABILITY_VERSION_3;
  header.pid = 0;
  __user_cap_data_struct data[2]{};
  if (syscall(SYS_capget, &header, data) != 0) return false;
  for (int cap : {CAP_SYS_NICE, CAP_IPC_LOCK}) data[cap / 32].effective &= ~(1u << (cap % 32));
  return syscall(SYS_capset, &header, data) == 0;
}

TEST(LinuxRtSystem, RefusalWithoutPrivilegesIsAWarningOrWithEnforceAnError) {
  rlimit rtprio{};
  ASSERT_EQ(getrlimit(RLIMIT_RTPRIO, &rtprio), 0);
  if (rtprio.rlim_cur >= 10) GTEST_SKIP() << "RLIMIT_RTPRIO allows SCHED_FIFO without privileges";
  OnThrowAwayThread([] {
    if (!DropRealtimeCapabilitiesOfThisThread()) {
      std::printf("cannot drop capabilities here; the refusal path is covered by the double\n");
      return;
    }
    LinuxRtSystem system;
    const RtGrant grant = RequestRealtime(system, RtRequest{10, -1, true, false});
    EXPECT_FALSE(grant.fifo);
    ASSERT_FALSE(grant.warnings.empty());
    EXPECT_NE(grant.warnings.back().find("SCHED_FIFO priority 10 refused: EPERM"),
              std::string::npos)
        << grant.warnings.back();
    // Without CAP_IPC_LOCK mlockall is bounded by RLIMIT_MEMLOCK (8 MiB by default): refused
    // with ENOMEM for a process this size, unless the limit is raised.
    if (grant.memory_locked) {
      EXPECT_EQ(system.UnlockMemory(), 0);
      EXPECT_EQ(grant.warnings.size(), 1u);
    } else {
      ASSERT_EQ(grant.warnings.size(), 2u);
      EXPECT_NE(grant.warnings[0].find("mlockall"), std::string::npos) << grant.warnings[0];
    }
    int policy = -1;
    sched_param param{};
    ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &param), 0);
    EXPECT_EQ(policy, SCHED_OTHER);
    EXPECT_THROW((void)RequestRealtime(system, RtRequest{10, -1, false, true}), std::runtime_error);
  });
}

TEST(LinuxRtSystem, EnforcedImpossibleRequestThrows) {
  OnThrowAwayThread([] {
    LinuxRtSystem system;
    RtRequest request;
    request.cpu = CPU_SETSIZE;  // no such CPU anywhere
    request.enforce = true;
    try {
      (void)RequestRealtime(system, request);
      ADD_FAILURE() << "expected a throw";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("EINVAL"), std::string::npos) << e.what();
    }
  });
}

// ---------------------------------------------------------------------------------------------
// RT throttling

TEST(RtThrottling, WarnsWhenTheSpinTakesHalfTheAllowedShare) {
  const RtThrottling linux_default{950'000, 1'000'000};
  constexpr std::int64_t kPeriod = 50'000;  // 20 kHz
  EXPECT_EQ(RtThrottlingWarning(0, kPeriod, linux_default), "");
  EXPECT_EQ(RtThrottlingWarning(10'000, kPeriod, linux_default), "");  // 20 % of the period
  EXPECT_EQ(RtThrottlingWarning(23'000, kPeriod, linux_default), "");  // 46 % < 47.5 %
  const std::string w = RtThrottlingWarning(40'000, kPeriod, linux_default);
  EXPECT_NE(w.find("40.0 us of each 50.0 us"), std::string::npos) << w;
  EXPECT_NE(w.find("~50 ms every 1000 ms"), std::string::npos) << w;
  EXPECT_NE(w.find("sched_rt_runtime_us = 950000"), std::string::npos) << w;
  // Throttling off (-1): no risk whatever the spin.
  EXPECT_EQ(RtThrottlingWarning(49'000, kPeriod, RtThrottling{-1, 1'000'000}), "");
  // A tighter budget warns earlier.
  EXPECT_NE(RtThrottlingWarning(15'000, kPeriod, RtThrottling{500'000, 1'000'000}), "");
}

TEST(RtThrottling, ReadsTheKernelSettings) {
  const std::optional<RtThrottling> t = ReadRtThrottling();
  if (!t) GTEST_SKIP() << "/proc/sys/kernel/sched_rt_* not readable here";
  EXPECT_GT(t->period_us, 0);
  EXPECT_TRUE(t->runtime_us == -1 || (t->runtime_us >= 0 && t->runtime_us <= t->period_us))
      << t->runtime_us;
}

}  // namespace
}  // namespace ambdrop::rt_loop_test
