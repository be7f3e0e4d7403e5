#pragma once
#include <cstdint>
#include <optional>
#include <string_view>

namespace ambdrop {

/// What to do when the controller falls silent (config value "hold" | "zero" | "stop").
enum class SilenceAction {
  kHold,  ///< keep applying the last currents received
  kZero,  ///< apply zero control currents (bias only)
  kStop,  ///< end the run; latched: it does not recover
};

/// Parses "hold" | "zero" | "stop" (exact, lower case); nullopt otherwise, so a config loader can
/// word its own error with file and line.
std::optional<SilenceAction> TryParseSilenceAction(std::string_view text) noexcept;
/// As TryParseSilenceAction, but throws std::invalid_argument naming the value found and the
/// values allowed.
SilenceAction ParseSilenceAction(std::string_view text);
/// "hold" | "zero" | "stop".
std::string_view ToString(SilenceAction action) noexcept;

/// What the loop must do with the currents this period.
enum class WatchdogVerdict {
  kNormal,  ///< the controller is talking: apply its latest currents
  kHold,    ///< silent: keep the last currents
  kZero,    ///< silent: zero the currents
  kStop,    ///< silent with action stop (or stopped earlier): end the run
};

/// Watches the controller's currents for silence. The loop calls Feed(now) whenever new currents
/// arrive and Check(now) once per period with the same clock's time (ns). When more than
/// `timeout_ns` has passed since the last feed (or since Start), the controller is silent and
/// Check returns the configured action; the first feed after that ends the silence episode
/// (recovery), except after kStop, which is latched. Counters say how often and how long it
/// was silent. noexcept and allocation-free after construction.
class ControllerWatchdog {
 public:
  /// Throws std::invalid_argument unless timeout_ns > 0.
  ControllerWatchdog(std::int64_t timeout_ns, SilenceAction action);

  /// Starts the timeout at `now_ns` (ns) and clears the state and counters. Without it, the
  /// first Feed or Check starts it.
  void Start(std::int64_t now_ns) noexcept;
  /// New currents arrived at `now_ns` (ns).
  void Feed(std::int64_t now_ns) noexcept;
  /// The verdict at `now_ns` (ns): kNormal unless silent for longer than the timeout.
  [[nodiscard]] WatchdogVerdict Check(std::int64_t now_ns) noexcept;

  /// Silent now (as of the last Check).
  bool silent() const noexcept { return silent_; }
  /// The stop action fired; latched until Start.
  bool stopped() const noexcept { return stopped_; }
  /// Silence episodes begun (each normal -> silent transition).
  std::int64_t silence_episodes() const noexcept { return silence_episodes_; }
  /// Episodes ended by a feed.
  std::int64_t recoveries() const noexcept { return recoveries_; }
  /// Feeds received.
  std::int64_t feeds() const noexcept { return feeds_; }
  /// Longest gap (ns) between consecutive feeds (or Start and the first feed) seen so far,
  /// including the current one as of the last Check or Feed.
  std::int64_t longest_gap_ns() const noexcept { return longest_gap_ns_; }
  std::int64_t timeout_ns() const noexcept { return timeout_ns_; }
  SilenceAction action() const noexcept { return action_; }

 private:
  WatchdogVerdict SilentVerdict() const noexcept;

  std::int64_t timeout_ns_;
  SilenceAction action_;
  bool started_ = false;
  bool silent_ = false;
  bool stopped_ = false;
  std::int64_t last_feed_ns_ = 0;
  std::int64_t silence_episodes_ = 0;
  std::int64_t recoveries_ = 0;
  std::int64_t feeds_ = 0;
  std::int64_t longest_gap_ns_ = 0;
};

}  // namespace ambdrop
