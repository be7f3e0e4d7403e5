// CanFrame against the kernel's struct can_frame / canfd_frame: sizes, offsets, flags, and
// byte-exact conversions both ways.
#include "io/can/can_frame.hpp"

#include <gtest/gtest.h>
#include <linux/can.h>

#include <array>
#include <cstddef>
#include <cstring>
#include <random>
#include <vector>

namespace ambdrop::can_frame_test {
namespace {

using Record = std::array<std::uint8_t, kCanFdMtu>;

TEST(CanFrameLayout, MatchesLinuxCanHeader) {
  EXPECT_EQ(sizeof(struct can_frame), kCanMtu);
  EXPECT_EQ(sizeof(struct canfd_frame), kCanFdMtu);
  EXPECT_EQ(CAN_MTU, 16u);
  EXPECT_EQ(CANFD_MTU, 72u);
  EXPECT_EQ(offsetof(struct can_frame, can_id), 0u);
  EXPECT_EQ(offsetof(struct can_frame, len), 4u);
  EXPECT_EQ(offsetof(struct can_frame, len8_dlc), 7u);
  EXPECT_EQ(offsetof(struct can_frame, data), 8u);
  EXPECT_EQ(offsetof(struct canfd_frame, can_id), 0u);
  EXPECT_EQ(offsetof(struct canfd_frame, len), 4u);
  EXPECT_EQ(offsetof(struct canfd_frame, flags), 5u);
  EXPECT_EQ(offsetof(struct canfd_frame, data), 8u);
  EXPECT_EQ(kCanEffFlag, CAN_EFF_FLAG);
  EXPECT_EQ(kCanRtrFlag, CAN_RTR_FLAG);
  EXPECT_EQ(kCanErrFlag, CAN_ERR_FLAG);
  EXPECT_EQ(kCanSffMaxId, CAN_SFF_MASK);
  EXPECT_EQ(kCanEffMaxId, CAN_EFF_MASK);
  EXPECT_EQ(kCanMaxLen, CAN_MAX_DLEN);
  EXPECT_EQ(kCanFdMaxLen, CANFD_MAX_DLEN);
}

TEST(CanFrameLayout, ClassicRecordIsTheKernelStruct) {
  CanFrame frame;
  frame.id = 0x123;
  frame.len = 3;
  frame.data[0] = 0xDE;
  frame.data[1] = 0xAD;
  frame.data[2] = 0xBE;
  Record record{};
  ASSERT_EQ(ToWire(frame, record), kCanMtu);

  struct can_frame expected;
  std::memset(&expected, 0, sizeof(expected));
  expected.can_id = 0x123;
  expected.len = 3;
  expected.data[0] = 0xDE;
  expected.data[1] = 0xAD;
  expected.data[2] = 0xBE;
  EXPECT_EQ(std::memcmp(record.data(), &expected, kCanMtu), 0);
  // The id word is in host order (little-endian on x86-64), the length at byte 4.
  EXPECT_EQ(record[0], 0x23);
  EXPECT_EQ(record[1], 0x01);
  EXPECT_EQ(record[4], 3);
  EXPECT_EQ(record[8], 0xDE);
}

TEST(CanFrameLayout, ExtendedAndRemoteFlagsGoInTheIdWord) {
  CanFrame frame;
  frame.id = 0x1ABCDEF0;
  frame.extended = true;
  frame.rtr = true;
  frame.len = 2;
  Record record{};
  ASSERT_EQ(ToWire(frame, record), kCanMtu);
  std::uint32_t can_id = 0;
  std::memcpy(&can_id, record.data(), 4);
  EXPECT_EQ(can_id, 0x1ABCDEF0u | CAN_EFF_FLAG | CAN_RTR_FLAG);
  EXPECT_EQ(frame.CanId(), can_id);
}

TEST(CanFrameLayout, FdRecordIsTheKernelStructWithFdf) {
  CanFrame frame;
  frame.id = 0x42;
  frame.fd = true;
  frame.brs = true;
  frame.len = 64;
  for (int i = 0; i < 64; ++i)
    frame.data[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i + 1);
  Record record{};
  ASSERT_EQ(ToWire(frame, record), kCanFdMtu);

  struct canfd_frame expected;
  std::memset(&expected, 0, sizeof(expected));
  expected.can_id = 0x42;
  expected.len = 64;
  expected.flags = CANFD_BRS | CANFD_FDF;
  for (int i = 0; i < 64; ++i) expected.data[i] = static_cast<__u8>(i + 1);
  EXPECT_EQ(std::memcmp(record.data(), &expected, kCanFdMtu), 0);
  EXPECT_EQ(record[5], CANFD_BRS | CANFD_FDF);
}

TEST(CanFrameLayout, KernelStructConversionsRoundTrip) {
  CanFrame frame;
  frame.id = 0x7FF;
  frame.len = 8;
  frame.data = {1, 2, 3, 4, 5, 6, 7, 8};
  struct can_frame classic;
  ASSERT_TRUE(ToKernel(frame, &classic));
  struct canfd_frame fd;
  EXPECT_FALSE(ToKernel(frame, &fd));  // a classic frame is not an FD struct
  CanFrame back;
  ASSERT_TRUE(FromKernel(classic, &back));
  EXPECT_EQ(back, frame);

  frame.fd = true;
  frame.esi = true;
  EXPECT_FALSE(ToKernel(frame, &classic));
  ASSERT_TRUE(ToKernel(frame, &fd));
  EXPECT_EQ(fd.flags, CANFD_ESI | CANFD_FDF);
  ASSERT_TRUE(FromKernel(fd, &back));
  EXPECT_EQ(back, frame);
}

/// A valid frame of random type, id, flags, length and bytes (the bytes beyond len too).
CanFrame RandomFrame(std::mt19937_64& rng) {
  CanFrame frame;
  frame.fd = (rng() & 1) != 0;
  frame.extended = (rng() & 1) != 0;
  frame.id = static_cast<std::uint32_t>(rng()) & (frame.extended ? kCanEffMaxId : kCanSffMaxId);
  if (frame.fd) {
    constexpr std::array<int, 16> kLengths = {0, 1,  2,  3,  4,  5,  6,  7,
                                              8, 12, 16, 20, 24, 32, 48, 64};
    frame.len = static_cast<std::uint8_t>(kLengths[rng() % kLengths.size()]);
    frame.brs = (rng() & 1) != 0;
    frame.esi = (rng() & 1) != 0;
  } else {
    frame.len = static_cast<std::uint8_t>(rng() % 9);
    frame.rtr = (rng() % 8) == 0;
  }
  const std::size_t carried = frame.fd ? kCanFdMaxLen : kCanMaxLen;
  for (std::size_t i = 0; i < carried; ++i) frame.data[i] = static_cast<std::uint8_t>(rng());
  return frame;
}

TEST(CanFrameWire, RandomFramesRoundTripByteExact) {
  std::mt19937_64 rng(20261122);
  for (int trial = 0; trial < 5000; ++trial) {
    const CanFrame frame = RandomFrame(rng);
    ASSERT_TRUE(IsValid(frame));
    Record record{};
    const std::size_t size = ToWire(frame, record);
    ASSERT_EQ(size, WireSize(frame));
    CanFrame back;
    ASSERT_TRUE(FromWire(std::span(record.data(), size), &back)) << "trial " << trial;
    EXPECT_EQ(back, frame) << "trial " << trial;
    // And the record written from the parsed frame is the same bytes.
    Record again{};
    ASSERT_EQ(ToWire(back, again), size);
    EXPECT_EQ(std::memcmp(record.data(), again.data(), size), 0);
  }
}

TEST(CanFrameWire, RejectsWhatIsNotADataFrame) {
  CanFrame frame;
  Record record{};
  struct can_frame classic;
  std::memset(&classic, 0, sizeof(classic));
  // Sizes other than 16 and 72.
  for (const std::size_t size : {0u, 1u, 15u, 17u, 64u, 71u, 73u}) {
    std::vector<std::uint8_t> bytes(size, 0);
    EXPECT_FALSE(FromWire(bytes, &frame)) << size << " bytes";
  }
  // An error frame.
  classic.can_id = CAN_ERR_FLAG | 0x4;
  EXPECT_FALSE(FromKernel(classic, &frame));
  // An 11-bit frame with an id bit above 0x7FF.
  classic.can_id = 0x800;
  EXPECT_FALSE(FromKernel(classic, &frame));
  // A classic length above 8.
  classic.can_id = 0x1;
  classic.len = 9;
  EXPECT_FALSE(FromKernel(classic, &frame));
  // FD: length above 64, and RTR (FD has no remote frames).
  struct canfd_frame fd;
  std::memset(&fd, 0, sizeof(fd));
  fd.len = 65;
  EXPECT_FALSE(FromKernel(fd, &frame));
  fd.len = 8;
  fd.can_id = CAN_RTR_FLAG | 0x5;
  EXPECT_FALSE(FromKernel(fd, &frame));
  std::memcpy(record.data(), &fd, sizeof(fd));
  EXPECT_FALSE(FromWire(record, &frame));
}

TEST(CanFrameWire, FdLengthBetweenStepsIsRoundedUp) {
  // Only a virtual bus can carry len 13; a real FD controller would send DLC 10 = 16 bytes.
  struct canfd_frame fd;
  std::memset(&fd, 0, sizeof(fd));
  fd.can_id = 0x10;
  fd.len = 13;
  CanFrame frame;
  ASSERT_TRUE(FromKernel(fd, &frame));
  EXPECT_EQ(frame.len, 16);
}

TEST(CanFrameWire, InvalidFramesAreNotWritten) {
  Record record{};
  record.fill(0xAA);
  CanFrame frame;
  frame.id = 0x800;  // 12 bits without the extended flag
  EXPECT_FALSE(IsValid(frame));
  EXPECT_EQ(ToWire(frame, record), 0u);
  EXPECT_EQ(record[0], 0xAA);

  frame = CanFrame{};
  frame.len = 9;
  EXPECT_FALSE(IsValid(frame));
  frame.fd = true;
  EXPECT_FALSE(IsValid(frame));  // 9 is not an FD length either
  frame.len = 12;
  EXPECT_TRUE(IsValid(frame));
  frame.rtr = true;
  EXPECT_FALSE(IsValid(frame));

  frame = CanFrame{};
  frame.brs = true;  // classic frames have no bit rate switch
  EXPECT_FALSE(IsValid(frame));

  frame = CanFrame{};
  frame.extended = true;
  frame.id = kCanEffMaxId;
  EXPECT_TRUE(IsValid(frame));
  frame.id = kCanEffMaxId + 1;
  EXPECT_FALSE(IsValid(frame));
}

TEST(CanFrameWire, FdLengthsAndDlcs) {
  constexpr std::array<int, 16> kLengths = {0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64};
  for (int dlc = 0; dlc < 16; ++dlc) {
    const int len = kLengths[static_cast<std::size_t>(dlc)];
    EXPECT_EQ(CanFdDlcToLength(dlc), len);
    EXPECT_EQ(CanFdLengthToDlc(len), dlc);
    EXPECT_TRUE(IsCanFdLength(len));
  }
  int valid = 0;
  for (int len = 0; len <= 64; ++len) valid += IsCanFdLength(len) ? 1 : 0;
  EXPECT_EQ(valid, 16);
  EXPECT_EQ(CanFdRoundUpLength(9), 12);
  EXPECT_EQ(CanFdRoundUpLength(33), 48);
  EXPECT_EQ(CanFdRoundUpLength(64), 64);
  EXPECT_EQ(CanFdLengthToDlc(13), 10);  // rounded up to 16
}

}  // namespace
}  // namespace ambdrop::can_frame_test
