// The step's inlined exp against the standard library's, which is correctly rounded to within
// an ulp on glibc: the two may differ in the last bits but not more.
#include "rt_core/deterministic_exp.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

namespace ambdrop::deterministic_exp_test {
namespace {

// Distance in units in the last place between two positive finite doubles.
std::int64_t UlpDistance(double a, double b) {
  const auto ia = std::bit_cast<std::int64_t>(a);
  const auto ib = std::bit_cast<std::int64_t>(b);
  return ia > ib ? ia - ib : ib - ia;
}

TEST(DeterministicExp, WithinTwoUlpOfTheLibraryOverTheNormalRange) {
  // A fixed, library-independent sweep: an irrational stride covers the range without pattern.
  std::int64_t worst = 0;
  double worst_x = 0.0;
  for (int i = 0; i < 400000; ++i) {
    const double u = std::fmod(i * 0.6180339887498949, 1.0);
    const double x = -708.0 + u * (709.7 + 708.0);
    const std::int64_t d = UlpDistance(DeterministicExp(x), std::exp(x));
    if (d > worst) {
      worst = d;
      worst_x = x;
    }
  }
  EXPECT_LE(worst, 2) << "at x = " << worst_x;
}

TEST(DeterministicExp, ExactWhereExpIsExactAndSmoothNearZero) {
  EXPECT_EQ(DeterministicExp(0.0), 1.0);
  EXPECT_EQ(DeterministicExp(-0.0), 1.0);
  // Around the Dahl envelopes' arguments (b u of order 1) and tiny ones, e^x ~ 1 + x.
  for (const double x : {1e-300, 1e-12, -1e-12, 1e-8}) {
    EXPECT_NEAR(DeterministicExp(x), 1.0 + x, 1e-16) << x;
  }
  EXPECT_LE(UlpDistance(DeterministicExp(1.0), std::numbers::e), 1);
  EXPECT_LE(UlpDistance(DeterministicExp(std::log(2.0)), 2.0), 1);
}

TEST(DeterministicExp, NearlyMonotonicAcrossTheReductionBoundaries) {
  // The reduction switches n at x = (k + 1/2) ln 2. The approximations on either side meet to
  // within an ulp, so the result may step back by one ulp there, never more.
  for (int k = -50; k <= 50; ++k) {
    double x = (k + 0.5) * std::log(2.0);
    for (int j = 0; j < 16; ++j) x = std::nextafter(x, -1e9);
    double previous = DeterministicExp(x);
    for (int j = 0; j < 32; ++j) {
      x = std::nextafter(x, 1e9);
      const double value = DeterministicExp(x);
      ASSERT_GE(value, std::nextafter(previous, 0.0)) << "k = " << k << ", x = " << x;
      previous = value;
    }
  }
}

TEST(DeterministicExp, OverflowUnderflowAndNaN) {
  EXPECT_EQ(DeterministicExp(710.0), std::numeric_limits<double>::infinity());
  EXPECT_EQ(DeterministicExp(std::numeric_limits<double>::infinity()),
            std::numeric_limits<double>::infinity());
  EXPECT_EQ(DeterministicExp(-709.0), 0.0);  // below 2^-1022: flushed, never subnormal
  EXPECT_EQ(DeterministicExp(-std::numeric_limits<double>::infinity()), 0.0);
  EXPECT_TRUE(std::isnan(DeterministicExp(std::numeric_limits<double>::quiet_NaN())));
  // The largest finite result and the smallest normal one are still reached.
  EXPECT_TRUE(std::isfinite(DeterministicExp(709.78)));
  EXPECT_GT(DeterministicExp(709.78), 1e308);
  EXPECT_GE(DeterministicExp(-708.39), std::numeric_limits<double>::min() * 0.5);
}

}  // namespace
}  // namespace ambdrop::deterministic_exp_test
