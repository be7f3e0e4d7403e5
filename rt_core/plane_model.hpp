#pragma once
#include <vector>

#include "rt_core/amb_params.hpp"
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

/// One AMB as the step applies it (per axis, times the input's force scale):
///   equivalent:   f = bias - k u - c u'
///   linearised:   f = ki i + ks u
///   electromagnet: f = k ((I0 + i)^2/(g0 - u)^2 - (I0 - i)^2/(g0 + u)^2)
struct PlaneAmb {
  PlaneStation shape;
  AmbParams params;
  double bias_x_N = 0.0;  ///< equivalent law with gravity compensation
  double bias_y_N = 0.0;
  double current_limit_A = 0.0;         ///< ControlCurrentLimit
  double electromagnet_constant = 0.0;  ///< k of the electromagnet law (N m^2/A^2)
  double max_coil_force_N = 0.0;        ///< SaturatedCoilForce (+inf without saturation)
};

/// The reduced equations split by bending plane, which is what the step integrates. Shaft,
/// discs, bearings and AMBs never couple the planes: the modal stiffness and damping are
/// diagonal, the gyroscopic matrix block off-diagonal, and each station's x sees only q_x, its y
/// only q_y. Supports act as station forces (O(h) each) rather than as dense projected matrices
/// (O(h^2)).
struct PlaneModel {
  int h = 0;  ///< modes per plane
  PlaneVector modal_stiffness_x, modal_stiffness_y, modal_damping_x, modal_damping_y;
  std::vector<PlaneSupport> bearings;  ///< linear supports, always acting
  std::vector<PlaneAmb> ambs;
  PlaneMatrix gyroscopic_xy;  ///< G block: rows q_x, columns q_y
  PlaneMatrix gyroscopic_yx;
  PlaneVector gravity_x, gravity_y;
  std::vector<PlaneStation> tdbs, sensors, unbalances;
};

}  // namespace ambdrop
