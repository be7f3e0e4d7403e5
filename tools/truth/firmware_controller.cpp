#include "firmware_controller.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ambdrop_truth {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Substitutes s = c (1 - q) / (1 + q), q = 1/z, into p2 s^2 + p1 s + p0 and multiplies by
/// (1 + q)^2: the coefficients of q^0, q^1, q^2.
std::array<double, 3> Substitute(const std::array<double, 3>& p, double c) {
  const double p2 = p[0] * c * c, p1 = p[1] * c, p0 = p[2];
  return {p2 + p1 + p0, 2.0 * (p0 - p2), p2 - p1 + p0};
}

}  // namespace

std::complex<double> Biquad::Response(double w_rad_s, double period_s) const {
  const std::complex<double> q = std::exp(std::complex<double>(0.0, -w_rad_s * period_s));
  return (b[0] + b[1] * q + b[2] * q * q) / (a[0] + a[1] * q + a[2] * q * q);
}

void SectionPolynomials(const FirmwareSectionRig& s, std::array<double, 3>* num,
                        std::array<double, 3>* den) {
  switch (s.kind) {
    case FirmwareSectionRig::Kind::kPd:  // kp + kd s / (tau s + 1)
      *num = {0.0, s.kp * s.derivative_filter_s + s.kd_s, s.kp};
      *den = {0.0, s.derivative_filter_s, 1.0};
      return;
    case FirmwareSectionRig::Kind::kLead: {  // (1 + s/wz) / (1 + s/wp)
      *num = {0.0, 1.0 / (kTwoPi * s.zero_Hz), 1.0};
      *den = {0.0, 1.0 / (kTwoPi * s.pole_Hz), 1.0};
      return;
    }
    case FirmwareSectionRig::Kind::kNotch: {
      const double w = kTwoPi * s.frequency_Hz;
      *num = {1.0, 2.0 * s.zero_damping * w, w * w};
      *den = {1.0, 2.0 * s.pole_damping * w, w * w};
      return;
    }
  }
}

std::complex<double> SectionResponse(const FirmwareSectionRig& s, double w_rad_s) {
  std::array<double, 3> num{}, den{};
  SectionPolynomials(s, &num, &den);
  const std::complex<double> jw(0.0, w_rad_s);
  return (num[0] * jw * jw + num[1] * jw + num[2]) / (den[0] * jw * jw + den[1] * jw + den[2]);
}

Biquad Discretise(const FirmwareSectionRig& s, double period_s) {
  std::array<double, 3> num{}, den{};
  SectionPolynomials(s, &num, &den);
  double c = 2.0 / period_s;
  if (s.prewarp_Hz > 0.0) {
    const double w0 = kTwoPi * s.prewarp_Hz;
    c = w0 / std::tan(0.5 * w0 * period_s);
  }
  const std::array<double, 3> n = Substitute(num, c);
  const std::array<double, 3> d = Substitute(den, c);
  Biquad q;
  for (int i = 0; i < 3; ++i) {
    q.b[i] = n[i] / d[0];
    q.a[i] = d[i] / d[0];
  }
  return q;
}

FirmwareAxis::FirmwareAxis(const ControllerRig& c, double limit_A, double feedforward_A)
    : c_(c), limit_A_(limit_A), feedforward_A_(feedforward_A) {
  for (const FirmwareSectionRig& s : c.sections) {
    sections_.push_back(Discretise(s, 1.0 / c.rate_Hz));
    state_.push_back({0.0, 0.0});
  }
}

double FirmwareAxis::Update(double reading_m) {
  double x = -c_.sensor_gain_V_per_m * reading_m;
  for (std::size_t i = 0; i < sections_.size(); ++i) {
    const Biquad& q = sections_[i];
    auto& s = state_[i];
    const double y = q.b[0] * x + s[0];
    s[0] = q.b[1] * x - q.a[1] * y + s[1];
    s[1] = q.b[2] * x - q.a[2] * y;
    x = y;
  }
  return std::clamp(c_.amplifier_gain_A_per_V * x + feedforward_A_, -limit_A_, limit_A_);
}

}  // namespace ambdrop_truth
