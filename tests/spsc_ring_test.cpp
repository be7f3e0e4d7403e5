// SpscRing: single-thread semantics (FIFO order, full/empty, drop counting, wrap-around) and a
// two-thread stress test of 1e6 records checking order, count and that no record is torn.
// Run it under ThreadSanitizer too (see the report of the real-time loop work).
#include "rt_core/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

#include "malloc_guard.hpp"

// Sanitizer builds compile the guard's malloc hooks out (AMBDROP_NO_MALLOC_HOOKS): their runtimes
// own malloc. The allocation checks are skipped there rather than passing vacuously.
#ifdef AMBDROP_NO_MALLOC_HOOKS
#define AMBDROP_SKIP_WITHOUT_MALLOC_HOOKS() GTEST_SKIP() << "no malloc hooks in sanitizer builds"
#else
#define AMBDROP_SKIP_WITHOUT_MALLOC_HOOKS() (void)0
#endif

namespace ambdrop::spsc_ring_test {
namespace {

TEST(SpscRing, EmptyRing) {
  SpscRing<int, 4> ring;
  int out = -1;
  EXPECT_FALSE(ring.TryPop(&out));
  EXPECT_EQ(out, -1);  // untouched
  EXPECT_EQ(ring.size(), 0u);
  EXPECT_EQ(ring.capacity(), 4u);
  EXPECT_EQ(ring.pushed(), 0u);
  EXPECT_EQ(ring.dropped(), 0u);
}

TEST(SpscRing, FifoOrderAndFullDropsAndCounts) {
  SpscRing<int, 4> ring;
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.TryPush(i));
  EXPECT_EQ(ring.size(), 4u);
  EXPECT_FALSE(ring.TryPush(99));  // full: dropped, not overwritten
  EXPECT_FALSE(ring.TryPush(100));
  EXPECT_EQ(ring.dropped(), 2u);
  EXPECT_EQ(ring.pushed(), 4u);
  int out = 0;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(ring.TryPop(&out));
    EXPECT_EQ(out, i);
  }
  EXPECT_FALSE(ring.TryPop(&out));
  EXPECT_EQ(ring.size(), 0u);
  // Room again after popping.
  EXPECT_TRUE(ring.TryPush(7));
  ASSERT_TRUE(ring.TryPop(&out));
  EXPECT_EQ(out, 7);
}

TEST(SpscRing, WrapsAroundManyTimes) {
  SpscRing<std::uint64_t, 8> ring;
  std::uint64_t next_in = 0, next_out = 0;
  // Varying fill levels so every slot is used at every phase of the index.
  for (int round = 0; round < 1000; ++round) {
    const int pushes = 1 + round % 8;
    for (int i = 0; i < pushes; ++i) ASSERT_TRUE(ring.TryPush(next_in++));
    const int pops = 1 + (round * 5) % pushes;
    for (int i = 0; i < pops; ++i) {
      std::uint64_t v = 0;
      ASSERT_TRUE(ring.TryPop(&v));
      ASSERT_EQ(v, next_out++);
    }
    std::uint64_t v = 0;
    while (ring.size() > 0) {
      ASSERT_TRUE(ring.TryPop(&v));
      ASSERT_EQ(v, next_out++);
    }
  }
  EXPECT_EQ(next_in, next_out);
  EXPECT_EQ(ring.pushed(), next_in);
  EXPECT_EQ(ring.dropped(), 0u);
}

TEST(SpscRing, PushAndPopDoNotAllocate) {
  AMBDROP_SKIP_WITHOUT_MALLOC_HOOKS();
  SpscRing<std::array<double, 16>, 64> ring;
  std::array<double, 16> record{};
  std::int64_t allocations = 0;
  {
    testing::MallocGuard guard;
    for (int i = 0; i < 10'000; ++i) {
      record[0] = i;
      (void)ring.TryPush(record);
      if (i % 3 != 0) (void)ring.TryPop(&record);
    }
    allocations = guard.allocations();
  }
  EXPECT_GT(ring.dropped(), 0u);
  EXPECT_EQ(allocations, 0);
}

// A record several words long: a torn (half-written) record would break its check words.
struct Record {
  std::uint64_t sequence = 0;
  std::array<std::uint64_t, 7> check{};
};

Record MakeRecord(std::uint64_t sequence) {
  Record r;
  r.sequence = sequence;
  for (std::size_t i = 0; i < r.check.size(); ++i) {
    r.check[i] = sequence * 0x9E3779B97F4A7C15ull + i;
  }
  return r;
}

bool Intact(const Record& r) {
  for (std::size_t i = 0; i < r.check.size(); ++i) {
    if (r.check[i] != r.sequence * 0x9E3779B97F4A7C15ull + i) return false;
  }
  return true;
}

constexpr std::uint64_t kRecords = 1'000'000;

TEST(SpscRing, TwoThreadsLosslessWhenTheProducerRetries) {
  // The producer retries on full (what a non-real-time producer may do): every record arrives,
  // in order, intact, and each failed attempt was counted as a drop.
  auto ring = std::make_unique<SpscRing<Record, 1024>>();
  std::uint64_t failed_attempts = 0;
  std::thread producer([&] {
    for (std::uint64_t s = 0; s < kRecords; ++s) {
      const Record r = MakeRecord(s);
      while (!ring->TryPush(r)) {
        ++failed_attempts;
        std::this_thread::yield();
      }
    }
  });
  std::uint64_t received = 0, out_of_order = 0, torn = 0;
  Record r;
  while (received < kRecords) {
    if (!ring->TryPop(&r)) {
      std::this_thread::yield();  // on a 2-CPU machine spinning would starve the producer
      continue;
    }
    out_of_order += r.sequence != received;
    torn += !Intact(r);
    ++received;
  }
  producer.join();
  EXPECT_EQ(received, kRecords);
  EXPECT_EQ(out_of_order, 0u);
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(ring->pushed(), kRecords);
  EXPECT_EQ(ring->dropped(), failed_attempts);
  EXPECT_FALSE(ring->TryPop(&r));
}

TEST(SpscRing, TwoThreadsDropWhenFullButKeepOrder) {
  // The real-time producer never waits: whatever does not fit is dropped and counted. The
  // consumer sees a strictly increasing subsequence, and received + dropped == sent.
  auto ring = std::make_unique<SpscRing<Record, 64>>();
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (std::uint64_t s = 0; s < kRecords; ++s) (void)ring->TryPush(MakeRecord(s));
    done.store(true, std::memory_order_release);
  });
  std::uint64_t received = 0, out_of_order = 0, torn = 0;
  std::int64_t last = -1;
  Record r;
  for (;;) {
    if (ring->TryPop(&r)) {
      out_of_order += static_cast<std::int64_t>(r.sequence) <= last;
      last = static_cast<std::int64_t>(r.sequence);
      torn += !Intact(r);
      ++received;
    } else if (done.load(std::memory_order_acquire) && ring->size() == 0) {
      break;
    }
  }
  producer.join();
  EXPECT_EQ(out_of_order, 0u);
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(received, ring->pushed());
  EXPECT_EQ(received + ring->dropped(), kRecords);
  EXPECT_GT(received, 0u);
}

}  // namespace
}  // namespace ambdrop::spsc_ring_test
