#include "io/can/socketcan_bus.hpp"

#include <fmt/format.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace ambdrop {

// CanFilter is handed to the kernel as struct can_filter.
static_assert(sizeof(CanFilter) == sizeof(struct can_filter));
static_assert(offsetof(CanFilter, can_id) == offsetof(struct can_filter, can_id));
static_assert(offsetof(CanFilter, can_mask) == offsetof(struct can_filter, can_mask));
static_assert(kCanInvFilter == CAN_INV_FILTER);

namespace {

constexpr std::int64_t kNsPerS = 1'000'000'000;

/// "EAFNOSUPPORT (Address family not supported by protocol)".
std::string DescribeErrno(int error_number) {
  const char* name = strerrorname_np(error_number);
  return fmt::format("{} ({})", name != nullptr ? name : "errno " + std::to_string(error_number),
                     std::strerror(error_number));
}

/// Closes the descriptor unless released: the constructor throws on many paths.
class FdCloser {
 public:
  explicit FdCloser(int fd) : fd_(fd) {}
  ~FdCloser() {
    if (fd_ >= 0) close(fd_);
  }
  FdCloser(const FdCloser&) = delete;
  FdCloser& operator=(const FdCloser&) = delete;
  int release() { return std::exchange(fd_, -1); }

 private:
  int fd_;
};

std::int64_t NowNs(clockid_t clock) noexcept {
  timespec now{};
  clock_gettime(clock, &now);
  return static_cast<std::int64_t>(now.tv_sec) * kNsPerS + now.tv_nsec;
}

int OpenCanSocket(int* error_number) noexcept {
  const int fd = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) *error_number = errno;
  return fd;
}

[[noreturn]] void ThrowSocketError(const std::string& interface, int error_number) {
  std::string why;
  if (error_number == EAFNOSUPPORT) {
    why =
        "this kernel has no CAN support (no PF_CAN). Load it with 'modprobe can-raw' (and "
        "'modprobe vcan' for a virtual bus); on a kernel built without CAN, run inside the VM "
        "harness (see ../shared/vm/README.md)";
  } else if (error_number == EPROTONOSUPPORT) {
    why = "the CAN_RAW protocol is not loaded: 'modprobe can-raw'";
  } else {
    why = "cannot create the socket";
  }
  throw CanBusError(
      fmt::format("CAN interface '{}': socket(PF_CAN, SOCK_RAW, CAN_RAW) failed with {}: {}",
                  interface, DescribeErrno(error_number), why));
}

void SetIntOption(int fd, int level, int name, int value, const std::string& interface,
                  const char* what) {
  if (setsockopt(fd, level, name, &value, sizeof(value)) != 0) {
    const int error_number = errno;
    throw CanBusError(fmt::format("CAN interface '{}': setsockopt({}) failed with {}", interface,
                                  what, DescribeErrno(error_number)));
  }
}

void FillIfreq(const std::string& interface, ifreq* request) {
  std::memset(request, 0, sizeof(*request));
  std::memcpy(request->ifr_name, interface.data(), interface.size());
}

}  // namespace

