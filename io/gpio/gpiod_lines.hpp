#pragma once
// GPIO lines on the kernel's GPIO character device, through libgpiod v1 (Debian 12: 1.6.3).
//
// Setup (open the chip, look the line up, request it) goes through libgpiod's C++ bindings and
// turns their errors into GpioError with the chip and line named. The bindings allocate on
// every per-line get/set/wait (line.cpp builds a line_bulk each call), so the calls the loop
// makes avoid them:
//   - events: ppoll() on the request's file descriptor, then one read() of up to 16 records
//     (the kernel FIFO's size) into a buffer owned by the line, through libgpiod's
//     gpiod_line_event_read_fd_multiple();
//   - output: line_bulk::set_values() on a line_bulk and value vectors built at setup.
// Event timestamps are CLOCK_MONOTONIC (uAPI v1 since Linux 5.7; older kernels stamp
// CLOCK_REALTIME, and debouncing across NowNs() would then be wrong).
#include <memory>
#include <string>

#include "io/gpio/gpio_line.hpp"

namespace ambdrop {

/// An input line requested for events on both edges (and active-low if asked).
class GpiodInputLine final : public GpioInputLine {
 public:
  /// Opens config.chip, finds config.line and requests it. Throws GpioError when the chip or
  /// line does not exist, the line is busy (the message names its consumer) or the kernel
  /// refuses the request.
  explicit GpiodInputLine(const GpioLineConfig& config);
  ~GpiodInputLine() override;

  [[nodiscard]] GpioStatus ReadEvents(std::span<GpioEdgeEvent> events,
                                      std::chrono::nanoseconds timeout,
                                      std::size_t* count) noexcept override;
  [[nodiscard]] GpioStatus ReadValue(bool* value) noexcept override;
  /// CLOCK_MONOTONIC, ns.
  std::int64_t NowNs() const noexcept override;
  int last_errno() const noexcept override { return last_errno_; }

  /// "gpiochip1 [hil-sim] line 3 'estop'", for logs.
  const std::string& description() const noexcept { return description_; }
  /// The line's offset on its chip (resolved from its name if it was given by name).
  unsigned offset() const noexcept { return offset_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string description_;
  unsigned offset_ = 0;
  int last_errno_ = 0;
};

/// An output line, driven to `initial_value` as soon as it is requested.
class GpiodOutputLine final : public GpioOutputLine {
 public:
  /// Opens config.chip, finds config.line and requests it as an output at `initial_value`
  /// (logical). Throws GpioError as GpiodInputLine does.
  GpiodOutputLine(const GpioLineConfig& config, bool initial_value);
  ~GpiodOutputLine() override;

  [[nodiscard]] GpioStatus SetValue(bool value) noexcept override;
  bool value() const noexcept override { return value_; }
  int last_errno() const noexcept override { return last_errno_; }

  /// "gpiochip1 [hil-sim] line 5", for logs.
  const std::string& description() const noexcept { return description_; }
  unsigned offset() const noexcept { return offset_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string description_;
  unsigned offset_ = 0;
  bool value_ = false;
  int last_errno_ = 0;
};

}  // namespace ambdrop
