#pragma once
// What an unpowered AMB axis applies, by power-loss current law and bias source
// (docs/equations.md, "AMBs after power loss"). Called by the power state every step, so it is
// noexcept, allocation-free and uses DeterministicExp.
#include <algorithm>
#include <cmath>

#include "rt_core/amb_force.hpp"
#include "rt_core/amb_params.hpp"
#include "rt_core/deterministic_exp.hpp"

namespace ambdrop {

/// The drive of one unpowered axis: the control current that flows, a scale on the whole force
/// and a scale on the bias current I0 (the step applies ki I0-scaled, ks by its square).
struct UnpoweredDrive {
  double current_A = 0.0;
  double force_scale = 0.0;
  double bias_scale = 1.0;
};

/// Fraction of a current left `seconds` after power loss for the laws that scale every coil
/// current alike: exp(-t/tau), or 1 until the hold time and exp(-(t - hold)/tau) after it
/// (the source-free RL circuit, tau = L/R; Hayt and Kemmerly, Engineering Circuit Analysis).
/// Squared (the force) it is computed as one exp of twice the argument, which keeps the
/// exponential law's force exactly as before the laws were added.
inline double UniformCurrentFraction(const FluxDecayParams& d, double seconds,
                                     double power) noexcept {
  const double t = d.current_law == PowerLossCurrentLaw::kHoldThenExponential
                       ? std::max(0.0, seconds - d.hold_time_s)
                       : seconds;
  if (t == 0.0) return 1.0;
  return DeterministicExp(-power * t / d.time_constant_s);
}

/// A coil current ramped toward zero by `drop_A` = slew rate x time, stopping there (L di/dt =
/// -V of a coil discharged at a held voltage, the same RL circuit with R i << V).
inline double RampedCurrent(double current_A, double drop_A) noexcept {
  return std::copysign(std::max(std::abs(current_A) - drop_A, 0.0), current_A);
}

/// The coils' bias current I0 of a current-driven AMB (electromagnet law: its geometry;
/// linearised law: the ramp's declared one).
inline double CoilBiasCurrent(const AmbParams& a) noexcept {
  return a.law == AmbForceLaw::kElectromagnet ? a.electromagnet.bias_current_A
                                              : a.flux_decay.bias_current_A;
}

/// `held_A` is the control current commanded when power failed.
inline UnpoweredDrive PowerLossDrive(const AmbParams& a, double held_A, double seconds) noexcept {
  const FluxDecayParams& d = a.flux_decay;
  const bool permanent_magnet =
      a.bias_source == AmbBiasSource::kPermanentMagnet && a.law != AmbForceLaw::kEquivalent;
  if (!permanent_magnet) {
    // Electromagnet bias: bias and control currents fall together, so ki and ks fade with them.
    if (!d.enabled) return {held_A, 0.0, 1.0};
    if (d.current_law == PowerLossCurrentLaw::kExponential) {
      return {held_A, FluxDecayForceScale(a, seconds), 1.0};
    }
    if (d.current_law == PowerLossCurrentLaw::kHoldThenExponential) {
      // The force is homogeneous of degree 2 in (I0, i): scaling both by s scales it by s^2.
      return {held_A, UniformCurrentFraction(d, seconds, 2.0), 1.0};
    }
    // Each coil, I0 + i and I0 - i, ramps toward zero at the slew rate on its own; the pair is
    // then again a bias (I+ + I-)/2 and a control current (I+ - I-)/2, which seed 003's law
    // (Eq. (2)) takes as they are and its linearisation as ki I0(t)/I0, ks (I0(t)/I0)^2.
    const double bias_A = CoilBiasCurrent(a);
    if (!(bias_A > 0.0)) return {0.0, 0.0, 0.0};
    const double i0 = LimitedCurrent(a, held_A);
    const double drop_A = d.slew_rate_A_per_s * seconds;
    const double plus = std::max(bias_A + i0 - drop_A, 0.0);
    const double minus = std::max(bias_A - i0 - drop_A, 0.0);
    return {0.5 * (plus - minus), 1.0, 0.5 * (plus + minus) / bias_A};
  }
  // Permanent-magnet bias: the magnet's flux stays, only the coil's control current falls.
  if (!d.enabled) return {0.0, 1.0, 1.0};
  if (d.current_law == PowerLossCurrentLaw::kSlewLimitedRamp) {
    return {RampedCurrent(LimitedCurrent(a, held_A), d.slew_rate_A_per_s * seconds), 1.0, 1.0};
  }
  return {held_A * UniformCurrentFraction(d, seconds, 1.0), 1.0, 1.0};
}

/// The drive of an unpowered axis whose control current is not modelled but measured
/// (`measurement.power_loss = "from_record"`): `recorded_A` is the coil's control current at
/// this instant. A magnet's bias stays, so the force follows the coil current as it does while
/// powered. An electromagnet's bias current is not in the record (its channel carries the control
/// current): it falls by the declared law, as PowerLossDrive's bias would, and the recorded control
/// current rides on it. For the uniform laws the declared bias fraction s and a record that
/// follows the same law (i = s held) give exactly PowerLossDrive's force: F(s I0, s i) = s^2 F(I0,
/// i).
inline UnpoweredDrive RecordedCurrentDrive(const AmbParams& a, double held_A, double recorded_A,
                                           double seconds) noexcept {
  const FluxDecayParams& d = a.flux_decay;
  if (a.law == AmbForceLaw::kEquivalent) return PowerLossDrive(a, held_A, seconds);
  if (a.bias_source == AmbBiasSource::kPermanentMagnet) return {recorded_A, 1.0, 1.0};
  // Without a declared decay the bias vanishes at once, and with it the force.
  if (!d.enabled) return {recorded_A, 0.0, 0.0};
  if (d.current_law == PowerLossCurrentLaw::kSlewLimitedRamp) {
    return {recorded_A, 1.0, PowerLossDrive(a, held_A, seconds).bias_scale};
  }
  return {recorded_A, 1.0, UniformCurrentFraction(d, seconds, 1.0)};
}

/// The control current the coil carries (what records and measured-like channels report): the
/// drive's current times the square root of the force scale, the uniform laws' current fraction.
inline double ReportedCoilCurrent(const UnpoweredDrive& u) noexcept {
  return u.current_A * std::sqrt(std::max(0.0, u.force_scale));
}

}  // namespace ambdrop
