#pragma once
#include <array>
#include <cstdint>

namespace ambdrop {

/// Quantiles of one TimingStats (all ns). Each quantile is the upper edge of the histogram bucket
/// holding it, clamped to [min, max]: at most 1/16 (6.25 %) above the exact value.
struct TimingSummary {
  std::int64_t count = 0;
  std::int64_t min_ns = 0;
  std::int64_t p50_ns = 0;
  std::int64_t p99_ns = 0;
  std::int64_t p999_ns = 0;  ///< 99.9th percentile
  std::int64_t max_ns = 0;   ///< exact
  double mean_ns = 0.0;
};

/// Log-scale histogram of durations (ns) for the real-time loop: recording is O(1), noexcept and
/// allocation-free, and the storage is a fixed array (~7.7 kB), so the loop thread can record
/// every period. Values 0..15 ns have a bucket each; above that every power of two is split into
/// 16 equal buckets, so a bucket is at most 1/16 of its lower edge wide and quantiles come out
/// within 6.25 % over the whole int64 range. Min, max, count and mean are exact. Not thread-safe:
/// read it when the loop has stopped (or copy it on the loop thread).
class TimingStats {
 public:
  /// Sub-buckets per power of two: 2^kSubBucketBits.
  static constexpr int kSubBucketBits = 4;
  static constexpr int kSubBuckets = 1 << kSubBucketBits;
  /// Buckets covering 0 .. INT64_MAX.
  static constexpr int kBucketCount = (63 - kSubBucketBits + 1) * kSubBuckets;

  /// Adds one duration (ns). Negative values are counted in clamped_negative() and recorded as 0.
  void Record(std::int64_t value_ns) noexcept;
  /// Adds all of `other`'s samples.
  void Merge(const TimingStats& other) noexcept;
  /// Forgets every sample.
  void Reset() noexcept;

  /// The value at quantile `q` (0..1, resolved to 1 ppm) by nearest rank: the smallest recorded
  /// value with at least ceil(q count) samples at or below it, as the upper edge of its bucket
  /// clamped to [min, max]. 0 when empty.
  std::int64_t Quantile(double q) const noexcept;
  TimingSummary Summarize() const noexcept;

  std::int64_t count() const noexcept { return count_; }
  std::int64_t min_ns() const noexcept { return count_ > 0 ? min_ns_ : 0; }
  std::int64_t max_ns() const noexcept { return max_ns_; }
  double mean_ns() const noexcept { return count_ > 0 ? sum_ns_ / static_cast<double>(count_) : 0; }
  std::int64_t clamped_negative() const noexcept { return clamped_negative_; }
  std::int64_t bucket_count(int index) const noexcept { return buckets_[index]; }

  /// Bucket holding `value_ns` (>= 0).
  static int BucketIndex(std::int64_t value_ns) noexcept;
  /// Smallest and largest value (ns) of bucket `index`.
  static std::int64_t BucketLowerBound(int index) noexcept;
  static std::int64_t BucketUpperBound(int index) noexcept;

 private:
  std::array<std::int64_t, kBucketCount> buckets_{};
  std::int64_t count_ = 0;
  std::int64_t min_ns_ = 0;
  std::int64_t max_ns_ = 0;
  double sum_ns_ = 0.0;
  std::int64_t clamped_negative_ = 0;
};

}  // namespace ambdrop
