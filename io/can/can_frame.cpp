#include "io/can/can_frame.hpp"

#include <linux/can.h>

#include <cstring>

namespace ambdrop {

// The constants in the header stand in for the kernel's; they must be the same numbers.
static_assert(kCanMtu == CAN_MTU && kCanFdMtu == CANFD_MTU);
static_assert(kCanMaxLen == CAN_MAX_DLEN && kCanFdMaxLen == CANFD_MAX_DLEN);
static_assert(kCanEffFlag == CAN_EFF_FLAG && kCanRtrFlag == CAN_RTR_FLAG &&
              kCanErrFlag == CAN_ERR_FLAG);
static_assert(kCanSffMaxId == CAN_SFF_MASK && kCanEffMaxId == CAN_EFF_MASK);
static_assert(sizeof(can_frame) == 16 && sizeof(canfd_frame) == 72);
static_assert(offsetof(can_frame, data) == 8 && offsetof(canfd_frame, data) == 8);

namespace {

bool IdFits(const CanFrame& frame) noexcept {
  return frame.id <= (frame.extended ? kCanEffMaxId : kCanSffMaxId);
}

std::uint8_t FdFlags(const CanFrame& frame) noexcept {
  return static_cast<std::uint8_t>(CANFD_FDF | (frame.brs ? CANFD_BRS : 0) |
                                   (frame.esi ? CANFD_ESI : 0));
}

/// Shared by both record types: the can_id word. False for what a data frame cannot carry.
bool SplitCanId(canid_t can_id, bool allow_rtr, CanFrame* out) noexcept {
  if ((can_id & CAN_ERR_FLAG) != 0) return false;
  out->extended = (can_id & CAN_EFF_FLAG) != 0;
  out->rtr = (can_id & CAN_RTR_FLAG) != 0;
  if (out->rtr && !allow_rtr) return false;
  out->id = can_id & (out->extended ? CAN_EFF_MASK : CAN_SFF_MASK);
  // An 11-bit frame with bits above 0x7FF set is not a frame any bus carries.
  return out->extended || (can_id & CAN_EFF_MASK) == out->id;
}

}  // namespace

int CanFdLengthToDlc(int len) noexcept {
  const int rounded = CanFdRoundUpLength(len);
  if (rounded <= 8) return rounded;
  constexpr std::array<int, 7> kSteps = {12, 16, 20, 24, 32, 48, 64};
  for (int i = 0; i < static_cast<int>(kSteps.size()); ++i) {
    if (kSteps[i] == rounded) return 9 + i;
  }
  return 15;
}

int CanFdDlcToLength(int dlc) noexcept {
  constexpr std::array<int, 16> kLengths = {0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64};
  if (dlc < 0) return 0;
  return kLengths[static_cast<std::size_t>(dlc > 15 ? 15 : dlc)];
}

bool IsValid(const CanFrame& frame) noexcept {
  if (!IdFits(frame)) return false;
  if (frame.fd) return !frame.rtr && IsCanFdLength(frame.len);
  return !frame.brs && !frame.esi && frame.len <= kCanMaxLen;
}

bool ToKernel(const CanFrame& frame, struct can_frame* out) noexcept {
  if (frame.fd || !IsValid(frame)) return false;
  std::memset(out, 0, sizeof(*out));
  out->can_id = frame.CanId();
  out->len = frame.len;
  std::memcpy(out->data, frame.data.data(), CAN_MAX_DLEN);
  return true;
}

bool ToKernel(const CanFrame& frame, struct canfd_frame* out) noexcept {
  if (!frame.fd || !IsValid(frame)) return false;
  std::memset(out, 0, sizeof(*out));
  out->can_id = frame.CanId();
  out->len = frame.len;
  out->flags = FdFlags(frame);
  std::memcpy(out->data, frame.data.data(), CANFD_MAX_DLEN);
  return true;
}

bool FromKernel(const struct can_frame& in, CanFrame* out) noexcept {
  *out = CanFrame{};
  if (!SplitCanId(in.can_id, /*allow_rtr=*/true, out)) return false;
  if (in.len > CAN_MAX_DLEN) return false;
  out->len = in.len;
  std::memcpy(out->data.data(), in.data, CAN_MAX_DLEN);
  return true;
}

bool FromKernel(const struct canfd_frame& in, CanFrame* out) noexcept {
  *out = CanFrame{};
  if (!SplitCanId(in.can_id, /*allow_rtr=*/false, out)) return false;
  if (in.len > CANFD_MAX_DLEN) return false;
  out->fd = true;
  out->brs = (in.flags & CANFD_BRS) != 0;
  out->esi = (in.flags & CANFD_ESI) != 0;
  out->len = static_cast<std::uint8_t>(CanFdRoundUpLength(in.len));
  std::memcpy(out->data.data(), in.data, CANFD_MAX_DLEN);
  return true;
}

std::size_t ToWire(const CanFrame& frame, std::span<std::uint8_t, kCanFdMtu> out) noexcept {
  // Through the kernel structs, so the layout is the compiler's view of <linux/can.h>.
  if (frame.fd) {
    struct canfd_frame record;
    if (!ToKernel(frame, &record)) return 0;
    std::memcpy(out.data(), &record, sizeof(record));
    return sizeof(record);
  }
  struct can_frame record;
  if (!ToKernel(frame, &record)) return 0;
  std::memcpy(out.data(), &record, sizeof(record));
  return sizeof(record);
}

bool FromWire(std::span<const std::uint8_t> record, CanFrame* out) noexcept {
  if (record.size() == CANFD_MTU) {
    struct canfd_frame kernel;
    std::memcpy(&kernel, record.data(), sizeof(kernel));
    return FromKernel(kernel, out);
  }
  if (record.size() == CAN_MTU) {
    struct can_frame kernel;
    std::memcpy(&kernel, record.data(), sizeof(kernel));
    return FromKernel(kernel, out);
  }
  return false;
}

}  // namespace ambdrop
