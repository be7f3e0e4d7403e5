#include "io/gpio/gpiod_lines.hpp"

#include <poll.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <filesystem>
#include <gpiod.hpp>
#include <system_error>
#include <utility>
#include <vector>

namespace ambdrop {
namespace {

constexpr std::int64_t kNsPerS = 1'000'000'000;

/// Whether /dev holds any GPIO character device, to tell "wrong chip" from "no GPIO at all".
bool AnyGpioChipDevice() {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator("/dev", error)) {
    if (entry.path().filename().string().starts_with("gpiochip")) return true;
  }
  return false;
}

gpiod::chip OpenChip(const GpioLineConfig& config) {
  if (config.chip.empty()) {
    throw GpioError(
        "gpio: no chip given for " + ToString(config.line) +
        " (give a path, name, label or number, e.g. /dev/gpiochip0, gpiochip0, hil-sim, 0)");
  }
  try {
    return gpiod::chip(config.chip, gpiod::chip::OPEN_LOOKUP);
  } catch (const std::system_error& error) {
    std::string message = "gpio: cannot open chip '" + config.chip + "': " + error.code().message();
    if (error.code().value() == EACCES || error.code().value() == EPERM) {
      message += " (no permission on its /dev/gpiochipN: run as root or join its group)";
    } else if (!AnyGpioChipDevice()) {
      message +=
          " (this machine has no GPIO chip at all: no /dev/gpiochip*. The kernel lacks the GPIO "
          "character device or no chip driver is loaded; tests/hw/run_in_vm.sh boots a kernel "
          "with a simulated chip)";
    } else {
      message += " (no chip with that path, name, label or number; gpiodetect lists them)";
    }
    throw GpioError(message);
  }
}

/// "gpiochip1 [hil-sim]".
std::string ChipDescription(const gpiod::chip& chip) {
  return chip.name() + " [" + chip.label() + "]";
}

/// "gpiochip1 [hil-sim] line 3 'estop'".
std::string LineDescription(const gpiod::chip& chip, const gpiod::line& line) {
  std::string text = ChipDescription(chip) + " line " + std::to_string(line.offset());
  const std::string name = line.name();
  if (!name.empty()) text += " '" + name + "'";
  return text;
}

gpiod::line FindLine(const gpiod::chip& chip, const GpioLineId& id) {
  if (const auto* offset = std::get_if<unsigned>(&id)) {
    const unsigned count = chip.num_lines();
    if (*offset >= count) {
      throw GpioError("gpio: chip " + ChipDescription(chip) + " has no line " +
                      std::to_string(*offset) + " (it has " + std::to_string(count) +
                      " lines, offsets 0.." + std::to_string(count - 1) + ")");
    }
    return chip.get_line(*offset);
  }
  const std::string& name = std::get<std::string>(id);
  gpiod::line line;
  try {
    line = chip.find_line(name);
  } catch (const std::system_error& error) {
    throw GpioError("gpio: cannot look up line '" + name + "' on chip " + ChipDescription(chip) +
                    ": " + error.code().message());
  }
  if (!line) {
    throw GpioError("gpio: chip " + ChipDescription(chip) + " has no line named '" + name +
                    "' (gpioinfo " + chip.name() + " lists the line names)");
  }
  return line;
}

/// Requests `line` and turns the bindings' errors into a GpioError that says who holds a busy
/// line.
void RequestLine(const gpiod::line& line, const gpiod::line_request& request, int default_value,
                 const std::string& description) {
  try {
    line.request(request, default_value);
  } catch (const std::system_error& error) {
    std::string message = "gpio: cannot request " + description + ": " + error.code().message();
    if (error.code().value() == EBUSY) {
      std::string holder;
      try {
        line.update();
        holder = line.consumer();
      } catch (const std::exception&) {
        // The holder's name is only a hint: say "busy" without it.
      }
      message += holder.empty() ? " (busy: another request holds it)"
                                : " (busy: held by consumer '" + holder + "')";
    }
    throw GpioError(message);
  }
}

/// Everything the setup resolves: the open chip, the line and its description.
struct OpenedLine {
  gpiod::chip chip;
  gpiod::line line;
  std::string description;
};

OpenedLine OpenLine(const GpioLineConfig& config) {
  OpenedLine opened;
  opened.chip = OpenChip(config);
  try {
    opened.line = FindLine(opened.chip, config.line);
    opened.description = LineDescription(opened.chip, opened.line);
  } catch (const GpioError&) {
    throw;
  } catch (const std::exception& error) {
    throw GpioError("gpio: cannot open " + ToString(config.line) + " on chip '" + config.chip +
                    "': " + error.what());
  }
  return opened;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Input

struct GpiodInputLine::Impl {
  gpiod::chip chip;
  gpiod::line line;
  int fd = -1;  ///< the event request's file descriptor (owned by libgpiod)
  /// Raw records of one read; the kernel's FIFO never holds more.
  std::array<gpiod_line_event, kGpioKernelEventFifo> raw{};
};

GpiodInputLine::GpiodInputLine(const GpioLineConfig& config) : impl_(std::make_unique<Impl>()) {
  OpenedLine opened = OpenLine(config);
  description_ = opened.description;
  offset_ = opened.line.offset();

  gpiod::line_request request;
  request.consumer = config.consumer;
  request.request_type = gpiod::line_request::EVENT_BOTH_EDGES;
  if (config.active_low) request.flags |= gpiod::line_request::FLAG_ACTIVE_LOW;
  RequestLine(opened.line, request, 0, description_);
  try {
    impl_->fd = opened.line.event_get_fd();
  } catch (const std::system_error& error) {
    throw GpioError("gpio: no event file descriptor for " + description_ + ": " +
                    error.code().message());
  }
  impl_->chip = std::move(opened.chip);
  impl_->line = std::move(opened.line);
}

GpiodInputLine::~GpiodInputLine() {
  // Closing the chip would release the line too; releasing first frees it even if a copy of
  // the chip handle lives on somewhere.
  try {
    if (impl_->line) impl_->line.release();
  } catch (const std::exception&) {
    // Nothing to do in a destructor: the kernel frees the line when the chip closes.
  }
}

GpioStatus GpiodInputLine::ReadEvents(std::span<GpioEdgeEvent> events,
                                      std::chrono::nanoseconds timeout,
                                      std::size_t* count) noexcept {
  *count = 0;
  // Wait with ppoll (nanosecond timeout, no allocation) instead of the bindings' event_wait.
  pollfd poll_fd{.fd = impl_->fd, .events = POLLIN | POLLPRI, .revents = 0};
  timespec limit{};
  const timespec* limit_ptr = nullptr;
  if (timeout.count() >= 0) {
    limit.tv_sec = static_cast<time_t>(timeout.count() / kNsPerS);
    limit.tv_nsec = static_cast<long>(timeout.count() % kNsPerS);
    limit_ptr = &limit;
  }
  const int ready = ::ppoll(&poll_fd, 1, limit_ptr, nullptr);
  if (ready < 0) {
    if (errno == EINTR) return GpioStatus::kTimeout;  // a signal: nothing read, caller polls again
    last_errno_ = errno;
    return GpioStatus::kError;
  }
  if (ready == 0) return GpioStatus::kTimeout;
  if ((poll_fd.revents & POLLIN) == 0) {
    last_errno_ = (poll_fd.revents & POLLNVAL) != 0 ? EBADF : EIO;
    return GpioStatus::kError;
  }
  if (events.empty()) return GpioStatus::kOk;

  // One read() of whole records; the fd is readable, so it does not block.
  const auto wanted = static_cast<unsigned>(std::min(events.size(), impl_->raw.size()));
  const int read = ::gpiod_line_event_read_fd_multiple(impl_->fd, impl_->raw.data(), wanted);
  if (read < 0) {
    last_errno_ = errno;
    return GpioStatus::kError;
  }
  for (int i = 0; i < read; ++i) {
    const gpiod_line_event& raw = impl_->raw[static_cast<std::size_t>(i)];
    GpioEdgeEvent& event = events[static_cast<std::size_t>(i)];
    event.edge =
        raw.event_type == GPIOD_LINE_EVENT_RISING_EDGE ? GpioEdge::kRising : GpioEdge::kFalling;
    event.timestamp_ns = static_cast<std::int64_t>(raw.ts.tv_sec) * kNsPerS + raw.ts.tv_nsec;
  }
  *count = static_cast<std::size_t>(read);
  return GpioStatus::kOk;
}

GpioStatus GpiodInputLine::ReadValue(bool* value) noexcept {
  try {
    *value = impl_->line.get_value() != 0;
    return GpioStatus::kOk;
  } catch (const std::system_error& error) {
    last_errno_ = error.code().value();
  } catch (const std::exception&) {
    last_errno_ = EIO;
  }
  return GpioStatus::kError;
}

std::int64_t GpiodInputLine::NowNs() const noexcept {
  timespec now{};
  ::clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::int64_t>(now.tv_sec) * kNsPerS + now.tv_nsec;
}

// ---------------------------------------------------------------------------------------------
// Output

struct GpiodOutputLine::Impl {
  gpiod::chip chip;
  gpiod::line line;
  /// Built once: line::set_value() would build a line_bulk and a value vector on every call.
  gpiod::line_bulk bulk;
  std::vector<int> low{0};
  std::vector<int> high{1};
};

GpiodOutputLine::GpiodOutputLine(const GpioLineConfig& config, bool initial_value)
    : impl_(std::make_unique<Impl>()), value_(initial_value) {
  OpenedLine opened = OpenLine(config);
  description_ = opened.description;
  offset_ = opened.line.offset();

  gpiod::line_request request;
  request.consumer = config.consumer;
  request.request_type = gpiod::line_request::DIRECTION_OUTPUT;
  if (config.active_low) request.flags |= gpiod::line_request::FLAG_ACTIVE_LOW;
  RequestLine(opened.line, request, initial_value ? 1 : 0, description_);
  impl_->bulk = gpiod::line_bulk({opened.line});
  impl_->chip = std::move(opened.chip);
  impl_->line = std::move(opened.line);
}

GpiodOutputLine::~GpiodOutputLine() {
  try {
    if (impl_->line) impl_->line.release();
  } catch (const std::exception&) {
    // As for the input: closing the chip frees the line anyway.
  }
}

GpioStatus GpiodOutputLine::SetValue(bool value) noexcept {
  try {
    impl_->bulk.set_values(value ? impl_->high : impl_->low);
    value_ = value;
    return GpioStatus::kOk;
  } catch (const std::system_error& error) {
    last_errno_ = error.code().value();
  } catch (const std::exception&) {
    last_errno_ = EIO;
  }
  return GpioStatus::kError;
}

}  // namespace ambdrop
