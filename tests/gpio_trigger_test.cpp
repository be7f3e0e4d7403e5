// GpioDouble (the in-memory chip with gpio-sim's and libgpiod v1's semantics) and GpioTrigger
// (edges → debounced power events, drop state → mirror output), with explicit timestamps.
// tests/gpio_sim_test.cpp runs the same logic on the kernel's gpio-sim in the VM harness.
#include "io/gpio/gpio_trigger.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "io/gpio/gpio_double.hpp"
#include "malloc_guard.hpp"

namespace ambdrop::gpio_trigger_test {
namespace {

using std::chrono::milliseconds;
using std::chrono::nanoseconds;
using ::testing::HasSubstr;

constexpr unsigned kEstop = 3;   // the power-fail input, named like the VM's gpio-sim line 3
constexpr unsigned kMirror = 5;  // the drop-state output
constexpr std::int64_t kMs = 1'000'000;
constexpr nanoseconds kNoWait{0};

GpioDouble MakeChip(std::size_t fifo = kGpioKernelEventFifo) {
  return GpioDouble("gpiochip0", "hil-sim", 8, {{kEstop, "estop"}}, fifo);
}

GpioLineConfig Line(GpioLineId id, bool active_low = false, std::string consumer = "ambdrop") {
  return GpioLineConfig{.chip = "hil-sim",
                        .line = std::move(id),
                        .active_low = active_low,
                        .consumer = std::move(consumer)};
}

/// Everything queued on `line` now.
std::vector<GpioEdgeEvent> Drain(GpioInputLine& line) {
  std::vector<GpioEdgeEvent> all;
  std::array<GpioEdgeEvent, 4> batch{};
  std::size_t count = 0;
  while (line.ReadEvents(batch, kNoWait, &count) == GpioStatus::kOk) {
    all.insert(all.end(), batch.begin(), batch.begin() + static_cast<std::ptrdiff_t>(count));
  }
  return all;
}

std::vector<GpioPowerEvent> PopAll(GpioTrigger& trigger) {
  std::vector<GpioPowerEvent> all;
  GpioPowerEvent event;
  while (trigger.PopEvent(&event)) all.push_back(event);
  return all;
}

GpioPowerEvent Fail(std::int64_t t_ns, std::int64_t accepted_ns) {
  return {.power_fail = true, .timestamp_ns = t_ns, .accepted_ns = accepted_ns};
}
GpioPowerEvent Restore(std::int64_t t_ns, std::int64_t accepted_ns) {
  return {.power_fail = false, .timestamp_ns = t_ns, .accepted_ns = accepted_ns};
}

// ---------------------------------------------------------------------------------------------
// GpioDouble

TEST(GpioDoubleTest, QueuesBothEdgesWithTheirTimestamps) {
  GpioDouble chip = MakeChip();
  auto input = chip.RequestInput(Line(kEstop));
  chip.Pull(kEstop, true, 100);
  chip.Pull(kEstop, false, 250);
  chip.Pull(kEstop, true, 400);
  EXPECT_THAT(Drain(*input), ::testing::ElementsAre(GpioEdgeEvent{GpioEdge::kRising, 100},
                                                    GpioEdgeEvent{GpioEdge::kFalling, 250},
                                                    GpioEdgeEvent{GpioEdge::kRising, 400}));
  bool value = false;
  ASSERT_EQ(input->ReadValue(&value), GpioStatus::kOk);
  EXPECT_TRUE(value);
  EXPECT_EQ(input->NowNs(), 400);
  std::size_t count = 7;
  std::array<GpioEdgeEvent, 2> buffer{};
  EXPECT_EQ(input->ReadEvents(buffer, kNoWait, &count), GpioStatus::kTimeout);
  EXPECT_EQ(count, 0u);
}

TEST(GpioDoubleTest, ActiveLowInvertsTheValueAndTheEdges) {
  GpioDouble chip = MakeChip();
  chip.Pull(kEstop, true, 0);  // a healthy PFAIL# line idles high
  auto input = chip.RequestInput(Line("estop", /*active_low=*/true));
  bool value = true;
  ASSERT_EQ(input->ReadValue(&value), GpioStatus::kOk);
  EXPECT_FALSE(value);
  chip.Pull(kEstop, false, 10);  // wire falls: logical rising
  chip.Pull(kEstop, true, 20);
  EXPECT_THAT(Drain(*input), ::testing::ElementsAre(GpioEdgeEvent{GpioEdge::kRising, 10},
                                                    GpioEdgeEvent{GpioEdge::kFalling, 20}));
}

TEST(GpioDoubleTest, APullToTheSameLevelMakesNoEvent) {
  GpioDouble chip = MakeChip();
  auto input = chip.RequestInput(Line(kEstop));
  chip.Pull(kEstop, false, 10);  // lines start pulled down
  chip.Pull(kEstop, true, 20);
  chip.Pull(kEstop, true, 30);
  EXPECT_THAT(Drain(*input), ::testing::ElementsAre(GpioEdgeEvent{GpioEdge::kRising, 20}));
}

TEST(GpioDoubleTest, AFullFifoDropsTheNewestEventsLikeTheKernel) {
  GpioDouble chip = MakeChip();
  auto input = chip.RequestInput(Line(kEstop));
  for (int i = 0; i < 20; ++i) chip.Pull(kEstop, i % 2 == 0, i);
  const std::vector<GpioEdgeEvent> events = Drain(*input);
  ASSERT_EQ(events.size(), kGpioKernelEventFifo);
  EXPECT_EQ(events.front().timestamp_ns, 0);
  EXPECT_EQ(events.back().timestamp_ns, 15);
  EXPECT_EQ(chip.dropped_events(kEstop), 4u);
  bool value = true;
  ASSERT_EQ(input->ReadValue(&value), GpioStatus::kOk);
  EXPECT_FALSE(value) << "the level follows the pull even when the event is lost";
}

TEST(GpioDoubleTest, ReadEventsFillsAtMostTheBufferAndKeepsTheRest) {
  GpioDouble chip = MakeChip();
  auto input = chip.RequestInput(Line(kEstop));
  for (int i = 0; i < 5; ++i) chip.Pull(kEstop, i % 2 == 0, 10 * i);
  std::array<GpioEdgeEvent, 3> buffer{};
  std::size_t count = 0;
  ASSERT_EQ(input->ReadEvents(buffer, kNoWait, &count), GpioStatus::kOk);
  EXPECT_EQ(count, 3u);
  EXPECT_EQ(buffer[2].timestamp_ns, 20);
  ASSERT_EQ(input->ReadEvents(buffer, kNoWait, &count), GpioStatus::kOk);
  EXPECT_EQ(count, 2u);
  EXPECT_EQ(buffer[1].timestamp_ns, 40);
}

TEST(GpioDoubleTest, OutputsReadBackWhatWasSetAndTheChipSeesThePhysicalLevel) {
  GpioDouble chip = MakeChip();
  auto plain = chip.RequestOutput(Line(kMirror), /*initial_value=*/true);
  EXPECT_TRUE(plain->value());
  EXPECT_TRUE(chip.Value(kMirror));
  ASSERT_EQ(plain->SetValue(false), GpioStatus::kOk);
  EXPECT_FALSE(plain->value());
  EXPECT_FALSE(chip.Value(kMirror));
  chip.Pull(kMirror, true, 0);
  EXPECT_FALSE(chip.Value(kMirror)) << "a pull does not change what an output drives";

  auto inverted = chip.RequestOutput(Line(6u, /*active_low=*/true), /*initial_value=*/false);
  EXPECT_TRUE(chip.Value(6));
  ASSERT_EQ(inverted->SetValue(true), GpioStatus::kOk);
  EXPECT_TRUE(inverted->value());
  EXPECT_FALSE(chip.Value(6));

  plain.reset();
  EXPECT_TRUE(chip.Value(kMirror)) << "a released line goes back to its pull";
}

TEST(GpioDoubleTest, OpeningErrorsNameTheChipAndLine) {
  GpioDouble chip = MakeChip();
  try {
    chip.RequestInput(GpioLineConfig{.chip = "no-such-chip", .line = 0u});
    FAIL() << "an unknown chip must throw";
  } catch (const GpioError& error) {
    EXPECT_THAT(error.what(), HasSubstr("cannot open chip 'no-such-chip'"));
  }
  try {
    chip.RequestInput(Line(8u));
    FAIL() << "offset 8 of 8 lines must throw";
  } catch (const GpioError& error) {
    EXPECT_THAT(error.what(), HasSubstr("has no line 8 (it has 8 lines, offsets 0..7)"));
  }
  try {
    chip.RequestInput(Line("pfail"));
    FAIL() << "an unknown name must throw";
  } catch (const GpioError& error) {
    EXPECT_THAT(error.what(), HasSubstr("has no line named 'pfail'"));
  }
  auto held = chip.RequestInput(Line(kEstop, false, "emulator"));
  EXPECT_EQ(chip.consumer(kEstop), "emulator");
  try {
    chip.RequestOutput(Line("estop"), false);
    FAIL() << "a busy line must throw";
  } catch (const GpioError& error) {
    EXPECT_THAT(error.what(), HasSubstr("line 3 'estop'"));
    EXPECT_THAT(error.what(), HasSubstr("busy: held by consumer 'emulator'"));
  }
  held.reset();
  EXPECT_EQ(chip.consumer(kEstop), "");
  EXPECT_NO_THROW(chip.RequestOutput(Line("estop"), false));
  // The chip may be named by name, label or path, or left empty (the only chip).
  EXPECT_NO_THROW(chip.RequestInput(GpioLineConfig{.chip = "/dev/gpiochip0", .line = 0u}));
  EXPECT_NO_THROW(chip.RequestInput(GpioLineConfig{.chip = "gpiochip0", .line = 1u}));
  EXPECT_NO_THROW(chip.RequestInput(GpioLineConfig{.chip = "", .line = 2u}));
}

TEST(GpioDoubleTest, AWaitingReadWakesWhenAnotherThreadPulls) {
  GpioDouble chip = MakeChip();
  auto input = chip.RequestInput(Line(kEstop));
  std::thread puller([&chip] {
    std::this_thread::sleep_for(milliseconds(20));
    chip.Pull(kEstop, true, 5 * kMs);
  });
  std::array<GpioEdgeEvent, 4> buffer{};
  std::size_t count = 0;
  const auto start = std::chrono::steady_clock::now();
  const GpioStatus status = input->ReadEvents(buffer, std::chrono::seconds(10), &count);
  const auto waited = std::chrono::steady_clock::now() - start;
  puller.join();
  ASSERT_EQ(status, GpioStatus::kOk);
  EXPECT_EQ(count, 1u);
  EXPECT_EQ(buffer[0], (GpioEdgeEvent{GpioEdge::kRising, 5 * kMs}));
  EXPECT_LT(waited, std::chrono::seconds(5));
}

TEST(GpioDoubleTest, PlannedFailuresReportErrno) {
  GpioDouble chip = MakeChip();
  auto input = chip.RequestInput(Line(kEstop));
  auto output = chip.RequestOutput(Line(kMirror), false);
  chip.FailNextCall(kEstop, EIO);
  chip.FailNextCall(kMirror, ENODEV);
  std::array<GpioEdgeEvent, 1> buffer{};
  std::size_t count = 0;
  EXPECT_EQ(input->ReadEvents(buffer, kNoWait, &count), GpioStatus::kError);
  EXPECT_EQ(input->last_errno(), EIO);
  EXPECT_EQ(output->SetValue(true), GpioStatus::kError);
  EXPECT_EQ(output->last_errno(), ENODEV);
  EXPECT_FALSE(output->value()) << "a failed set leaves the old value";
  EXPECT_EQ(output->SetValue(true), GpioStatus::kOk);
}

// ---------------------------------------------------------------------------------------------
// GpioTrigger

/// A chip with the power-fail input and the mirror output requested, and a trigger over them.
struct Rig {
  explicit Rig(GpioTriggerConfig config, bool idle_high = true, bool line_active_low = false,
               std::size_t fifo = kGpioKernelEventFifo)
      : chip(MakeChip(fifo)) {
    chip.Pull(kEstop, idle_high, 0);
    input = chip.RequestInput(Line(kEstop, line_active_low));
    mirror = chip.RequestOutput(Line(kMirror), false);
    trigger.emplace(*input, mirror.get(), config);
    EXPECT_EQ(trigger->Start(), GpioStatus::kOk);
  }
  /// The trigger polls without waiting at `now_ns` on the chip's clock.
  GpioStatus PollAt(std::int64_t now_ns) {
    chip.SetNowNs(now_ns);
    return trigger->Poll(kNoWait);
  }

