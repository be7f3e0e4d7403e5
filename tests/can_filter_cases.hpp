#pragma once
// The CAN_RAW filter matrix of the kernel's own test (tools/testing/selftests/net/can/
// test_raw_filter.c): one filter per case on a socket that receives its own frames, four frames
// sent (id 0x123 as 11-bit, 11-bit RTR, 29-bit, 29-bit RTR), and the frames that must come back.
// Shared by the double's test and the SocketCAN test, so both run the same vectors.
#include <array>
#include <cstdint>

#include "io/can/can_frame.hpp"

namespace ambdrop::can_filter_cases {

inline constexpr std::uint32_t kId = 0x123;
inline constexpr int kCases = 18;

/// Filter can_id of case `c`: bit 0 adds CAN_EFF_FLAG, bit 1 CAN_RTR_FLAG.
constexpr std::uint32_t FilterId(int c) {
  return kId | ((c & 1) != 0 ? kCanEffFlag : 0U) | ((c & 2) != 0 ? kCanRtrFlag : 0U);
}

/// Filter can_mask of case `c`: the 11-bit mask, plus CAN_EFF_FLAG (bit 2) and CAN_RTR_FLAG
/// (bit 3); cases 16 and 17 match a whole 29-bit id with both flags.
constexpr std::uint32_t FilterMask(int c) {
  if (c > 15) return kCanEffMaxId | kCanEffFlag | kCanRtrFlag;
  return kCanSffMaxId | ((c & 4) != 0 ? kCanEffFlag : 0U) | ((c & 8) != 0 ? kCanRtrFlag : 0U);
}

/// The four frames sent per case, as (extended, rtr).
inline constexpr std::array<std::array<bool, 2>, 4> kSent = {
    {{false, false}, {false, true}, {true, false}, {true, true}}};

/// Bit of a received frame in the case's result: 1 << ((can_id flags) >> 28), i.e. 1 for an
/// 11-bit data frame, 16 for 11-bit RTR, 256 for 29-bit data, 4096 for 29-bit RTR.
constexpr int RxBit(bool extended, bool rtr) {
  return 1 << (((extended ? 8 : 0) | (rtr ? 4 : 0)));
}

/// Frames received per case, and which (sum of RxBit).
inline constexpr std::array<int, kCases> kRxCount = {4, 4, 4, 4, 2, 2, 2, 2, 2,
                                                     2, 2, 2, 1, 1, 1, 1, 1, 1};
inline constexpr std::array<int, kCases> kRxBits = {
    4369, 4369, 4369, 4369, 17, 4352, 17, 4352, 257, 257, 4112, 4112, 1, 256, 16, 4096, 1, 256};

}  // namespace ambdrop::can_filter_cases
