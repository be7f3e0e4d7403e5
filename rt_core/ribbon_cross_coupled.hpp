#pragma once
#include <cmath>
#include <numbers>

#include "rt_core/four_dof_params.hpp"

namespace ambdrop {

/// Whirl speed (m/s, > 0 along +spin, i.e. anticlockwise seen from +z) of a point at (x, y)
/// moving at (vx, vy): the tangential part of its velocity, (x vy - y vx) / |(x, y)|; 0 at the
/// centre.
inline double WhirlSpeed(double x_m, double y_m, double vx_m_s, double vy_m_s) noexcept {
  const double radius = std::sqrt(x_m * x_m + y_m * y_m);
  return radius > 0.0 ? (x_m * vy_m_s - y_m * vx_m_s) / radius : 0.0;
}

/// Restoring force frd (N) of the cross-coupled ribbon for the outer-race position (x, y) and
/// velocity (vx, vy) relative to the housing centre; the outer race feels -frd.
/// Jarroux 2016 (seed 001), Eq. (1):
///   -frd = -kcrd [[1, -eta s], [eta s, 1]] (x, y) - ccrd (vx, vy),
///   s = sgn(v_or) as an arctan law, (2/pi) atan(vref v_or), v_or the outer race's whirl speed.
/// The cross-coupled part, kcrd eta s (-y, x), is tangential and against the whirl: its power on
/// the outer race, -kcrd eta s |(x, y)| v_or, is never positive.
inline void CrossCoupledRibbonForce(const CrossCoupledRibbonParams& p, double x_m, double y_m,
                                    double vx_m_s, double vy_m_s, double* frd_x_N,
                                    double* frd_y_N) noexcept {
  const double whirl = WhirlSpeed(x_m, y_m, vx_m_s, vy_m_s);
  // Jarroux 2016 (seed 001), Eq. (1): sign as an arctan law.
  const double sign = (2.0 / std::numbers::pi) * std::atan(p.sign_regularisation_s_per_m * whirl);
  const double eta_s = p.cross_coupling * sign;
  // Jarroux 2016 (seed 001), Eq. (1)
  *frd_x_N = p.stiffness_N_per_m * (x_m - eta_s * y_m) + p.damping_N_s_per_m * vx_m_s;
  *frd_y_N = p.stiffness_N_per_m * (eta_s * x_m + y_m) + p.damping_N_s_per_m * vy_m_s;
}

}  // namespace ambdrop