  GpioDouble chip;
  std::unique_ptr<GpioInputLine> input;
  std::unique_ptr<GpioOutputLine> mirror;
  std::optional<GpioTrigger> trigger;
};

TEST(GpioTriggerTest, ActiveLowLineFailsOnTheFallingEdgeAndRestoresOnTheRisingOne) {
  Rig rig({.fail_level = PowerFailLevel::kLow});
  EXPECT_TRUE(PopAll(*rig.trigger).empty()) << "a high PFAIL# line at start means power is on";
  EXPECT_FALSE(rig.chip.Value(kMirror));

  rig.chip.Pull(kEstop, false, 1000);
  ASSERT_EQ(rig.PollAt(1500), GpioStatus::kOk);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Fail(1000, 1000)));
  EXPECT_TRUE(rig.trigger->power_failed());
  EXPECT_TRUE(rig.chip.Value(kMirror)) << "the mirror shows the drop";

  rig.chip.Pull(kEstop, true, 9000);
  ASSERT_EQ(rig.PollAt(9000), GpioStatus::kOk);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Restore(9000, 9000)));
  EXPECT_FALSE(rig.trigger->power_failed());
  EXPECT_FALSE(rig.chip.Value(kMirror));
  EXPECT_EQ(rig.trigger->counters().failures, 1u);
  EXPECT_EQ(rig.trigger->counters().restores, 1u);
  EXPECT_EQ(rig.trigger->counters().edges, 2u);
  EXPECT_EQ(rig.PollAt(9500), GpioStatus::kTimeout);
}

