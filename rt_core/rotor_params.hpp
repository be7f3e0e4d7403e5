#pragma once
#include <string>
#include <vector>

namespace ambdrop {

/// Isotropic linear-elastic shaft material.
struct Material {
  double youngs_modulus_Pa = 211e9;
  double shear_modulus_Pa = 81.2e9;
  double density_kg_m3 = 7810.0;
  friend bool operator==(const Material&, const Material&) = default;
};

/// One cylindrical (optionally bored) shaft section; sections follow each other along +z from 0.
struct ShaftSection {
  double length_m = 0.0;
  double outer_diameter_m = 0.0;
  double inner_diameter_m = 0.0;
  Material material;
  int elements = 1;  ///< shaft elements in this section (more are added at stations)
  friend bool operator==(const ShaftSection&, const ShaftSection&) = default;
};

/// Rigid disc or added mass at an axial position (coupling halves, impellers, laminations).
struct Disc {
  std::string name;
  double position_m = 0.0;
  double mass_kg = 0.0;
  double polar_inertia_kg_m2 = 0.0;
  double transverse_inertia_kg_m2 = 0.0;
  friend bool operator==(const Disc&, const Disc&) = default;
};

/// Rigid rotor: 4 DOF (x, y, theta_x, theta_y) at the centre of mass.
struct RigidRotorParams {
  double mass_kg = 0.0;
  double polar_inertia_kg_m2 = 0.0;
  double transverse_inertia_kg_m2 = 0.0;
  double centre_of_mass_m = 0.0;  ///< axial position of the centre of mass
  friend bool operator==(const RigidRotorParams&, const RigidRotorParams&) = default;
};

enum class RotorKind { kFlexible, kRigid };

/// Beam theory of the FE shaft elements (Friswell et al. 2010, Sec. 5.4-5.5).
enum class ShaftElementTheory {
  kTimoshenko,     ///< shear deformation, rotary inertia and its gyroscopics
  kRayleigh,       ///< rotary inertia and its gyroscopics, no shear deformation
  kEulerBernoulli  ///< neither shear deformation nor rotary inertia (nor its gyroscopics)
};

/// Torques that slow the rotor once its drive stops (seals, bearings' drag, windage), opposing
/// the spin: T = -(T0 sgn(W) + c1 W + c2 W |W|), sgn regularised (see rt_core/coast_down.hpp).
struct CoastDownParams {
  bool enabled = false;
  double constant_torque_N_m = 0.0;  ///< T0
  double viscous_N_m_s = 0.0;        ///< c1
  double windage_N_m_s2 = 0.0;       ///< c2
  /// k of the constant torque's smooth sign, k W / sqrt(1 + (k W)^2), so that it does not
  /// chatter about W = 0 (at 100 s/rad it is within 0.5 % of +-1 above 0.1 rad/s).
  double sign_regularisation_s_per_rad = 100.0;
  friend bool operator==(const CoastDownParams&, const CoastDownParams&) = default;
};

struct RotorParams {
  RotorKind kind = RotorKind::kFlexible;
  std::vector<ShaftSection> sections;  ///< flexible rotor only
  std::vector<Disc> discs;             ///< flexible rotor only
  RigidRotorParams rigid;              ///< rigid rotor only
  int modes = 12;                      ///< pseudo-modal basis size (Jarroux 2019, Sec. 5)
  double modal_damping_ratio = 0.005;  ///< applied to the flexible modes only
  ShaftElementTheory element_theory = ShaftElementTheory::kTimoshenko;  ///< flexible rotor only
  CoastDownParams coast_down;  ///< acts once the drive stops; not an input of the reduction
  friend bool operator==(const RotorParams&, const RotorParams&) = default;
};

/// Linear spring/damper support between the rotor and ground (tests, linearised bearings).
struct LinearBearingParams {
  std::string name;
  double position_m = 0.0;
  double stiffness_x_N_per_m = 0.0;
  double stiffness_y_N_per_m = 0.0;
  double damping_x_N_s_per_m = 0.0;
  double damping_y_N_s_per_m = 0.0;
  friend bool operator==(const LinearBearingParams&, const LinearBearingParams&) = default;
};

/// Unbalance mass; the phase is the angle from +x at spin angle zero (at t = 0).
struct UnbalanceParams {
  std::string name;
  bool enabled = true;
  double position_m = 0.0;
  double mass_kg = 0.0;
  double eccentricity_m = 0.0;
  double phase_rad = 0.0;
  friend bool operator==(const UnbalanceParams&, const UnbalanceParams&) = default;
};

}  // namespace ambdrop
