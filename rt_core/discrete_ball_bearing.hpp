#pragma once
#include <cmath>
#include <numbers>

#include "rt_core/ball_bearing_tdb_params.hpp"

namespace ambdrop {

/// Harris's curvature quantities of one ball / raceway contact, Chen 2019 (seed 002),
/// Eq. (16)-(17), gamma = Db cos(alpha) / dm:
///   inner: sum_rho = (4 - 1/fi + 2 gamma/(1 - gamma)) / Db,
///          F(rho)  = (1/fi + 2 gamma/(1 - gamma)) / (4 - 1/fi + 2 gamma/(1 - gamma));
///   outer: sum_rho = (4 - 1/fo - 2 gamma/(1 + gamma)) / Db,
///          F(rho)  = (1/fo - 2 gamma/(1 + gamma)) / (4 - 1/fo - 2 gamma/(1 + gamma)).
struct RacewayCurvature {
  double sum_rho_per_m = 0.0;
  double difference = 0.0;  ///< F(rho)
};
RacewayCurvature InnerRacewayCurvature(const DiscreteBallParams& p);
RacewayCurvature OuterRacewayCurvature(const DiscreteBallParams& p);

/// Ball / raceway load-deflection constant (N/m^1.5), Chen 2019 (seed 002) Eq. (15):
///   k = 2^2.5 / (3 ((1 - nu_r^2)/E_r + (1 - nu_b^2)/E_b) delta*^1.5 sqrt(sum_rho)).
double RacewayContactStiffness(const DiscreteBallParams& p, double sum_rho_per_m,
                               double delta_star);

/// Coefficients derived once from DiscreteBallParams.
struct DiscreteBallBearing {
  int balls = 0;
  double ball_stiffness_N_per_m1_5 = 0.0;  ///< krb, Eq. (14)
  double radial_clearance_m = 0.0;
  double damping_N_s_per_m = 0.0;  ///< Cb
  double cage_speed_ratio = 0.0;   ///< cage speed / inner-race speed, (1 - gamma)/2 (Harris)
  bool cage_rotation = true;
};

/// krb = (ki^(-2/3) + ko^(-2/3))^(-3/2), Chen 2019 (seed 002) Eq. (14), with ki, ko from
/// Eq. (15)-(17). Throws std::invalid_argument on unusable parameters.
DiscreteBallBearing MakeDiscreteBallBearing(const DiscreteBallParams& p);

/// Turns the unit vector (c, s) by the angle whose cosine and sine are (cp, sp).
inline void RotateBy(double cp, double sp, double* c, double* s) noexcept {
  const double c0 = *c;
  *c = c0 * cp - *s * sp;
  *s = *s * cp + c0 * sp;
}

/// Spring force (N) the balls put on the inner race displaced by (dx, dy) (m) from the outer
/// race, the ball set turned by cage_angle_rad: Chen 2019 (seed 002) Eq. (13), (18)-(19),
///   deltaj = dx cos(theta_j) + dy sin(theta_j) - clearance,  theta_j = cage + 2 pi j / Z,
///   Qj = krb deltaj^(3/2) (deltaj > 0),  F = -sum_j Qj (cos theta_j, sin theta_j).
/// Returns the largest ball load (N).
inline double DiscreteBallForce(const DiscreteBallBearing& b, double dx, double dy,
                                double cage_angle_rad, double* fx_N, double* fy_N) noexcept {
  double fx = 0.0, fy = 0.0, largest = 0.0;
  // Ball j's direction (cos theta_j, sin theta_j) by turning ball j - 1's by the pitch: two
  // sincos per call instead of one per ball, which took over half of a run's time (rounding
  // grows by a few ulp over a ball set).
  const double pitch = 2.0 * std::numbers::pi / b.balls;
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  double c = std::cos(cage_angle_rad), s = std::sin(cage_angle_rad);
  for (int j = 0; j < b.balls; ++j, RotateBy(cp, sp, &c, &s)) {
    const double deflection = dx * c + dy * s - b.radial_clearance_m;
    if (!(deflection > 0.0)) continue;
    // Chen 2019 (seed 002), Eq. (13)
    const double q = b.ball_stiffness_N_per_m1_5 * deflection * std::sqrt(deflection);
    // Chen 2019 (seed 002), Eq. (18)-(19)
    fx -= q * c;
    fy -= q * s;
    largest = q > largest ? q : largest;
  }
  *fx_N = fx;
  *fy_N = fy;
  return largest;
}

}  // namespace ambdrop