TEST(GpioTriggerTest, ActiveHighLineFailsOnTheRisingEdge) {
  Rig rig({.fail_level = PowerFailLevel::kHigh}, /*idle_high=*/false);
  rig.chip.Pull(kEstop, true, 200);
  ASSERT_EQ(rig.PollAt(200), GpioStatus::kOk);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Fail(200, 200)));
  rig.chip.Pull(kEstop, false, 700);
  ASSERT_EQ(rig.PollAt(700), GpioStatus::kOk);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Restore(700, 700)));
}

TEST(GpioTriggerTest, ALineRequestedActiveLowIsAnActiveHighFailLevel) {
  // The same active-low wire as the first test, inverted by the request instead.
  Rig rig({.fail_level = PowerFailLevel::kHigh}, /*idle_high=*/true, /*line_active_low=*/true);
  EXPECT_TRUE(PopAll(*rig.trigger).empty());
  rig.chip.Pull(kEstop, false, 300);
  ASSERT_EQ(rig.PollAt(300), GpioStatus::kOk);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Fail(300, 300)));
}

TEST(GpioTriggerTest, AGlitchShorterThanTheDebounceIsIgnored) {
  Rig rig({.fail_level = PowerFailLevel::kLow, .debounce_ns = 2 * kMs});
  rig.chip.Pull(kEstop, false, 10 * kMs);
  ASSERT_EQ(rig.PollAt(10 * kMs + 500'000), GpioStatus::kOk);
  EXPECT_TRUE(rig.trigger->change_pending());
  EXPECT_EQ(rig.trigger->pending_accept_ns(), 12 * kMs);
  rig.chip.Pull(kEstop, true, 11 * kMs + 999'999);  // back 1 ns before the debounce ends
  ASSERT_EQ(rig.PollAt(20 * kMs), GpioStatus::kOk);
  EXPECT_TRUE(PopAll(*rig.trigger).empty());
  EXPECT_FALSE(rig.trigger->power_failed());
  EXPECT_FALSE(rig.trigger->change_pending());
  EXPECT_FALSE(rig.chip.Value(kMirror));
  EXPECT_EQ(rig.trigger->counters().glitches, 1u);
  EXPECT_EQ(rig.trigger->counters().edges, 2u);
}

TEST(GpioTriggerTest, AChangeThatHoldsForTheDebounceIsStampedWithItsEdge) {
  Rig rig({.fail_level = PowerFailLevel::kLow, .debounce_ns = 2 * kMs});
  rig.chip.Pull(kEstop, false, 10 * kMs);
  ASSERT_EQ(rig.PollAt(11 * kMs), GpioStatus::kOk);
  EXPECT_TRUE(PopAll(*rig.trigger).empty()) << "not yet held for 2 ms";
  EXPECT_FALSE(rig.chip.Value(kMirror));
  EXPECT_EQ(rig.PollAt(12 * kMs - 1), GpioStatus::kTimeout);
  EXPECT_TRUE(PopAll(*rig.trigger).empty());
  EXPECT_EQ(rig.PollAt(12 * kMs), GpioStatus::kTimeout);  // held exactly 2 ms: accepted
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Fail(10 * kMs, 12 * kMs)));
  EXPECT_TRUE(rig.chip.Value(kMirror));

  // A restore is debounced the same way, and a glitch back to "failed" is ignored.
  rig.chip.Pull(kEstop, true, 30 * kMs);
  rig.chip.Pull(kEstop, false, 30 * kMs + 100);
  rig.chip.Pull(kEstop, true, 30 * kMs + 200);
  ASSERT_EQ(rig.PollAt(31 * kMs), GpioStatus::kOk);
  EXPECT_EQ(rig.trigger->counters().glitches, 1u);
  EXPECT_EQ(rig.trigger->pending_accept_ns(), 32 * kMs + 200) << "the bounce restarts the wait";
  ASSERT_EQ(rig.PollAt(40 * kMs), GpioStatus::kTimeout);
  EXPECT_THAT(PopAll(*rig.trigger),
              ::testing::ElementsAre(Restore(30 * kMs + 200, 32 * kMs + 200)));
  EXPECT_FALSE(rig.chip.Value(kMirror));
}

TEST(GpioTriggerTest, AnEdgeAfterTheDebounceFirstAcceptsThePendingChange) {
  // Fail at 1 ms, restore at 5 ms, both read in one poll at 6 ms: the failure held 4 ms > 2 ms.
  Rig rig({.fail_level = PowerFailLevel::kLow, .debounce_ns = 2 * kMs});
  rig.chip.Pull(kEstop, false, 1 * kMs);
  rig.chip.Pull(kEstop, true, 5 * kMs);
  ASSERT_EQ(rig.PollAt(6 * kMs), GpioStatus::kOk);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Fail(1 * kMs, 3 * kMs)));
  ASSERT_EQ(rig.PollAt(7 * kMs), GpioStatus::kTimeout);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Restore(5 * kMs, 7 * kMs)));
  EXPECT_EQ(rig.trigger->counters().glitches, 0u);
}

