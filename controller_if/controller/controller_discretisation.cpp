#include "controller_if/controller/controller_discretisation.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace ambdrop {
namespace {

using Poly = std::array<double, 3>;  // coefficients of 1, q, q^2 with q = z^-1

Poly Multiply(const Poly& a, const Poly& b) {
  Poly out{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; i + j < 3; ++j) out[i + j] += a[i] * b[j];
  }
  return out;
}

int Degree(const std::array<double, 3>& s_coefficients) {
  if (s_coefficients[0] != 0.0) return 2;
  if (s_coefficients[1] != 0.0) return 1;
  return 0;
}

/// Substitutes s = P(q) / Q(q) into n[0] s^2 + n[1] s + n[2] and multiplies by Q^order.
Poly Substitute(const std::array<double, 3>& n, int order, const Poly& p, const Poly& q) {
  Poly out{};
  for (int k = 0; k <= order; ++k) {
    Poly term{1.0, 0.0, 0.0};
    for (int i = 0; i < k; ++i) term = Multiply(term, p);
    for (int i = 0; i < order - k; ++i) term = Multiply(term, q);
    const double c = n[2 - k];  // coefficient of s^k
    for (int i = 0; i < 3; ++i) out[i] += c * term[i];
  }
  return out;
}

BiquadCoefficients Normalised(const Poly& num, const Poly& den) {
  if (den[0] == 0.0 || !std::isfinite(den[0])) {
    throw std::invalid_argument("a section whose discrete denominator has no z^0 term");
  }
  return BiquadCoefficients{num[0] / den[0], num[1] / den[0], num[2] / den[0], den[1] / den[0],
                            den[2] / den[0]};
}

/// Zero-order hold: x' = A x + B u, y = C x + D u sampled exactly (Franklin, Powell & Workman,
/// "Digital Control of Dynamic Systems", 3rd ed., Sec. 4.3.3: Phi = e^{AT}, Gamma = int_0^T
/// e^{As} ds B, both from one exponential of [[A, B], [0, 0]] T, their Eq. (4.60)), then
/// H(z) = C (zI - Phi)^-1 Gamma + D.
BiquadCoefficients ZeroOrderHold(const ContinuousSection& s, int order, double t) {
  const auto& n = s.numerator;
  const auto& d = s.denominator;
  if (order == 1) {
    const double p = d[2] / d[1];  // H = (n1 s + n2) / (d1 s + d2) = D + C / (s + p)
    const double dd = n[1] / d[1];
    const double c = (n[2] - dd * d[2]) / d[1];
    const auto e = SmallMatrixExp<2>({{{-p * t, t}, {0.0, 0.0}}});
    const double phi = e[0][0];
    const double gamma = e[0][1];
    return Normalised({dd, c * gamma - dd * phi, 0.0}, {1.0, -phi, 0.0});
  }
  // Controllable canonical form of (n/d0) / (s^2 + a1 s + a2).
  const double a1 = d[1] / d[0];
  const double a2 = d[2] / d[0];
  const double dd = n[0] / d[0];
  // x2 = x1' / sigma with sigma ~ the natural frequency: a balanced matrix needs few squarings
  // (x1' itself puts w^2 T, thousands, beside 1); H(z) does not depend on the state's scale.
  const double sigma = a2 != 0.0 ? std::sqrt(std::abs(a2)) : (a1 != 0.0 ? std::abs(a1) : 1.0 / t);
  const double c0 = n[2] / d[0] - dd * a2;            // on x1
  const double c1 = (n[1] / d[0] - dd * a1) * sigma;  // on x2
  const auto e = SmallMatrixExp<3>(
      {{{0.0, sigma * t, 0.0}, {-a2 / sigma * t, -a1 * t, t / sigma}, {0.0, 0.0, 0.0}}});
  const double p00 = e[0][0], p01 = e[0][1], p10 = e[1][0], p11 = e[1][1];
  const double g0 = e[0][2], g1 = e[1][2];
  const double trace = p00 + p11;
  const double det = p00 * p11 - p01 * p10;
  // C adj(zI - Phi) Gamma = z (C Gamma) + C0 (Phi01 G1 - Phi11 G0) + C1 (Phi10 G0 - Phi00 G1).
  const double first = c0 * g0 + c1 * g1;
  const double second = c0 * (p01 * g1 - p11 * g0) + c1 * (p10 * g0 - p00 * g1);
  return Normalised({dd, first - dd * trace, second + dd * det}, {1.0, -trace, det});
}

}  // namespace

template <int N>
std::array<std::array<double, N>, N> SmallMatrixExp(const std::array<std::array<double, N>, N>& m) {
  using Matrix = std::array<std::array<double, N>, N>;
  const auto multiply = [](const Matrix& a, const Matrix& b) {
    Matrix out{};
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < N; ++j) {
        double sum = 0.0;
        for (int k = 0; k < N; ++k) sum += a[i][k] * b[k][j];
        out[i][j] = sum;
      }
    }
    return out;
  };
  double norm = 0.0;
  for (int i = 0; i < N; ++i) {
    double row = 0.0;
    for (int j = 0; j < N; ++j) row += std::abs(m[i][j]);
    norm = std::max(norm, row);
  }
  // Scale by 2^-s to a norm below 1/2, where 20 Taylor terms are exact to rounding.
  int squarings = 0;
  double scale = 1.0;
  while (norm * scale > 0.5 && squarings < 1000) {
    scale *= 0.5;
    ++squarings;
  }
  Matrix a{};
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) a[i][j] = m[i][j] * scale;
  }
  Matrix sum{};
  Matrix term{};
  for (int i = 0; i < N; ++i) sum[i][i] = term[i][i] = 1.0;
  for (int k = 1; k <= 20; ++k) {
    term = multiply(term, a);
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < N; ++j) {
        term[i][j] /= k;
        sum[i][j] += term[i][j];
      }
    }
  }
  for (int s = 0; s < squarings; ++s) sum = multiply(sum, sum);
  return sum;
}

