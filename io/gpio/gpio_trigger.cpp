#include "io/gpio/gpio_trigger.hpp"

#include <algorithm>

namespace ambdrop {

GpioTrigger::GpioTrigger(GpioInputLine& input, GpioOutputLine* mirror,
                         const GpioTriggerConfig& config)
    : input_(&input), mirror_(mirror), config_(config) {
  config_.debounce_ns = std::max<std::int64_t>(config_.debounce_ns, 0);
  // An output reads back what was set, so the first MirrorDropState to the same value can skip
  // the write.
  if (mirror_ != nullptr) {
    mirror_known_ = true;
    mirror_value_ = mirror_->value();
  }
}

GpioStatus GpioTrigger::Start() noexcept {
  counters_ = GpioTriggerCounters{};
  event_head_ = 0;
  event_count_ = 0;
  pending_ = false;

  bool level = false;
  const GpioStatus status = input_->ReadValue(&level);
  if (status != GpioStatus::kOk) {
    ++counters_.read_errors;
    level = !IsFailLevel(true);  // unknown: assume power is on, the next edge will tell
  }
  raw_level_ = level;
  stable_level_ = level;
  power_failed_ = IsFailLevel(level);
  if (power_failed_) {
    // Already failed: report it now, undebounced (it has been there for an unknown time).
    const std::int64_t now_ns = input_->NowNs();
    ++counters_.failures;
    Push(GpioPowerEvent{.power_fail = true, .timestamp_ns = now_ns, .accepted_ns = now_ns});
  }
  FollowMirror(power_failed_);
  return status;
}

GpioStatus GpioTrigger::Poll(std::chrono::nanoseconds timeout) noexcept {
  // Do not sleep past the moment a pending change becomes accepted.
  if (pending_) {
    const std::int64_t remaining_ns =
        std::max<std::int64_t>(pending_accept_ns() - input_->NowNs(), 0);
    if (timeout.count() < 0 || timeout.count() > remaining_ns) {
      timeout = std::chrono::nanoseconds(remaining_ns);
    }
  }
  GpioStatus status = GpioStatus::kTimeout;
  // A full batch may leave more in the kernel FIFO: read again without waiting.
  for (std::size_t count = edges_.size(); count == edges_.size();) {
    const GpioStatus read = input_->ReadEvents(edges_, timeout, &count);
    if (read == GpioStatus::kError) {
      ++counters_.read_errors;
      status = read;
      break;
    }
    if (read == GpioStatus::kOk) status = read;
    for (std::size_t i = 0; i < count; ++i) OnEdge(edges_[i]);
    timeout = std::chrono::nanoseconds(0);
  }
  AdvanceTo(input_->NowNs());
  return status;
}

void GpioTrigger::OnEdge(const GpioEdgeEvent& edge) noexcept {
  // A change that held until this edge is accepted before the edge counts.
  AdvanceTo(edge.timestamp_ns);
  ++counters_.edges;
  const bool level = edge.edge == GpioEdge::kRising;
  if (level == raw_level_) {
    // The opposite edge was lost, so the line was away in between: a pending change was
    // interrupted and restarts here; with nothing pending the excursion is simply ignored.
    ++counters_.repeated_edges;
    if (pending_) {
      ++counters_.glitches;
      pending_since_ns_ = edge.timestamp_ns;
    }
    return;
  }
  raw_level_ = level;
  if (raw_level_ == stable_level_) {
    pending_ = false;  // back before the debounce time: a glitch
    ++counters_.glitches;
    return;
  }
  pending_ = true;
  pending_since_ns_ = edge.timestamp_ns;
  if (config_.debounce_ns == 0) Accept();
}

void GpioTrigger::AdvanceTo(std::int64_t now_ns) noexcept {
  if (pending_ && now_ns >= pending_accept_ns()) Accept();
}

void GpioTrigger::Accept() noexcept {
  pending_ = false;
  stable_level_ = raw_level_;
  const GpioPowerEvent event{.power_fail = IsFailLevel(stable_level_),
                             .timestamp_ns = pending_since_ns_,
                             .accepted_ns = pending_accept_ns()};
  if (event.power_fail) {
    if (power_failed_) return;  // latched: failed again while still failed
    power_failed_ = true;
    ++counters_.failures;
    Push(event);
    FollowMirror(true);
    return;
  }
  if (!power_failed_) return;
  if (!config_.honour_restore) {
    ++counters_.restores_ignored;
    return;
  }
  power_failed_ = false;
  ++counters_.restores;
  Push(event);
  FollowMirror(false);
}

void GpioTrigger::Push(const GpioPowerEvent& event) noexcept {
  if (event_count_ == events_.size()) {
    event_head_ = (event_head_ + 1) % events_.size();
    --event_count_;
    ++counters_.events_overwritten;
  }
  events_[(event_head_ + event_count_) % events_.size()] = event;
  ++event_count_;
}

bool GpioTrigger::PopEvent(GpioPowerEvent* event) noexcept {
  if (event_count_ == 0) return false;
  *event = events_[event_head_];
  event_head_ = (event_head_ + 1) % events_.size();
  --event_count_;
  return true;
}

GpioStatus GpioTrigger::MirrorDropState(bool dropped) noexcept {
  if (mirror_ == nullptr) return GpioStatus::kOk;
  if (mirror_known_ && mirror_value_ == dropped) return GpioStatus::kOk;
  const GpioStatus status = mirror_->SetValue(dropped);
  if (status == GpioStatus::kOk) {
    mirror_known_ = true;
    mirror_value_ = dropped;
  } else {
    ++counters_.mirror_errors;
    mirror_known_ = false;  // unknown now: the next call writes again
  }
  return status;
}

void GpioTrigger::FollowMirror(bool dropped) noexcept {
  if (config_.mirror_follows_trigger) (void)MirrorDropState(dropped);
}

}  // namespace ambdrop
