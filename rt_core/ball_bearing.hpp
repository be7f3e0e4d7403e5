#pragma once
#include <cmath>

#include "rt_core/four_dof_params.hpp"

namespace ambdrop {

/// Ball-bearing coefficients derived once from BallBearingParams (Jarroux 2019 Sec. 3.1).
struct BallBearingCoefficients {
  double radial_constant_N_per_m1_5 = 0.0;   ///< K in Fr = K ur^(3/2), Eq. (5)
  double stiffness_N_per_m = 0.0;            ///< kbrg, dFr/dur at the operating load
  double damping_N_s_per_m = 0.0;            ///< cbrg, Eq. (8)
  double quadratic_constant_N_per_m2 = 0.0;  ///< kq in Fr = kq ur^2 (Jarroux 2016, seed 001)
};

/// Coupled ball contact stiffness kn (N/m^1.5) of the inner and outer race contacts in series,
/// Jarroux 2019 Eq. (6): kn = (k_ir^(-2/3) + k_or^(-2/3))^(-3/2).
double CoupledBallStiffness(double inner_N_per_m1_5, double outer_N_per_m1_5);

/// Radial integral of Jarroux 2019 Eq. (5) without internal clearance (load distribution factor
/// epsilon = 1/2, loaded arc +-pi/2): Jr = 1/(2 pi) int cos^(5/2) theta dtheta = 0.2288 (Harris).
double RadialLoadIntegral();

/// K, kbrg and cbrg of the bearing: Fr = Z kn cos^(5/2)(alpha_c) Jr ur^(3/2) (Eq. (5)-(6)),
/// kbrg = dFr/dur = 3/2 K^(2/3) F0^(1/3) at the operating load F0, cbrg = factor 1e-5 kbrg
/// (Eq. (8)); kq of the quadratic law as given, or the secant F0 / ur0^2 through the Hertz
/// operating point. The linear law takes kbrg and cbrg as given (K and kq stay 0).
/// Throws std::invalid_argument on non-positive inputs.
BallBearingCoefficients BallBearingFromHertz(const BallBearingParams& params);

/// Force (N) the balls put on the inner race for the inner-race displacement (dx, dy) and
/// velocity (dvx, dvy) relative to the outer race; the outer race gets the opposite.
///   linearised or linear: f = -(kbrg d + cbrg d'),
///   Hertz:      f = -(K |d|^(3/2) d/|d| + cbrg d')   (Jarroux 2019 Eq. (5), (8)),
///   quadratic:  f = -(kq |d|^2 d/|d| + cbrg d')      (Jarroux 2016 (seed 001), Sec. 2).
inline void BallBearingForce(BearingLaw law, const BallBearingCoefficients& c, double dx, double dy,
                             double dvx, double dvy, double* fx_N, double* fy_N) noexcept {
  double spring = c.stiffness_N_per_m;  // force per metre of deflection, along d
  if (law == BearingLaw::kHertz) {
    // Jarroux 2019, Eq. (5): K ur^(3/2) along d is K sqrt(ur) d.
    spring = c.radial_constant_N_per_m1_5 * std::sqrt(std::sqrt(dx * dx + dy * dy));
  } else if (law == BearingLaw::kQuadratic) {
    // Jarroux 2016 (seed 001), Sec. 2: kq ur^2 along d is kq |d| d.
    spring = c.quadratic_constant_N_per_m2 * std::sqrt(dx * dx + dy * dy);
  }
  *fx_N = -(spring * dx + c.damping_N_s_per_m * dvx);
  *fy_N = -(spring * dy + c.damping_N_s_per_m * dvy);
}

}  // namespace ambdrop
