#pragma once
// An in-memory GPIO chip with the semantics of the kernel's gpio-sim driver seen through
// libgpiod v1, for tests and for runs without hardware:
//   - a test drives an input as gpio-sim's sim_gpioN/pull attribute does (Pull), and reads what
//     a line carries as sim_gpioN/value does (Value): an output's driven level, else the pull;
//   - an input requested for events queues one event per change of level, on both edges, with
//     the timestamp the test gives (its clock never goes backwards), in a FIFO of 16 events that
//     drops new events when full (uAPI v1's lineevent FIFO); a pull to the level the line already
//     has makes no event;
//   - active_low inverts the logical value, and so the direction of edges (a falling wire is a
//     rising edge), for inputs and outputs alike;
//   - reading an output gives what was set; releasing it (destroying the line) returns the line
//     to its pull, as gpio-sim does;
//   - opening fails as libgpiod does: unknown chip, unknown line (offset or name), busy line
//     (the message names its consumer).
// Lines share the chip's state (they keep it alive). One mutex guards the chip: a test thread
// may Pull while the code under test waits in ReadEvents, which wakes at once. ReadEvents and
// SetValue do not allocate; Pull does not either.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "io/gpio/gpio_line.hpp"

namespace ambdrop {

/// An in-memory GPIO chip: the test's side of the lines that GpioDouble::RequestInput and
/// RequestOutput hand to the code under test.
class GpioDouble {
 public:
  /// A chip named `name` (e.g. "gpiochip0") labelled `label` (e.g. "hil-sim") with `num_lines`
  /// lines, every one pulled down; `line_names` gives names to some offsets (like gpio-sim's
  /// lineN/name). `event_fifo` is each input's event capacity.
  GpioDouble(std::string name, std::string label, unsigned num_lines,
             std::vector<std::pair<unsigned, std::string>> line_names = {},
             std::size_t event_fifo = kGpioKernelEventFifo);

  /// Requests config.line as an input with events on both edges. config.chip must be empty or
  /// this chip's name, label or path ("/dev/" + name). Throws GpioError as the real adapter
  /// does.
  std::unique_ptr<GpioInputLine> RequestInput(const GpioLineConfig& config);
  /// Requests config.line as an output driven at `initial_value` (logical).
  std::unique_ptr<GpioOutputLine> RequestOutput(const GpioLineConfig& config, bool initial_value);

  /// Sets the level a line is pulled to (gpio-sim's "pull-up"/"pull-down"), at `timestamp_ns`
  /// on the chip's clock (which advances to it; earlier times are taken as now). An input
  /// requested for events gets an edge event if its level changes. No effect on the value of a
  /// line requested as an output.
  void Pull(unsigned offset, bool high, std::int64_t timestamp_ns);
  /// Pull at the chip's current time.
  void Pull(unsigned offset, bool high);
  /// The physical level on the line (gpio-sim's sim_gpioN/value): the output's drive if it is
  /// requested as an output, else its pull.
  bool Value(unsigned offset) const;

  /// The chip's clock, ns: the time of event stamps and of every line's NowNs().
  std::int64_t now_ns() const;
  /// Moves the clock to `now_ns` (never backwards).
  void SetNowNs(std::int64_t now_ns);
  /// Moves the clock forward by `delta_ns`.
  void AdvanceNs(std::int64_t delta_ns);

  /// Events lost because an input's FIFO was full, on `offset` since it was requested.
  std::uint64_t dropped_events(unsigned offset) const;
  /// Whether `offset` is requested, and by whom ("" if free).
  std::string consumer(unsigned offset) const;
  /// The next ReadEvents/ReadValue/SetValue on `offset` fails with `error_number` (e.g. EIO),
  /// to test error paths.
  void FailNextCall(unsigned offset, int error_number);

  struct Chip;  ///< The shared state (in gpio_double.cpp).

 private:
  std::shared_ptr<Chip> chip_;
};

}  // namespace ambdrop
