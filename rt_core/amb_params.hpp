#pragma once
#include <limits>
#include <string>
#include <vector>

namespace ambdrop {

enum class AmbForceLaw {
  /// Equivalent stiffness and damping per axis from the controller's transfer function at the
  /// running speed (Jarroux 2019, Sec. 5): f = -k u - c du/dt (+ gravity bias).
  kEquivalent,
  /// Linearised actuator, f = ki i + ks u (ks > 0 destabilises), control current i.
  kLinearisedCurrents,
  /// Differential-driving electromagnet pair from its geometry (seed 003):
  /// f = k ((I0 + i)^2 / (g0 - u)^2 - (I0 - i)^2 / (g0 + u)^2), k = mu0 N^2 A cos(alpha) / 4.
  kElectromagnet,
};

/// Geometry of one axis of a differential-driving heteropolar AMB (seed 003, Sec. 2).
struct ElectromagnetParams {
  double pole_area_m2 = 0.0;                        ///< A, one pole face
  double turns = 0.0;                               ///< N, per coil
  double nominal_gap_m = 0.0;                       ///< g0, air gap with the rotor centred
  double bias_current_A = 0.0;                      ///< I0
  double pole_half_angle_rad = 0.3926990816987241;  ///< alpha: 22.5 deg for an 8-pole stator
  /// Magnetic saturation of the iron: the air-gap flux density B = mu0 N I / (2 g) of a coil
  /// cannot exceed saturation_flux_density_T, which caps the coil's force (an effect switch).
  bool saturation_enabled = false;
  double saturation_flux_density_T = 0.0;
  /// k (N m^2/A^2) as a rig sheet gives it; 0: from the geometry, mu0 N^2 A cos(alpha) / 4.
  /// Last, so that brace-initialised geometries keep their order.
  double constant_N_m2_per_A2 = 0.0;
  friend bool operator==(const ElectromagnetParams&, const ElectromagnetParams&) = default;
};

/// What makes the bias flux of a current-driven AMB: the amplifiers (the coils carry I0 +- i,
/// so the bias fades with the power) or permanent magnets (the bias flux, its force and its
/// negative stiffness stay after power loss; only the control current fades).
enum class AmbBiasSource { kElectromagnet, kPermanentMagnet };

/// How each coil current falls after power loss (docs/equations.md, "AMBs after power loss").
enum class PowerLossCurrentLaw {
  kExponential,          ///< i(t) = i0 exp(-t/tau): the coil's L/R
  kSlewLimitedRamp,      ///< |i| falls at slew_rate_A_per_s and stops at zero
  kHoldThenExponential,  ///< i0 until hold_time_s, then exp(-(t - hold)/tau)
};

/// After power loss the coil currents fall by `current_law` (default exp(-t/tau), the coils'
/// L/R and the amplifier's discharge; with an electromagnet bias the force, quadratic in the
/// currents, then decays as exp(-2t/tau)). Disabled: the currents vanish at once.
struct FluxDecayParams {
  bool enabled = false;
  double time_constant_s = 0.0;  ///< tau, of the currents (not of the force)
  PowerLossCurrentLaw current_law = PowerLossCurrentLaw::kExponential;
  double slew_rate_A_per_s = 0.0;  ///< slew-limited ramp
  double hold_time_s = 0.0;        ///< hold then exponential
  /// Slew-limited ramp of a linearised-law AMB with an electromagnet bias: the coils' bias
  /// current I0 (the law itself does not declare it; the electromagnet law's geometry does).
  double bias_current_A = 0.0;
  friend bool operator==(const FluxDecayParams&, const FluxDecayParams&) = default;
};

/// Control currents of one radial AMB at one instant (linear interpolation in between).
struct CurrentSample {
  double time_s = 0.0;
  double current_x_A = 0.0;
  double current_y_A = 0.0;
  friend bool operator==(const CurrentSample&, const CurrentSample&) = default;
};

struct AmbParams {
  std::string name;
  double position_m = 0.0;
  AmbForceLaw law = AmbForceLaw::kEquivalent;
  double stiffness_N_per_m = 0.0;  ///< equivalent law
  double damping_N_s_per_m = 0.0;  ///< equivalent law
  /// Equivalent law: add the constant force an integrating controller holds so that the
  /// levitated rotor sits on the magnetic centre under gravity.
  bool gravity_compensation = true;
  double current_gain_N_per_A = 0.0;           ///< ki, linearised law
  double position_gain_N_per_m = 0.0;          ///< ks (negative stiffness), linearised law
  std::vector<CurrentSample> current_profile;  ///< control currents when no controller runs
  ElectromagnetParams electromagnet;           ///< electromagnet law
  /// Amplifier limit on the control current |i| (A); the electromagnet law further keeps both
  /// coil currents I0 +- i within [0, limit]. Infinite: no limit.
  double current_limit_A = std::numeric_limits<double>::infinity();
  AmbBiasSource bias_source = AmbBiasSource::kElectromagnet;  ///< current-driven laws
  FluxDecayParams flux_decay;
  std::string sensor;  ///< sensor plane that feeds this AMB's controller (default: same name)
  friend bool operator==(const AmbParams&, const AmbParams&) = default;
};

}  // namespace ambdrop