SocketCanBus::SocketCanBus(const SocketCanOptions& options)
    : interface_(options.interface), timestamp_(options.timestamp) {
  if (interface_.empty() || interface_.size() >= IFNAMSIZ) {
    throw CanBusError(fmt::format("CAN interface '{}': the name must have 1 to {} characters",
                                  interface_, IFNAMSIZ - 1));
  }
  int error_number = 0;
  const int fd = OpenCanSocket(&error_number);
  if (fd < 0) ThrowSocketError(interface_, error_number);
  FdCloser closer(fd);

  // The interface: it must exist, be up, and carry FD frames if we asked for them.
  ifreq request;
  FillIfreq(interface_, &request);
  if (ioctl(fd, SIOCGIFINDEX, &request) != 0) {
    error_number = errno;
    throw CanBusError(fmt::format(
        "CAN interface '{}' not found ({}). For a virtual bus: 'ip link add dev {} type vcan && "
        "ip link set up {}'; for an adapter, check its driver and name with 'ip link'",
        interface_, DescribeErrno(error_number), interface_, interface_));
  }
  const int ifindex = request.ifr_ifindex;
  FillIfreq(interface_, &request);
  if (ioctl(fd, SIOCGIFMTU, &request) != 0) {
    error_number = errno;
    throw CanBusError(fmt::format("CAN interface '{}': SIOCGIFMTU failed with {}", interface_,
                                  DescribeErrno(error_number)));
  }
  mtu_ = request.ifr_mtu;
  FillIfreq(interface_, &request);
  if (ioctl(fd, SIOCGIFFLAGS, &request) == 0 && (request.ifr_flags & IFF_UP) == 0) {
    throw CanBusError(
        fmt::format("CAN interface '{}' is down: 'ip link set up {}' (for an "
                    "adapter, set its bitrate first: 'ip link set {} type can "
                    "bitrate 1000000')",
                    interface_, interface_, interface_));
  }
  const CanSocketOptions& socket_options = options.socket;
  if (socket_options.fd_frames && mtu_ < static_cast<int>(CANFD_MTU)) {
    throw CanBusError(fmt::format(
        "CAN interface '{}' is not CAN FD capable (MTU {} bytes, FD needs {}): use classic frames "
        "(fd = false), or 'ip link set {} mtu 72' (vcan) / 'ip link set {} type can ... fd on'",
        interface_, mtu_, CANFD_MTU, interface_, interface_));
  }

  // Socket options, all before bind so that no frame slips through the default filter.
  if (socket_options.filters.size() > CAN_RAW_FILTER_MAX) {
    throw CanBusError(fmt::format("CAN interface '{}': {} filters, the kernel takes at most {}",
                                  interface_, socket_options.filters.size(), CAN_RAW_FILTER_MAX));
  }
  std::vector<can_filter> filters(socket_options.filters.size());
  std::memcpy(filters.data(), socket_options.filters.data(), filters.size() * sizeof(can_filter));
  if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, filters.empty() ? nullptr : filters.data(),
                 static_cast<socklen_t>(filters.size() * sizeof(can_filter))) != 0) {
    error_number = errno;
    throw CanBusError(fmt::format("CAN interface '{}': setsockopt(CAN_RAW_FILTER) failed with {}",
                                  interface_, DescribeErrno(error_number)));
  }
  SetIntOption(fd, SOL_CAN_RAW, CAN_RAW_LOOPBACK, socket_options.loopback ? 1 : 0, interface_,
               "CAN_RAW_LOOPBACK");
  SetIntOption(fd, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, socket_options.recv_own_msgs ? 1 : 0,
               interface_, "CAN_RAW_RECV_OWN_MSGS");
  if (socket_options.join_filters) {
    SetIntOption(fd, SOL_CAN_RAW, CAN_RAW_JOIN_FILTERS, 1, interface_, "CAN_RAW_JOIN_FILTERS");
  }
  if (socket_options.fd_frames) {
    SetIntOption(fd, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, 1, interface_, "CAN_RAW_FD_FRAMES");
    fd_enabled_ = true;
  }
  // Frames lost because our receive queue was full come back as a count with the next frame.
  SetIntOption(fd, SOL_SOCKET, SO_RXQ_OVFL, 1, interface_, "SO_RXQ_OVFL");
  if (timestamp_ == CanTimestampSource::kKernel) {
    SetIntOption(fd, SOL_SOCKET, SO_TIMESTAMPNS, 1, interface_, "SO_TIMESTAMPNS");
  }
  if (options.receive_buffer_bytes > 0) {
    SetIntOption(fd, SOL_SOCKET, SO_RCVBUF, options.receive_buffer_bytes, interface_, "SO_RCVBUF");
  }

  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = ifindex;
  if (bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
    error_number = errno;
    throw CanBusError(fmt::format("CAN interface '{}': bind failed with {}{}", interface_,
                                  DescribeErrno(error_number),
                                  error_number == ENODEV ? ": it is not a CAN interface" : ""));
  }
  fd_ = closer.release();
}

SocketCanBus::~SocketCanBus() {
  if (fd_ >= 0) close(fd_);
}

CanStatus SocketCanBus::Send(const CanFrame& frame) noexcept {
  alignas(8) std::array<std::uint8_t, kCanFdMtu> record;
  const std::size_t size = ToWire(frame, record);
  CanStatus status = CanStatus::kInvalid;
  if (size != 0) {
    ssize_t written = 0;
    do {
      written = send(fd_, record.data(), size, MSG_DONTWAIT | MSG_NOSIGNAL);
    } while (written < 0 && errno == EINTR);
    if (written == static_cast<ssize_t>(size)) {
      status = CanStatus::kOk;
    } else {
      const int error_number = written < 0 ? errno : EIO;
      SetErrno(error_number);
      switch (error_number) {
        case EINVAL:
          status = CanStatus::kInvalid;
          break;
        case ENOBUFS:
        case EAGAIN:
          status = CanStatus::kDropped;
          break;
        default:
          status = CanStatus::kError;
          break;
      }
    }
  }
  counters_.CountSend(status);
  return status;
}

