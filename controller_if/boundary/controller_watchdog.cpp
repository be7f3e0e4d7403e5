#include "controller_if/boundary/controller_watchdog.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ambdrop {

std::optional<SilenceAction> TryParseSilenceAction(std::string_view text) noexcept {
  if (text == "hold") return SilenceAction::kHold;
  if (text == "zero") return SilenceAction::kZero;
  if (text == "stop") return SilenceAction::kStop;
  return std::nullopt;
}

SilenceAction ParseSilenceAction(std::string_view text) {
  if (const auto action = TryParseSilenceAction(text)) return *action;
  throw std::invalid_argument(
      "controller silence action: expected \"hold\", \"zero\" or \"stop\", "
      "found \"" +
      std::string(text) + "\"");
}

std::string_view ToString(SilenceAction action) noexcept {
  switch (action) {
    case SilenceAction::kHold:
      return "hold";
    case SilenceAction::kZero:
      return "zero";
    case SilenceAction::kStop:
      return "stop";
  }
  return "?";
}

ControllerWatchdog::ControllerWatchdog(std::int64_t timeout_ns, SilenceAction action)
    : timeout_ns_(timeout_ns), action_(action) {
  if (timeout_ns <= 0) {
    throw std::invalid_argument("controller watchdog: timeout must be > 0 ns, got " +
                                std::to_string(timeout_ns));
  }
}

void ControllerWatchdog::Start(std::int64_t now_ns) noexcept {
  started_ = true;
  silent_ = false;
  stopped_ = false;
  last_feed_ns_ = now_ns;
  silence_episodes_ = 0;
  recoveries_ = 0;
  feeds_ = 0;
  longest_gap_ns_ = 0;
}

void ControllerWatchdog::Feed(std::int64_t now_ns) noexcept {
  if (!started_) Start(now_ns);
  longest_gap_ns_ = std::max(longest_gap_ns_, now_ns - last_feed_ns_);
  last_feed_ns_ = now_ns;
  ++feeds_;
  // A stop is final: the run is being torn down, late currents must not revive it.
  if (silent_ && !stopped_) {
    silent_ = false;
    ++recoveries_;
  }
}

WatchdogVerdict ControllerWatchdog::SilentVerdict() const noexcept {
  switch (action_) {
    case SilenceAction::kHold:
      return WatchdogVerdict::kHold;
    case SilenceAction::kZero:
      return WatchdogVerdict::kZero;
    case SilenceAction::kStop:
      return WatchdogVerdict::kStop;
  }
  return WatchdogVerdict::kStop;
}

WatchdogVerdict ControllerWatchdog::Check(std::int64_t now_ns) noexcept {
  if (!started_) Start(now_ns);
  if (stopped_) return WatchdogVerdict::kStop;
  const std::int64_t gap = now_ns - last_feed_ns_;
  longest_gap_ns_ = std::max(longest_gap_ns_, gap);
  if (gap > timeout_ns_ && !silent_) {
    silent_ = true;
    ++silence_episodes_;
    if (action_ == SilenceAction::kStop) stopped_ = true;
  }
  return silent_ ? SilentVerdict() : WatchdogVerdict::kNormal;
}

}  // namespace ambdrop
