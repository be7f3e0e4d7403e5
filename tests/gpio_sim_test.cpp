// The libgpiod adapter (GpiodInputLine, GpiodOutputLine) and GpioTrigger on the kernel's
// simulated GPIO chip (gpio-sim): the chip labelled "hil-sim" with 8 lines, line 3 named
// "estop", that tests/hw/run_in_vm.sh creates in its Debian-kernel VM:
//   bash tests/hw/run_in_vm.sh build/tests/gpio_sim_test --gtest_color=no
// The test drives an input as a wire would by writing "pull-up"/"pull-down" to the chip's
// sim_gpioN/pull attribute, and reads an output's level from sim_gpioN/value. Where no such chip
// exists (this machine's kernel has no GPIO at all) every test skips, except that the harness
// sets AMBDROP_REQUIRE_HW=1 so a missing chip in the VM is a failure, not a silent skip.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <time.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <thread>

#include "io/gpio/gpio_trigger.hpp"
#include "io/gpio/gpiod_lines.hpp"
#include "malloc_guard.hpp"

namespace ambdrop::gpio_sim_test {
namespace {

using std::chrono::milliseconds;
using ::testing::HasSubstr;

constexpr char kLabel[] = "hil-sim";
constexpr char kConfigfs[] = "/sys/kernel/config/gpio-sim/hil";
constexpr unsigned kLines = 8;
constexpr unsigned kEstop = 3;
constexpr unsigned kMirror = 5;
constexpr std::int64_t kMs = 1'000'000;
constexpr milliseconds kEventWait{1000};  // an edge normally arrives within microseconds

std::int64_t MonotonicNs() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

std::string ReadLine(const std::string& path) {
  std::ifstream file(path);
  std::string line;
  std::getline(file, line);
  return line;
}

/// Where the simulated chip lives: names from configfs (gpio-sim's dev_name and chip_name).
struct SimChip {
  std::string dev_name;   ///< "gpio-sim.0"
  std::string chip_name;  ///< "gpiochip0"
  std::string Attribute(unsigned offset, const char* name) const {
    return "/sys/devices/platform/" + dev_name + "/" + chip_name + "/sim_gpio" +
           std::to_string(offset) + "/" + name;
  }
};

/// The live "hil-sim" chip, or why there is none.
std::optional<SimChip> FindSimChip(std::string* why) {
  const std::string base = kConfigfs;
  if (ReadLine(base + "/live") != "1") {
    *why = base +
           "/live is not 1: no gpio-sim chip 'hil-sim' here (the kernel has no gpio-sim, "
           "or the chip was not created). Run inside tests/hw/run_in_vm.sh";
    return std::nullopt;
  }
  SimChip chip{ReadLine(base + "/dev_name"), ReadLine(base + "/bank0/chip_name")};
  if (ReadLine(base + "/bank0/label") != kLabel || chip.dev_name.empty() ||
      chip.chip_name.empty()) {
    *why = base + " exists but its bank0 is not a live chip labelled 'hil-sim'";
    return std::nullopt;
  }
  return chip;
}

class GpioSimTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    std::optional<SimChip> found = FindSimChip(&why);
    if (!found) {
      const char* require = std::getenv("AMBDROP_REQUIRE_HW");
      if (require != nullptr && std::string(require) == "1") {
        FAIL() << "AMBDROP_REQUIRE_HW=1 but " << why;
      }
      GTEST_SKIP() << why;
    }
    sim_ = *found;
    // Known start: every line the tests use pulled down.
    for (unsigned offset : {kEstop, 4u, kMirror, 6u}) Pull(offset, false);
  }

  /// Drives the input like a wire: gpio-sim's pull attribute.
  void Pull(unsigned offset, bool high) {
    std::ofstream file(sim_.Attribute(offset, "pull"));
    file << (high ? "pull-up" : "pull-down");
    file.flush();
    ASSERT_TRUE(file.good()) << "cannot write " << sim_.Attribute(offset, "pull");
  }
  /// The level on the line (an output's drive, else its pull): gpio-sim's value attribute.
  int SimValue(unsigned offset) const {
    const std::string text = ReadLine(sim_.Attribute(offset, "value"));
    return text == "1" ? 1 : text == "0" ? 0 : -1;
  }

  static GpioLineConfig Config(std::string chip, GpioLineId line, bool active_low = false,
                               std::string consumer = "gpio_sim_test") {
    return GpioLineConfig{.chip = std::move(chip),
                          .line = std::move(line),
                          .active_low = active_low,
                          .consumer = std::move(consumer)};
  }

