#include "controller_if/loop/rt_system.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace ambdrop {

// ---------------------------------------------------------------------------------------------
// LinuxRtSystem

int LinuxRtSystem::LockMemory() noexcept {
  return mlockall(MCL_CURRENT | MCL_FUTURE) == 0 ? 0 : errno;
}

int LinuxRtSystem::UnlockMemory() noexcept {
  return munlockall() == 0 ? 0 : errno;
}

int LinuxRtSystem::SetFifoPriority(int priority) noexcept {
  sched_param param{};
  param.sched_priority = priority;
  // pthread_* return the error number rather than setting errno.
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
}

int LinuxRtSystem::SetCpuAffinity(int cpu) noexcept {
  if (cpu < 0 || cpu >= CPU_SETSIZE) return EINVAL;  // CPU_SET out of range is undefined
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
}

int LinuxRtSystem::SetTimerSlack(std::int64_t slack_ns) noexcept {
  if (slack_ns < 1) return EINVAL;  // 0 would mean "back to the default", not "no slack"
  return prctl(PR_SET_TIMERSLACK, static_cast<unsigned long>(slack_ns), 0, 0, 0) == 0 ? 0 : errno;
}

// ---------------------------------------------------------------------------------------------
// RtSystemDouble

int RtSystemDouble::Finish(Call call, std::int64_t argument, int result) noexcept {
  // calls_ is a test double's log: it may allocate, and a failed push_back would only lose a
  // record, so swallow bad_alloc rather than break noexcept.
  try {
    calls_.push_back(Record{call, argument, result});
  } catch (...) {
  }
  return result;
}

int RtSystemDouble::LockMemory() noexcept {
  const int injected = fail_with_[static_cast<int>(Call::kLockMemory)];
  if (injected == 0) memory_locked_ = true;
  return Finish(Call::kLockMemory, 0, injected);
}

int RtSystemDouble::UnlockMemory() noexcept {
  const int injected = fail_with_[static_cast<int>(Call::kUnlockMemory)];
  if (injected == 0) memory_locked_ = false;
  return Finish(Call::kUnlockMemory, 0, injected);
}

int RtSystemDouble::SetFifoPriority(int priority) noexcept {
  int result = fail_with_[static_cast<int>(Call::kSetFifoPriority)];
  if (result == 0 && (priority < 1 || priority > 99)) result = EINVAL;
  if (result == 0) fifo_priority_ = priority;
  return Finish(Call::kSetFifoPriority, priority, result);
}

int RtSystemDouble::SetCpuAffinity(int cpu) noexcept {
  int result = fail_with_[static_cast<int>(Call::kSetCpuAffinity)];
  if (result == 0 && (cpu < 0 || cpu >= cpu_count_)) result = EINVAL;
  if (result == 0) cpu_ = cpu;
  return Finish(Call::kSetCpuAffinity, cpu, result);
}

int RtSystemDouble::SetTimerSlack(std::int64_t slack_ns) noexcept {
  int result = fail_with_[static_cast<int>(Call::kSetTimerSlack)];
  if (result == 0 && slack_ns < 1) result = EINVAL;
  if (result == 0) timer_slack_ns_ = slack_ns;
  return Finish(Call::kSetTimerSlack, slack_ns, result);
}

// ---------------------------------------------------------------------------------------------
// RequestRealtime

namespace {

// "EPERM (Operation not permitted)": the symbolic name is what people search for.
std::string DescribeErrno(int error) {
  const char* name = strerrorname_np(error);
  const char* text = strerrordesc_np(error);
  std::string out = name != nullptr ? name : "errno " + std::to_string(error);
  if (text != nullptr) out += std::string(" (") + text + ")";
  return out;
}

std::string MemoryHint(int error) {
  switch (error) {
    case EPERM:
      return "needs root or CAP_IPC_LOCK";
    case ENOMEM:
      return "the RLIMIT_MEMLOCK limit is too small (ulimit -l), or not enough RAM";
    case EAGAIN:
      return "some pages could not be locked";
    default:
      return "";
  }
}

std::string FifoHint(int error) {
  switch (error) {
    case EPERM:
      return "needs root, CAP_SYS_NICE or RLIMIT_RTPRIO >= the priority (ulimit -r); user "
             "namespaces (unshare -r, rootless containers) refuse it even to their root";
    case EINVAL:
      return "the SCHED_FIFO priority must be 1..99";
    default:
      return "";
  }
}

std::string AffinityHint(int error) {
  switch (error) {
    case EINVAL:
      return "that CPU does not exist or is outside this process's cpuset";
    case EPERM:
      return "not allowed to change this thread's affinity";
    default:
      return "";
  }
}

std::string Refusal(const std::string& what, int error, const std::string& hint,
                    const std::string& consequence) {
  std::string line = what + " refused: " + DescribeErrno(error);
  if (!hint.empty()) line += "; " + hint;
  return line + "; " + consequence;
}

}  // namespace