TEST(GpioTriggerTest, WithoutHonouredRestoresTheFirstFailureLatches) {
  Rig rig({.fail_level = PowerFailLevel::kLow, .debounce_ns = 1 * kMs, .honour_restore = false});
  rig.chip.Pull(kEstop, false, 1 * kMs);
  rig.chip.Pull(kEstop, true, 5 * kMs);
  rig.chip.Pull(kEstop, false, 9 * kMs);
  ASSERT_EQ(rig.PollAt(20 * kMs), GpioStatus::kOk);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Fail(1 * kMs, 2 * kMs)));
  EXPECT_TRUE(rig.trigger->power_failed());
  EXPECT_TRUE(rig.chip.Value(kMirror));
  EXPECT_EQ(rig.trigger->counters().restores_ignored, 1u);
  EXPECT_EQ(rig.trigger->counters().failures, 1u);
  EXPECT_FALSE(rig.trigger->stable_level());

  // Start again: the line is low, so power has failed from the start.
  ASSERT_EQ(rig.trigger->Start(), GpioStatus::kOk);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Fail(20 * kMs, 20 * kMs)));
}

TEST(GpioTriggerTest, PowerAlreadyFailedAtStartIsReportedAtOnce) {
  Rig rig({.fail_level = PowerFailLevel::kLow, .debounce_ns = 5 * kMs}, /*idle_high=*/false);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Fail(0, 0)));
  EXPECT_TRUE(rig.chip.Value(kMirror));
  rig.chip.Pull(kEstop, true, 1 * kMs);
  ASSERT_EQ(rig.PollAt(6 * kMs), GpioStatus::kOk);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Restore(1 * kMs, 6 * kMs)));
}

