#include "controller_if/loop/timing_stats.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace ambdrop {

int TimingStats::BucketIndex(std::int64_t value_ns) noexcept {
  if (value_ns < kSubBuckets) return static_cast<int>(std::max<std::int64_t>(value_ns, 0));
  const auto v = static_cast<std::uint64_t>(value_ns);
  // exponent: position of the leading bit (>= kSubBucketBits here); the next kSubBucketBits bits
  // pick the sub-bucket.
  const int exponent = std::bit_width(v) - 1;
  const int shift = exponent - kSubBucketBits;
  const int sub = static_cast<int>(v >> shift) - kSubBuckets;
  return (shift + 1) * kSubBuckets + sub;
}

std::int64_t TimingStats::BucketLowerBound(int index) noexcept {
  if (index < kSubBuckets) return index;
  const int shift = index / kSubBuckets - 1;
  const int sub = index % kSubBuckets;
  return static_cast<std::int64_t>(static_cast<std::uint64_t>(kSubBuckets + sub) << shift);
}

std::int64_t TimingStats::BucketUpperBound(int index) noexcept {
  if (index < kSubBuckets) return index;
  const int shift = index / kSubBuckets - 1;
  // Computed in unsigned arithmetic: the last bucket ends exactly at INT64_MAX.
  const std::uint64_t lower = static_cast<std::uint64_t>(BucketLowerBound(index));
  return static_cast<std::int64_t>(lower + ((std::uint64_t{1} << shift) - 1));
}

void TimingStats::Record(std::int64_t value_ns) noexcept {
  if (value_ns < 0) {
    ++clamped_negative_;
    value_ns = 0;
  }
  ++buckets_[BucketIndex(value_ns)];
  if (count_ == 0 || value_ns < min_ns_) min_ns_ = value_ns;
  if (value_ns > max_ns_) max_ns_ = value_ns;
  ++count_;
  sum_ns_ += static_cast<double>(value_ns);
}

void TimingStats::Merge(const TimingStats& other) noexcept {
  if (other.count_ == 0) return;
  for (int i = 0; i < kBucketCount; ++i) buckets_[i] += other.buckets_[i];
  min_ns_ = count_ == 0 ? other.min_ns_ : std::min(min_ns_, other.min_ns_);
  max_ns_ = std::max(max_ns_, other.max_ns_);
  count_ += other.count_;
  sum_ns_ += other.sum_ns_;
  clamped_negative_ += other.clamped_negative_;
}

void TimingStats::Reset() noexcept {
  *this = TimingStats();
}

std::int64_t TimingStats::Quantile(double q) const noexcept {
  if (count_ == 0) return 0;
  // Rank in exact integer arithmetic from q in ppm: ceil(q * count) done in floating point
  // misrounds (0.99 * 100 = 99.000000000000014 would give rank 100).
  constexpr std::int64_t kPpm = 1'000'000;
  const std::int64_t q_ppm =
      std::clamp<std::int64_t>(std::llround(q * static_cast<double>(kPpm)), 0, kPpm);
  const std::int64_t whole = count_ / kPpm;
  const std::int64_t rest = count_ % kPpm;
  std::int64_t rank = whole * q_ppm + (rest * q_ppm + kPpm - 1) / kPpm;
  rank = std::clamp<std::int64_t>(rank, 1, count_);
  std::int64_t cumulative = 0;
  for (int i = 0; i < kBucketCount; ++i) {
    cumulative += buckets_[i];
    if (cumulative >= rank) return std::clamp(BucketUpperBound(i), min_ns_, max_ns_);
  }
  return max_ns_;  // unreachable: the buckets add up to count_
}

TimingSummary TimingStats::Summarize() const noexcept {
  TimingSummary s;
  s.count = count_;
  s.min_ns = min_ns();
  s.p50_ns = Quantile(0.5);
  s.p99_ns = Quantile(0.99);
  s.p999_ns = Quantile(0.999);
  s.max_ns = max_ns_;
  s.mean_ns = mean_ns();
  return s;
}

}  // namespace ambdrop
