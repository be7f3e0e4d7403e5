#include "rt_core/discrete_ball_bearing.hpp"

#include <stdexcept>

#include "rt_core/ball_bearing.hpp"

namespace ambdrop {
namespace {

double Gamma(const DiscreteBallParams& p) {
  return p.ball_diameter_m * std::cos(p.contact_angle_rad) / p.pitch_diameter_m;
}

}  // namespace

RacewayCurvature InnerRacewayCurvature(const DiscreteBallParams& p) {
  const double g = Gamma(p);
  const double conformity = 2.0 * g / (1.0 - g);
  // Chen 2019 (seed 002), Eq. (16)-(17), inner raceway
  const double sum = 4.0 - 1.0 / p.inner_groove_conformity + conformity;
  return {sum / p.ball_diameter_m, (1.0 / p.inner_groove_conformity + conformity) / sum};
}

RacewayCurvature OuterRacewayCurvature(const DiscreteBallParams& p) {
  const double g = Gamma(p);
  const double conformity = 2.0 * g / (1.0 + g);
  // Chen 2019 (seed 002), Eq. (16)-(17), outer raceway
  const double sum = 4.0 - 1.0 / p.outer_groove_conformity - conformity;
  return {sum / p.ball_diameter_m, (1.0 / p.outer_groove_conformity - conformity) / sum};
}

double RacewayContactStiffness(const DiscreteBallParams& p, double sum_rho_per_m,
                               double delta_star) {
  const double compliance =
      (1.0 - p.race_poisson_ratio * p.race_poisson_ratio) / p.race_youngs_modulus_Pa +
      (1.0 - p.ball_poisson_ratio * p.ball_poisson_ratio) / p.ball_youngs_modulus_Pa;
  // Chen 2019 (seed 002), Eq. (15)
  return std::pow(2.0, 2.5) /
         (3.0 * compliance * delta_star * std::sqrt(delta_star) * std::sqrt(sum_rho_per_m));
}

DiscreteBallBearing MakeDiscreteBallBearing(const DiscreteBallParams& p) {
  const bool geometry_ok = p.balls > 0 && p.ball_diameter_m > 0.0 &&
                           p.pitch_diameter_m > p.ball_diameter_m &&
                           std::cos(p.contact_angle_rad) > 0.0 && p.inner_groove_conformity > 0.5 &&
                           p.outer_groove_conformity > 0.5;
  const bool material_ok = p.race_youngs_modulus_Pa > 0.0 && p.ball_youngs_modulus_Pa > 0.0 &&
                           p.inner_delta_star > 0.0 && p.outer_delta_star > 0.0;
  if (!geometry_ok || !material_ok || !(p.radial_clearance_m >= 0.0) ||
      !(p.damping_N_s_per_m >= 0.0)) {
    throw std::invalid_argument(
        "discrete ball bearing: balls, diameters (dm > Db), moduli, delta* must be positive, "
        "groove conformities above 0.5");
  }
  const double ki =
      RacewayContactStiffness(p, InnerRacewayCurvature(p).sum_rho_per_m, p.inner_delta_star);
  const double ko =
      RacewayContactStiffness(p, OuterRacewayCurvature(p).sum_rho_per_m, p.outer_delta_star);
  DiscreteBallBearing b;
  b.balls = p.balls;
  // Chen 2019 (seed 002), Eq. (14): the same series law as Jarroux 2019 Eq. (6).
  b.ball_stiffness_N_per_m1_5 = CoupledBallStiffness(ki, ko);
  b.radial_clearance_m = p.radial_clearance_m;
  b.damping_N_s_per_m = p.damping_N_s_per_m;
  // Cage (ball set) speed with the outer race still, Harris: omega_c = omega_i (1 - gamma) / 2.
  b.cage_speed_ratio = 0.5 * (1.0 - Gamma(p));
  b.cage_rotation = p.cage_rotation;
  return b;
}

}  // namespace ambdrop
