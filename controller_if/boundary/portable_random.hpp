#pragma once
#include <cstdint>

namespace ambdrop {

/// xoshiro256** (Blackman & Vigna 2018) seeded through SplitMix64: the same stream on every
/// platform and standard library, unlike std::normal_distribution.
class PortableRandom {
 public:
  explicit PortableRandom(std::uint64_t seed = 1) noexcept {
    for (std::uint64_t& word : s_) word = SplitMix64(&seed);
  }
  /// Starts from an explicit state (reference vectors in tests).
  static PortableRandom FromState(std::uint64_t a, std::uint64_t b, std::uint64_t c,
                                  std::uint64_t d) noexcept {
    PortableRandom r;
    r.s_[0] = a;
    r.s_[1] = b;
    r.s_[2] = c;
    r.s_[3] = d;
    return r;
  }

  std::uint64_t Next() noexcept {
    const std::uint64_t result = Rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = Rotl(s_[3], 45);
    return result;
  }

  /// Uniform in [0, 1) with 53 random bits.
  double Uniform() noexcept { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }

  /// Zero mean, unit variance, approximately normal: the sum of 12 uniforms minus 6
  /// (Irwin-Hall). Only additions: bit-identical everywhere; tails end at +-6.
  double StandardNormalApprox() noexcept {
    double sum = 0.0;
    for (int i = 0; i < 12; ++i) sum += Uniform();
    return sum - 6.0;
  }

 private:
  static std::uint64_t Rotl(std::uint64_t x, int k) noexcept { return (x << k) | (x >> (64 - k)); }
  static std::uint64_t SplitMix64(std::uint64_t* x) noexcept {
    std::uint64_t z = (*x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::uint64_t s_[4]{};
};

}  // namespace ambdrop
