#pragma once
#include <Eigen/Core>

#include "rt_core/fe_rotor.hpp"
#include "rt_core/reduced_rotor.hpp"

namespace ambdrop {

/// Pseudo-modal reduction (Jarroux 2019 Sec. 5; Lalanne & Ferraris): the basis is the first
/// `modes`/2 free-free modes of each bending plane (K, M), rigid-body modes included,
/// mass-normalised, ordered [xz-plane modes | yz-plane modes]. Modal damping 2 zeta omega is put
/// on the flexible modes; bearings and gyroscopics are projected.
ReducedRotor ReduceFeRotor(const FeRotor& fe, const Eigen::MatrixXd& bearing_stiffness,
                           const Eigen::MatrixXd& bearing_damping, int modes,
                           double modal_damping_ratio);

/// Rigid rotor as 4 mass-normalised coordinates (x, y, theta_x, theta_y at the centre of mass).
ReducedRotor RigidReducedRotor(const RigidRotorParams& rigid,
                               const std::vector<LinearBearingParams>& bearings);

/// The reduced rotor a config describes (flexible or rigid).
ReducedRotor BuildReducedRotor(const ModelParams& params);

/// Everything BuildReducedRotor reads: two configs with equal inputs have the same reduced
/// rotor, so a caller that builds many models of one rig (a fit) can reduce it once.
struct ReductionInputs {
  RotorParams rotor;
  std::vector<LinearBearingParams> bearings;
  std::vector<double> stations_m;  ///< StationPositions, in their order
  friend bool operator==(const ReductionInputs&, const ReductionInputs&) = default;
};
ReductionInputs ReductionInputsOf(const ModelParams& params);

}  // namespace ambdrop
