// The general linear controller's sections against closed forms written here from the
// textbook formulas, not from controller_if/controller/controller_discretisation.cpp: a notch's
// response against its bilinear H(z), a prewarped notch's zero, a zero-order-hold low-pass's step
// response, the PID shorthand against the PID recurrence, a lead's phase at its centre, and the
// anti-windup rules' limits.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "controller_if/controller/biquad.hpp"
#include "controller_if/controller/controller_discretisation.hpp"
#include "controller_if/controller/discrete_controller.hpp"

namespace ambdrop::discrete_controller_test {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;
constexpr double kRate_Hz = 20000.0;
constexpr double kT = 1.0 / kRate_Hz;

/// Steady-state response of `section` to cos(2 pi k n / N): drives it long enough for its
/// transient to die, then takes the DFT bin k of N samples of the output.
Complex MeasuredResponse(const BiquadCoefficients& c, int k, int n, int settle) {
  Biquad b(c);
  const double theta = 2.0 * kPi * k / n;
  for (int i = 0; i < settle; ++i) b.Update(std::cos(theta * i));
  Complex sum = 0.0;
  for (int i = settle; i < settle + n; ++i) {
    sum += b.Update(std::cos(theta * i)) * std::polar(1.0, -theta * i);
  }
  return 2.0 * sum / static_cast<double>(n);
}

/// H(z) = (b0 + b1 z^-1 + b2 z^-2) / (a0 + a1 z^-1 + a2 z^-2) at z = e^{j theta}.
Complex Evaluate(const std::array<double, 3>& b, const std::array<double, 3>& a, double theta) {
  const Complex q = std::polar(1.0, -theta);
  return (b[0] + b[1] * q + b[2] * q * q) / (a[0] + a[1] * q + a[2] * q * q);
}

ControllerSectionParams Notch(double f_Hz, double zero_damping, double pole_damping) {
  ControllerSectionParams s;
  s.kind = SectionKind::kNotch;
  s.frequency_Hz = f_Hz;
  s.zero_damping = zero_damping;
  s.pole_damping = pole_damping;
  return s;
}

TEST(DiscreteController, NotchMatchesItsBilinearTransferFunction) {
  const double f0 = 1000.0, zz = 0.02, zp = 0.2;
  const BiquadCoefficients c = SectionBiquad(Notch(f0, zz, zp), kT);
  // s = (2/T)(1 - q)/(1 + q) in (s^2 + 2 zeta w s + w^2), times (1 + q)^2 (Franklin, Powell &
  // Workman, Eq. (6.6)).
  const double w = 2 * kPi * f0, k = 2 / kT;
  const auto bilinear = [&](double zeta) {
    return std::array<double, 3>{k * k + 2 * zeta * w * k + w * w, 2 * w * w - 2 * k * k,
                                 k * k - 2 * zeta * w * k + w * w};
  };
  const int n = 2000;  // bins of 10 Hz
  for (int bin : {10, 30, 60, 80, 95, 100, 105, 120, 200, 500}) {
    const Complex expected = Evaluate(bilinear(zz), bilinear(zp), 2 * kPi * bin / n);
    const Complex measured = MeasuredResponse(c, bin, n, 20000);
    EXPECT_NEAR(measured.real(), expected.real(), 1e-9) << bin * 10 << " Hz";
    EXPECT_NEAR(measured.imag(), expected.imag(), 1e-9) << bin * 10 << " Hz";
  }
}

TEST(DiscreteController, PrewarpedTustinPutsTheNotchZeroAtItsFrequency) {
  // 3 kHz at 20 kHz: far enough up that plain Tustin misplaces the zero.
  const double f0 = 3000.0;
  ControllerSectionParams notch = Notch(f0, 0.0, 0.3);
  const int n = 20, bin = 3;  // 3 cycles in 20 samples: 3 kHz exactly
  const Complex plain = MeasuredResponse(SectionBiquad(notch, kT), bin, n, 2000);
  EXPECT_GT(std::abs(plain), 0.05);
  notch.prewarp_Hz = f0;
  const Complex prewarped = MeasuredResponse(SectionBiquad(notch, kT), bin, n, 2000);
  EXPECT_LT(std::abs(prewarped), 1e-9);
}

TEST(DiscreteController, ZeroOrderHoldLowPassStepMatchesTheExactStepResponse) {
  ControllerSectionParams lp;
  lp.kind = SectionKind::kLowPass;
  lp.cutoff_Hz = 800.0;
  lp.discretisation = Discretisation::kZeroOrderHold;
  Biquad b(SectionBiquad(lp, kT));
  const double tau = 1.0 / (2 * kPi * lp.cutoff_Hz);
  // A held unit step from t = 0: y(nT) = 1 - exp(-nT / tau), sample n giving y(nT).
  for (int i = 0; i < 200; ++i) {
    EXPECT_NEAR(b.Update(1.0), 1.0 - std::exp(-i * kT / tau), 1e-13) << i;
  }
}

TEST(DiscreteController, ZeroOrderHoldSecondOrderLowPassStepMatchesTheUnderdampedResponse) {
  ControllerSectionParams lp;
  lp.kind = SectionKind::kLowPass;
  lp.order = 2;
  lp.cutoff_Hz = 1200.0;
  lp.damping_ratio = 0.3;
  lp.discretisation = Discretisation::kZeroOrderHold;
  Biquad b(SectionBiquad(lp, kT));
  const double w = 2 * kPi * lp.cutoff_Hz, z = lp.damping_ratio, wd = w * std::sqrt(1 - z * z);
  for (int i = 0; i < 200; ++i) {
    const double t = i * kT;
    // Ogata, "Modern Control Engineering", 5th ed., Eq. (5-21).
    const double expected =
        1 - std::exp(-z * w * t) * (std::cos(wd * t) + z / std::sqrt(1 - z * z) * std::sin(wd * t));
    EXPECT_NEAR(b.Update(1.0), expected, 1e-12) << i;
  }
}

TEST(DiscreteController, PidShorthandReproducesThePidRecurrence) {
  LinearControllerParams p;
  p.sensor_gain_V_per_m = 1.0;
  p.amplifier_gain_A_per_V = 1.0;
  ControllerSectionParams pid;
  pid.kind = SectionKind::kPid;
  pid.kp = 2.0;
  pid.ki_per_s = 300.0;
  pid.kd_s = 4e-3;
  pid.derivative_filter_s = 1e-4;
  pid.discretisation = Discretisation::kBackwardEuler;
  p.sections = {pid};
  LinearAxis axis(p, kT, 0.0, 1e9);
  // By hand: I_n = I_{n-1} + ki T e_n; (tau + T) D_n = tau D_{n-1} + kd (e_n - e_{n-1}), e_{-1} =
  // 0.
  double integral = 0.0, derivative = 0.0, previous = 0.0;
  for (int i = 0; i < 300; ++i) {
    const double e = std::sin(0.05 * i) + (i > 100 ? 0.5 : 0.0);
    integral += pid.ki_per_s * kT * e;
    derivative = (pid.derivative_filter_s * derivative + pid.kd_s * (e - previous)) /
                 (pid.derivative_filter_s + kT);
    previous = e;
    const double expected = pid.kp * e + integral + derivative;
    EXPECT_NEAR(axis.Update(-e), expected, 1e-11 * (1 + std::abs(expected))) << i;
  }
}

TEST(DiscreteController, LeadPhaseAtItsCentreMatchesTheArctangentFormula) {
  ControllerSectionParams lead;
  lead.kind = SectionKind::kLeadLag;
  lead.zero_Hz = 100.0;
  lead.pole_Hz = 900.0;
  lead.gain = 2.0;
  const double centre = std::sqrt(lead.zero_Hz * lead.pole_Hz);  // 300 Hz
  lead.prewarp_Hz = centre;
  // phi = atan(wc / wz) - atan(wc / wp) (Franklin, Powell & Emami-Naeini, Eq. (6.40)).
  const double expected = std::atan(centre / lead.zero_Hz) - std::atan(centre / lead.pole_Hz);
  const Complex h = MeasuredResponse(SectionBiquad(lead, kT), 3, 200, 20000);  // 300 Hz
  EXPECT_NEAR(std::arg(h), expected, 1e-9);
  EXPECT_NEAR(std::abs(h), lead.gain * std::sqrt(lead.pole_Hz / lead.zero_Hz), 1e-9);
}

struct WindupRun {
  double unlimited_A;
  double limited_A;
};

/// An integrator (ki = 100/s) driven by a constant error of 0.5 V into a 1 A limit for 2000
/// samples of 1 ms.
WindupRun Windup(AntiWindup rule) {
  LinearControllerParams p;
  p.sensor_gain_V_per_m = 1.0;
  p.amplifier_gain_A_per_V = 1.0;
  p.anti_windup = rule;
  p.back_calculation_time_s = 0.01;
  ControllerSectionParams pid;
  pid.kind = SectionKind::kPid;
  pid.ki_per_s = 100.0;
  pid.discretisation = Discretisation::kBackwardEuler;
  p.sections = {pid};
  LinearAxis axis(p, 1e-3, 0.0, 1.0);
  WindupRun run{};
  for (int i = 0; i < 2000; ++i) run.limited_A = axis.Update(-0.5);
  run.unlimited_A = axis.unlimited_A();
  return run;
}

TEST(DiscreteController, AntiWindupRules) {
  // None: the integral keeps growing, ki T e per sample.
  EXPECT_NEAR(Windup(AntiWindup::kNone).unlimited_A, 100.0 * 1e-3 * 0.5 * 2000, 1e-9);
  // Conditional: it stops where the next sample would first pass the limit.
  const WindupRun held = Windup(AntiWindup::kConditional);
  EXPECT_GT(held.unlimited_A, 1.0);
  EXPECT_LE(held.unlimited_A, 1.0 + 100.0 * 1e-3 * 0.5 + 1e-12);
  // Back-calculation: dI/dt = ki e + (limit - u) / Tt settles at u = limit + Tt ki e.
  EXPECT_NEAR(Windup(AntiWindup::kBackCalculation).unlimited_A, 1.0 + 0.01 * 100.0 * 0.5, 1e-9);
  EXPECT_EQ(Windup(AntiWindup::kBackCalculation).limited_A, 1.0);
}

}  // namespace
}  // namespace ambdrop::discrete_controller_test