TEST(GpioTriggerTest, TheMirrorIsWrittenOnlyWhenTheDropStateChanges) {
  Rig rig({.fail_level = PowerFailLevel::kLow, .mirror_follows_trigger = false});
  rig.chip.Pull(kEstop, false, 10);
  ASSERT_EQ(rig.PollAt(10), GpioStatus::kOk);
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Fail(10, 10)));
  EXPECT_FALSE(rig.chip.Value(kMirror)) << "not following: the emulator says when it dropped";

  ASSERT_EQ(rig.trigger->MirrorDropState(true), GpioStatus::kOk);
  EXPECT_TRUE(rig.chip.Value(kMirror));
  EXPECT_TRUE(rig.mirror->value());
  // An unchanged state does not touch the line: a planned failure stays unused.
  rig.chip.FailNextCall(kMirror, EIO);
  EXPECT_EQ(rig.trigger->MirrorDropState(true), GpioStatus::kOk);
  EXPECT_EQ(rig.trigger->MirrorDropState(false), GpioStatus::kError);
  EXPECT_EQ(rig.trigger->counters().mirror_errors, 1u);
  EXPECT_TRUE(rig.chip.Value(kMirror));
  EXPECT_EQ(rig.trigger->MirrorDropState(false), GpioStatus::kOk);
  EXPECT_FALSE(rig.chip.Value(kMirror));
}

