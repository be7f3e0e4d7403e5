#pragma once
// The real CAN adapter: one Linux CAN_RAW socket (PF_CAN, SOCK_RAW) bound to an interface
// (can0, vcan0, ...). Opening it is setup: it may allocate and throws CanBusError with what went
// wrong and what to do (no CAN in the kernel, no such interface, interface down, no FD on a
// classic interface). Send and Receive are non-blocking system calls (write, recvmsg, ppoll)
// with no allocation.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "io/can/can_bus.hpp"

namespace ambdrop {

/// Where a received frame's timestamp comes from.
enum class CanTimestampSource : std::uint8_t {
  /// The kernel's receive time (SO_TIMESTAMPNS), CLOCK_REALTIME, ns: when the frame reached the
  /// CAN stack, so it excludes our own scheduling delay.
  kKernel,
  /// clock_gettime(CLOCK_MONOTONIC) right after the read, ns: the clock the real-time loop
  /// uses for its deadlines.
  kMonotonicAtRead,
};

/// How to open a SocketCanBus.
struct SocketCanOptions {
  std::string interface = "vcan0";  ///< network interface name
  CanSocketOptions socket;          ///< CAN_RAW options (FD, loopback, filters, ...)
  CanTimestampSource timestamp = CanTimestampSource::kKernel;
  /// SO_RCVBUF, bytes; 0 keeps the system default (about 200-300 frames of queue).
  int receive_buffer_bytes = 0;
};

/// A CAN_RAW socket as a CanBus.
class SocketCanBus final : public CanBus {
 public:
  /// Opens, configures and binds the socket; throws CanBusError on any failure.
  explicit SocketCanBus(const SocketCanOptions& options);
  ~SocketCanBus() override;

  [[nodiscard]] CanStatus Send(const CanFrame& frame) noexcept override;
  [[nodiscard]] CanStatus Receive(CanFrame* frame,
                                  std::chrono::nanoseconds timeout) noexcept override;
  CanBusCounters counters() const noexcept override { return counters_.Snapshot(); }
  bool fd_enabled() const noexcept override { return fd_enabled_; }
  int last_errno() const noexcept override { return last_errno_.load(std::memory_order_relaxed); }

  const std::string& interface() const noexcept { return interface_; }
  /// The interface MTU, bytes: 16 (classic only) or 72 (CAN FD capable).
  int interface_mtu() const noexcept { return mtu_; }
  /// The socket, for an outside poll loop.
  int fd() const noexcept { return fd_; }

 private:
  void SetErrno(int error_number) noexcept {
    last_errno_.store(error_number, std::memory_order_relaxed);
  }

  std::string interface_;
  int fd_ = -1;
  int mtu_ = 0;
  bool fd_enabled_ = false;
  CanTimestampSource timestamp_;
  std::uint32_t last_overflow_count_ = 0;  // the kernel's cumulative SO_RXQ_OVFL value
  can_detail::AtomicCanBusCounters counters_;
  std::atomic<int> last_errno_{0};
};

/// Whether this kernel has CAN_RAW sockets at all (socket(PF_CAN, SOCK_RAW, CAN_RAW) works).
bool SocketCanAvailable() noexcept;

/// Whether a CAN interface with this name exists (and the kernel has CAN). Does not throw.
bool CanInterfaceExists(const std::string& interface) noexcept;

}  // namespace ambdrop
