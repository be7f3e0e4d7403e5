#pragma once
// The CAN transport behind a small interface: SocketCanBus talks to the kernel (CAN_RAW),
// CanBusDouble is an in-memory bus with the same records and semantics, for tests and for runs
// without hardware. Opening a bus may allocate, block and throw (CanBusError); Send and Receive
// do none of these and report through a [[nodiscard]] CanStatus plus counters.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "io/can/can_frame.hpp"

namespace ambdrop {

/// A bus that cannot be opened (no CAN in the kernel, no such interface, ...). what() says which
/// and what to do about it.
class CanBusError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Result of one Send or Receive.
enum class CanStatus : std::uint8_t {
  kOk,          ///< one frame sent, or one frame received
  kWouldBlock,  ///< Receive: no frame arrived within the timeout (0 = just polled)
  kDropped,     ///< Send: the transmit queue is full (ENOBUFS/EAGAIN); the frame is lost, counted
  kInvalid,     ///< Send: the frame cannot go on this bus (not IsValid, or FD on a classic
                ///< socket/interface: EINVAL); nothing was sent
  kError,       ///< anything else (interface down, ...); see last_errno()
};

/// "ok", "would block", ... for messages.
constexpr const char* ToString(CanStatus status) noexcept {
  switch (status) {
    case CanStatus::kOk:
      return "ok";
    case CanStatus::kWouldBlock:
      return "would block";
    case CanStatus::kDropped:
      return "dropped";
    case CanStatus::kInvalid:
      return "invalid";
    case CanStatus::kError:
      return "error";
  }
  return "?";
}

/// Cumulative counts of one bus endpoint since it was opened, in frames (or calls).
struct CanBusCounters {
  std::uint64_t sent = 0;          ///< Send returned kOk
  std::uint64_t send_dropped = 0;  ///< Send returned kDropped
  std::uint64_t send_invalid = 0;  ///< Send returned kInvalid
  std::uint64_t send_errors = 0;   ///< Send returned kError
  std::uint64_t received = 0;      ///< Receive returned kOk
  /// Frames lost at this endpoint because its receive queue was full (the kernel's
  /// SO_RXQ_OVFL count; the double's full queue). The sender is never blocked by them.
  std::uint64_t receive_overflows = 0;
  /// Records read but not delivered: wrong size, truncated, error frames, bad ids (skipped).
  std::uint64_t receive_invalid = 0;
  std::uint64_t receive_errors = 0;  ///< Receive returned kError
};

/// The kernel's CAN_INV_FILTER bit of can_filter.can_id (inverts the match).
inline constexpr std::uint32_t kCanInvFilter = 0x20000000U;

/// One CAN_RAW_FILTER entry (struct can_filter): a received can_id (with CAN_EFF_FLAG and
/// CAN_RTR_FLAG bits) matches when `received & can_mask == can_id & can_mask`, inverted when
/// can_id has kCanInvFilter.
struct CanFilter {
  std::uint32_t can_id = 0;
  std::uint32_t can_mask = 0;

  /// Exactly this data frame: the id, its format (11/29-bit) and no RTR.
  static constexpr CanFilter Exact(std::uint32_t id, bool extended) noexcept {
    return extended ? CanFilter{id | kCanEffFlag, kCanEffMaxId | kCanEffFlag | kCanRtrFlag}
                    : CanFilter{id, kCanSffMaxId | kCanEffFlag | kCanRtrFlag};
  }
  bool operator==(const CanFilter&) const = default;
};

/// Whether a data frame with `can_id` (flags included) passes `filter`, exactly as the kernel's
/// receive lists decide (net/can/af_can.c): a mask with CAN_ERR_FLAG selects error frames only;
/// a filter for an 11-bit id that checks CAN_EFF_FLAG ignores id bits above 0x7FF.
constexpr bool CanFilterMatches(const CanFilter& filter, std::uint32_t can_id) noexcept {
  if ((filter.can_mask & kCanErrFlag) != 0) return false;  // an error-frame filter
  if ((can_id & kCanErrFlag) != 0) return false;           // error frames need an error filter
  std::uint32_t mask = filter.can_mask;
  if ((mask & kCanEffFlag) != 0 && (filter.can_id & kCanEffFlag) == 0) {
    mask &= kCanSffMaxId | kCanEffFlag | kCanRtrFlag;
  }
  const bool equal = (can_id & mask) == (filter.can_id & mask);
  return (filter.can_id & kCanInvFilter) != 0 ? !equal : equal;
}

/// Whether a socket with these filters receives `can_id`: any filter matches (each frame is
/// delivered once however many match), or, with CAN_RAW_JOIN_FILTERS, all of them do. No filters
/// at all means nothing is received.
constexpr bool CanFiltersAccept(std::span<const CanFilter> filters, bool join_filters,
                                std::uint32_t can_id) noexcept {
  std::size_t matches = 0;
  for (const CanFilter& filter : filters) {
    if (CanFilterMatches(filter, can_id)) ++matches;
  }
  return join_filters ? (matches == filters.size() && matches > 0) : matches > 0;
}

/// The CAN_RAW socket options, with the kernel's defaults. SocketCanBus sets them on its socket;
/// CanBusDouble applies the same rules in memory.
struct CanSocketOptions {
  bool fd_frames = false;      ///< CAN_RAW_FD_FRAMES: may send and receive 72-byte FD records
  bool loopback = true;        ///< CAN_RAW_LOOPBACK: other sockets on this host see our frames
  bool recv_own_msgs = false;  ///< CAN_RAW_RECV_OWN_MSGS: we see our own frames
  bool join_filters = false;   ///< CAN_RAW_JOIN_FILTERS: a frame must pass all filters
  /// CAN_RAW_FILTER. The default {0, 0} passes everything; an empty list passes nothing.
  std::vector<CanFilter> filters = {CanFilter{0, 0}};
};

/// A CAN bus endpoint (one CAN_RAW socket). One thread may Send while another Receives; neither
/// call allocates, locks for long, throws or blocks longer than asked.
class CanBus {
 public:
  virtual ~CanBus() = default;

