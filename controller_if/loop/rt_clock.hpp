#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <utility>

namespace ambdrop {

/// Nanoseconds per second, for converting periods and rates.
inline constexpr std::int64_t kNsPerSecond = 1'000'000'000;

/// A monotonic time source the real-time loop sleeps on. Times are nanoseconds (int64, ~292 years
/// of range) since an arbitrary epoch. Both calls are noexcept and allocation-free, so the loop can
/// use them after setup.
class Clock {
 public:
  virtual ~Clock() = default;
  /// Current time (ns). Never goes backwards.
  virtual std::int64_t Now() noexcept = 0;
  /// Returns once Now() >= deadline_ns (ns, absolute); at once if the deadline has passed.
  virtual void SleepUntil(std::int64_t deadline_ns) noexcept = 0;
};

/// The wall clock for real-time runs: CLOCK_MONOTONIC, and clock_nanosleep with TIMER_ABSTIME.
/// Sleeping to an absolute deadline (rather than for a duration) keeps a periodic loop from
/// drifting: a late wake-up does not push the following deadlines back. The sleep resumes when a
/// signal interrupts it (EINTR). How late it wakes depends on the timer slack of the calling
/// thread (50 us by default on Linux; RequestRealtime sets 1 ns), the scheduling policy and the
/// hypervisor: on the development VM a wake-up comes ~40 us late at the median even under
/// SCHED_FIFO, most of a 50 us (20 kHz) period.
///
/// Optionally the last `spin_ns` before each deadline are spent polling the clock instead of
/// sleeping, which removes the wake-up latency from the loop at the cost of burning that CPU
/// time. A spin at least as long as the wake-up latency makes the loop wake on time; with the
/// spin close to the period the thread never sleeps, and a SCHED_FIFO thread that never sleeps
/// is throttled by the kernel (sched_rt_runtime_us: 50 ms out of every second by default), so
/// use long spins only under SCHED_OTHER or with RT throttling turned off on an isolated CPU.
class MonotonicClock final : public Clock {
 public:
  /// `spin_ns` (ns, >= 0; negative is taken as 0): how long before each deadline to stop
  /// sleeping and poll the clock. 0: sleep only.
  explicit MonotonicClock(std::int64_t spin_ns = 0) noexcept
      : spin_ns_(spin_ns > 0 ? spin_ns : 0) {}

  std::int64_t Now() noexcept override;
  void SleepUntil(std::int64_t deadline_ns) noexcept override;
  std::int64_t spin_ns() const noexcept { return spin_ns_; }

 private:
  std::int64_t spin_ns_;
};

/// Simulated time for offline runs and tests: SleepUntil jumps time forward to the deadline at
/// once, so a loop runs as fast as the CPU allows and every wake-up is exactly on time unless a
/// lateness hook says otherwise. Advance() lets a callback model its own compute time. Time is an
/// atomic so another thread (a test's controller emulation) may read it while the loop runs.
class VirtualClock final : public Clock {
 public:
  /// Extra delay (ns, >= 0) added after reaching `deadline_ns` in SleepUntil: injects wake-up
  /// lateness in tests. Set it at setup; calling it does not allocate.
  using LatenessHook = std::function<std::int64_t(std::int64_t deadline_ns)>;

  /// Starts at `start_ns` (ns).
  explicit VirtualClock(std::int64_t start_ns = 0) noexcept : now_ns_(start_ns) {}

  std::int64_t Now() noexcept override { return now_ns_.load(std::memory_order_relaxed); }
  /// Time becomes max(Now(), deadline_ns), plus the hook's lateness if a hook is set.
  void SleepUntil(std::int64_t deadline_ns) noexcept override;

  /// Moves time forward by `duration_ns` (ns; negative values are ignored: time never goes back).
  void Advance(std::int64_t duration_ns) noexcept;
  /// Sets the lateness hook (empty: no lateness). Setup only.
  void SetLatenessHook(LatenessHook hook) { lateness_hook_ = std::move(hook); }
  /// How many times SleepUntil was called.
  std::int64_t sleeps() const noexcept { return sleeps_; }

 private:
  std::atomic<std::int64_t> now_ns_;
  std::int64_t sleeps_ = 0;
  LatenessHook lateness_hook_;
};

}  // namespace ambdrop
