#pragma once
#include <atomic>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>

#include "controller_if/loop/rt_clock.hpp"
#include "controller_if/loop/timing_stats.hpp"

namespace ambdrop {

/// What the callback is told about the period it runs in.
struct LoopTick {
  std::int64_t index = 0;  ///< period number since Run started (0-based), counting missed ones
  std::int64_t deadline_ns = 0;    ///< when this period was due (ns, clock time)
  std::int64_t wake_ns = 0;        ///< when the loop actually woke (ns, clock time)
  std::int64_t missed_before = 0;  ///< periods skipped just before this one after an overrun
};

/// Why Run returned.
enum class LoopStopReason {
  kPeriods,   ///< max_periods elapsed
  kStopFlag,  ///< the stop flag was set
  kCallback,  ///< the callback returned false
};

/// Limits of one Run.
struct LoopRunOptions {
  /// Periods to run, missed ones included (so a run lasts max_periods x period of clock time
  /// whatever the overruns); < 0: until stopped.
  std::int64_t max_periods = -1;
  /// Checked once per period, before sleeping; set it from any thread to end the run. May be null.
  const std::atomic<bool>* stop = nullptr;
  /// The first deadline (ns, clock time); kFirstDeadlineNow: one period after Run starts.
  std::int64_t first_deadline_ns = kFirstDeadlineNow;
  static constexpr std::int64_t kFirstDeadlineNow = std::numeric_limits<std::int64_t>::min();
};

/// The counts of one Run. periods == cycles + missed_periods.
struct LoopResult {
  std::int64_t periods = 0;            ///< deadlines that elapsed
  std::int64_t cycles = 0;             ///< callbacks run
  std::int64_t overruns = 0;           ///< callbacks that finished after the next deadline
  std::int64_t missed_periods = 0;     ///< deadlines skipped, without a callback, after overruns
  std::int64_t first_deadline_ns = 0;  ///< ns, clock time
  std::int64_t end_ns = 0;             ///< clock time (ns) when the last callback returned
  LoopStopReason stop_reason = LoopStopReason::kPeriods;
};

/// A fixed-rate loop on a Clock: sleeps to absolute deadlines (deadline_k = first + k period, so
/// a late wake-up never shifts later deadlines: no drift), runs the callback once per deadline
/// and measures:
/// - lateness = wake time - deadline (ns): what the OS and hypervisor add;
/// - compute = callback return time - wake time (ns).
/// An overrun is a callback that returns after the next deadline. The loop then does not run the
/// periods it fell behind on back to back; it skips to the first deadline at or after "now" and
/// counts the skipped ones as missed (a late controller answer is worse than none). The callback
/// sees each period's index, so it can tell how much clock time passed.
///
/// After construction nothing allocates or throws; the same loop runs on a MonotonicClock for
/// real time and on a VirtualClock for offline runs and tests. Not thread-safe apart from the
/// stop flag: read the stats after Run returns.
class PeriodicLoop {
 public:
  /// `clock` must outlive the loop. Throws std::invalid_argument unless period_ns > 0.
  PeriodicLoop(Clock* clock, std::int64_t period_ns);

  /// Runs `callback` once per period until `options` says stop. The callback is called as
  /// `callback(const LoopTick&)` and returns void, or bool (false: stop after this period). It
  /// should be noexcept; it is not copied or stored. Resets the stats first.
  template <typename Callback>
  LoopResult Run(Callback&& callback, const LoopRunOptions& options) noexcept {
    using F = std::remove_reference_t<Callback>;
    return RunErased(
        [](void* f, const LoopTick& tick) -> bool {
          if constexpr (std::is_void_v<std::invoke_result_t<F&, const LoopTick&>>) {
            (*static_cast<F*>(f))(tick);
            return true;
          } else {
            return static_cast<bool>((*static_cast<F*>(f))(tick));
          }
        },
        const_cast<void*>(static_cast<const void*>(&callback)), options);
  }

  std::int64_t period_ns() const noexcept { return period_ns_; }
  /// Wake-up lateness of each period run (ns).
  const TimingStats& lateness() const noexcept { return lateness_; }
  /// Callback duration of each period run (ns).
  const TimingStats& compute() const noexcept { return compute_; }

 private:
  using Trampoline = bool (*)(void* callback, const LoopTick& tick);
  LoopResult RunErased(Trampoline call, void* callback, const LoopRunOptions& options) noexcept;

  Clock* clock_;
  std::int64_t period_ns_;
  TimingStats lateness_;
  TimingStats compute_;
};

}  // namespace ambdrop
