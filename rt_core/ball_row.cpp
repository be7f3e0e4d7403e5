#include "rt_core/ball_row.hpp"

#include <numbers>
#include <stdexcept>
#include <string>

#include "rt_core/ball_bearing.hpp"

namespace ambdrop {

BallRow MakeBallRow(const BallBearingRowParams& p, const char* what) {
  if (p.balls < 1 || p.balls > kMaxBallsPerRow || p.rows < 1 ||
      !(p.inner_contact_stiffness_N_per_m1_5 > 0.0) ||
      !(p.outer_contact_stiffness_N_per_m1_5 > 0.0) || !(p.pitch_diameter_m > 0.0) ||
      !(p.ball_diameter_m > 0.0) || !(p.ball_diameter_m < p.pitch_diameter_m) ||
      !(p.diametric_clearance_m >= 0.0) || !(p.contact_damping_N_s_per_m >= 0.0) ||
      !(p.full_damping_deflection_m >= 0.0)) {
    throw std::invalid_argument(std::string(what) + ": balls (1.." +
                                std::to_string(kMaxBallsPerRow) +
                                "), rows, contact stiffnesses, 0 < ball diameter < pitch "
                                "diameter are required; clearance and damping >= 0");
  }
  BallRow r;
  // Inner and outer ball contacts in series (Harris; Jarroux 2019 Eq. (6)).
  r.ball_contact.stiffness_N_per_m_e = CoupledBallStiffness(p.inner_contact_stiffness_N_per_m1_5,
                                                            p.outer_contact_stiffness_N_per_m1_5);
  r.ball_contact.exponent = 1.5;  // seed 003 Table 2: contact parameter 3/2
  r.ball_contact.max_damping_N_s_per_m = p.contact_damping_N_s_per_m;
  r.ball_contact.full_damping_penetration_m = p.full_damping_deflection_m;
  r.radial_clearance_m = 0.5 * p.diametric_clearance_m;
  r.balls = p.balls;
  r.rows = p.rows;
  // Cage speed of a deep-groove bearing in pure rolling (Harris):
  // w_c = 1/2 [w_i (1 - D/dm) + w_o (1 + D/dm)].
  const double gamma = p.ball_diameter_m / p.pitch_diameter_m;
  r.cage_inner_factor = 0.5 * (1.0 - gamma);
  r.cage_outer_factor = 0.5 * (1.0 + gamma);
  r.viscous_drag_N_m_s = p.viscous_drag_N_m_s;
  r.palmgren_moment_per_N_m = p.palmgren_f1 * p.pitch_diameter_m;
  for (int j = 0; j < p.balls; ++j) {
    const double angle = 2.0 * std::numbers::pi * j / p.balls;
    r.cos_ball[j] = std::cos(angle);
    r.sin_ball[j] = std::sin(angle);
  }
  return r;
}

}  // namespace ambdrop