template std::array<std::array<double, 2>, 2> SmallMatrixExp<2>(
    const std::array<std::array<double, 2>, 2>&);
template std::array<std::array<double, 3>, 3> SmallMatrixExp<3>(
    const std::array<std::array<double, 3>, 3>&);

ContinuousSection ContinuousForm(const ControllerSectionParams& p) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  switch (p.kind) {
    case SectionKind::kGain:
      return {{0.0, 0.0, p.gain}, {0.0, 0.0, 1.0}};
    case SectionKind::kPid: {
      // kp + ki/s + kd s / (tau s + 1) over one denominator (Åström & Hägglund, "Advanced PID
      // Control", 2006, Eq. (3.11) with the filtered derivative of their Sec. 3.3).
      const double tau = p.derivative_filter_s;
      if (p.ki_per_s == 0.0) return {{0.0, p.kp * tau + p.kd_s, p.kp}, {0.0, tau, 1.0}};
      return {{p.kp * tau + p.kd_s, p.kp + p.ki_per_s * tau, p.ki_per_s}, {tau, 1.0, 0.0}};
    }
    case SectionKind::kLeadLag: {
      // k (1 + s/wz) / (1 + s/wp) (Franklin, Powell & Emami-Naeini, "Feedback Control of
      // Dynamic Systems", 7th ed., Sec. 6.7, Eq. (6.39)).
      const double wz = kTwoPi * p.zero_Hz;
      const double wp = kTwoPi * p.pole_Hz;
      return {{0.0, p.gain / wz, p.gain}, {0.0, 1.0 / wp, 1.0}};
    }
    case SectionKind::kNotch: {
      // (s^2 + 2 zeta_z w s + w^2) / (s^2 + 2 zeta_p w s + w^2) (Schweitzer & Maslen, "Magnetic
      // Bearings", 2009, Sec. 8.6; Franklin, Powell & Emami-Naeini, Sec. 10.2).
      const double w = kTwoPi * p.frequency_Hz;
      return {{1.0, 2.0 * p.zero_damping * w, w * w}, {1.0, 2.0 * p.pole_damping * w, w * w}};
    }
    case SectionKind::kLowPass: {
      const double w = kTwoPi * p.cutoff_Hz;
      if (p.order == 1) return {{0.0, 0.0, 1.0}, {0.0, 1.0 / w, 1.0}};
      return {{0.0, 0.0, w * w}, {1.0, 2.0 * p.damping_ratio * w, w * w}};
    }
    case SectionKind::kSBiquad:
      return {p.numerator, p.denominator};
    case SectionKind::kZBiquad:
      break;
  }
  throw std::invalid_argument("a z_biquad section has no continuous form");
}

BiquadCoefficients Discretise(const ContinuousSection& s, Discretisation method, double period_s,
                              double prewarp_Hz) {
  const int num_order = Degree(s.numerator);
  const int den_order = Degree(s.denominator);
  if (den_order == 0 && s.denominator[2] == 0.0) {
    throw std::invalid_argument("a section whose denominator is zero");
  }
  const int order = std::max(num_order, den_order);
  if (num_order > den_order && method != Discretisation::kBackwardEuler) {
    throw std::invalid_argument(
        "an improper section (more zeros than poles) can only be discretised by backward Euler");
  }
  const double t = period_s;
  switch (method) {
    case Discretisation::kTustin: {
      // s = c (1 - z^-1) / (1 + z^-1), c = 2/T, or w0 / tan(w0 T / 2) to match the continuous
      // response at w0 (Franklin, Powell & Workman, 3rd ed., Sec. 6.3.1, Eqs. (6.6) and (6.10)).
      double c = 2.0 / t;
      if (prewarp_Hz > 0.0) {
        const double w0 = 2.0 * std::numbers::pi * prewarp_Hz;
        if (!(w0 * t / 2.0 < std::numbers::pi / 2.0)) {
          throw std::invalid_argument("a prewarp frequency at or beyond the Nyquist frequency");
        }
        c = w0 / std::tan(w0 * t / 2.0);
      }
      return Normalised(Substitute(s.numerator, order, {c, -c, 0.0}, {1.0, 1.0, 0.0}),
                        Substitute(s.denominator, order, {c, -c, 0.0}, {1.0, 1.0, 0.0}));
    }
    case Discretisation::kBackwardEuler:
      // s = (1 - z^-1) / T (Franklin, Powell & Workman, 3rd ed., Sec. 6.2, Eq. (6.4)).
      return Normalised(Substitute(s.numerator, order, {1.0, -1.0, 0.0}, {t, 0.0, 0.0}),
                        Substitute(s.denominator, order, {1.0, -1.0, 0.0}, {t, 0.0, 0.0}));
    case Discretisation::kZeroOrderHold:
      if (order == 0) return BiquadCoefficients{s.numerator[2] / s.denominator[2], 0, 0, 0, 0};
      return ZeroOrderHold(s, den_order, t);
  }
  return {};
}

BiquadCoefficients SectionBiquad(const ControllerSectionParams& section, double period_s) {
  if (section.kind == SectionKind::kZBiquad) {
    return Normalised(section.numerator, section.denominator);
  }
  return Discretise(ContinuousForm(section), section.discretisation, period_s, section.prewarp_Hz);
}

}  // namespace ambdrop