  /// Queues one frame for transmission without blocking.
  [[nodiscard]] virtual CanStatus Send(const CanFrame& frame) noexcept = 0;

  /// Waits up to `timeout` (0: poll once; negative: no limit) for one frame and writes it to
  /// `*frame`, timestamp included. Records that are not valid data frames are counted in
  /// receive_invalid and skipped. Returns kOk, kWouldBlock or kError.
  [[nodiscard]] virtual CanStatus Receive(CanFrame* frame,
                                          std::chrono::nanoseconds timeout) noexcept = 0;

  /// A snapshot of the counters; may be read from any thread.
  virtual CanBusCounters counters() const noexcept = 0;

  /// Whether FD frames may be sent and received (CAN_RAW_FD_FRAMES on an FD-capable interface).
  virtual bool fd_enabled() const noexcept = 0;

  /// errno of the last failed call (0 if none); for diagnostics after kError.
  virtual int last_errno() const noexcept = 0;

 protected:
  CanBus() = default;
  CanBus(const CanBus&) = delete;
  CanBus& operator=(const CanBus&) = delete;
};

namespace can_detail {

/// Counters written by the sending and the receiving thread and read by any: each field has a
/// single writer, so relaxed atomics are enough.
struct AtomicCanBusCounters {
  std::atomic<std::uint64_t> sent{0};
  std::atomic<std::uint64_t> send_dropped{0};
  std::atomic<std::uint64_t> send_invalid{0};
  std::atomic<std::uint64_t> send_errors{0};
  std::atomic<std::uint64_t> received{0};
  std::atomic<std::uint64_t> receive_overflows{0};
  std::atomic<std::uint64_t> receive_invalid{0};
  std::atomic<std::uint64_t> receive_errors{0};

  static void Add(std::atomic<std::uint64_t>& counter, std::uint64_t n = 1) noexcept {
    counter.fetch_add(n, std::memory_order_relaxed);
  }
  /// Counts a Send result.
  void CountSend(CanStatus status) noexcept {
    switch (status) {
      case CanStatus::kOk:
        Add(sent);
        break;
      case CanStatus::kDropped:
        Add(send_dropped);
        break;
      case CanStatus::kInvalid:
        Add(send_invalid);
        break;
      case CanStatus::kError:
        Add(send_errors);
        break;
      case CanStatus::kWouldBlock:
        break;
    }
  }
  CanBusCounters Snapshot() const noexcept {
    constexpr auto kRelaxed = std::memory_order_relaxed;
    return CanBusCounters{.sent = sent.load(kRelaxed),
                          .send_dropped = send_dropped.load(kRelaxed),
                          .send_invalid = send_invalid.load(kRelaxed),
                          .send_errors = send_errors.load(kRelaxed),
                          .received = received.load(kRelaxed),
                          .receive_overflows = receive_overflows.load(kRelaxed),
                          .receive_invalid = receive_invalid.load(kRelaxed),
                          .receive_errors = receive_errors.load(kRelaxed)};
  }
};

}  // namespace can_detail
}  // namespace ambdrop
