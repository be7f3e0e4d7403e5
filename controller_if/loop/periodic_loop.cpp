#include "controller_if/loop/periodic_loop.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ambdrop {

PeriodicLoop::PeriodicLoop(Clock* clock, std::int64_t period_ns)
    : clock_(clock), period_ns_(period_ns) {
  if (clock == nullptr) throw std::invalid_argument("PeriodicLoop: clock is null");
  if (period_ns <= 0) {
    throw std::invalid_argument("PeriodicLoop: period must be > 0 ns, got " +
                                std::to_string(period_ns));
  }
}

LoopResult PeriodicLoop::RunErased(Trampoline call, void* callback,
                                   const LoopRunOptions& options) noexcept {
  lateness_.Reset();
  compute_.Reset();
  LoopResult result;
  std::int64_t deadline = options.first_deadline_ns == LoopRunOptions::kFirstDeadlineNow
                              ? clock_->Now() + period_ns_
                              : options.first_deadline_ns;
  result.first_deadline_ns = deadline;
  result.end_ns = clock_->Now();
  std::int64_t missed_before = 0;
  for (;;) {
    // Stop checks come before the sleep, so a stop costs at most one period.
    if (options.max_periods >= 0 && result.periods >= options.max_periods) {
      result.stop_reason = LoopStopReason::kPeriods;
      break;
    }
    if (options.stop != nullptr && options.stop->load(std::memory_order_relaxed)) {
      result.stop_reason = LoopStopReason::kStopFlag;
      break;
    }

    // Sleep, run, measure.
    clock_->SleepUntil(deadline);
    const std::int64_t wake = clock_->Now();
    const LoopTick tick{result.periods, deadline, wake, missed_before};
    const bool keep_going = call(callback, tick);
    const std::int64_t end = clock_->Now();
    lateness_.Record(wake - deadline);
    compute_.Record(end - wake);
    ++result.cycles;
    ++result.periods;
    result.end_ns = end;

    // Next deadline; on an overrun skip to the first deadline at or after `end`. end - deadline
    // > period here, so at least one deadline is skipped.
    std::int64_t next = deadline + period_ns_;
    missed_before = 0;
    if (end > next) {
      ++result.overruns;
      const std::int64_t ahead = (end - deadline + period_ns_ - 1) / period_ns_;  // ceil, >= 2
      missed_before = ahead - 1;
      if (options.max_periods >= 0) {
        // Never count periods beyond the end of the run as missed.
        missed_before = std::min(missed_before, options.max_periods - result.periods);
      }
      result.missed_periods += missed_before;
      result.periods += missed_before;
      next = deadline + ahead * period_ns_;
    }
    deadline = next;

    if (!keep_going) {
      result.stop_reason = LoopStopReason::kCallback;
      break;
    }
  }
  return result;
}

}  // namespace ambdrop