CanStatus SocketCanBus::Receive(CanFrame* frame, std::chrono::nanoseconds timeout) noexcept {
  const bool forever = timeout < std::chrono::nanoseconds::zero();
  const std::int64_t deadline_ns = NowNs(CLOCK_MONOTONIC) + (forever ? 0 : timeout.count());
  alignas(8) std::array<std::uint8_t, kCanFdMtu> record;
  // Room for a timestamp and the overflow count, aligned for cmsghdr.
  union {
    cmsghdr align;
    char bytes[CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(std::uint32_t))];
  } control;

  for (;;) {
    iovec io{.iov_base = record.data(), .iov_len = record.size()};
    msghdr message{};
    message.msg_iov = &io;
    message.msg_iovlen = 1;
    message.msg_control = control.bytes;
    message.msg_controllen = sizeof(control.bytes);
    const ssize_t size = recvmsg(fd_, &message, MSG_DONTWAIT);

    if (size < 0) {
      const int error_number = errno;
      if (error_number == EINTR) continue;
      if (error_number != EAGAIN && error_number != EWOULDBLOCK) {
        SetErrno(error_number);
        can_detail::AtomicCanBusCounters::Add(counters_.receive_errors);
        return CanStatus::kError;
      }
      // Nothing queued: wait for the rest of the timeout.
      const std::int64_t remaining_ns = deadline_ns - NowNs(CLOCK_MONOTONIC);
      if (!forever && remaining_ns <= 0) return CanStatus::kWouldBlock;
      const timespec wait{.tv_sec = remaining_ns / kNsPerS, .tv_nsec = remaining_ns % kNsPerS};
      pollfd poll_fd{.fd = fd_, .events = POLLIN, .revents = 0};
      const int ready = ppoll(&poll_fd, 1, forever ? nullptr : &wait, nullptr);
      if (ready < 0 && errno != EINTR) {
        SetErrno(errno);
        can_detail::AtomicCanBusCounters::Add(counters_.receive_errors);
        return CanStatus::kError;
      }
      continue;
    }

    // Ancillary data: the receive time and the kernel's cumulative drop count.
    std::int64_t kernel_time_ns = 0;
    for (cmsghdr* header = CMSG_FIRSTHDR(&message); header != nullptr;
         header = CMSG_NXTHDR(&message, header)) {
      if (header->cmsg_level != SOL_SOCKET) continue;
      if (header->cmsg_type == SO_TIMESTAMPNS) {
        timespec stamp;
        std::memcpy(&stamp, CMSG_DATA(header), sizeof(stamp));
        kernel_time_ns = static_cast<std::int64_t>(stamp.tv_sec) * kNsPerS + stamp.tv_nsec;
      } else if (header->cmsg_type == SO_RXQ_OVFL) {
        std::uint32_t drops = 0;
        std::memcpy(&drops, CMSG_DATA(header), sizeof(drops));
        // Unsigned difference: correct across the kernel counter's wrap-around.
        can_detail::AtomicCanBusCounters::Add(counters_.receive_overflows,
                                              drops - last_overflow_count_);
        last_overflow_count_ = drops;
      }
    }

    if ((message.msg_flags & MSG_TRUNC) != 0 ||
        !FromWire(std::span(record.data(), static_cast<std::size_t>(size)), frame)) {
      can_detail::AtomicCanBusCounters::Add(counters_.receive_invalid);
      continue;  // not a data frame we can use; look for the next one
    }
    frame->timestamp_ns =
        timestamp_ == CanTimestampSource::kKernel ? kernel_time_ns : NowNs(CLOCK_MONOTONIC);
    can_detail::AtomicCanBusCounters::Add(counters_.received);
    return CanStatus::kOk;
  }
}

bool SocketCanAvailable() noexcept {
  int error_number = 0;
  const int fd = OpenCanSocket(&error_number);
  if (fd < 0) return false;
  close(fd);
  return true;
}

bool CanInterfaceExists(const std::string& interface) noexcept {
  if (interface.empty() || interface.size() >= IFNAMSIZ) return false;
  int error_number = 0;
  const int fd = OpenCanSocket(&error_number);
  if (fd < 0) return false;
  ifreq request;
  std::memset(&request, 0, sizeof(request));
  std::memcpy(request.ifr_name, interface.data(), interface.size());
  bool exists = false;
  if (ioctl(fd, SIOCGIFINDEX, &request) == 0) {
    // bind() refuses anything that is not a CAN device (ENODEV).
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = request.ifr_ifindex;
    exists = bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0;
  }
  close(fd);
  return exists;
}

}  // namespace ambdrop
