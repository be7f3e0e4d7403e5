#pragma once
// The rotor's lateral dynamics as n generalised coordinates per bending plane, the same
// matrices in both planes (the rotor is axisymmetric). With W the spin:
//   M qx'' + C qx' + K qx + G (W qy' + W' qy) = sum of phi(z)^T Fx
//   M qy'' + C qy' + K qy - G (W qx' + W' qx) = sum of phi(z)^T Fy - g r
// where phi(z) gives the displacement at station z and r the coordinates' share of the weight.
// The slope of the x plane is dx/dz = theta_y, of the y plane dy/dz = -theta_x (rig.hpp's
// frame), which makes G enter both planes with one matrix.
//
// Rigid rotor: q = (displacement at the centre of mass, slope), M = diag(m, It), G = diag(0, Ip)
// (Jarroux 2019 Eq. (13), rigid limit). Flexible: Rayleigh beam elements with cubic Hermite
// shape functions (Friswell, Penny, Garvey & Lees, "Dynamics of Rotating Machines", 2010,
// Sec. 5.4.1: Eq. (5.59) stiffness, (5.61) translational mass, (5.62) rotary inertia; the
// gyroscopic matrix is twice the rotary-inertia matrix for a circular section, Sec. 5.4.2),
// rigid discs at nodes, reduced to the two rigid-body and the first bending free-free modes,
// mass-normalised (the pseudo-modal basis of Jarroux 2019 Sec. 5), 2 zeta omega on the bending
// modes.
#include <vector>

#include <Eigen/Core>

#include "rig.hpp"

namespace ambdrop_truth {

struct RotorModes {
  int n = 0;  ///< coordinates per plane
  /// M is diagonal in both models (diag(m, It); the identity of mass-normalised modes), so the
  /// accelerations divide by its diagonal: for the rigid rotor bit for bit the old 4-DOF form.
  Eigen::VectorXd mass;
  Eigen::MatrixXd damping, stiffness, gyroscopic;
  Eigen::VectorXd weight_share;          ///< r: the generalised force of a unit acceleration (kg)
  Eigen::VectorXd gravity_acceleration;  ///< r / M: each coordinate's acceleration per unit g
  std::vector<double> bending_rad_s;

  // The flexible model's mesh and mode shapes (node i: rows 2i displacement, 2i + 1 slope).
  std::vector<double> nodes_m;
  Eigen::MatrixXd shapes;
  double centre_of_mass_m = 0.0;  ///< the rigid model's

  /// Displacement per coordinate at station z (Hermite interpolation inside an element).
  Eigen::RowVectorXd AtStation(double z_m) const;
};

/// The rigid rotor of `rotor`.
RotorModes RigidRotorModes(const RotorRig& rotor);

/// The flexible shaft's reduced model; every station in `stations_m` becomes a node.
RotorModes FlexibleRotorModes(const FlexibleShaftRig& shaft, std::vector<double> stations_m);

/// The mass, centre of mass, transverse inertia about it and polar inertia of a flexible shaft
/// with its discs (for the rig's RotorRig numbers and the effects placed at the centre of mass).
RotorRig ShaftInertia(const FlexibleShaftRig& shaft);

/// The full (unreduced) free-free bending frequencies of the shaft at rest, ascending, rigid
/// modes left out (tests: beam closed forms).
std::vector<double> FreeFreeBendingFrequencies(const FlexibleShaftRig& shaft,
                                               std::vector<double> stations_m);

}  // namespace ambdrop_truth