  /// Reads exactly one event, waiting up to kEventWait.
  static GpioEdgeEvent ReadOne(GpioInputLine& line) {
    std::array<GpioEdgeEvent, 1> buffer{};
    std::size_t count = 0;
    const GpioStatus status = line.ReadEvents(buffer, kEventWait, &count);
    EXPECT_EQ(status, GpioStatus::kOk) << ToString(status) << ", errno " << line.last_errno();
    EXPECT_EQ(count, 1u);
    return buffer[0];
  }

  /// Polls `trigger` until it has an event or `limit` passes; the event, if any.
  static std::optional<GpioPowerEvent> AwaitPowerEvent(GpioTrigger& trigger, GpioInputLine& line,
                                                       milliseconds limit) {
    const std::int64_t give_up = line.NowNs() + limit.count() * kMs;
    GpioPowerEvent event;
    while (!trigger.PopEvent(&event)) {
      if (line.NowNs() > give_up) return std::nullopt;
      EXPECT_NE(trigger.Poll(milliseconds(50)), GpioStatus::kError);
    }
    return event;
  }

  SimChip sim_;
};

// Runs everywhere: on a machine without the chip (or without GPIO at all), opening says so.
TEST(GpiodLinesTest, AMissingChipIsAClearErrorAtSetup) {
  try {
    GpiodInputLine line(GpioLineConfig{.chip = "ambdrop-no-such-chip", .line = 0u});
    FAIL() << "opening a chip that does not exist must throw";
  } catch (const GpioError& error) {
    std::printf("message: %s\n", error.what());
    EXPECT_THAT(error.what(), HasSubstr("cannot open chip 'ambdrop-no-such-chip'"));
  }
  try {
    GpiodOutputLine line(GpioLineConfig{.chip = "", .line = "estop"}, false);
    FAIL() << "an empty chip must throw";
  } catch (const GpioError& error) {
    EXPECT_THAT(error.what(), HasSubstr("no chip given for line 'estop'"));
  }
}

TEST_F(GpioSimTest, EdgesArriveWithMonotonicKernelTimestamps) {
  GpiodInputLine input(Config(kLabel, "estop"));
  EXPECT_EQ(input.offset(), kEstop);
  EXPECT_THAT(input.description(), HasSubstr("[hil-sim] line 3 'estop'"));
  EXPECT_THAT(input.description(), HasSubstr(sim_.chip_name));
  bool value = true;
  ASSERT_EQ(input.ReadValue(&value), GpioStatus::kOk);
  EXPECT_FALSE(value);

  const std::int64_t before_rise = MonotonicNs();
  Pull(kEstop, true);
  const GpioEdgeEvent rise = ReadOne(input);
  const std::int64_t after_rise = MonotonicNs();
  EXPECT_EQ(rise.edge, GpioEdge::kRising);
  EXPECT_GE(rise.timestamp_ns, before_rise) << "timestamps are CLOCK_MONOTONIC";
  EXPECT_LE(rise.timestamp_ns, after_rise);
  EXPECT_LE(rise.timestamp_ns, input.NowNs());

  Pull(kEstop, false);
  const GpioEdgeEvent fall = ReadOne(input);
  EXPECT_EQ(fall.edge, GpioEdge::kFalling);
  EXPECT_GT(fall.timestamp_ns, rise.timestamp_ns);
  ASSERT_EQ(input.ReadValue(&value), GpioStatus::kOk);
  EXPECT_FALSE(value);

  // A pull to the level the line has makes no event.
  Pull(kEstop, false);
  std::array<GpioEdgeEvent, 4> buffer{};
  std::size_t count = 9;
  EXPECT_EQ(input.ReadEvents(buffer, milliseconds(50), &count), GpioStatus::kTimeout);
  EXPECT_EQ(count, 0u);
}

TEST_F(GpioSimTest, SeveralQueuedEdgesComeInOneRead) {
  GpiodInputLine input(Config(kLabel, kEstop));
  // uAPI v1 takes an edge's direction from the level its interrupt thread reads, so the pulls
  // are spaced for each edge to be handled before the next; nothing is read meanwhile.
  for (int i = 0; i < 6; ++i) {
    Pull(kEstop, i % 2 == 0);
    std::this_thread::sleep_for(milliseconds(20));
  }
  std::array<GpioEdgeEvent, kGpioKernelEventFifo> buffer{};
  std::size_t count = 0;
  ASSERT_EQ(input.ReadEvents(buffer, kEventWait, &count), GpioStatus::kOk);
  ASSERT_EQ(count, 6u);
  for (std::size_t i = 0; i < count; ++i) {
    EXPECT_EQ(buffer[i].edge, i % 2 == 0 ? GpioEdge::kRising : GpioEdge::kFalling) << i;
    if (i > 0) {
      EXPECT_GT(buffer[i].timestamp_ns, buffer[i - 1].timestamp_ns) << i;
    }
  }
}

