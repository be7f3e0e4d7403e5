#pragma once
// The rotor (rigid or flexible, rotor_modes.hpp), its AMBs and TDBs as one first-order system
// y' = f(y, input), integrated by classical RK4 at the rig's fine step (contact events are
// resolved by the step alone).
//
// Rotor: rotor_modes.hpp's equations in each bending plane; the motor holds W until the power
// fails, then Ip W' = sum of the TDBs' friction torques - (c1 W + c2 W |W|) (coast-down).
// AMB axis: seed 003 Eq. (2), f = k ((I0 + i)^2 / (g0 - u)^2 - (I0 - i)^2 / (g0 + u)^2), here
// with the two coil currents given directly (the power-loss laws scale them); while the
// amplifier is powered its coil control current is a state, i' = w (c - i) within the slew
// rate (a first-order current loop).
// Unbalance (m e at phase p, spin angle phi): m e (W^2 cos a + W' sin a, W^2 sin a - W' cos a),
// a = phi + p.
#include <array>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "rig.hpp"
#include "rotor_modes.hpp"
#include "tdb_contact.hpp"

namespace ambdrop_truth {

/// Where each part of the state sits, for n rotor coordinates per plane.
struct StateLayout {
  int n = 2;
  int qx(int i) const { return i; }
  int qy(int i) const { return n + i; }
  int vx(int i) const { return 2 * n + i; }
  int vy(int i) const { return 3 * n + i; }
  int spin_angle() const { return 4 * n; }
  int spin() const { return 4 * n + 1; }
  int race(int tdb) const { return 4 * n + 2 + tdb; }
  /// The low-passed displacement (m) of a sensor axis.
  int lag(int sensor, int axis) const { return 4 * n + 4 + 2 * sensor + axis; }
  /// + 0..5: ux, uy, vx, vy, Dahl fx, Dahl fy of a TDB's housing (with the 4-DOF mount: the
  /// inner race's ux, uy, vx, vy, then the Dahl ribbon's forces under the outer race);
  /// + 6..9: ux, uy, vx, vy of the 4-DOF mount's outer race.
  int housing(int tdb) const { return 4 * n + 8 + 10 * tdb; }
  int outer_race(int tdb) const { return housing(tdb) + 6; }
  /// The coil control current (A) an amplifier drives.
  int coil(int amb, int axis) const { return 4 * n + 28 + 2 * amb + axis; }
  int size() const { return 4 * n + 32; }
};
using PlantState = Eigen::VectorXd;

/// Held over a step: each AMB axis's two coil currents (A; [.][.][0] pulls towards +u) and the
/// motor (on: the spin is held).
/// With `amplifier_on` the coils carry I0 +- the amplifier's state and `command_A` drives it;
/// otherwise they carry `coil_A`.
struct PlantInput {
  std::array<std::array<std::array<double, 2>, 2>, 2> coil_A{};
  std::array<std::array<double, 2>, 2> command_A{};
  bool amplifier_on = false;
  bool motor_on = true;
};

/// What a derivative evaluation also reports (for the record and the tests).
struct PlantOutputs {
  std::array<ContactForces, 2> tdb{};
  std::array<std::array<double, 2>, 2> amb_force_N{};
  std::array<std::array<double, 2>, 2> sensor_displacement_m{};  ///< true, before the lag
  std::array<std::array<double, 2>, 2> amb_displacement_m{};     ///< [amb][axis], the rotor
  /// The force each TDB puts on its ground along +x, +y (N): the contact's reaction, or with
  /// the 4-DOF mount the ribbon's, its races' weight included (a load cell reads it tared).
  std::array<std::array<double, 2>, 2> support_N{};
};

class Plant {
 public:
  explicit Plant(const Rig& rig);
  const Rig& rig() const { return rig_; }
  const StateLayout& layout() const { return layout_; }
  const RotorModes& modes() const { return modes_; }
  /// A zero state of the right size.
  PlantState ZeroState() const { return PlantState::Zero(layout_.size()); }

  void Derivative(const PlantState& y, const PlantInput& in, PlantState* rate,
                  PlantOutputs* out) const;
  void Step(PlantState* y, const PlantInput& in) const;

  /// Displacement (x, y) at station z for a state.
  std::array<double, 2> AtStation(const PlantState& y, double z_m) const;
  std::array<double, 2> VelocityAtStation(const PlantState& y, double z_m) const;

  /// Total mechanical energy (J): kinetic (rotor, races), the shaft's strain, gravity's
  /// potential, the contacts' springs (linear or Hunt-Crossley's k u^(n+1)/(n+1)), a 4-DOF
  /// mount's races, bearing and Kelvin-Voigt ribbon. Used by the energy tests (no AMB, no Dahl).
  double Energy(const PlantState& y) const;

 private:
  const Eigen::RowVectorXd& Shape(double z_m) const;

  Rig rig_;
  RotorModes modes_;
  StateLayout layout_;
  std::vector<std::pair<double, Eigen::RowVectorXd>> shapes_;  ///< per station, cached
  mutable PlantState k1_, k2_, k3_, k4_, stage_;
  mutable Eigen::VectorXd fx_, fy_, ax_, ay_;
  mutable PlantOutputs scratch_{};
};

/// AMB force along +u of one axis for its two coil currents (seed 003 Eq. (2)).
/// The fraction of an AMB's air gap beyond which AmbAxisForce clamps the rotor's displacement:
/// the law is singular at the poles, and nothing models a pole strike.
inline constexpr double kAmbLawGapFraction = 0.95;

double AmbAxisForce(const AmbRig& a, double coil_plus_A, double coil_minus_A, double u_m);

}  // namespace ambdrop_truth
