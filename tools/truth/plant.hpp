#pragma once
// The rigid rotor, its AMBs and TDBs as one first-order system y' = f(y, input), integrated by
// classical RK4 at the rig's fine step (contact events are resolved by the step alone).
//
// Rotor (rigid, 4 lateral DOF plus spin; frame of rig.hpp): at station offset d = z - z_cm the
// lateral displacement is (x + d thy, y - d thx); a force (Fx, Fy) there gives the moments
// (Mx, My) = (-d Fy, d Fx). With H = (It thx' + Ip W thy, It thy' - Ip W thx, Ip W):
//   m x'' = Fx,  m y'' = Fy - m g,
//   It thx'' = Mx - Ip (W' thy + W thy'),  It thy'' = My + Ip (W' thx + W thx')
// (the rigid-rotor limit of Jarroux 2019 Eq. (13)); the motor holds W until the power fails,
// then Ip W' = sum of the TDBs' friction torques.
// AMB axis: seed 003 Eq. (2), f = k ((I0 + i)^2 / (g0 - u)^2 - (I0 - i)^2 / (g0 + u)^2), here
// with the two coil currents given directly (the power-loss laws scale them).
// Unbalance (m e at phase p, spin angle phi): m e (W^2 cos a + W' sin a, W^2 sin a - W' cos a),
// a = phi + p.
#include <array>

#include <Eigen/Core>

#include "rig.hpp"
#include "tdb_contact.hpp"

namespace ambdrop_truth {

/// State indices.
inline constexpr int kX = 0, kY = 1, kThx = 2, kThy = 3, kVx = 4, kVy = 5, kWx = 6, kWy = 7;
inline constexpr int kSpinAngle = 8, kSpin = 9;
inline constexpr int kRace = 10;     ///< + TDB index: race speed (rad/s)
inline constexpr int kLag = 12;      ///< + 2 sensor + axis: the low-passed displacement (m)
inline constexpr int kHousing = 16;  ///< + 6 TDB: ux, uy, vx, vy, Dahl fx, Dahl fy
inline constexpr int kStateSize = 28;
using PlantState = Eigen::Matrix<double, kStateSize, 1>;

/// Held over a step: each AMB axis's two coil currents (A; [.][.][0] pulls towards +u) and the
/// motor (on: the spin is held).
struct PlantInput {
  std::array<std::array<std::array<double, 2>, 2>, 2> coil_A{};
  bool motor_on = true;
};

/// What a derivative evaluation also reports (for the record and the tests).
struct PlantOutputs {
  std::array<ContactForces, 2> tdb{};
  std::array<std::array<double, 2>, 2> amb_force_N{};
  std::array<std::array<double, 2>, 2> sensor_displacement_m{};  ///< true, before the lag
};

class Plant {
 public:
  explicit Plant(const Rig& rig);
  const Rig& rig() const { return rig_; }

  void Derivative(const PlantState& y, const PlantInput& in, PlantState* rate,
                  PlantOutputs* out) const;
  void Step(PlantState* y, const PlantInput& in) const;

  /// Displacement (x, y) at station z for a state.
  std::array<double, 2> AtStation(const PlantState& y, double z_m) const;
  std::array<double, 2> VelocityAtStation(const PlantState& y, double z_m) const;

  /// Total mechanical energy (J): kinetic (rotor, races, housings), gravity's potential, the
  /// linear contacts' springs. Used by the energy test (no AMB, no Dahl).
  double Energy(const PlantState& y) const;

 private:
  Rig rig_;
  mutable PlantState k1_, k2_, k3_, k4_, stage_;
  mutable PlantOutputs scratch_{};
};

/// AMB force along +u of one axis for its two coil currents (seed 003 Eq. (2)).
double AmbAxisForce(const AmbRig& a, double coil_plus_A, double coil_minus_A, double u_m);

}  // namespace ambdrop_truth
