#include "io/can/can_bus_double.hpp"

#include <linux/can.h>
#include <sys/socket.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace ambdrop {
namespace {

// Byte positions inside a record (struct can_frame / canfd_frame).
constexpr std::size_t kLenOffset = offsetof(struct canfd_frame, len);
constexpr std::size_t kFlagsOffset = offsetof(struct canfd_frame, flags);
static_assert(offsetof(struct can_frame, len) == kLenOffset);

CanStatus SendStatusOf(ssize_t result) noexcept {
  if (result >= 0) return CanStatus::kOk;
  switch (-result) {
    case EINVAL:
      return CanStatus::kInvalid;
    case ENOBUFS:
    case EAGAIN:
      return CanStatus::kDropped;
    default:
      return CanStatus::kError;
  }
}

}  // namespace

std::int64_t CanMonotonicNowNs() noexcept {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

VirtualCanBus::VirtualCanBus(bool fd_capable)
    : fd_capable_(fd_capable), clock_(&CanMonotonicNowNs) {}

VirtualCanBus::~VirtualCanBus() {
  // An endpoint left behind would later lock a destroyed mutex: fail loudly now instead.
  if (!endpoints_.empty()) {
    std::fprintf(stderr, "VirtualCanBus destroyed with %zu endpoint(s) still attached\n",
                 endpoints_.size());
    std::abort();
  }
}

void VirtualCanBus::SetLinkUp(bool up) {
  const std::lock_guard lock(mutex_);
  link_up_ = up;
}

void VirtualCanBus::FailNextWrites(int error_number, int count) {
  const std::lock_guard lock(mutex_);
  fail_errno_ = error_number;
  fail_count_ = count;
}

void VirtualCanBus::SetClock(CanClock clock) {
  const std::lock_guard lock(mutex_);
  clock_ = clock != nullptr ? clock : &CanMonotonicNowNs;
}

std::size_t VirtualCanBus::endpoint_count() const {
  const std::lock_guard lock(mutex_);
  return endpoints_.size();
}

CanBusDouble::CanBusDouble(VirtualCanBus& bus, CanSocketOptions options, std::size_t queue_frames)
    : bus_(bus), options_(std::move(options)) {
  if (queue_frames == 0) throw CanBusError("CanBusDouble: the receive queue needs >= 1 frame");
  slots_.resize(queue_frames);
  const std::lock_guard lock(bus_.mutex_);
  bus_.endpoints_.push_back(this);
}

CanBusDouble::~CanBusDouble() {
  const std::lock_guard lock(bus_.mutex_);
  std::erase(bus_.endpoints_, this);
}

void CanBusDouble::SetFilters(std::vector<CanFilter> filters) {
  const std::lock_guard lock(bus_.mutex_);
  options_.filters = std::move(filters);
}

std::size_t CanBusDouble::queued() const {
  const std::lock_guard lock(bus_.mutex_);
  return count_;
}

ssize_t CanBusDouble::WriteRecord(std::span<const std::uint8_t> record) noexcept {
  // The size and length checks of raw_sendmsg() / can_send(), before the bus is touched.
  const std::size_t size = record.size();
  const bool fd = size == kCanFdMtu;
  if (size != kCanMtu && !(fd && options_.fd_frames && bus_.fd_capable())) {
    SetErrno(EINVAL);
    return -EINVAL;
  }
  if (record[kLenOffset] > (fd ? kCanFdMaxLen : kCanMaxLen)) {
    SetErrno(EINVAL);
    return -EINVAL;
  }
  Slot slot{};
  std::memcpy(slot.bytes.data(), record.data(), size);
  slot.size = static_cast<std::uint8_t>(size);
  if (fd) slot.bytes[kFlagsOffset] |= CANFD_FDF;
  std::uint32_t can_id = 0;
  std::memcpy(&can_id, record.data(), sizeof(can_id));

  const std::lock_guard lock(bus_.mutex_);
  if (!bus_.link_up_) {
    SetErrno(ENETDOWN);
    return -ENETDOWN;
  }
  if (bus_.fail_count_ > 0) {
    --bus_.fail_count_;
    SetErrno(bus_.fail_errno_);
    return -bus_.fail_errno_;
  }
  slot.timestamp_ns = bus_.clock_();
  // With loopback off the frame would only reach the wire, and a virtual bus has none.
  if (options_.loopback) {
    for (CanBusDouble* endpoint : bus_.endpoints_) {
      endpoint->DeliverLocked(slot, can_id, endpoint == this);
    }
  }
  return static_cast<ssize_t>(size);
}

void CanBusDouble::DeliverLocked(const Slot& slot, std::uint32_t can_id, bool from_self) noexcept {
  // The checks of raw_rcv(), in its order.
  if (from_self && !options_.recv_own_msgs) return;
  if (slot.size == kCanFdMtu && !options_.fd_frames) return;
  if (!CanFiltersAccept(options_.filters, options_.join_filters, can_id)) return;
  if (count_ == slots_.size()) {
    can_detail::AtomicCanBusCounters::Add(counters_.receive_overflows);
    return;
  }
  Slot& target = slots_[(head_ + count_) % slots_.size()];
  target = slot;
  target.own = from_self;
  ++count_;
  readable_.notify_one();
}

ssize_t CanBusDouble::ReadUntil(std::span<std::uint8_t> buffer, bool wait, bool forever,
                                Deadline deadline, CanRecordInfo* info) noexcept {
  if (buffer.empty()) {
    SetErrno(EINVAL);
    return -EINVAL;
  }
  std::unique_lock lock(bus_.mutex_);
  if (wait) {
    const auto readable = [this] { return count_ > 0; };
    if (forever) {
      readable_.wait(lock, readable);
    } else {
      readable_.wait_until(lock, deadline, readable);
    }
  }
  if (count_ == 0) {
    SetErrno(EAGAIN);
    return -EAGAIN;
  }
  const Slot& slot = slots_[head_];
  const std::size_t copied = std::min<std::size_t>(slot.size, buffer.size());
  std::memcpy(buffer.data(), slot.bytes.data(), copied);
  if (info != nullptr) {
    info->timestamp_ns = slot.timestamp_ns;
    info->msg_flags =
        MSG_DONTROUTE | (slot.own ? MSG_CONFIRM : 0) | (copied < slot.size ? MSG_TRUNC : 0);
  }
  head_ = (head_ + 1) % slots_.size();
  --count_;
  return static_cast<ssize_t>(copied);
}

ssize_t CanBusDouble::ReadRecord(std::span<std::uint8_t> buffer, std::chrono::nanoseconds timeout,
                                 CanRecordInfo* info) noexcept {
  const bool wait = timeout != std::chrono::nanoseconds::zero();
  const bool forever = timeout < std::chrono::nanoseconds::zero();
  const Deadline deadline = forever ? Deadline{} : std::chrono::steady_clock::now() + timeout;
  return ReadUntil(buffer, wait, forever, deadline, info);
}

CanStatus CanBusDouble::Send(const CanFrame& frame) noexcept {
  alignas(8) std::array<std::uint8_t, kCanFdMtu> record;
  const std::size_t size = ToWire(frame, record);
  CanStatus status = CanStatus::kInvalid;
  if (size != 0) status = SendStatusOf(WriteRecord(std::span(record.data(), size)));
  counters_.CountSend(status);
  return status;
}

CanStatus CanBusDouble::Receive(CanFrame* frame, std::chrono::nanoseconds timeout) noexcept {
  const bool wait = timeout != std::chrono::nanoseconds::zero();
  const bool forever = timeout < std::chrono::nanoseconds::zero();
  const Deadline deadline = forever ? Deadline{} : std::chrono::steady_clock::now() + timeout;
  alignas(8) std::array<std::uint8_t, kCanFdMtu> record;
  for (;;) {
    CanRecordInfo info;
    const ssize_t size = ReadUntil(record, wait, forever, deadline, &info);
    if (size == -EAGAIN) return CanStatus::kWouldBlock;
    if (size < 0) {
      can_detail::AtomicCanBusCounters::Add(counters_.receive_errors);
      return CanStatus::kError;
    }
    if ((info.msg_flags & MSG_TRUNC) == 0 &&
        FromWire(std::span(record.data(), static_cast<std::size_t>(size)), frame)) {
      frame->timestamp_ns = info.timestamp_ns;
      can_detail::AtomicCanBusCounters::Add(counters_.received);
      return CanStatus::kOk;
    }
    // Not a data frame we can use (e.g. an error frame or a bad id written raw): skip it.
    can_detail::AtomicCanBusCounters::Add(counters_.receive_invalid);
  }
}

}  // namespace ambdrop
