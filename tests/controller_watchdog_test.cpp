// The controller watchdog: each silence action, recovery, the latched stop, counters, parsing,
// and the watchdog driving a PeriodicLoop on the VirtualClock.
#include "controller_if/boundary/controller_watchdog.hpp"

#include <gtest/gtest.h>

#include <array>
#include <stdexcept>
#include <string>

#include "controller_if/loop/periodic_loop.hpp"
#include "controller_if/loop/rt_clock.hpp"
#include "malloc_guard.hpp"

// Sanitizer builds compile the guard's malloc hooks out (AMBDROP_NO_MALLOC_HOOKS): their runtimes
// own malloc. The allocation checks are skipped there rather than passing vacuously.
#ifdef AMBDROP_NO_MALLOC_HOOKS
#define AMBDROP_SKIP_WITHOUT_MALLOC_HOOKS() GTEST_SKIP() << "no malloc hooks in sanitizer builds"
#else
#define AMBDROP_SKIP_WITHOUT_MALLOC_HOOKS() (void)0
#endif

namespace ambdrop::controller_watchdog_test {
namespace {

constexpr std::int64_t kTimeout = 1'000;  // ns

TEST(SilenceAction, ParsesTheThreeWords) {
  EXPECT_EQ(ParseSilenceAction("hold"), SilenceAction::kHold);
  EXPECT_EQ(ParseSilenceAction("zero"), SilenceAction::kZero);
  EXPECT_EQ(ParseSilenceAction("stop"), SilenceAction::kStop);
  for (SilenceAction a : {SilenceAction::kHold, SilenceAction::kZero, SilenceAction::kStop}) {
    EXPECT_EQ(ParseSilenceAction(ToString(a)), a);
  }
  EXPECT_FALSE(TryParseSilenceAction("Hold").has_value());
  EXPECT_FALSE(TryParseSilenceAction("").has_value());
  EXPECT_FALSE(TryParseSilenceAction("hold ").has_value());
}

TEST(SilenceAction, BadWordNamesValueAndAlternatives) {
  try {
    (void)ParseSilenceAction("freeze");
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("\"freeze\""), std::string::npos) << message;
    EXPECT_NE(message.find("\"hold\", \"zero\" or \"stop\""), std::string::npos) << message;
  }
}

TEST(ControllerWatchdog, RejectsNonPositiveTimeout) {
  EXPECT_THROW(ControllerWatchdog(0, SilenceAction::kHold), std::invalid_argument);
  EXPECT_THROW(ControllerWatchdog(-1, SilenceAction::kHold), std::invalid_argument);
}

TEST(ControllerWatchdog, NormalWhileFedWithinTheTimeout) {
  ControllerWatchdog dog(kTimeout, SilenceAction::kZero);
  dog.Start(0);
  for (std::int64_t t = 0; t <= 100'000; t += 500) {
    dog.Feed(t);
    EXPECT_EQ(dog.Check(t + 400), WatchdogVerdict::kNormal);
  }
  EXPECT_FALSE(dog.silent());
  EXPECT_EQ(dog.silence_episodes(), 0);
  EXPECT_EQ(dog.feeds(), 201);
  EXPECT_EQ(dog.longest_gap_ns(), 500);
}

TEST(ControllerWatchdog, TimeoutIsStrict) {
  ControllerWatchdog dog(kTimeout, SilenceAction::kHold);
  dog.Start(0);
  dog.Feed(100);
  EXPECT_EQ(dog.Check(100 + kTimeout), WatchdogVerdict::kNormal);  // exactly the timeout: fine
  EXPECT_EQ(dog.Check(101 + kTimeout), WatchdogVerdict::kHold);    // 1 ns more: silent
}

TEST(ControllerWatchdog, SilentFromTheStartIfNeverFed) {
  ControllerWatchdog dog(kTimeout, SilenceAction::kZero);
  dog.Start(5'000);
  EXPECT_EQ(dog.Check(5'000 + kTimeout), WatchdogVerdict::kNormal);
  EXPECT_EQ(dog.Check(5'001 + kTimeout), WatchdogVerdict::kZero);
  EXPECT_EQ(dog.feeds(), 0);
}

TEST(ControllerWatchdog, FirstCheckStartsItWithoutStart) {
  ControllerWatchdog dog(kTimeout, SilenceAction::kHold);
  // A monotonic clock's epoch is far from 0: without Start, the first call starts the timeout,
  // so the controller is not silent at once.
  EXPECT_EQ(dog.Check(1'000'000'000), WatchdogVerdict::kNormal);
  EXPECT_EQ(dog.Check(1'000'000'000 + 2 * kTimeout), WatchdogVerdict::kHold);
}

class EachRecoveringAction : public ::testing::TestWithParam<SilenceAction> {};

TEST_P(EachRecoveringAction, SilenceThenRecoveryThenSilenceAgain) {
  const SilenceAction action = GetParam();
  const WatchdogVerdict silent_verdict =
      action == SilenceAction::kHold ? WatchdogVerdict::kHold : WatchdogVerdict::kZero;
  ControllerWatchdog dog(kTimeout, action);
  dog.Start(0);
  dog.Feed(0);
  EXPECT_EQ(dog.Check(2'000), silent_verdict);
  EXPECT_TRUE(dog.silent());
  EXPECT_EQ(dog.Check(3'000), silent_verdict);  // still the same episode
  EXPECT_EQ(dog.silence_episodes(), 1);

  dog.Feed(3'500);  // currents again: recovered at once
  EXPECT_FALSE(dog.silent());
  EXPECT_EQ(dog.recoveries(), 1);
  EXPECT_EQ(dog.Check(3'600), WatchdogVerdict::kNormal);
  EXPECT_EQ(dog.longest_gap_ns(), 3'500);

  EXPECT_EQ(dog.Check(10'000), silent_verdict);  // a second episode
  EXPECT_EQ(dog.silence_episodes(), 2);
  dog.Feed(10'100);
  EXPECT_EQ(dog.Check(10'100), WatchdogVerdict::kNormal);
  EXPECT_EQ(dog.recoveries(), 2);
  EXPECT_EQ(dog.longest_gap_ns(), 6'600);
  EXPECT_FALSE(dog.stopped());
}

INSTANTIATE_TEST_SUITE_P(HoldAndZero, EachRecoveringAction,
                         ::testing::Values(SilenceAction::kHold, SilenceAction::kZero),
                         [](const auto& info) { return std::string(ToString(info.param)); });

TEST(ControllerWatchdog, StopIsLatched) {
  ControllerWatchdog dog(kTimeout, SilenceAction::kStop);
  dog.Start(0);
  dog.Feed(0);
  EXPECT_EQ(dog.Check(500), WatchdogVerdict::kNormal);
  EXPECT_EQ(dog.Check(1'500), WatchdogVerdict::kStop);
  EXPECT_TRUE(dog.stopped());
  dog.Feed(1'600);  // late currents do not revive a stopped run
  EXPECT_EQ(dog.Check(1'600), WatchdogVerdict::kStop);
  EXPECT_TRUE(dog.silent());
  EXPECT_EQ(dog.recoveries(), 0);
  EXPECT_EQ(dog.silence_episodes(), 1);
  EXPECT_EQ(dog.feeds(), 2);
  dog.Start(2'000);  // a new run clears it
  EXPECT_FALSE(dog.stopped());
  EXPECT_EQ(dog.Check(2'500), WatchdogVerdict::kNormal);
  EXPECT_EQ(dog.silence_episodes(), 0);
}

TEST(ControllerWatchdog, FeedAfterTimeoutWithoutCheckIsNoEpisode) {
  // Silence is decided by Check: a gap nobody checked during counts in longest_gap_ns only.
  ControllerWatchdog dog(kTimeout, SilenceAction::kHold);
  dog.Start(0);
  dog.Feed(5'000);
  EXPECT_EQ(dog.Check(5'000), WatchdogVerdict::kNormal);
  EXPECT_EQ(dog.silence_episodes(), 0);
  EXPECT_EQ(dog.longest_gap_ns(), 5'000);
}

// The loop as the HIL will run it: the emulated controller answers every period until it goes
// quiet for a while, then comes back; the loop applies the verdict to the currents.
struct Currents {
  std::array<double, 4> amps{};
};

struct LoopOutcome {
  LoopResult result;
  int normal = 0, held = 0, zeroed = 0;
  double last_applied = 0.0;
};

LoopOutcome RunWithSilence(SilenceAction action) {
  constexpr std::int64_t kPeriod = 50'000;  // 20 kHz
  VirtualClock clock(0);
  PeriodicLoop loop(&clock, kPeriod);
  ControllerWatchdog dog(5 * kPeriod, action);  // 250 us
  LoopOutcome out;
  Currents last;
  Currents applied;
  dog.Start(clock.Now());
  out.result = loop.Run(
      [&](const LoopTick& t) {
        // The controller is quiet for periods 100..199.
        if (t.index < 100 || t.index >= 200) {
          last.amps.fill(1.0 + static_cast<double>(t.index));
          dog.Feed(t.wake_ns);
        }
        switch (dog.Check(t.wake_ns)) {
          case WatchdogVerdict::kNormal:
            applied = last;
            ++out.normal;
            break;
          case WatchdogVerdict::kHold:
            ++out.held;  // applied stays as it was
            break;
          case WatchdogVerdict::kZero:
            applied.amps.fill(0.0);
            ++out.zeroed;
            break;
          case WatchdogVerdict::kStop:
            return false;
        }
        out.last_applied = applied.amps[0];
        return true;
      },
      LoopRunOptions{.max_periods = 300});
  EXPECT_EQ(dog.silence_episodes(), 1);
  return out;
}

TEST(ControllerWatchdog, DrivesTheLoopHold) {
  const LoopOutcome o = RunWithSilence(SilenceAction::kHold);
  // Silent from period 105 (gap 6 periods > 5) to 199: 95 held periods, then normal again.
  EXPECT_EQ(o.held, 95);
  EXPECT_EQ(o.normal, 205);
  EXPECT_EQ(o.last_applied, 300.0);
  EXPECT_EQ(o.result.stop_reason, LoopStopReason::kPeriods);
}

TEST(ControllerWatchdog, DrivesTheLoopZero) {
  const LoopOutcome o = RunWithSilence(SilenceAction::kZero);
  EXPECT_EQ(o.zeroed, 95);
  EXPECT_EQ(o.normal, 205);
}

TEST(ControllerWatchdog, DrivesTheLoopStop) {
  const LoopOutcome o = RunWithSilence(SilenceAction::kStop);
  EXPECT_EQ(o.result.stop_reason, LoopStopReason::kCallback);
  EXPECT_EQ(o.result.cycles, 106);  // periods 0..105, the last one returned false
  EXPECT_EQ(o.normal, 105);
}

TEST(ControllerWatchdog, CheckAndFeedDoNotAllocate) {
  AMBDROP_SKIP_WITHOUT_MALLOC_HOOKS();
  ControllerWatchdog dog(kTimeout, SilenceAction::kHold);
  int silent = 0;
  std::int64_t allocations = 0;
  {
    testing::MallocGuard guard;
    dog.Start(0);
    for (std::int64_t t = 0; t < 1'000'000; t += 100) {
      if ((t / 10'000) % 2 == 0) dog.Feed(t);
      silent += dog.Check(t) != WatchdogVerdict::kNormal;
    }
    allocations = guard.allocations();
  }
  EXPECT_GT(silent, 0);
  EXPECT_EQ(dog.silence_episodes(), 50);
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace ambdrop::controller_watchdog_test
