#pragma once
// One second-order section in direct form II transposed: y = b0 x + s1, s1 <- b1 x - a1 y + s2,
// s2 <- b2 x - a2 y. Transposed form II keeps two states and has good numerics for the
// low-frequency poles of a controller (Åström & Wittenmark, "Computer-Controlled Systems",
// 3rd ed., Sec. 13.4).

namespace ambdrop {

/// H(z) = (b0 + b1 z^-1 + b2 z^-2) / (1 + a1 z^-1 + a2 z^-2).
struct BiquadCoefficients {
  double b0 = 1.0;
  double b1 = 0.0;
  double b2 = 0.0;
  double a1 = 0.0;
  double a2 = 0.0;

  /// A pole at z = 1: the section integrates (what anti-windup acts on).
  bool Integrates() const noexcept;
};

class Biquad {
 public:
  Biquad() = default;
  explicit Biquad(const BiquadCoefficients& c) : c_(c) {}

  double Update(double x) noexcept {
    const double y = c_.b0 * x + s1_;
    s1_ = c_.b1 * x - c_.a1 * y + s2_;
    s2_ = c_.b2 * x - c_.a2 * y;
    return y;
  }

  const BiquadCoefficients& coefficients() const noexcept { return c_; }
  double s1() const noexcept { return s1_; }
  double s2() const noexcept { return s2_; }
  void SetState(double s1, double s2) noexcept {
    s1_ = s1;
    s2_ = s2;
  }
  /// The state of the section at rest with constant input x and output y: s1 = y - b0 x,
  /// s2 = b2 x - a2 y. A rest when y (1 + a1 + a2) = x (b0 + b1 + b2): y = H(1) x, or for an
  /// integrating section x = 0 and any y (the integral it holds).
  void HoldAt(double x, double y) noexcept {
    s1_ = y - c_.b0 * x;
    s2_ = c_.b2 * x - c_.a2 * y;
  }
  /// Adds w to every later output of an integrating section (see back-calculation in
  /// discrete_controller.cpp): with 1 + a1 + a2 = 0, s1 += w and s2 -= a2 w keep it there.
  void AddToIntegral(double w) noexcept {
    s1_ += w;
    s2_ -= c_.a2 * w;
  }

 private:
  BiquadCoefficients c_{};
  double s1_ = 0.0;
  double s2_ = 0.0;
};

}  // namespace ambdrop
