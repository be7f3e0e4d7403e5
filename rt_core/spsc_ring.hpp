#pragma once
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace ambdrop {

/// Single-producer/single-consumer ring of fixed-size records for hand-off between the real-time
/// thread and an I/O thread. Lock-free, allocation-free, wait-free on both sides. Capacity is a
/// power of two; when full, TryPush drops the record and counts it (the real-time side never
/// blocks); `dropped()` says how many were lost.
template <typename T, std::size_t Capacity>
class SpscRing {
  static_assert(Capacity >= 2 && (Capacity & (Capacity - 1)) == 0, "capacity: a power of two");

 public:
  /// Producer side. False (and the drop counter incremented) when the ring is full.
  bool TryPush(const T& value) noexcept {
    const std::uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) == Capacity) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    slots_[head & (Capacity - 1)] = value;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  /// Consumer side. False when empty.
  bool TryPop(T* out) noexcept {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    *out = slots_[tail & (Capacity - 1)];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  std::size_t size() const noexcept {
    return static_cast<std::size_t>(head_.load(std::memory_order_acquire) -
                                    tail_.load(std::memory_order_acquire));
  }
  static constexpr std::size_t capacity() noexcept { return Capacity; }
  std::uint64_t pushed() const noexcept { return head_.load(std::memory_order_acquire); }
  std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

 private:
  // Head and tail on separate cache lines: the two threads never share a written line.
  alignas(64) std::atomic<std::uint64_t> head_{0};
  alignas(64) std::atomic<std::uint64_t> tail_{0};
  alignas(64) std::atomic<std::uint64_t> dropped_{0};
  std::array<T, Capacity> slots_{};
};

}  // namespace ambdrop
