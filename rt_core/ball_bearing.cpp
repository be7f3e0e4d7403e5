#include "rt_core/ball_bearing.hpp"

#include <numbers>
#include <stdexcept>

namespace ambdrop {

double CoupledBallStiffness(double inner_N_per_m1_5, double outer_N_per_m1_5) {
  // Jarroux 2019, Eq. (6)
  return std::pow(std::pow(inner_N_per_m1_5, -2.0 / 3.0) + std::pow(outer_N_per_m1_5, -2.0 / 3.0),
                  -1.5);
}

double RadialLoadIntegral() {
  // int_{-pi/2}^{pi/2} cos^(5/2) = B(1/2, 7/4) = Gamma(1/2) Gamma(7/4) / Gamma(9/4).
  return std::tgamma(0.5) * std::tgamma(1.75) / std::tgamma(2.25) / (2.0 * std::numbers::pi);
}

BallBearingCoefficients BallBearingFromHertz(const BallBearingParams& p) {
  if (p.law == BearingLaw::kLinear) {
    // A rig sheet's kbrg and cbrg: the force law is the linearised one (Jarroux 2019 Sec. 3.1)
    // with its numbers given rather than derived from Hertz's.
    if (!(p.stiffness_N_per_m > 0.0) || !(p.damping_N_s_per_m >= 0.0)) {
      throw std::invalid_argument(
          "ball bearing: a linear bearing needs a positive stiffness and a damping >= 0");
    }
    BallBearingCoefficients c;
    c.stiffness_N_per_m = p.stiffness_N_per_m;
    c.damping_N_s_per_m = p.damping_N_s_per_m;
    return c;
  }
  if (p.balls <= 0 || !(p.inner_contact_stiffness_N_per_m1_5 > 0.0) ||
      !(p.outer_contact_stiffness_N_per_m1_5 > 0.0) || !(p.operating_load_N > 0.0) ||
      !(std::cos(p.contact_angle_rad) > 0.0) || !(p.quadratic_stiffness_N_per_m2 >= 0.0)) {
    throw std::invalid_argument(
        "ball bearing: balls, contact stiffnesses, operating load and cos(contact angle) must be "
        "positive");
  }
  const double kn = CoupledBallStiffness(p.inner_contact_stiffness_N_per_m1_5,
                                         p.outer_contact_stiffness_N_per_m1_5);
  const double cos_a = std::cos(p.contact_angle_rad);
  BallBearingCoefficients c;
  // Jarroux 2019, Eq. (5) with epsilon = 1/2: Fr = Z kn cos a (ur cos a)^(3/2) Jr.
  c.radial_constant_N_per_m1_5 =
      p.balls * kn * cos_a * cos_a * std::sqrt(cos_a) * RadialLoadIntegral();
  // Linearised at F0: ur0 = (F0 / K)^(2/3), kbrg = 3/2 K ur0^(1/2) (Jarroux 2019 Sec. 3.1).
  const double load_ratio = p.operating_load_N / c.radial_constant_N_per_m1_5;
  const double ur0 = std::cbrt(load_ratio * load_ratio);
  c.stiffness_N_per_m = 1.5 * c.radial_constant_N_per_m1_5 * std::sqrt(ur0);
  // Jarroux 2019, Eq. (8): cbrg / kbrg * 1e5 = damping_factor.
  c.damping_N_s_per_m = p.damping_factor * 1e-5 * c.stiffness_N_per_m;
  // Jarroux 2016 (seed 001), Sec. 2: quadratic law Fr = kq ur^2; by default the secant through
  // the Hertz operating point (F0 at ur0).
  c.quadratic_constant_N_per_m2 = p.quadratic_stiffness_N_per_m2 > 0.0
                                      ? p.quadratic_stiffness_N_per_m2
                                      : p.operating_load_N / (ur0 * ur0);
  return c;
}

}  // namespace ambdrop
