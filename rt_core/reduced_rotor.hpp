#pragma once
#include <Eigen/Core>
#include <vector>

#include "rt_core/eigen_types.hpp"

namespace ambdrop {

/// Rotor in mass-normalised generalized coordinates q = [q_x | q_y], the first half moving
/// the rotor in the xz plane only, the second in the yz plane only (pseudo-modal basis of a
/// flexible rotor, Jarroux 2019 Sec. 5, or the scaled 4 DOF of a rigid rotor):
///   q'' + (C + Omega G) q' + (K + dOmega/dt G) q = S^T f.
/// The mass matrix is the identity. G is the skew gyroscopic matrix per unit spin speed; with the
/// spin axis taken as (theta_y, -theta_x, 1) it is also the transient matrix KG of Eq. (13).
struct ReducedRotor {
  int size = 0;
  ModalVector modal_stiffness;  ///< diagonal of K without the bearings (omega^2; 0 rigid-body)
  ModalVector modal_damping;    ///< diagonal of C without the bearings (2 zeta omega)
  ModalMatrix stiffness;        ///< K: modal stiffness plus linear bearings
  ModalMatrix damping;          ///< C: modal damping plus linear bearings
  ModalMatrix gyroscopic;       ///< G
  ModalVector free_frequencies_rad_s;  ///< of the retained free-free modes (0 for rigid-body)
  /// Generalized force of a unit acceleration field along +y (basis^T M e_y): gravity is
  /// -g times this.
  ModalVector vertical_unit_force;
  double mass_kg = 0.0;
  double polar_inertia_kg_m2 = 0.0;
  double length_m = 0.0;
  double centre_of_mass_m = 0.0;  ///< axial position

  /// Physical DOF (x, y, theta_x, theta_y per node) = basis * q, and the node positions, kept to
  /// evaluate station shapes anywhere (linear between nodes for the translations).
  Eigen::MatrixXd basis;
  std::vector<double> node_positions_m;

  /// (x, y) at axial position z as a 2 x size map of q.
  StationShape ShapeAt(double z_m) const;
};

}  // namespace ambdrop
