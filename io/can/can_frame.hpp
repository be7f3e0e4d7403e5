#pragma once
// One CAN or CAN FD frame, independent of the transport, and its exact conversion to and from the
// records a Linux CAN_RAW socket reads and writes: `struct can_frame` (CAN_MTU = 16 bytes) and
// `struct canfd_frame` (CANFD_MTU = 72 bytes) of <linux/can.h>.
//
// Wire layout (host byte order for can_id, as the kernel uses it):
//   bytes 0..3   can_id: identifier | CAN_EFF_FLAG (29-bit) | CAN_RTR_FLAG | CAN_ERR_FLAG
//   byte  4      len: payload bytes (classic 0..8, FD 0..64)
//   byte  5      classic: __pad; FD: flags (CANFD_BRS, CANFD_ESI, CANFD_FDF)
//   bytes 6..7   reserved (written 0; classic byte 7 is len8_dlc, not carried: see below)
//   bytes 8..    data (8 bytes classic, 64 bytes FD)
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

// The kernel's types, declared here so that this header does not pull in <linux/can.h>.
struct can_frame;
struct canfd_frame;

namespace ambdrop {

inline constexpr std::size_t kCanMtu = 16;                 ///< sizeof(struct can_frame), bytes
inline constexpr std::size_t kCanFdMtu = 72;               ///< sizeof(struct canfd_frame), bytes
inline constexpr int kCanMaxLen = 8;                       ///< classic CAN payload, bytes
inline constexpr int kCanFdMaxLen = 64;                    ///< CAN FD payload, bytes
inline constexpr std::uint32_t kCanSffMaxId = 0x7FF;       ///< 11-bit identifier
inline constexpr std::uint32_t kCanEffMaxId = 0x1FFFFFFF;  ///< 29-bit identifier

/// The kernel's can_id flag bits (CAN_EFF_FLAG, CAN_RTR_FLAG, CAN_ERR_FLAG), for filters and keys.
inline constexpr std::uint32_t kCanEffFlag = 0x80000000U;
inline constexpr std::uint32_t kCanRtrFlag = 0x40000000U;
inline constexpr std::uint32_t kCanErrFlag = 0x20000000U;

/// True for a payload length a CAN FD frame can carry: 0..8, 12, 16, 20, 24, 32, 48, 64 (the
/// lengths its 4-bit DLC encodes).
constexpr bool IsCanFdLength(int len) noexcept {
  if (len >= 0 && len <= 8) return true;
  switch (len) {
    case 12:
    case 16:
    case 20:
    case 24:
    case 32:
    case 48:
    case 64:
      return true;
    default:
      return false;
  }
}

/// The smallest CAN FD length >= `len` (what an FD controller pads a payload to); 64 beyond it.
constexpr int CanFdRoundUpLength(int len) noexcept {
  constexpr std::array<int, 7> kSteps = {12, 16, 20, 24, 32, 48, 64};
  if (len <= 8) return len < 0 ? 0 : len;
  for (const int step : kSteps) {
    if (len <= step) return step;
  }
  return kCanFdMaxLen;
}

/// DLC (0..15) of a CAN FD length (rounded up to the next step first).
int CanFdLengthToDlc(int len) noexcept;
/// Payload length of a DLC: 0..8 as is, 9..15 → 12, 16, 20, 24, 32, 48, 64 (FD).
int CanFdDlcToLength(int dlc) noexcept;

/// A CAN 2.0 or CAN FD data frame. `data` beyond `len` is carried too (zero unless set), so a
/// conversion to the wire and back is byte-exact.
struct CanFrame {
  std::uint32_t id = 0;   ///< identifier without flags: <= 0x7FF, or <= 0x1FFFFFFF if extended
  bool extended = false;  ///< 29-bit identifier (CAN_EFF_FLAG)
  bool rtr = false;       ///< remote request (classic only; carries no data)
  bool fd = false;        ///< CAN FD frame (72-byte record on the wire)
  bool brs = false;       ///< FD: bit rate switch for the data phase (CANFD_BRS)
  bool esi = false;       ///< FD: error state indicator of the sender (CANFD_ESI; receive only)
  std::uint8_t len = 0;   ///< payload bytes: 0..8 classic; an IsCanFdLength value for FD
  /// Receive time, ns, set by the bus that delivered the frame (0 for frames built locally).
  /// SocketCanBus: CLOCK_REALTIME from the kernel (SO_TIMESTAMPNS) or CLOCK_MONOTONIC at read,
  /// as configured; CanBusDouble: its bus clock (CLOCK_MONOTONIC by default) at the write.
  std::int64_t timestamp_ns = 0;
  alignas(8) std::array<std::uint8_t, kCanFdMaxLen> data{};

  /// The can_id the kernel would carry: id | CAN_EFF_FLAG | CAN_RTR_FLAG as set.
  std::uint32_t CanId() const noexcept {
    return id | (extended ? kCanEffFlag : 0U) | (rtr ? kCanRtrFlag : 0U);
  }
  /// Payload bytes (`len` of them).
  std::span<const std::uint8_t> payload() const noexcept { return {data.data(), len}; }

  /// Field by field, timestamp and the bytes beyond `len` included.
  bool operator==(const CanFrame&) const = default;
};

/// The identifier fits its format, `len` fits the frame type, and no RTR, BRS or ESI where the
/// frame type has none (RTR is classic only; BRS and ESI are FD only).
bool IsValid(const CanFrame& frame) noexcept;

/// Size of the frame's record on a CAN_RAW socket: kCanMtu (classic) or kCanFdMtu (FD).
constexpr std::size_t WireSize(const CanFrame& frame) noexcept {
  return frame.fd ? kCanFdMtu : kCanMtu;
}

/// Writes `frame` as the kernel's record into `out`: 16 bytes (struct can_frame) or 72 bytes
/// (struct canfd_frame, with CANFD_FDF set, as the kernel's can_send() sets it on every FD
/// frame: Linux 6.2+ and Debian 12's 6.1). Reserved bytes are written 0. Returns the record
/// size, or 0 (nothing written) for a frame that is not IsValid.
std::size_t ToWire(const CanFrame& frame, std::span<std::uint8_t, kCanFdMtu> out) noexcept;

/// Reads a record as read() returns it from a CAN_RAW socket: 16 bytes → classic, 72 → FD.
/// False (and `*out` unspecified) for any other size, an error frame (CAN_ERR_FLAG), an 11-bit
/// id above 0x7FF, a classic len above 8, an FD len above 64, or RTR in an FD record.
/// An FD len between the DLC steps (possible only on a virtual bus) is rounded up to the next
/// step, as an FD controller would put it on a real bus. The classic len8_dlc byte is ignored
/// (it only matters with CAN_CTRLMODE_CC_LEN8_DLC, which ambdrop does not use). The timestamp is
/// left 0.
bool FromWire(std::span<const std::uint8_t> record, CanFrame* out) noexcept;

/// Direct conversions to and from the kernel structs (same rules as ToWire/FromWire). ToKernel
/// returns false for a frame that is not IsValid or whose type does not match the struct.
bool ToKernel(const CanFrame& frame, struct can_frame* out) noexcept;
bool ToKernel(const CanFrame& frame, struct canfd_frame* out) noexcept;
bool FromKernel(const struct can_frame& in, CanFrame* out) noexcept;
bool FromKernel(const struct canfd_frame& in, CanFrame* out) noexcept;

}  // namespace ambdrop
