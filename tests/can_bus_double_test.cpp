// The in-memory CAN bus keeps CAN_RAW's semantics: record sizes (EINVAL), FD only when enabled,
// broadcast without echo unless asked, kernel filter rules, drop-at-receiver when full, whole
// records only and never 0 bytes, and no allocation in Send/Receive.
#include "io/can/can_bus_double.hpp"

#include <gtest/gtest.h>
#include <linux/can.h>
#include <sys/socket.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>
#include <thread>
#include <vector>

#include "can_filter_cases.hpp"
#include "malloc_guard.hpp"

namespace ambdrop::can_bus_double_test {
namespace {

using std::chrono::milliseconds;
using std::chrono::nanoseconds;
using Record = std::array<std::uint8_t, kCanFdMtu>;

constexpr nanoseconds kPoll{0};

CanFrame Classic(std::uint32_t id, std::uint8_t first_byte = 0, std::uint8_t len = 1) {
  CanFrame frame;
  frame.id = id;
  frame.len = len;
  frame.data[0] = first_byte;
  return frame;
}

CanFrame Fd(std::uint32_t id, std::uint8_t len) {
  CanFrame frame;
  frame.id = id;
  frame.fd = true;
  frame.brs = true;
  frame.len = len;
  for (std::size_t i = 0; i < len; ++i) frame.data[i] = static_cast<std::uint8_t>(0xF0 ^ i);
  return frame;
}

Record ClassicRecord(std::uint32_t can_id, std::uint8_t len) {
  Record record{};
  std::memcpy(record.data(), &can_id, 4);
  record[4] = len;
  return record;
}

CanSocketOptions FdOptions() {
  CanSocketOptions options;
  options.fd_frames = true;
  return options;
}

TEST(CanBusDouble, WriteOfWrongSizeFailsWithEinvalAndDeliversNothing) {
  VirtualCanBus bus;
  CanBusDouble a(bus), b(bus);
  const Record record = ClassicRecord(0x100, 1);
  for (const std::size_t size : {0u, 1u, 8u, 15u, 17u, 71u, 72u, 73u}) {
    EXPECT_EQ(a.WriteRecord(std::span(record.data(), size)), -EINVAL) << size << " bytes";
    EXPECT_EQ(a.last_errno(), EINVAL);
  }
  EXPECT_EQ(b.queued(), 0u);
  EXPECT_EQ(a.WriteRecord(std::span(record.data(), kCanMtu)), static_cast<ssize_t>(kCanMtu));
  EXPECT_EQ(b.queued(), 1u);
}

TEST(CanBusDouble, LengthBeyondTheFrameTypeFailsWithEinval) {
  VirtualCanBus bus;
  CanBusDouble a(bus, FdOptions()), b(bus, FdOptions());
  const Record classic_9 = ClassicRecord(0x100, 9);
  EXPECT_EQ(a.WriteRecord(std::span(classic_9.data(), kCanMtu)), -EINVAL);
  Record fd_65 = ClassicRecord(0x100, 65);
  EXPECT_EQ(a.WriteRecord(fd_65), -EINVAL);
  fd_65[4] = 64;
  EXPECT_EQ(a.WriteRecord(fd_65), static_cast<ssize_t>(kCanFdMtu));
  EXPECT_EQ(b.queued(), 1u);
}

TEST(CanBusDouble, FdRecordsOnlyWhenEnabledAndTheBusIsFdCapable) {
  VirtualCanBus bus;
  CanBusDouble classic(bus), fd(bus, FdOptions()), listener(bus, FdOptions());
  EXPECT_FALSE(classic.fd_enabled());
  EXPECT_TRUE(fd.fd_enabled());
  EXPECT_EQ(classic.Send(Fd(0x10, 12)), CanStatus::kInvalid);  // EINVAL: FD not enabled
  EXPECT_EQ(classic.counters().send_invalid, 1u);
  EXPECT_EQ(fd.Send(Fd(0x10, 12)), CanStatus::kOk);
  EXPECT_EQ(listener.queued(), 1u);
  EXPECT_EQ(classic.queued(),
            0u);  // a classic socket never sees FD frames, and does not count them

  VirtualCanBus classic_bus(/*fd_capable=*/false);  // MTU 16
  CanBusDouble wants_fd(classic_bus, FdOptions());
  EXPECT_FALSE(wants_fd.fd_enabled());
  EXPECT_EQ(wants_fd.Send(Fd(0x10, 12)), CanStatus::kInvalid);
  EXPECT_EQ(wants_fd.Send(Classic(0x10)), CanStatus::kOk);
}

TEST(CanBusDouble, ClassicFramesReachFdSocketsAsSixteenBytes) {
  VirtualCanBus bus;
  CanBusDouble sender(bus), fd_reader(bus, FdOptions());
  ASSERT_EQ(sender.Send(Classic(0x55, 7, 8)), CanStatus::kOk);
  Record buffer{};
  EXPECT_EQ(fd_reader.ReadRecord(buffer, kPoll), static_cast<ssize_t>(kCanMtu));
}

TEST(CanBusDouble, RecordsAreDeliveredByteForByte) {
  VirtualCanBus bus;
  CanBusDouble a(bus, FdOptions()), b(bus, FdOptions());
  // Padding and reserved bytes set: the kernel passes them through on vcan, and so does the
  // double. Only CANFD_FDF is added to FD records.
  Record classic = ClassicRecord(0x321, 2);
  for (std::size_t i = 5; i < kCanMtu; ++i) classic[i] = static_cast<std::uint8_t>(0xA0 + i);
  ASSERT_EQ(a.WriteRecord(std::span(classic.data(), kCanMtu)), 16);
  Record fd = ClassicRecord(0x322, 20);
  for (std::size_t i = 5; i < kCanFdMtu; ++i) fd[i] = static_cast<std::uint8_t>(i * 3);
  fd[5] = CANFD_BRS;
  ASSERT_EQ(a.WriteRecord(fd), 72);

  Record got{};
  ASSERT_EQ(b.ReadRecord(got, kPoll), 16);
  EXPECT_EQ(std::memcmp(got.data(), classic.data(), kCanMtu), 0);
  ASSERT_EQ(b.ReadRecord(got, kPoll), 72);
  Record expected = fd;
  expected[5] = CANFD_BRS | CANFD_FDF;
  EXPECT_EQ(got, expected);
}

TEST(CanBusDouble, ReadsReturnWholeRecordsTruncatedWithMsgTrunc) {
  VirtualCanBus bus;
  CanBusDouble a(bus, FdOptions()), b(bus, FdOptions());
  ASSERT_EQ(a.Send(Fd(0x1, 64)), CanStatus::kOk);
  ASSERT_EQ(a.Send(Classic(0x2, 0x77)), CanStatus::kOk);
  Record buffer{};
  CanRecordInfo info;
  // A 16-byte read of a 72-byte record: 16 bytes, MSG_TRUNC, the rest of that record is gone.
  EXPECT_EQ(b.ReadRecord(std::span(buffer.data(), kCanMtu), kPoll, &info), 16);
  EXPECT_NE(info.msg_flags & MSG_TRUNC, 0);
  EXPECT_EQ(b.ReadRecord(buffer, kPoll, &info), 16);  // the next record, whole
  EXPECT_EQ(info.msg_flags & MSG_TRUNC, 0);
  EXPECT_EQ(buffer[8], 0x77);
}

TEST(CanBusDouble, NeverReturnsZeroBytes) {
  VirtualCanBus bus;
  CanBusDouble reader(bus);
  Record buffer{};
  {
    CanBusDouble writer(bus);
    ASSERT_EQ(writer.Send(Classic(0x1)), CanStatus::kOk);
  }  // the writer is gone: a socketpair would now read 0 (end of stream); CAN has no such thing
  EXPECT_EQ(reader.ReadRecord(std::span(buffer.data(), 0), kPoll), -EINVAL);
  EXPECT_EQ(reader.queued(), 1u);  // a refused read does not consume the record
  EXPECT_EQ(reader.ReadRecord(buffer, kPoll), 16);
  EXPECT_EQ(reader.ReadRecord(buffer, kPoll), -EAGAIN);
  CanFrame frame;
  EXPECT_EQ(reader.Receive(&frame, kPoll), CanStatus::kWouldBlock);
}

TEST(CanBusDouble, FullQueueDropsAtTheReceiverAndNeverBlocksTheSender) {
  VirtualCanBus bus;
  CanBusDouble sender(bus), small(bus, {}, 4), large(bus, {}, 64);
  for (int i = 0; i < 10; ++i) {
    ASSERT_EQ(sender.Send(Classic(0x100, static_cast<std::uint8_t>(i))), CanStatus::kOk);
  }
  EXPECT_EQ(sender.counters().sent, 10u);
  EXPECT_EQ(small.counters().receive_overflows, 6u);
  EXPECT_EQ(large.counters().receive_overflows, 0u);
  // The small queue kept the oldest four, in order.
  CanFrame frame;
  for (int i = 0; i < 4; ++i) {
    ASSERT_EQ(small.Receive(&frame, kPoll), CanStatus::kOk);
    EXPECT_EQ(frame.data[0], i);
  }
  EXPECT_EQ(small.Receive(&frame, kPoll), CanStatus::kWouldBlock);
  EXPECT_EQ(small.counters().received, 4u);
  EXPECT_EQ(large.queued(), 10u);
}

TEST(CanBusDouble, BroadcastToOthersAndOwnFramesOnlyOnRequest) {
  VirtualCanBus bus;
  CanSocketOptions own;
  own.recv_own_msgs = true;
  CanBusDouble a(bus), b(bus), c(bus, own);
  ASSERT_EQ(a.Send(Classic(0x10)), CanStatus::kOk);
  EXPECT_EQ(a.queued(), 0u);
  EXPECT_EQ(b.queued(), 1u);
  EXPECT_EQ(c.queued(), 1u);

  ASSERT_EQ(c.Send(Classic(0x11)), CanStatus::kOk);
  Record buffer{};
  CanRecordInfo info;
  ASSERT_EQ(c.ReadRecord(buffer, kPoll, &info), 16);  // a's frame
  EXPECT_EQ(info.msg_flags, MSG_DONTROUTE);
  ASSERT_EQ(c.ReadRecord(buffer, kPoll, &info), 16);  // its own, marked as such
  EXPECT_EQ(info.msg_flags, MSG_DONTROUTE | MSG_CONFIRM);
  EXPECT_EQ(a.queued(), 1u);
}

TEST(CanBusDouble, LoopbackOffReachesNoOne) {
  VirtualCanBus bus;
  CanSocketOptions quiet;
  quiet.loopback = false;
  quiet.recv_own_msgs = true;
  CanBusDouble a(bus, quiet), b(bus);
  ASSERT_EQ(a.Send(Classic(0x10)), CanStatus::kOk);  // vcan has no wire: the frame goes nowhere
  EXPECT_EQ(a.queued(), 0u);
  EXPECT_EQ(b.queued(), 0u);
}

TEST(CanBusDouble, FiltersFollowTheKernelsFilterTest) {
  namespace cases = can_filter_cases;
  VirtualCanBus bus;
  CanSocketOptions options;
  options.recv_own_msgs = true;
  CanBusDouble socket(bus, options);
  for (int c = 0; c < cases::kCases; ++c) {
    socket.SetFilters({CanFilter{cases::FilterId(c), cases::FilterMask(c)}});
    for (const auto& [extended, rtr] : cases::kSent) {
      CanFrame frame = Classic(cases::kId, static_cast<std::uint8_t>(c));
      frame.extended = extended;
      frame.rtr = rtr;
      ASSERT_EQ(socket.Send(frame), CanStatus::kOk);
    }
    int rx = 0;
    int rx_bits = 0;
    CanFrame frame;
    while (socket.Receive(&frame, kPoll) == CanStatus::kOk) {
      EXPECT_EQ(frame.id, cases::kId);
      EXPECT_EQ(frame.data[0], c);
      const int bit = cases::RxBit(frame.extended, frame.rtr);
      EXPECT_EQ(rx_bits & bit, 0) << "case " << c << ": a frame delivered twice";
      rx_bits |= bit;
      ++rx;
    }
    EXPECT_EQ(rx, cases::kRxCount[static_cast<std::size_t>(c)]) << "case " << c;
    EXPECT_EQ(rx_bits, cases::kRxBits[static_cast<std::size_t>(c)]) << "case " << c;
  }
}

TEST(CanBusDouble, InverseJoinedAndEmptyFilters) {
  VirtualCanBus bus;
  CanBusDouble sender(bus);
  CanSocketOptions inverse;
  inverse.filters = {CanFilter{0x123 | kCanInvFilter, kCanSffMaxId}};
  CanSocketOptions any_of;
  any_of.filters = {CanFilter{0x100, 0x700}, CanFilter{0x020, 0x0F0}};
  CanSocketOptions all_of = any_of;
  all_of.join_filters = true;
  CanSocketOptions none;
  none.filters = {};
  CanBusDouble inv(bus, inverse), any(bus, any_of), all(bus, all_of), deaf(bus, none);

  for (const std::uint32_t id : {0x123u, 0x130u, 0x321u}) {
    ASSERT_EQ(sender.Send(Classic(id)), CanStatus::kOk);
  }
  const auto ids = [](CanBusDouble& endpoint) {
    std::vector<std::uint32_t> out;
    CanFrame frame;
    while (endpoint.Receive(&frame, kPoll) == CanStatus::kOk) out.push_back(frame.id);
    return out;
  };
  EXPECT_EQ(ids(inv), (std::vector<std::uint32_t>{0x130, 0x321}));
  EXPECT_EQ(ids(any), (std::vector<std::uint32_t>{0x123, 0x130, 0x321}));  // 0x321 by the 2nd
  EXPECT_EQ(ids(all), (std::vector<std::uint32_t>{0x123}));  // the only one passing both
  EXPECT_TRUE(ids(deaf).empty());
}

TEST(CanBusDouble, ExactFilterPassesOnlyItsIdAndFormat) {
  VirtualCanBus bus;
  CanBusDouble sender(bus);
  CanSocketOptions options;
  options.filters = {CanFilter::Exact(0x100, false), CanFilter::Exact(0x100, true)};
  CanBusDouble reader(bus, options);
  CanFrame sff = Classic(0x100);
  CanFrame eff = Classic(0x100);
  eff.extended = true;
  CanFrame other_eff = Classic(0x1100);
  other_eff.extended = true;
  CanFrame rtr = Classic(0x100);
  rtr.rtr = true;
  for (const CanFrame& frame : {sff, eff, other_eff, rtr, Classic(0x101)}) {
    ASSERT_EQ(sender.Send(frame), CanStatus::kOk);
  }
  CanFrame got;
  ASSERT_EQ(reader.Receive(&got, kPoll), CanStatus::kOk);
  got.timestamp_ns = 0;
  EXPECT_EQ(got, sff);
  ASSERT_EQ(reader.Receive(&got, kPoll), CanStatus::kOk);
  got.timestamp_ns = 0;
  EXPECT_EQ(got, eff);
  EXPECT_EQ(reader.Receive(&got, kPoll), CanStatus::kWouldBlock);
}

TEST(CanBusDouble, RecordsThatAreNotDataFramesAreSkippedAndCounted) {
  VirtualCanBus bus;
  CanBusDouble writer(bus), reader(bus);
  // An error frame goes nowhere (no endpoint has an error mask, the kernel's default).
  const Record error = ClassicRecord(CAN_ERR_FLAG | 0x4, 8);
  ASSERT_EQ(writer.WriteRecord(std::span(error.data(), kCanMtu)), 16);
  EXPECT_EQ(reader.queued(), 0u);
  // An 11-bit id with bit 11 set is delivered (the kernel does not check) but is no frame.
  const Record bad_id = ClassicRecord(0x900, 1);
  ASSERT_EQ(writer.WriteRecord(std::span(bad_id.data(), kCanMtu)), 16);
  ASSERT_EQ(writer.Send(Classic(0x42, 9)), CanStatus::kOk);
  CanFrame frame;
  ASSERT_EQ(reader.Receive(&frame, kPoll), CanStatus::kOk);
  EXPECT_EQ(frame.id, 0x42u);
  EXPECT_EQ(reader.counters().receive_invalid, 1u);
  EXPECT_EQ(reader.counters().received, 1u);
}

TEST(CanBusDouble, SendFailuresMapToStatusesAndCounters) {
  VirtualCanBus bus;
  CanBusDouble a(bus), b(bus);
  bus.SetLinkUp(false);
  EXPECT_EQ(a.Send(Classic(0x1)), CanStatus::kError);
  EXPECT_EQ(a.last_errno(), ENETDOWN);
  bus.SetLinkUp(true);
  bus.FailNextWrites(ENOBUFS, 2);
  EXPECT_EQ(a.Send(Classic(0x1)), CanStatus::kDropped);
  EXPECT_EQ(a.Send(Classic(0x1)), CanStatus::kDropped);
  EXPECT_EQ(a.Send(Classic(0x1)), CanStatus::kOk);
  EXPECT_EQ(a.Send(Classic(0x1, 0, 9)), CanStatus::kInvalid);  // not IsValid: never written
  const CanBusCounters counters = a.counters();
  EXPECT_EQ(counters.sent, 1u);
  EXPECT_EQ(counters.send_dropped, 2u);
  EXPECT_EQ(counters.send_errors, 1u);
  EXPECT_EQ(counters.send_invalid, 1u);
  EXPECT_EQ(b.queued(), 1u);
}

std::int64_t FakeClock() noexcept {
  return 123'456'789;
}

TEST(CanBusDouble, FramesCarryTheBusClockAtTheWrite) {
  VirtualCanBus bus;
  bus.SetClock(&FakeClock);
  CanBusDouble a(bus), b(bus);
  ASSERT_EQ(a.Send(Classic(0x1)), CanStatus::kOk);
  CanFrame frame;
  ASSERT_EQ(b.Receive(&frame, kPoll), CanStatus::kOk);
  EXPECT_EQ(frame.timestamp_ns, 123'456'789);
}

TEST(CanBusDouble, ReceiveWaitsForTheTimeout) {
  VirtualCanBus bus;
  CanBusDouble a(bus);
  CanFrame frame;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(a.Receive(&frame, milliseconds(20)), CanStatus::kWouldBlock);
  EXPECT_GE(std::chrono::steady_clock::now() - start, milliseconds(19));
}

TEST(CanBusDouble, ReceiveWakesWhenAFrameArrives) {
  VirtualCanBus bus;
  CanBusDouble a(bus), b(bus);
  std::thread writer([&a] {
    std::this_thread::sleep_for(milliseconds(10));
    (void)a.Send(Classic(0x77));
  });
  CanFrame frame;
  EXPECT_EQ(b.Receive(&frame, nanoseconds(-1)), CanStatus::kOk);  // no time limit
  EXPECT_EQ(frame.id, 0x77u);
  writer.join();
}

TEST(CanBusDouble, OneWriterOneReaderThreadLoseNothingUncounted) {
  VirtualCanBus bus;
  CanBusDouble writer(bus), reader(bus, {}, 32);
  constexpr int kFrames = 20000;
  std::thread sending([&writer] {
    for (int i = 0; i < kFrames; ++i) {
      CanFrame frame = Classic(0x200, 0, 4);
      std::memcpy(frame.data.data(), &i, sizeof(i));
      ASSERT_EQ(writer.Send(frame), CanStatus::kOk);
    }
  });
  int received = 0;
  int last = -1;
  CanFrame frame;
  for (;;) {
    const CanStatus status = reader.Receive(&frame, milliseconds(200));
    if (status != CanStatus::kOk) break;
    int sequence = 0;
    std::memcpy(&sequence, frame.data.data(), sizeof(sequence));
    EXPECT_GT(sequence, last);  // in order; gaps are the counted drops
    last = sequence;
    ++received;
    if (last == kFrames - 1) break;
  }
  sending.join();
  while (reader.Receive(&frame, kPoll) == CanStatus::kOk) ++received;
  EXPECT_EQ(static_cast<std::uint64_t>(received) + reader.counters().receive_overflows,
            static_cast<std::uint64_t>(kFrames));
}

TEST(CanBusDouble, SendAndReceiveDoNotAllocate) {
  VirtualCanBus bus;
  CanBusDouble a(bus, FdOptions()), b(bus, FdOptions());
  CanBus& sender = a;  // through the interface, as the real-time loop uses it
  CanBus& receiver = b;
  CanFrame frame;
  std::int64_t allocations = 0;
  {
    testing::MallocGuard guard;
    for (int i = 0; i < 1000; ++i) {
      if (sender.Send(i % 2 == 0 ? Classic(0x10) : Fd(0x11, 48)) != CanStatus::kOk) break;
      if (receiver.Receive(&frame, kPoll) != CanStatus::kOk) break;
    }
    (void)receiver.Receive(&frame, kPoll);  // the empty path too
    allocations = guard.allocations();
  }
  EXPECT_EQ(b.counters().received, 1000u);
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace ambdrop::can_bus_double_test
