#pragma once
// The GPIO shutdown trigger: edges on a power-fail input (the amplifier's power-fail line, an
// e-stop) become power events for the emulator, and an output line mirrors the emulator's drop
// state back to the rig.
//
// Debounce: a change of the input's level is accepted once it has held for debounce_ns. If the
// line goes back before that, both edges are ignored and counted as a glitch. An accepted
// change is stamped with the kernel time of its first edge, so a debounce delays the report,
// not the event's time: a failure whose edge is at t0 is reported at t0 + debounce_ns or
// later (when Poll or AdvanceTo runs), with timestamp_ns = t0.
//
// Pure logic over GpioInputLine/GpioOutputLine: deterministic (time comes only from event
// timestamps and the caller's "now"), allocation-free after construction, noexcept. One thread
// uses a trigger.
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "io/gpio/gpio_line.hpp"

namespace ambdrop {

/// Which logical level of the input means "power has failed".
enum class PowerFailLevel : std::uint8_t {
  kLow,   ///< active-low signalling (a PFAIL# line pulled low by the supply)
  kHigh,  ///< active-high signalling
};

/// How the trigger reads its input.
struct GpioTriggerConfig {
  /// The level that means power has failed, in the logical values the input line reports: a
  /// line requested with active_low = true already inverts the wire, so an active-low wire is
  /// either (active_low = false, kLow) or (active_low = true, kHigh), not both.
  PowerFailLevel fail_level = PowerFailLevel::kLow;
  /// How long a new level must hold before it counts, ns (0: every edge counts at once).
  std::int64_t debounce_ns = 0;
  /// Whether the opposite edge (power back) produces a restore event. If false, the first
  /// failure latches until the trigger is started again; later restores are counted only.
  bool honour_restore = true;
  /// Whether the mirror output follows the trigger's own events (set on a failure, cleared on
  /// an honoured restore). The emulator may also set it from other sources with MirrorDropState.
  bool mirror_follows_trigger = true;
};

/// One accepted change of power, for the emulator (which maps it onto controller_if's
/// PowerEvent: power_fail = !restore).
struct GpioPowerEvent {
  bool power_fail = true;  ///< true: power failed; false: power came back
  /// The edge that started the change, ns on the input's clock (CLOCK_MONOTONIC for the real
  /// line). For the level found at Start: the time of Start.
  std::int64_t timestamp_ns = 0;
  /// When the debounce accepted it: timestamp_ns + debounce_ns (or Start's time), ns.
  std::int64_t accepted_ns = 0;

  bool operator==(const GpioPowerEvent&) const = default;
};

/// Cumulative counts since Start.
struct GpioTriggerCounters {
  std::uint64_t edges = 0;             ///< edge events read from the input
  std::uint64_t glitches = 0;          ///< changes that reverted within the debounce time
  std::uint64_t failures = 0;          ///< power-fail events produced
  std::uint64_t restores = 0;          ///< restore events produced
  std::uint64_t restores_ignored = 0;  ///< accepted restores dropped (honour_restore = false)
  /// Edges that repeat the level the line already had: the opposite edge was lost (the kernel
  /// FIFO overflowed, or a pulse was too short for the edge detector). They change nothing.
  std::uint64_t repeated_edges = 0;
  std::uint64_t events_overwritten = 0;  ///< oldest events lost because nobody popped them
  std::uint64_t read_errors = 0;         ///< ReadEvents/ReadValue returned kError
  std::uint64_t mirror_errors = 0;       ///< SetValue on the mirror returned kError
};

/// Edges on a power-fail input → debounced power events; the drop state → a mirror output.
class GpioTrigger {
 public:
  /// Events waiting to be popped; when full, the oldest is overwritten (the newest say what
  /// the power is now).
  static constexpr std::size_t kEventCapacity = 16;

  /// `input` is requested for both edges; `mirror` may be null (no mirror line). Both must
  /// outlive the trigger.
  GpioTrigger(GpioInputLine& input, GpioOutputLine* mirror, const GpioTriggerConfig& config);

  /// Reads the input's level as the starting point at input.NowNs() and clears counters and
  /// events. If power has already failed, that is a power-fail event at once (no debounce:
  /// nobody knows how long it has been low). Sets the mirror to the drop state. Returns the
  /// ReadValue status; on kError the trigger assumes power is on.
  [[nodiscard]] GpioStatus Start() noexcept;

  /// Waits up to `timeout` for edges (cut short to when a pending change would be accepted;
  /// 0: poll once; negative: no limit), feeds them in, then accepts pending changes that have
  /// held until input.NowNs(). Returns the read status (kTimeout when no edge came).
  [[nodiscard]] GpioStatus Poll(std::chrono::nanoseconds timeout) noexcept;

  /// Feeds one edge (Poll does this for each edge read). Edges must come in time order.
  void OnEdge(const GpioEdgeEvent& edge) noexcept;
  /// Accepts a pending change that has held until `now_ns` (Poll does this).
  void AdvanceTo(std::int64_t now_ns) noexcept;

  /// Takes the oldest waiting event; false if none.
  bool PopEvent(GpioPowerEvent* event) noexcept;
  /// Number of events waiting.
  std::size_t pending_events() const noexcept { return event_count_; }

  /// Drives the mirror output to `dropped` (the emulator's drop state, from any source), writing
  /// the line only when the value changes. Without a mirror it does nothing and returns kOk.
  [[nodiscard]] GpioStatus MirrorDropState(bool dropped) noexcept;

  /// Whether power is failed as far as accepted events go (latched if restores are not
  /// honoured).
  bool power_failed() const noexcept { return power_failed_; }
  /// The input's last known logical level, before the debounce.
  bool raw_level() const noexcept { return raw_level_; }
  /// The input's debounced logical level.
  bool stable_level() const noexcept { return stable_level_; }
  /// Whether a change is waiting for its debounce time, and when it would be accepted (ns).
  bool change_pending() const noexcept { return pending_; }
  std::int64_t pending_accept_ns() const noexcept {
    return pending_since_ns_ + config_.debounce_ns;
  }

  const GpioTriggerCounters& counters() const noexcept { return counters_; }
  const GpioTriggerConfig& config() const noexcept { return config_; }

 private:
  /// Whether a logical level of the input means "power failed".
  bool IsFailLevel(bool level) const noexcept {
    return level == (config_.fail_level == PowerFailLevel::kHigh);
  }
  /// Accepts the pending change (the level has held long enough).
  void Accept() noexcept;
  void Push(const GpioPowerEvent& event) noexcept;
  void FollowMirror(bool dropped) noexcept;

  GpioInputLine* input_;
  GpioOutputLine* mirror_;
  GpioTriggerConfig config_;

  bool raw_level_ = false;     ///< last logical level seen on the input
  bool stable_level_ = false;  ///< the debounced level
  bool power_failed_ = false;  ///< accepted power state (latched if restores are not honoured)
  bool pending_ = false;       ///< raw_level_ != stable_level_, not yet held for the debounce
  std::int64_t pending_since_ns_ = 0;  ///< the edge that started the pending change
  bool mirror_known_ = false;          ///< whether mirror_value_ is what the line carries
  bool mirror_value_ = false;

  std::array<GpioEdgeEvent, kGpioKernelEventFifo> edges_{};  ///< one read's worth of edges
  std::array<GpioPowerEvent, kEventCapacity> events_{};      ///< ring of accepted events
  std::size_t event_head_ = 0;
  std::size_t event_count_ = 0;
  GpioTriggerCounters counters_;
};

}  // namespace ambdrop
