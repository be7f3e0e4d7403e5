#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "rt_core/amb_params.hpp"
#include "rt_core/deterministic_exp.hpp"

namespace ambdrop {

inline constexpr double kVacuumPermeability_H_per_m = 1.25663706212e-6;

/// k of the electromagnet law (N m^2 / A^2): as given, or from the geometry,
/// mu0 N^2 A cos(alpha) / 4 (seed 003, Eq. (2)).
inline double ElectromagnetConstant(const ElectromagnetParams& e) noexcept {
  if (e.constant_N_m2_per_A2 > 0.0) return e.constant_N_m2_per_A2;
  return kVacuumPermeability_H_per_m * e.turns * e.turns * e.pole_area_m2 *
         std::cos(e.pole_half_angle_rad) / 4.0;
}

/// Current and position gains of the electromagnet law linearised at the centre:
/// ki = 4 k I0 / g0^2 (N/A), ks = 4 k I0^2 / g0^3 (N/m).
inline double ElectromagnetCurrentGain(const ElectromagnetParams& e) noexcept {
  return 4.0 * ElectromagnetConstant(e) * e.bias_current_A / (e.nominal_gap_m * e.nominal_gap_m);
}
inline double ElectromagnetPositionGain(const ElectromagnetParams& e) noexcept {
  return 4.0 * ElectromagnetConstant(e) * e.bias_current_A * e.bias_current_A /
         (e.nominal_gap_m * e.nominal_gap_m * e.nominal_gap_m);
}

/// The control current the amplifier can deliver: |i| <= limit, and for the electromagnet law
/// both coil currents I0 +- i inside [0, limit]. A permanent-magnet bias is no coil current, so
/// there the amplifier carries i alone (|i| <= limit) and I0 - |i| >= 0 keeps the weaker
/// pole's flux from reversing.
inline double ControlCurrentLimit(const AmbParams& a) noexcept {
  if (a.law != AmbForceLaw::kElectromagnet) return a.current_limit_A;
  const double i0 = a.electromagnet.bias_current_A;
  if (a.bias_source == AmbBiasSource::kPermanentMagnet) return std::min(i0, a.current_limit_A);
  return std::min(i0, a.current_limit_A - i0);
}
inline double LimitedCurrent(const AmbParams& a, double current_A) noexcept {
  const double limit = ControlCurrentLimit(a);
  return std::clamp(current_A, -limit, limit);
}

/// Largest force one coil of the axis can pull with when the iron saturates:
/// F = B^2 A cos(alpha) / mu0 at B = B_sat (the law below with mu0 N I / (2 g) = B_sat);
/// +infinity with saturation off.
inline double SaturatedCoilForce(const ElectromagnetParams& e) noexcept {
  if (!e.saturation_enabled) return std::numeric_limits<double>::infinity();
  const double b = e.saturation_flux_density_T;
  return b * b * e.pole_area_m2 * std::cos(e.pole_half_angle_rad) / kVacuumPermeability_H_per_m;
}

/// Force of one electromagnet axis (N, along +u) for control current i and rotor displacement u
/// (seed 003's law, Eq. (2)), each coil's pull capped at `max_coil_force_N` (saturation).
/// The displacement is held short of the pole faces: the TDBs stop the rotor long before, and
/// the law is singular there.
/// The same with the constant k precomputed (the step's form: no cos per call).
inline double ElectromagnetForce(
    double k, double nominal_gap_m, double bias_current_A, double current_A, double displacement_m,
    double max_coil_force_N = std::numeric_limits<double>::infinity()) noexcept {
  const double g0 = nominal_gap_m;
  const double u = std::clamp(displacement_m, -0.95 * g0, 0.95 * g0);
  const double plus = bias_current_A + current_A;
  const double minus = bias_current_A - current_A;
  const double pull_plus = std::min(k * (plus * plus / ((g0 - u) * (g0 - u))), max_coil_force_N);
  const double pull_minus = std::min(k * (minus * minus / ((g0 + u) * (g0 + u))), max_coil_force_N);
  return pull_plus - pull_minus;
}
inline double ElectromagnetForce(const ElectromagnetParams& e, double current_A,
                                 double displacement_m) noexcept {
  return ElectromagnetForce(ElectromagnetConstant(e), e.nominal_gap_m, e.bias_current_A, current_A,
                            displacement_m, SaturatedCoilForce(e));
}

/// Control current that makes the static force f at the centre (feedforward for gravity).
inline double CurrentForStaticForce(const AmbParams& a, double force_N) noexcept {
  switch (a.law) {
    case AmbForceLaw::kLinearisedCurrents:
      return force_N / a.current_gain_N_per_A;
    case AmbForceLaw::kElectromagnet:
      return force_N / ElectromagnetCurrentGain(a.electromagnet);
    case AmbForceLaw::kEquivalent:
      break;
  }
  return 0.0;
}

/// Scale on an AMB's force `seconds` after it lost power: 0 without flux decay, else
/// exp(-2 t / tau) (currents decay as exp(-t/tau); the force is quadratic in them).
inline double FluxDecayForceScale(const AmbParams& a, double seconds) noexcept {
  if (!a.flux_decay.enabled || !(a.flux_decay.time_constant_s > 0.0)) return 0.0;
  return DeterministicExp(-2.0 * seconds / a.flux_decay.time_constant_s);
}

}  // namespace ambdrop
