#pragma once
// GPIO lines behind two small interfaces: an input that reports edge events with kernel
// timestamps, and an output that can be set. GpiodInputLine/GpiodOutputLine (gpiod_lines.hpp)
// talk to the kernel through libgpiod v1; GpioDouble (gpio_double.hpp) is an in-memory chip
// with the same semantics, for tests and for runs without hardware. Opening a line may
// allocate, block and throw (GpioError); reading events and setting values do none of these and
// report through a [[nodiscard]] GpioStatus.
//
// Values are logical, as libgpiod reports them: with active_low, the value and the edge
// direction are the inverse of the physical level (a falling wire is a rising edge).
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <variant>

namespace ambdrop {

/// A line that cannot be opened: no such chip, no such line, busy, or the kernel refused the
/// request. what() names the chip and line and says what to check.
class GpioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Result of one ReadEvents, ReadValue or SetValue.
enum class GpioStatus : std::uint8_t {
  kOk,       ///< events read (at least one), value read or set
  kTimeout,  ///< ReadEvents: no event within the timeout (0 = just polled)
  kError,    ///< the kernel call failed; see last_errno()
};

/// "ok", "timeout", "error" for messages.
constexpr const char* ToString(GpioStatus status) noexcept {
  switch (status) {
    case GpioStatus::kOk:
      return "ok";
    case GpioStatus::kTimeout:
      return "timeout";
    case GpioStatus::kError:
      return "error";
  }
  return "?";
}

/// Direction of an edge of the logical value.
enum class GpioEdge : std::uint8_t {
  kRising,   ///< the logical value went 0 -> 1
  kFalling,  ///< the logical value went 1 -> 0
};

/// One edge event, as the kernel's line-event FIFO holds it.
struct GpioEdgeEvent {
  GpioEdge edge = GpioEdge::kRising;
  /// When the edge was seen, ns on the line's clock (CLOCK_MONOTONIC for the kernel since
  /// Linux 5.7; the test-driven clock for GpioDouble). See GpioInputLine::NowNs().
  std::int64_t timestamp_ns = 0;

  bool operator==(const GpioEdgeEvent&) const = default;
};

/// Which line of a chip: its offset (0-based) or its name (gpio-sim's line names, the
/// device tree's gpio-line-names).
using GpioLineId = std::variant<unsigned, std::string>;

/// "line 3" or "line 'estop'" for messages.
inline std::string ToString(const GpioLineId& line) {
  if (const auto* offset = std::get_if<unsigned>(&line)) return "line " + std::to_string(*offset);
  return "line '" + std::get<std::string>(line) + "'";
}

/// Where a line is and how to request it.
struct GpioLineConfig {
  /// The chip: a path ("/dev/gpiochip0"), a name ("gpiochip0"), a label ("hil-sim") or a
  /// number ("0"), tried in that order as libgpiod's lookup does.
  std::string chip;
  GpioLineId line = 0u;
  /// The logical value is the inverse of the physical level (for active-low wiring, e.g. an
  /// open-drain PFAIL# line).
  bool active_low = false;
  /// Who holds the line, as gpioinfo shows it (the kernel keeps up to 31 characters).
  std::string consumer = "ambdrop";
};

/// The kernel's per-line event FIFO (struct lineevent_state in gpiolib-cdev.c, uAPI v1) holds
/// 16 events; when full, new events are dropped. GpioDouble has the same capacity by default.
inline constexpr std::size_t kGpioKernelEventFifo = 16;

/// An input line requested for events on both edges. One thread uses it at a time. Neither
/// call allocates, throws or blocks longer than asked.
class GpioInputLine {
 public:
  virtual ~GpioInputLine() = default;

  /// Waits up to `timeout` (0: poll once; negative: no limit) for at least one queued edge,
  /// then moves up to events.size() queued edges, oldest first, into `events` (a buffer the
  /// caller allocated once) without waiting again. `*count` is the number written (0 unless
  /// kOk). Returns kOk, kTimeout or kError.
  [[nodiscard]] virtual GpioStatus ReadEvents(std::span<GpioEdgeEvent> events,
                                              std::chrono::nanoseconds timeout,
                                              std::size_t* count) noexcept = 0;

  /// The current logical value (true = 1). The real adapter's read allocates a little inside
  /// libgpiod's C++ bindings: call it at start-up and for diagnostics, not every cycle.
  [[nodiscard]] virtual GpioStatus ReadValue(bool* value) noexcept = 0;

  /// Now, ns, on the clock that timestamps this line's events (CLOCK_MONOTONIC for the real
  /// adapter). Debouncing compares event timestamps with it.
  virtual std::int64_t NowNs() const noexcept = 0;

  /// errno of the last failed call (0 if none); for diagnostics after kError.
  virtual int last_errno() const noexcept = 0;

 protected:
  GpioInputLine() = default;
  GpioInputLine(const GpioInputLine&) = delete;
  GpioInputLine& operator=(const GpioInputLine&) = delete;
};

/// An output line. One thread uses it at a time. SetValue does not allocate or throw.
class GpioOutputLine {
 public:
  virtual ~GpioOutputLine() = default;

  /// Drives the logical value (true = 1; the physical level is inverted when active_low).
  [[nodiscard]] virtual GpioStatus SetValue(bool value) noexcept = 0;

  /// The logical value last set (or the initial value): reading an output gives what was set.
  virtual bool value() const noexcept = 0;

  /// errno of the last failed call (0 if none); for diagnostics after kError.
  virtual int last_errno() const noexcept = 0;

 protected:
  GpioOutputLine() = default;
  GpioOutputLine(const GpioOutputLine&) = delete;
  GpioOutputLine& operator=(const GpioOutputLine&) = delete;
};

}  // namespace ambdrop
