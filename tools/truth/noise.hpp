#pragma once
// The generator's own seeded noise: splitmix64 seeds xoshiro256** (Blackman & Vigna,
// "Scrambled linear pseudorandom number generators", 2021), and Box-Muller turns its uniforms
// into Gaussians. No std distribution: their algorithms differ between standard libraries.
#include <cmath>
#include <cstdint>
#include <numbers>

namespace ambdrop_truth {

/// splitmix64 (Steele, Lea & Flood 2014): one 64-bit output per call, used to expand a seed.
inline std::uint64_t SplitMix64(std::uint64_t* state) {
  std::uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

class GaussianNoise {
 public:
  /// `stream` separates the channels of one record: each has its own sequence.
  GaussianNoise(std::uint64_t seed, std::uint64_t stream) {
    std::uint64_t s = seed ^ (stream * 0xd1342543de82ef95ULL);
    for (auto& word : s_) word = SplitMix64(&s);
  }

  /// A uniform in (0, 1]: 53 random bits, never 0 (Box-Muller takes its logarithm).
  double Uniform() { return (static_cast<double>(Next() >> 11) + 1.0) * 0x1.0p-53; }

  /// A standard normal by Box-Muller, both of each pair used.
  double Normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double r = std::sqrt(-2.0 * std::log(Uniform()));
    const double angle = 2.0 * std::numbers::pi * Uniform();
    spare_ = r * std::sin(angle);
    has_spare_ = true;
    return r * std::cos(angle);
  }

 private:
  static std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t Next() {
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
  std::uint64_t s_[4]{};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace ambdrop_truth