TEST_F(GpioSimTest, ActiveLowInvertsValueAndEdges) {
  Pull(kEstop, true);  // a healthy PFAIL# wire idles high
  // The chip by its name this time, the line by offset.
  GpiodInputLine input(Config(sim_.chip_name, kEstop, /*active_low=*/true));
  bool value = true;
  ASSERT_EQ(input.ReadValue(&value), GpioStatus::kOk);
  EXPECT_FALSE(value);
  Pull(kEstop, false);
  EXPECT_EQ(ReadOne(input).edge, GpioEdge::kRising);
  ASSERT_EQ(input.ReadValue(&value), GpioStatus::kOk);
  EXPECT_TRUE(value);
  Pull(kEstop, true);
  EXPECT_EQ(ReadOne(input).edge, GpioEdge::kFalling);
}

TEST_F(GpioSimTest, OutputsDriveTheLineAndReadBackWhatWasSet) {
  GpiodOutputLine output(Config("/dev/" + sim_.chip_name, kMirror), /*initial_value=*/true);
  EXPECT_TRUE(output.value());
  EXPECT_EQ(SimValue(kMirror), 1);
  ASSERT_EQ(output.SetValue(false), GpioStatus::kOk);
  EXPECT_FALSE(output.value());
  EXPECT_EQ(SimValue(kMirror), 0);
  ASSERT_EQ(output.SetValue(true), GpioStatus::kOk);
  EXPECT_EQ(SimValue(kMirror), 1);

  GpiodOutputLine inverted(Config(kLabel, 6u, /*active_low=*/true), /*initial_value=*/false);
  EXPECT_EQ(SimValue(6), 1);
  ASSERT_EQ(inverted.SetValue(true), GpioStatus::kOk);
  EXPECT_EQ(SimValue(6), 0);
}

TEST_F(GpioSimTest, OpeningErrorsAreClearExceptions) {
  try {
    GpiodInputLine line(Config("no-such-chip", 0u));
    FAIL() << "an unknown chip must throw";
  } catch (const GpioError& error) {
    EXPECT_THAT(error.what(), HasSubstr("cannot open chip 'no-such-chip'"));
    EXPECT_THAT(error.what(), HasSubstr("gpiodetect"));
  }
  try {
    GpiodInputLine line(Config(kLabel, kLines));
    FAIL() << "offset 8 of 8 must throw";
  } catch (const GpioError& error) {
    EXPECT_THAT(error.what(), HasSubstr("has no line 8 (it has 8 lines, offsets 0..7)"));
  }
  try {
    GpiodInputLine line(Config(kLabel, "pfail"));
    FAIL() << "an unknown line name must throw";
  } catch (const GpioError& error) {
    EXPECT_THAT(error.what(), HasSubstr("has no line named 'pfail'"));
  }
  GpiodInputLine holder(Config(kLabel, "estop", false, "holder"));
  try {
    GpiodInputLine line(Config(kLabel, kEstop));
    FAIL() << "a busy line must throw";
  } catch (const GpioError& error) {
    EXPECT_THAT(error.what(), HasSubstr("line 3 'estop'"));
    EXPECT_THAT(error.what(), HasSubstr("busy: held by consumer 'holder'"));
  }
  try {
    GpiodOutputLine line(Config(kLabel, "estop"), false);
    FAIL() << "a busy line must throw for an output too";
  } catch (const GpioError& error) {
    EXPECT_THAT(error.what(), HasSubstr("busy"));
  }
}

TEST_F(GpioSimTest, TriggerReportsFailureAndRestoreAndMirrorsTheDrop) {
  Pull(kEstop, true);  // power on: PFAIL# high
  GpiodInputLine input(Config(kLabel, "estop"));
  GpiodOutputLine mirror(Config(kLabel, kMirror), false);
  GpioTrigger trigger(input, &mirror, {.fail_level = PowerFailLevel::kLow, .debounce_ns = 5 * kMs});
  ASSERT_EQ(trigger.Start(), GpioStatus::kOk);
  EXPECT_FALSE(trigger.power_failed());
  EXPECT_EQ(SimValue(kMirror), 0);

  const std::int64_t before_fail = MonotonicNs();
  Pull(kEstop, false);
  const std::int64_t after_fail = MonotonicNs();
  const std::optional<GpioPowerEvent> fail = AwaitPowerEvent(trigger, input, milliseconds(2000));
  ASSERT_TRUE(fail.has_value()) << "no power-fail event within 2 s";
  EXPECT_TRUE(fail->power_fail);
  EXPECT_GE(fail->timestamp_ns, before_fail);
  EXPECT_LE(fail->timestamp_ns, after_fail);
  EXPECT_EQ(fail->accepted_ns, fail->timestamp_ns + 5 * kMs);
  EXPECT_LE(fail->accepted_ns, input.NowNs());
  EXPECT_EQ(SimValue(kMirror), 1) << "the mirror line shows the drop";
  EXPECT_TRUE(mirror.value());

  Pull(kEstop, true);
  const std::optional<GpioPowerEvent> restore = AwaitPowerEvent(trigger, input, milliseconds(2000));
  ASSERT_TRUE(restore.has_value()) << "no restore event within 2 s";
  EXPECT_FALSE(restore->power_fail);
  EXPECT_GT(restore->timestamp_ns, fail->timestamp_ns);
  EXPECT_EQ(SimValue(kMirror), 0);
  EXPECT_EQ(trigger.counters().edges, 2u);
  EXPECT_EQ(trigger.counters().glitches, 0u);
  EXPECT_EQ(trigger.counters().read_errors, 0u);
}

