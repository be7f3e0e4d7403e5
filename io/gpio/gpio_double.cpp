#include "io/gpio/gpio_double.hpp"

#include <algorithm>
#include <cerrno>
#include <system_error>

namespace ambdrop {

struct GpioDouble::Chip {
  enum class Mode : std::uint8_t { kFree, kInput, kOutput };

  struct Line {
    std::string name;
    bool pull_high = false;  ///< the pull's physical level
    Mode mode = Mode::kFree;
    std::string consumer;
    bool active_low = false;
    bool drive_high = false;  ///< an output's physical level
    /// Event FIFO (a ring), sized when the line is requested as an input.
    std::vector<GpioEdgeEvent> fifo;
    std::size_t head = 0;
    std::size_t size = 0;
    std::uint64_t dropped = 0;
    int fail_errno = 0;  ///< the next call fails with this (0: none)

    bool physical() const noexcept { return mode == Mode::kOutput ? drive_high : pull_high; }
  };

  std::string name;
  std::string label;
  std::size_t fifo_capacity = kGpioKernelEventFifo;
  std::vector<Line> lines;
  std::int64_t now_ns = 0;
  mutable std::mutex mutex;  // guards everything above
  std::condition_variable changed;

  /// "gpiochip0 [hil-sim] line 3 'estop'".
  std::string Describe(unsigned offset) const {
    std::string text = name + " [" + label + "] line " + std::to_string(offset);
    if (!lines[offset].name.empty()) text += " '" + lines[offset].name + "'";
    return text;
  }

  /// The offset `id` names; throws GpioError as the real adapter's lookup does.
  unsigned Find(const GpioLineConfig& config) const {
    if (!config.chip.empty() && config.chip != name && config.chip != label &&
        config.chip != "/dev/" + name) {
      throw GpioError("gpio: cannot open chip '" + config.chip +
                      "': " + std::generic_category().message(ENOENT) +
                      " (no chip with that path, name, label or number; the double has " + name +
                      " [" + label + "])");
    }
    if (const auto* offset = std::get_if<unsigned>(&config.line)) {
      if (*offset >= lines.size()) {
        throw GpioError("gpio: chip " + name + " [" + label + "] has no line " +
                        std::to_string(*offset) + " (it has " + std::to_string(lines.size()) +
                        " lines, offsets 0.." + std::to_string(lines.size() - 1) + ")");
      }
      return *offset;
    }
    const std::string& wanted = std::get<std::string>(config.line);
    for (unsigned offset = 0; offset < lines.size(); ++offset) {
      if (!wanted.empty() && lines[offset].name == wanted) return offset;
    }
    throw GpioError("gpio: chip " + name + " [" + label + "] has no line named '" + wanted + "'");
  }

  /// Claims `offset` for `consumer`, or throws the kernel's EBUSY.
  void Claim(unsigned offset, const GpioLineConfig& config, Mode mode) {
    Line& line = lines[offset];
    if (line.mode != Mode::kFree) {
      throw GpioError("gpio: cannot request " + Describe(offset) + ": " +
                      std::generic_category().message(EBUSY) + " (busy: held by consumer '" +
                      line.consumer + "')");
    }
    line.mode = mode;
    line.consumer = config.consumer;
    line.active_low = config.active_low;
    line.fail_errno = 0;
  }

  void Release(unsigned offset) noexcept {
    std::lock_guard lock(mutex);
    Line& line = lines[offset];
    line.mode = Mode::kFree;
    line.consumer.clear();
    line.size = 0;
    line.head = 0;
  }

  /// Consumes a planned failure: true (and *error set) if this call must fail.
  bool TakeFailure(unsigned offset, int* error) noexcept {
    Line& line = lines[offset];
    if (line.fail_errno == 0) return false;
    *error = line.fail_errno;
    line.fail_errno = 0;
    return true;
  }
};

namespace {

using Chip = GpioDouble::Chip;

class DoubleInputLine final : public GpioInputLine {
 public:
  DoubleInputLine(std::shared_ptr<Chip> chip, unsigned offset)
      : chip_(std::move(chip)), offset_(offset) {}
  ~DoubleInputLine() override { chip_->Release(offset_); }

  GpioStatus ReadEvents(std::span<GpioEdgeEvent> events, std::chrono::nanoseconds timeout,
                        std::size_t* count) noexcept override {
    *count = 0;
    std::unique_lock lock(chip_->mutex);
    Chip::Line& line = chip_->lines[offset_];
    if (chip_->TakeFailure(offset_, &last_errno_)) return GpioStatus::kError;
    // Waiting is in real time (another thread may Pull); the chip's clock does not move.
    const auto has_events = [&line] { return line.size > 0; };
    if (timeout.count() < 0) {
      chip_->changed.wait(lock, has_events);
    } else if (timeout.count() > 0) {
      chip_->changed.wait_for(lock, timeout, has_events);
    }
    if (line.size == 0) return GpioStatus::kTimeout;
    const std::size_t n = std::min(events.size(), line.size);
    for (std::size_t i = 0; i < n; ++i) {
      events[i] = line.fifo[line.head];
      line.head = (line.head + 1) % line.fifo.size();
    }
    line.size -= n;
    *count = n;
    return GpioStatus::kOk;
  }

  GpioStatus ReadValue(bool* value) noexcept override {
    std::lock_guard lock(chip_->mutex);
    if (chip_->TakeFailure(offset_, &last_errno_)) return GpioStatus::kError;
    const Chip::Line& line = chip_->lines[offset_];
    *value = line.physical() != line.active_low;
    return GpioStatus::kOk;
  }

