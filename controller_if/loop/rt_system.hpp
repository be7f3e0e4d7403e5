#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ambdrop {

/// The operating-system calls that make a thread real-time, behind an interface so tests can
/// run without privileges (RtSystemDouble) and check what a setup asked for. Each call returns 0
/// on success or an errno value (EPERM, EINVAL, ...), never throws, and applies to the calling
/// thread except LockMemory/UnlockMemory, which apply to the whole process. Setup-time only.
class RtSystem {
 public:
  virtual ~RtSystem() = default;
  /// Locks every current and future page of the process in RAM (mlockall(MCL_CURRENT |
  /// MCL_FUTURE)), so the loop never takes a page fault on first touch or after swapping.
  virtual int LockMemory() noexcept = 0;
  /// Undoes LockMemory (munlockall), e.g. when a run ends inside a longer-lived process.
  virtual int UnlockMemory() noexcept = 0;
  /// SCHED_FIFO at `priority` (1..99 on Linux) for the calling thread.
  virtual int SetFifoPriority(int priority) noexcept = 0;
  /// Pins the calling thread to CPU `cpu` (0-based).
  virtual int SetCpuAffinity(int cpu) noexcept = 0;
  /// Timer slack of the calling thread (ns, >= 1). Linux defers timer wake-ups of normal threads
  /// by up to 50 us to batch them; 1 ns removes that from the loop's lateness.
  virtual int SetTimerSlack(std::int64_t slack_ns) noexcept = 0;
};

/// The real calls: mlockall/munlockall, pthread_setschedparam(pthread_self(), SCHED_FIFO),
/// pthread_setaffinity_np, prctl(PR_SET_TIMERSLACK).
class LinuxRtSystem final : public RtSystem {
 public:
  int LockMemory() noexcept override;
  int UnlockMemory() noexcept override;
  int SetFifoPriority(int priority) noexcept override;
  int SetCpuAffinity(int cpu) noexcept override;
  int SetTimerSlack(std::int64_t slack_ns) noexcept override;
};

/// In-memory double of RtSystem with Linux's argument checks: priority outside 1..99, a CPU
/// outside [0, cpu_count) and a slack < 1 ns give EINVAL, as the kernel does. It records each call
/// and the resulting state, and can be told to fail a given call with a chosen errno (as an
/// unprivileged process or a container without CAP_SYS_NICE would). A failed call changes no
/// state. Not thread-safe: one thread sets up, then the test reads.
class RtSystemDouble final : public RtSystem {
 public:
  enum class Call { kLockMemory, kUnlockMemory, kSetFifoPriority, kSetCpuAffinity, kSetTimerSlack };
  struct Record {
    Call call;
    std::int64_t argument;  ///< priority, CPU or slack (ns); 0 for the memory calls
    int result;             ///< 0 or the errno returned
  };

  /// A machine with `cpu_count` CPUs.
  explicit RtSystemDouble(int cpu_count = 2) : cpu_count_(cpu_count) {}

  int LockMemory() noexcept override;
  int UnlockMemory() noexcept override;
  int SetFifoPriority(int priority) noexcept override;
  int SetCpuAffinity(int cpu) noexcept override;
  int SetTimerSlack(std::int64_t slack_ns) noexcept override;

  /// From now on `call` fails with `error` (an errno; 0 makes it succeed again).
  void FailWith(Call call, int error) { fail_with_[static_cast<int>(call)] = error; }

  const std::vector<Record>& calls() const { return calls_; }
  bool memory_locked() const { return memory_locked_; }
  /// 0 while the (simulated) thread is still SCHED_OTHER.
  int fifo_priority() const { return fifo_priority_; }
  /// -1 while the thread may run on any CPU.
  int cpu() const { return cpu_; }
  /// Linux's default for a normal thread: 50 us.
  std::int64_t timer_slack_ns() const { return timer_slack_ns_; }

 private:
  int Finish(Call call, std::int64_t argument, int result) noexcept;

  int cpu_count_;
  int fail_with_[5] = {0, 0, 0, 0, 0};
  std::vector<Record> calls_;
  bool memory_locked_ = false;
  int fifo_priority_ = 0;
  int cpu_ = -1;
  std::int64_t timer_slack_ns_ = 50'000;
};

/// What a run asks of the operating system, typically from its config.
struct RtRequest {
  int priority = 0;                 ///< SCHED_FIFO priority 1..99; 0: stay SCHED_OTHER
  int cpu = -1;                     ///< CPU to pin the loop thread to; -1: any
  bool lock_memory = false;         ///< mlockall the process
  bool enforce = false;             ///< any failure is an error (throws) instead of a warning
  std::int64_t timer_slack_ns = 1;  ///< timer slack (ns); <= 0: leave unchanged
};

/// What RequestRealtime obtained. A request item not asked for is reported as not granted.
struct RtGrant {
  bool memory_locked = false;
  bool fifo = false;
  int priority = 0;  ///< the SCHED_FIFO priority granted, 0 if none
  bool pinned = false;
  int cpu = -1;  ///< the CPU pinned to, -1 if none
  bool timer_slack_set = false;
  std::vector<std::string> warnings;  ///< one human-readable line per item refused
  /// Everything requested was granted.
  bool complete() const { return warnings.empty(); }
};

/// The kernel's real-time throttling (/proc/sys/kernel/sched_rt_runtime_us and
/// sched_rt_period_us): SCHED_FIFO threads together may run at most runtime_us out of every
/// period_us on a CPU; past that they are stopped until the next period starts. Linux's default
/// is 950 000 of 1 000 000 us, so a FIFO thread that never sleeps stalls ~50 ms every second
/// (measured here with a MonotonicClock spinning for most of a 50 us period).
struct RtThrottling {
  std::int64_t runtime_us = 950'000;  ///< < 0 (-1): throttling off
  std::int64_t period_us = 1'000'000;
};

/// The throttling settings from /proc/sys/kernel; nullopt when they cannot be read.
std::optional<RtThrottling> ReadRtThrottling();

/// A warning (empty: none) when a SCHED_FIFO loop of period `loop_period_ns` that polls the
/// clock for `spin_ns` before each deadline risks throttling: throttling is on and the spin
/// alone takes at least half the share the kernel allows (the compute, the wake-up and other RT
/// threads take the rest). The loop then sleeps too little, or not at all when the wake-up
/// latency exceeds the time left to sleep.
std::string RtThrottlingWarning(std::int64_t spin_ns, std::int64_t loop_period_ns,
                                const RtThrottling& throttling);

/// Applies `request` to the calling thread (and, for memory, the process): call it from the loop
/// thread before running the loop. Tries every item even after a failure, so the warnings list
/// all of them. Setup only: allocates. Throws std::runtime_error naming every refused item and
/// the likely cause when `request.enforce` is set and anything was refused; the items that did
/// succeed stay applied.
RtGrant RequestRealtime(RtSystem& system, const RtRequest& request);

}  // namespace ambdrop
