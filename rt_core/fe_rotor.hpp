#pragma once
#include <Eigen/Core>
#include <vector>

#include "rt_core/model_params.hpp"

namespace ambdrop {

/// Finite-element rotor, 4 DOF per node ordered (x, y, theta_x, theta_y): shaft beam
/// elements plus rigid discs. Lateral displacement at offset dz from a node is
/// (x + dz theta_y, y - dz theta_x). Equation of motion (Jarroux 2019 Eq. (13)):
///   M q'' + (Omega G + C) q' + (dOmega/dt G + K) q = F.
struct FeRotor {
  std::vector<double> node_positions_m;
  Eigen::MatrixXd mass;
  Eigen::MatrixXd stiffness;   ///< shaft only (free-free)
  Eigen::MatrixXd gyroscopic;  ///< per unit spin speed, skew-symmetric
  double mass_kg = 0.0;
  double polar_inertia_kg_m2 = 0.0;
  double length_m = 0.0;
  double centre_of_mass_m = 0.0;  ///< axial, of the shaft's elements and the discs together

  int dofs() const { return static_cast<int>(mass.rows()); }
  /// Node at axial position z (every station is meshed as a node); -1 if none.
  int NodeAt(double z_m) const;
};

/// Meshes the shaft sections (each into its element count, split again at every station
/// position so that stations fall on nodes) and assembles M, K and G.
FeRotor AssembleFeRotor(const RotorParams& rotor, const std::vector<double>& station_positions_m);

/// Stiffness and damping of the linear bearings in the FE DOF ordering.
void LinearBearingMatrices(const FeRotor& fe, const std::vector<LinearBearingParams>& bearings,
                           Eigen::MatrixXd* stiffness, Eigen::MatrixXd* damping);

/// Axial positions where the model needs nodes: bearings, AMBs, TDBs, sensors, unbalances, discs.
std::vector<double> StationPositions(const ModelParams& params);

}  // namespace ambdrop