std::optional<RtThrottling> ReadRtThrottling() {
  const auto read = [](const char* path) -> std::optional<std::int64_t> {
    std::ifstream file(path);
    std::int64_t value = 0;
    if (!(file >> value)) return std::nullopt;
    return value;
  };
  const std::optional<std::int64_t> runtime = read("/proc/sys/kernel/sched_rt_runtime_us");
  const std::optional<std::int64_t> period = read("/proc/sys/kernel/sched_rt_period_us");
  if (!runtime || !period || *period <= 0) return std::nullopt;
  return RtThrottling{*runtime, *period};
}

std::string RtThrottlingWarning(std::int64_t spin_ns, std::int64_t loop_period_ns,
                                const RtThrottling& throttling) {
  if (throttling.runtime_us < 0 || spin_ns <= 0 || loop_period_ns <= 0) return "";
  if (throttling.period_us <= 0) return "";
  const double spin_share = static_cast<double>(spin_ns) / static_cast<double>(loop_period_ns);
  const double allowed_share =
      static_cast<double>(throttling.runtime_us) / static_cast<double>(throttling.period_us);
  if (spin_share < 0.5 * allowed_share) return "";
  char text[512];
  std::snprintf(text, sizeof(text),
                "a SCHED_FIFO loop spinning %.1f us of each %.1f us period risks the kernel's RT "
                "throttling (sched_rt_runtime_us = %lld of sched_rt_period_us = %lld): the loop "
                "would stall for ~%.0f ms every %.0f ms. Use a shorter spin, normal scheduling, "
                "or an isolated CPU with throttling off (echo -1 > "
                "/proc/sys/kernel/sched_rt_runtime_us)",
                static_cast<double>(spin_ns) / 1e3, static_cast<double>(loop_period_ns) / 1e3,
                static_cast<long long>(throttling.runtime_us),
                static_cast<long long>(throttling.period_us),
                static_cast<double>(throttling.period_us - throttling.runtime_us) / 1e3,
                static_cast<double>(throttling.period_us) / 1e3);
  return text;
}

RtGrant RequestRealtime(RtSystem& system, const RtRequest& request) {
  RtGrant grant;
  // Memory first: it is process-wide and the others do not depend on it.
  if (request.lock_memory) {
    const int error = system.LockMemory();
    if (error == 0) {
      grant.memory_locked = true;
    } else {
      grant.warnings.push_back(Refusal("mlockall(MCL_CURRENT | MCL_FUTURE)", error,
                                       MemoryHint(error),
                                       "page faults may delay the loop by milliseconds"));
    }
  }
  if (request.timer_slack_ns > 0) {
    const int error = system.SetTimerSlack(request.timer_slack_ns);
    if (error == 0) {
      grant.timer_slack_set = true;
    } else {
      grant.warnings.push_back(
          Refusal("timer slack of " + std::to_string(request.timer_slack_ns) + " ns", error, "",
                  "wake-ups may come up to 50 us late"));
    }
  }
  // Pin before raising the priority, so the thread does not start competing for a CPU it is
  // about to leave.
  if (request.cpu >= 0) {
    const int error = system.SetCpuAffinity(request.cpu);
    if (error == 0) {
      grant.pinned = true;
      grant.cpu = request.cpu;
    } else {
      grant.warnings.push_back(Refusal("pinning to CPU " + std::to_string(request.cpu), error,
                                       AffinityHint(error), "the loop may migrate between CPUs"));
    }
  }
  if (request.priority != 0) {
    const int error = system.SetFifoPriority(request.priority);
    if (error == 0) {
      grant.fifo = true;
      grant.priority = request.priority;
    } else {
      grant.warnings.push_back(Refusal("SCHED_FIFO priority " + std::to_string(request.priority),
                                       error, FifoHint(error),
                                       "the loop runs under normal scheduling (SCHED_OTHER)"));
    }
  }
  if (request.enforce && !grant.complete()) {
    std::string message = "real-time setup was refused and is enforced:";
    for (const std::string& w : grant.warnings) message += "\n  " + w;
    throw std::runtime_error(message);
  }
  return grant;
}

}  // namespace ambdrop
