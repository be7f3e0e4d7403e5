#pragma once
#include <vector>

#include "rt_core/eigen_types.hpp"

namespace ambdrop {

inline constexpr int kMaxPlaneModes = kMaxModes / 2;
using PlaneMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxPlaneModes, kMaxPlaneModes>;
using PlaneVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxPlaneModes, 1>;

/// Displacement of one station: x = sx . q_x, y = sy . q_y.
struct PlaneStation {
  PlaneVector sx;
  PlaneVector sy;
};

/// A linear spring/damper acting at a station: f = -(k u + c u') per axis.
struct PlaneSupport {
  PlaneStation shape;
  double stiffness_x_N_per_m = 0.0;
  double stiffness_y_N_per_m = 0.0;
  double damping_x_N_s_per_m = 0.0;
  double damping_y_N_s_per_m = 0.0;
};

/// The reduced equations split by bending plane, which is what the step integrates. Shaft,
/// discs, bearings and AMBs never couple the planes: the modal stiffness and damping are
/// diagonal, the gyroscopic matrix block off-diagonal, and each station's x sees only q_x, its y
/// only q_y. Supports act as station forces (O(h) each) rather than as dense projected matrices
/// (O(h^2)).
struct PlaneModel {
  int h = 0;  ///< modes per plane
  PlaneVector modal_stiffness_x, modal_stiffness_y, modal_damping_x, modal_damping_y;
  std::vector<PlaneSupport> bearings;          ///< always acting
  std::vector<PlaneSupport> powered_supports;  ///< AMB stiffness/damping while powered
  PlaneMatrix gyroscopic_xy;                   ///< G block: rows q_x, columns q_y
  PlaneMatrix gyroscopic_yx;
  PlaneVector gravity_x, gravity_y;
  PlaneVector amb_bias_x, amb_bias_y;
  std::vector<PlaneStation> ambs, tdbs, sensors, unbalances;
};

}  // namespace ambdrop