TEST_F(GpioSimTest, TriggerIgnoresAGlitchShorterThanTheDebounce) {
  constexpr std::int64_t kDebounce = 300 * kMs;
  Pull(kEstop, true);
  GpiodInputLine input(Config(kLabel, "estop"));
  GpiodOutputLine mirror(Config(kLabel, kMirror), false);
  GpioTrigger trigger(input, &mirror,
                      {.fail_level = PowerFailLevel::kLow, .debounce_ns = kDebounce});
  ASSERT_EQ(trigger.Start(), GpioStatus::kOk);

  const std::int64_t glitch_start = MonotonicNs();
  Pull(kEstop, false);
  Pull(kEstop, true);
  const std::int64_t glitch_end = MonotonicNs();
  ASSERT_LT(glitch_end - glitch_start, kDebounce / 2)
      << "the two sysfs writes took too long for a glitch test";
  EXPECT_FALSE(AwaitPowerEvent(trigger, input, milliseconds(600)).has_value());
  // uAPI v1 reads the level in the interrupt thread to name an edge, and gpio-sim merges an
  // interrupt still pending: a pulse this short may come as a falling + rising pair (a glitch),
  // as two rising edges, or as one (repeated edges). None of them may fail the power.
  const GpioTriggerCounters& counters = trigger.counters();
  EXPECT_GE(counters.edges, 1u);
  EXPECT_LE(counters.edges, 2u);
  EXPECT_GE(counters.glitches + counters.repeated_edges, 1u);
  std::printf("glitch of %.3f ms: %llu edges, %llu glitches, %llu repeated edges\n",
              static_cast<double>(glitch_end - glitch_start) / 1e6,
              static_cast<unsigned long long>(counters.edges),
              static_cast<unsigned long long>(counters.glitches),
              static_cast<unsigned long long>(counters.repeated_edges));
  EXPECT_FALSE(trigger.power_failed());
  EXPECT_EQ(SimValue(kMirror), 0);

  // The same edge held past the debounce counts, stamped with its edge.
  const std::int64_t before_fail = MonotonicNs();
  Pull(kEstop, false);
  const std::optional<GpioPowerEvent> fail = AwaitPowerEvent(trigger, input, milliseconds(3000));
  ASSERT_TRUE(fail.has_value());
  EXPECT_TRUE(fail->power_fail);
  EXPECT_GE(fail->timestamp_ns, before_fail);
  EXPECT_EQ(fail->accepted_ns, fail->timestamp_ns + kDebounce);
  EXPECT_GE(input.NowNs(), fail->accepted_ns) << "not reported before the debounce ended";
  EXPECT_EQ(SimValue(kMirror), 1);
}

TEST_F(GpioSimTest, TheEventPathDoesNotAllocate) {
  Pull(kEstop, true);
  GpiodInputLine input(Config(kLabel, "estop"));
  GpiodOutputLine mirror(Config(kLabel, kMirror), false);
  GpioTrigger trigger(input, &mirror, {.fail_level = PowerFailLevel::kLow});
  ASSERT_EQ(trigger.Start(), GpioStatus::kOk);
  std::int64_t allocations = 0;
  int events = 0;
  for (int i = 0; i < 20; ++i) {
    Pull(kEstop, i % 2 != 0);  // the sysfs write allocates: outside the guard
    testing::MallocGuard guard;
    GpioPowerEvent event;
    bool got = trigger.PopEvent(&event);
    for (int polls = 0; !got && polls < 20; ++polls) {
      (void)trigger.Poll(milliseconds(50));
      got = trigger.PopEvent(&event);
    }
    (void)trigger.MirrorDropState(trigger.power_failed());
    allocations += guard.allocations();
    if (got) ++events;
  }
  EXPECT_EQ(allocations, 0) << "ppoll + read of the event fd, line_bulk::set_values";
  EXPECT_EQ(trigger.counters().failures, 10u);
  EXPECT_EQ(trigger.counters().restores, 10u);
  EXPECT_EQ(events, 20);
}

}  // namespace
}  // namespace ambdrop::gpio_sim_test
