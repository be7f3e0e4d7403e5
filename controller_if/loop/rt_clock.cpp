#include "controller_if/loop/rt_clock.hpp"

#include <time.h>

#include <cerrno>

namespace ambdrop {

std::int64_t MonotonicClock::Now() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);  // cannot fail for CLOCK_MONOTONIC with a valid pointer
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerSecond + ts.tv_nsec;
}

namespace {

// Sleeps until the absolute CLOCK_MONOTONIC time `deadline_ns`.
void SleepAbsolute(std::int64_t deadline_ns) noexcept {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline_ns / kNsPerSecond);
  ts.tv_nsec = static_cast<long>(deadline_ns % kNsPerSecond);
  if (ts.tv_nsec < 0) {  // a negative deadline (already passed): keep tv_nsec in [0, 1e9)
    ts.tv_nsec += kNsPerSecond;
    --ts.tv_sec;
  }
  // With TIMER_ABSTIME the same deadline can be passed again after a signal: no drift from
  // restarting. clock_nanosleep returns the error number itself, not through errno.
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

}  // namespace

void MonotonicClock::SleepUntil(std::int64_t deadline_ns) noexcept {
  if (spin_ns_ == 0) {
    SleepAbsolute(deadline_ns);
    return;
  }
  const std::int64_t wake_ns = deadline_ns - spin_ns_;
  if (Now() < wake_ns) SleepAbsolute(wake_ns);
  while (Now() < deadline_ns) {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();  // tells the core (and a hyperthread sibling) this is a spin
#endif
  }
}

void VirtualClock::SleepUntil(std::int64_t deadline_ns) noexcept {
  ++sleeps_;
  std::int64_t now = now_ns_.load(std::memory_order_relaxed);
  if (deadline_ns > now) now = deadline_ns;
  if (lateness_hook_) {
    const std::int64_t late_ns = lateness_hook_(deadline_ns);
    if (late_ns > 0) now += late_ns;
  }
  now_ns_.store(now, std::memory_order_relaxed);
}

void VirtualClock::Advance(std::int64_t duration_ns) noexcept {
  if (duration_ns > 0) now_ns_.fetch_add(duration_ns, std::memory_order_relaxed);
}

}  // namespace ambdrop
