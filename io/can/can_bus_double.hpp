#pragma once
// An in-memory CAN bus with the semantics of the kernel's CAN_RAW sockets on a vcan interface,
// for tests and for runs without a CAN adapter. Endpoints exchange the same 16/72-byte records
// the kernel would, and the rules are the kernel's (net/can/raw.c, af_can.c, drivers/net/can/
// vcan.c):
//   - a write must be 16 bytes (struct can_frame), or 72 (struct canfd_frame) when the endpoint
//     enabled FD frames and the bus is FD-capable; a classic len above 8 or an FD len above 64 is
//     refused too. Refusals return -EINVAL; a bus set down returns -ENETDOWN;
//   - FD records get CANFD_FDF set, as can_send() does (Linux 6.2+ and Debian 12's 6.1);
//   - every frame goes to every other endpoint (a broadcast medium), and back to the sender only
//     if it asked (recv_own_msgs); with loopback off, no endpoint sees it (vcan has no wire);
//   - an endpoint without FD frames silently never sees FD frames; its filters
//     (CAN_RAW_FILTER, CAN_RAW_JOIN_FILTERS) pick what it receives; error frames go nowhere (no
//     endpoint has an error mask, the kernel's default);
//   - a full receive queue drops the frame at that receiver and counts it (receive_overflows,
//     the kernel's SO_RXQ_OVFL); the sender is never blocked or told;
//   - a read returns one whole record (truncated to the buffer with MSG_TRUNC, the rest of that
//     record discarded, as the kernel does), never 0 bytes: a 0-byte buffer is refused with
//     -EINVAL (the kernel would return 0 and discard the frame), and there is no end of stream.
// tests/socketcan_test.cpp (KernelAndDoubleAgreeByteForByte) writes the same records to vcan0
// and to a double and checks that write results, delivered bytes and msg_flags are identical.
// The queues are fixed-size rings allocated when an endpoint is made; writes and reads do not
// allocate. One mutex (per bus) guards the queues: any number of threads may write and read,
// which covers one writer and one reader per endpoint. The bus must outlive its endpoints.
#include <sys/types.h>

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

#include "io/can/can_bus.hpp"

namespace ambdrop {

class CanBusDouble;

/// A clock for receive timestamps, ns.
using CanClock = std::int64_t (*)() noexcept;

/// CLOCK_MONOTONIC, ns (the default clock of a VirtualCanBus).
std::int64_t CanMonotonicNowNs() noexcept;

/// The medium (like one vcan interface) that CanBusDouble endpoints attach to.
class VirtualCanBus {
 public:
  /// `fd_capable`: the interface MTU is CANFD_MTU (vcan's default), so FD frames may pass;
  /// false models an MTU of CAN_MTU (`ip link set vcan0 mtu 16`).
  explicit VirtualCanBus(bool fd_capable = true);
  ~VirtualCanBus();
  VirtualCanBus(const VirtualCanBus&) = delete;
  VirtualCanBus& operator=(const VirtualCanBus&) = delete;

  bool fd_capable() const noexcept { return fd_capable_; }

  /// Interface up (default) or down: writes to a down bus fail with ENETDOWN.
  void SetLinkUp(bool up);
  /// The next `count` writes fail with `error_number` (e.g. ENOBUFS for a full transmit queue).
  void FailNextWrites(int error_number, int count);
  /// Where receive timestamps come from (e.g. a fake clock for deterministic tests).
  void SetClock(CanClock clock);
  /// Endpoints attached now.
  std::size_t endpoint_count() const;

 private:
  friend class CanBusDouble;

  const bool fd_capable_;
  mutable std::mutex mutex_;  // guards everything below and every endpoint's queue
  std::vector<CanBusDouble*> endpoints_;
  bool link_up_ = true;
  int fail_errno_ = 0;
  int fail_count_ = 0;
  CanClock clock_;
};

/// What recvmsg() would report besides the bytes.
struct CanRecordInfo {
  std::int64_t timestamp_ns = 0;  ///< the bus clock when the record was written, ns
  /// MSG_DONTROUTE (sent from this host: always, on a virtual bus), MSG_CONFIRM (our own frame),
  /// MSG_TRUNC (the record was longer than the buffer).
  int msg_flags = 0;
};

/// One endpoint (one CAN_RAW socket) on a VirtualCanBus.
class CanBusDouble final : public CanBus {
 public:
  /// Default receive queue, frames (about what a default socket buffer holds on vcan).
  static constexpr std::size_t kDefaultQueueFrames = 256;

  /// Attaches to `bus` with the given socket options; the receive queue holds `queue_frames`
  /// records (>= 1, else CanBusError). As with the kernel, fd_frames is accepted on a bus that
  /// is not FD-capable; FD writes then fail with EINVAL.
  CanBusDouble(VirtualCanBus& bus, CanSocketOptions options = {},
               std::size_t queue_frames = kDefaultQueueFrames);
  ~CanBusDouble() override;

  /// write(2) on the socket: `record.size()` bytes. Returns the size written, or -errno.
  ssize_t WriteRecord(std::span<const std::uint8_t> record) noexcept;
  /// recvmsg(2): waits up to `timeout` (0: poll; negative: no limit) for a record and copies it
  /// (truncated to the buffer). Returns the bytes copied, -EAGAIN after the timeout, -EINVAL for
  /// an empty buffer.
  ssize_t ReadRecord(std::span<std::uint8_t> buffer, std::chrono::nanoseconds timeout,
                     CanRecordInfo* info = nullptr) noexcept;

  /// setsockopt(CAN_RAW_FILTER) while attached; takes effect for frames written afterwards.
  /// Allocates: setup only.
  void SetFilters(std::vector<CanFilter> filters);

  [[nodiscard]] CanStatus Send(const CanFrame& frame) noexcept override;
  [[nodiscard]] CanStatus Receive(CanFrame* frame,
                                  std::chrono::nanoseconds timeout) noexcept override;
  CanBusCounters counters() const noexcept override { return counters_.Snapshot(); }
  bool fd_enabled() const noexcept override { return options_.fd_frames && bus_.fd_capable(); }
  int last_errno() const noexcept override { return last_errno_.load(std::memory_order_relaxed); }

  /// Records waiting in the receive queue.
  std::size_t queued() const;
  std::size_t queue_capacity() const noexcept { return slots_.size(); }

 private:
  struct Slot {
    std::array<std::uint8_t, kCanFdMtu> bytes;
    std::uint8_t size;
    bool own;
    std::int64_t timestamp_ns;
  };
  using Deadline = std::chrono::steady_clock::time_point;

  /// Under the bus mutex: queue a record for this endpoint if its options and filters take it.
  void DeliverLocked(const Slot& slot, std::uint32_t can_id, bool from_self) noexcept;
  ssize_t ReadUntil(std::span<std::uint8_t> buffer, bool wait, bool forever, Deadline deadline,
                    CanRecordInfo* info) noexcept;
  void SetErrno(int error_number) noexcept {
    last_errno_.store(error_number, std::memory_order_relaxed);
  }

  VirtualCanBus& bus_;
  CanSocketOptions options_;
  std::vector<Slot> slots_;  // ring, sized at construction
  std::size_t head_ = 0;     // oldest record
  std::size_t count_ = 0;
  std::condition_variable readable_;
  can_detail::AtomicCanBusCounters counters_;
  std::atomic<int> last_errno_{0};
};

}  // namespace ambdrop
