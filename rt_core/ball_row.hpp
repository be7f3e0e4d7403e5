#pragma once
#include <array>
#include <cmath>

#include "rt_core/catcher_bearing_params.hpp"
#include "rt_core/impact_function.hpp"

namespace ambdrop {

inline constexpr int kMaxBallsPerRow = 64;

/// A ball bearing's coefficients, derived once from BallBearingRowParams (seed 003 Table 2).
struct BallRow {
  ImpactParams ball_contact;        ///< one ball, inner and outer contacts in series, e = 3/2
  double radial_clearance_m = 0.0;  ///< Pd / 2
  int balls = 0;
  double rows = 1.0;
  double cage_inner_factor = 0.0;  ///< (1 - D/dm) / 2: cage speed per inner-ring speed
  double cage_outer_factor = 0.0;  ///< (1 + D/dm) / 2: cage speed per outer-ring speed
  double viscous_drag_N_m_s = 0.0;
  double palmgren_moment_per_N_m = 0.0;            ///< f1 dm
  std::array<double, kMaxBallsPerRow> cos_ball{};  ///< cos(2 pi j / Z)
  std::array<double, kMaxBallsPerRow> sin_ball{};
};

/// Builds the row; throws std::invalid_argument on unusable parameters.
BallRow MakeBallRow(const BallBearingRowParams& p, const char* what);

/// Force (N) the balls put on the inner ring for the inner-ring displacement (dx, dy) and
/// velocity relative to the outer ring, balls at cage_angle + 2 pi j / Z (seed 003 Sec. 2.3,
/// Eq. (1) per ball with e = 3/2 and the radial clearance). The outer ring gets the opposite.
inline void BallRowForce(const BallRow& r, double cage_angle_rad, double dx, double dy, double dvx,
                         double dvy, double* fx_N, double* fy_N) noexcept {
  const double cc = std::cos(cage_angle_rad);
  const double sc = std::sin(cage_angle_rad);
  double fx = 0.0, fy = 0.0;
  for (int j = 0; j < r.balls; ++j) {
    // Ball j's direction: cage angle + 2 pi j / Z.
    const double c = cc * r.cos_ball[j] - sc * r.sin_ball[j];
    const double s = sc * r.cos_ball[j] + cc * r.sin_ball[j];
    const double deflection = dx * c + dy * s - r.radial_clearance_m;
    if (!(deflection > 0.0)) continue;
    // Seed 003, Eq. (1) for the ball contact
    const double q = ImpactForce(r.ball_contact, deflection, dvx * c + dvy * s);
    fx -= q * c;
    fy -= q * s;
  }
  *fx_N = r.rows * fx;
  *fy_N = r.rows * fy;
}

/// Friction moment (N m) on the inner ring's relative rotation, opposing it: viscous plus
/// Palmgren's load moment f1 F dm, its sign regularised as x / sqrt(1 + x^2) with x = vref *
/// relative surface speed at the pitch circle (as tdb_common.hpp's RaceAcceleration).
inline double BallRowMoment(const BallRow& r, double relative_speed_rad_s, double load_N,
                            double pitch_radius_m, double vref_s_per_m) noexcept {
  double moment = r.viscous_drag_N_m_s * relative_speed_rad_s;
  const double load_moment = r.palmgren_moment_per_N_m * load_N;
  if (load_moment != 0.0) {
    const double x = vref_s_per_m * relative_speed_rad_s * pitch_radius_m;
    moment += load_moment * x / std::sqrt(1.0 + x * x);
  }
  return moment;
}

}  // namespace ambdrop