TEST(GpioTriggerTest, TheMirrorMayBeActiveLow) {
  GpioDouble chip = MakeChip();
  chip.Pull(kEstop, true, 0);
  auto input = chip.RequestInput(Line(kEstop));
  auto mirror = chip.RequestOutput(Line(kMirror, /*active_low=*/true), /*initial_value=*/false);
  GpioTrigger trigger(*input, mirror.get(), {.fail_level = PowerFailLevel::kLow});
  ASSERT_EQ(trigger.Start(), GpioStatus::kOk);
  EXPECT_TRUE(chip.Value(kMirror)) << "not dropped: an active-low mirror idles high";
  chip.Pull(kEstop, false, 100);
  ASSERT_EQ(trigger.Poll(kNoWait), GpioStatus::kOk);
  EXPECT_TRUE(trigger.power_failed());
  EXPECT_FALSE(chip.Value(kMirror));
}

TEST(GpioTriggerTest, WorksWithoutAMirror) {
  GpioDouble chip = MakeChip();
  chip.Pull(kEstop, true, 0);
  auto input = chip.RequestInput(Line(kEstop));
  GpioTrigger trigger(*input, nullptr, {.fail_level = PowerFailLevel::kLow});
  ASSERT_EQ(trigger.Start(), GpioStatus::kOk);
  EXPECT_EQ(trigger.MirrorDropState(true), GpioStatus::kOk);
  chip.Pull(kEstop, false, 100);
  ASSERT_EQ(trigger.Poll(kNoWait), GpioStatus::kOk);
  EXPECT_TRUE(trigger.power_failed());
}

TEST(GpioTriggerTest, ALostOppositeEdgeRestartsThePendingChange) {
  GpioDouble chip = MakeChip();
  chip.Pull(kEstop, true, 0);
  auto input = chip.RequestInput(Line(kEstop));
  GpioTrigger trigger(*input, nullptr,
                      {.fail_level = PowerFailLevel::kLow, .debounce_ns = 10 * kMs});
  ASSERT_EQ(trigger.Start(), GpioStatus::kOk);
  // Two falling edges in a row: the rising one between them was lost.
  trigger.OnEdge({GpioEdge::kFalling, 1 * kMs});
  trigger.OnEdge({GpioEdge::kFalling, 8 * kMs});
  EXPECT_EQ(trigger.counters().repeated_edges, 1u);
  EXPECT_EQ(trigger.counters().glitches, 1u);
  trigger.AdvanceTo(12 * kMs);
  EXPECT_FALSE(trigger.power_failed()) << "the line was high somewhere in 1..8 ms";
  trigger.AdvanceTo(18 * kMs);
  EXPECT_THAT(PopAll(trigger), ::testing::ElementsAre(Fail(8 * kMs, 18 * kMs)));
  // With nothing pending a repeated edge changes nothing.
  trigger.OnEdge({GpioEdge::kFalling, 30 * kMs});
  EXPECT_EQ(trigger.counters().repeated_edges, 2u);
  EXPECT_FALSE(trigger.change_pending());
}

