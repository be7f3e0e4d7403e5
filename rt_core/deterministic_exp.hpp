#pragma once
// exp for the step, written out so that it is inlined and gives the same bits on every x86-64
// CPU. glibc picks its exp at run time by CPU feature (__exp_fma), and an out-of-line call makes
// the caller spill every live SSE register: inlined, the 4-DOF Dahl step runs ~7 % faster
// (tests/bench/tdb_models_bench). (An inlined Cephes atan was tried too and was slower than
// glibc's.) Moshier's Cephes algorithm: argument reduction, then a rational approximation,
// within ~1.5 ulp; tests/deterministic_exp_test.cpp holds it against the standard library.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

namespace ambdrop {

/// e^x, within ~1 ulp of std::exp. Results below 2^-1022 (x < -708.39) are returned as 0:
/// the step has no use for subnormals, which are slow.
inline double DeterministicExp(double x) noexcept {
  constexpr double kMaxArgument = 709.782712893383973096;   // ln(DBL_MAX)
  constexpr double kMinArgument = -708.396418532264106224;  // ln(2^-1022)
  if (!(x < kMaxArgument)) return x != x ? x : std::numeric_limits<double>::infinity();
  if (x < kMinArgument) return 0.0;
  // n = round(x / ln 2) by the 1.5 * 2^52 shift (exact for |x / ln 2| < 2^51, round to nearest).
  constexpr double kShift = 6755399441055744.0;
  const double n = (x * std::numbers::log2e + kShift) - kShift;
  // r = x - n ln 2 in two parts (Cody and Waite), |r| <= ln(2) / 2.
  constexpr double kLn2High = 6.93145751953125e-1;
  constexpr double kLn2Low = 1.42860682030941723212e-6;
  double r = x - n * kLn2High;
  r = r - n * kLn2Low;
  // e^r = 1 + 2 r P(r^2) / (Q(r^2) - r P(r^2)) (Cephes exp.c).
  const double rr = r * r;
  const double p = r * ((1.26177193074810590878e-4 * rr + 3.02994407707441961300e-2) * rr +
                        9.99999999999999999910e-1);
  const double q = ((3.00198505138664455042e-6 * rr + 2.52448340349684104192e-3) * rr +
                    2.27265548208155028766e-1) *
                       rr +
                   2.00000000000000000009e0;
  const double er = 1.0 + 2.0 * (p / (q - p));
  // Scale by 2^n, built in the exponent field; n lies in [-1022, 1024], and 2^1024 is split in
  // two so that both factors are normal numbers.
  const auto k = static_cast<std::int64_t>(n);
  if (k <= 1023) return er * std::bit_cast<double>(static_cast<std::uint64_t>(k + 1023) << 52);
  return (er * std::bit_cast<double>(static_cast<std::uint64_t>(k - 1 + 1023) << 52)) * 2.0;
}

}  // namespace ambdrop