  std::int64_t NowNs() const noexcept override {
    std::lock_guard lock(chip_->mutex);
    return chip_->now_ns;
  }

  int last_errno() const noexcept override { return last_errno_; }

 private:
  std::shared_ptr<Chip> chip_;
  unsigned offset_;
  int last_errno_ = 0;
};

class DoubleOutputLine final : public GpioOutputLine {
 public:
  DoubleOutputLine(std::shared_ptr<Chip> chip, unsigned offset, bool value)
      : chip_(std::move(chip)), offset_(offset), value_(value) {}
  ~DoubleOutputLine() override { chip_->Release(offset_); }

  GpioStatus SetValue(bool value) noexcept override {
    std::lock_guard lock(chip_->mutex);
    if (chip_->TakeFailure(offset_, &last_errno_)) return GpioStatus::kError;
    Chip::Line& line = chip_->lines[offset_];
    line.drive_high = value != line.active_low;
    value_ = value;
    return GpioStatus::kOk;
  }

  bool value() const noexcept override { return value_; }
  int last_errno() const noexcept override { return last_errno_; }

 private:
  std::shared_ptr<Chip> chip_;
  unsigned offset_;
  bool value_;
  int last_errno_ = 0;
};

}  // namespace

GpioDouble::GpioDouble(std::string name, std::string label, unsigned num_lines,
                       std::vector<std::pair<unsigned, std::string>> line_names,
                       std::size_t event_fifo)
    : chip_(std::make_shared<Chip>()) {
  if (num_lines == 0) throw GpioError("gpio double: a chip needs at least one line");
  if (event_fifo == 0) throw GpioError("gpio double: the event FIFO needs room for one event");
  chip_->name = std::move(name);
  chip_->label = std::move(label);
  chip_->fifo_capacity = event_fifo;
  chip_->lines.resize(num_lines);
  for (auto& [offset, line_name] : line_names) {
    if (offset >= num_lines) {
      throw GpioError("gpio double: line name '" + line_name + "' for offset " +
                      std::to_string(offset) + " beyond " + std::to_string(num_lines) + " lines");
    }
    chip_->lines[offset].name = std::move(line_name);
  }
}

std::unique_ptr<GpioInputLine> GpioDouble::RequestInput(const GpioLineConfig& config) {
  std::lock_guard lock(chip_->mutex);
  const unsigned offset = chip_->Find(config);
  chip_->Claim(offset, config, Chip::Mode::kInput);
  Chip::Line& line = chip_->lines[offset];
  line.fifo.assign(chip_->fifo_capacity, GpioEdgeEvent{});
  line.head = 0;
  line.size = 0;
  line.dropped = 0;
  return std::make_unique<DoubleInputLine>(chip_, offset);
}

std::unique_ptr<GpioOutputLine> GpioDouble::RequestOutput(const GpioLineConfig& config,
                                                          bool initial_value) {
  std::lock_guard lock(chip_->mutex);
  const unsigned offset = chip_->Find(config);
  chip_->Claim(offset, config, Chip::Mode::kOutput);
  Chip::Line& line = chip_->lines[offset];
  line.drive_high = initial_value != config.active_low;
  return std::make_unique<DoubleOutputLine>(chip_, offset, initial_value);
}

void GpioDouble::Pull(unsigned offset, bool high, std::int64_t timestamp_ns) {
  {
    std::lock_guard lock(chip_->mutex);
    if (offset >= chip_->lines.size()) {
      throw GpioError("gpio double: Pull on line " + std::to_string(offset) + " of " +
                      std::to_string(chip_->lines.size()));
    }
    chip_->now_ns = std::max(chip_->now_ns, timestamp_ns);
    Chip::Line& line = chip_->lines[offset];
    if (line.pull_high == high) return;
    line.pull_high = high;
    if (line.mode != Chip::Mode::kInput) return;
    if (line.size == line.fifo.size()) {
      ++line.dropped;  // the kernel's kfifo_put fails and the newest event is lost
      return;
    }
    const bool logical = high != line.active_low;
    line.fifo[(line.head + line.size) % line.fifo.size()] =
        GpioEdgeEvent{logical ? GpioEdge::kRising : GpioEdge::kFalling, chip_->now_ns};
    ++line.size;
  }
  chip_->changed.notify_all();
}

void GpioDouble::Pull(unsigned offset, bool high) {
  Pull(offset, high, now_ns());
}

bool GpioDouble::Value(unsigned offset) const {
  std::lock_guard lock(chip_->mutex);
  return chip_->lines.at(offset).physical();
}

std::int64_t GpioDouble::now_ns() const {
  std::lock_guard lock(chip_->mutex);
  return chip_->now_ns;
}

void GpioDouble::SetNowNs(std::int64_t now_ns) {
  std::lock_guard lock(chip_->mutex);
  chip_->now_ns = std::max(chip_->now_ns, now_ns);
}

void GpioDouble::AdvanceNs(std::int64_t delta_ns) {
  std::lock_guard lock(chip_->mutex);
  chip_->now_ns += std::max<std::int64_t>(delta_ns, 0);
}

std::uint64_t GpioDouble::dropped_events(unsigned offset) const {
  std::lock_guard lock(chip_->mutex);
  return chip_->lines.at(offset).dropped;
}

std::string GpioDouble::consumer(unsigned offset) const {
  std::lock_guard lock(chip_->mutex);
  return chip_->lines.at(offset).consumer;
}

void GpioDouble::FailNextCall(unsigned offset, int error_number) {
  std::lock_guard lock(chip_->mutex);
  chip_->lines.at(offset).fail_errno = error_number;
}

}  // namespace ambdrop