TEST(GpioTriggerTest, EdgesBeyondOneReadBatchAreAllConsumedInOnePoll) {
  Rig rig({.fail_level = PowerFailLevel::kLow}, true, false, /*fifo=*/64);
  for (int i = 1; i <= 40; ++i) rig.chip.Pull(kEstop, i % 2 == 0, i * 1000);
  ASSERT_EQ(rig.PollAt(50'000), GpioStatus::kOk);
  EXPECT_EQ(rig.trigger->counters().edges, 40u);
  EXPECT_EQ(rig.trigger->counters().failures, 20u);
  EXPECT_EQ(rig.trigger->counters().restores, 20u);
  // 40 events, 16 kept: the newest, ending with the last restore.
  EXPECT_EQ(rig.trigger->counters().events_overwritten, 24u);
  const std::vector<GpioPowerEvent> events = PopAll(*rig.trigger);
  ASSERT_EQ(events.size(), GpioTrigger::kEventCapacity);
  EXPECT_EQ(events.back(), Restore(40'000, 40'000));
}

TEST(GpioTriggerTest, ReadErrorsAreCountedAndReported) {
  Rig rig({.fail_level = PowerFailLevel::kLow});
  rig.chip.FailNextCall(kEstop, EIO);
  EXPECT_EQ(rig.PollAt(10), GpioStatus::kError);
  EXPECT_EQ(rig.trigger->counters().read_errors, 1u);
  EXPECT_EQ(rig.input->last_errno(), EIO);

  // A failed ReadValue at Start assumes power is on.
  rig.chip.Pull(kEstop, false, 20);
  rig.chip.FailNextCall(kEstop, EIO);
  EXPECT_EQ(rig.trigger->Start(), GpioStatus::kError);
  EXPECT_FALSE(rig.trigger->power_failed());
  EXPECT_EQ(rig.trigger->counters().read_errors, 1u);
}

TEST(GpioTriggerTest, PollDoesNotWaitPastAPendingAcceptance) {
  Rig rig({.fail_level = PowerFailLevel::kLow, .debounce_ns = 1 * kMs});
  rig.chip.Pull(kEstop, false, 1 * kMs);
  ASSERT_EQ(rig.PollAt(1 * kMs), GpioStatus::kOk);
  ASSERT_TRUE(rig.trigger->change_pending());
  rig.chip.SetNowNs(5 * kMs);  // the chip's clock is already past the acceptance
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(rig.trigger->Poll(std::chrono::seconds(10)), GpioStatus::kTimeout);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  EXPECT_THAT(PopAll(*rig.trigger), ::testing::ElementsAre(Fail(1 * kMs, 2 * kMs)));
}

TEST(GpioTriggerTest, EventsAreHandledWithoutHeapAllocation) {
  Rig rig({.fail_level = PowerFailLevel::kLow, .debounce_ns = 100});
  GpioPowerEvent event;
  std::int64_t pops = 0;
  testing::MallocGuard guard;
  for (std::int64_t i = 1; i <= 5000; ++i) {
    rig.chip.Pull(kEstop, i % 2 == 0, i * 1000);
    if (i % 7 == 0) rig.chip.Pull(kEstop, i % 2 != 0, i * 1000 + 50);  // a glitch now and then
    rig.chip.SetNowNs(i * 1000 + 500);
    (void)rig.trigger->Poll(kNoWait);
    (void)rig.trigger->MirrorDropState(rig.trigger->power_failed());
    while (rig.trigger->PopEvent(&event)) ++pops;
  }
  EXPECT_EQ(guard.allocations(), 0);
  // Every 7th change reverts after 50 ns (< 100 ns): no event, and the next pull, back to the
  // level the line already has, makes none either.
  constexpr std::int64_t kGlitches = 5000 / 7;
  EXPECT_EQ(pops, 5000 - 2 * kGlitches);
  EXPECT_EQ(rig.trigger->counters().glitches, static_cast<std::uint64_t>(kGlitches));
}

}  // namespace
}  // namespace ambdrop::gpio_trigger_test
