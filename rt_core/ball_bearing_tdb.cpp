#include "rt_core/ball_bearing_tdb.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rt_core/hertz_line_contact.hpp"
#include "rt_core/slip_friction.hpp"
#include "rt_core/tdb_common.hpp"

namespace ambdrop {

BallBearingTdb::BallBearingTdb(const TdbParams& params)
    : TouchdownBearing(params),
      bearing_(MakeDiscreteBallBearing(params.ball_bearing().bearing)),
      state_size_(params.ball_bearing().support.enabled ? kStatesElasticSupport
                                                        : kStatesRigidSupport) {
  const BallBearingTdbParams& b = params.ball_bearing();
  const bool support_ok = !b.support.enabled ||
                          (b.support.outer_race_mass_kg > 0.0 &&
                           b.support.stiffness_N_per_m > 0.0 && b.support.damping_N_s_per_m >= 0.0);
  if (!(b.inner_race_mass_kg > 0.0) || !(b.line_contact.youngs_modulus_Pa > 0.0) ||
      !(b.line_contact.length_m > 0.0) || !support_ok || !(params.spin.inertia_kg_m2 > 0.0)) {
    throw std::invalid_argument("tdb '" + params.name +
                                "': race masses, line contact E and L, Ks and the race inertia "
                                "must be positive");
  }
}

void BallBearingTdb::InitialState(double* s) const noexcept {
  const BallBearingTdbParams& b = params_.ball_bearing();
  std::fill(s, s + state_size_, 0.0);
  if (b.support.enabled) {
    // Ks carries both races: Ks y = (mi + mo) g.
    s[kOuterY] = (b.inner_race_mass_kg + b.support.outer_race_mass_kg) * b.gravity_y_m_s2 /
                 b.support.stiffness_N_per_m;
  }
  // The balls carry the inner race: bisection on the sag magnitude until the ball force
  // (which grows monotonically with it) equals the weight mi g.
  const double weight_N = b.inner_race_mass_kg * b.gravity_y_m_s2;
  if (weight_N == 0.0) return;
  double low = 0.0, high = bearing_.radial_clearance_m + 1e-3;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (low + high);
    double fx = 0.0, fy = 0.0;
    DiscreteBallForce(bearing_, 0.0, std::copysign(mid, weight_N), 0.0, &fx, &fy);
    (std::abs(fy) < std::abs(weight_N) ? low : high) = mid;
  }
  // The ball set is not symmetric about the vertical: a few Newton-like corrections with the
  // tangent 3/2 W / sag of Eq. (13) remove the small sideways residual.
  double ex = 0.0, ey = std::copysign(0.5 * (low + high), weight_N);
  const double tangent = 1.5 * std::abs(weight_N) / std::abs(ey);
  for (int i = 0; i < 100; ++i) {
    double fx = 0.0, fy = 0.0;
    DiscreteBallForce(bearing_, ex, ey, 0.0, &fx, &fy);
    ex += fx / tangent;
    ey += (fy + weight_N) / tangent;
  }
  // Without the support there is no outer race state: the outer race is the housing, at 0.
  const double ox = b.support.enabled ? s[kOuterX] : 0.0;
  const double oy = b.support.enabled ? s[kOuterY] : 0.0;
  s[kInnerX] = ox + ex;
  s[kInnerY] = oy + ey;
}

void BallBearingTdb::Evaluate(const JournalMotion& j, const double* s, double* rate,
                              TdbForce* out) const noexcept {
  const TdbParams& p = params_;
  const BallBearingTdbParams& b = p.ball_bearing();
  const double race_speed = s[kRaceSpin];
  const double ix = s[kInnerX], iy = s[kInnerY], ivx = s[kInnerVx], ivy = s[kInnerVy];
  double ox = 0.0, oy = 0.0, ovx = 0.0, ovy = 0.0;
  if (b.support.enabled) {
    ox = s[kOuterX];
    oy = s[kOuterY];
    ovx = s[kOuterVx];
    ovy = s[kOuterVy];
  }
  // Journal / inner race deflection, Chen 2019 (seed 002) Eq. (6); normal n from the race
  // centre to the journal (the force on the rotor is along -n, Eq. (7)-(8)); no whirl damping.
  const JournalContact contact = TouchJournal(
      p, j, {ix, iy, ivx, ivy}, race_speed, 0.0,
      [&](double deflection, const ContactGeometry&) {
        return LineContactForce(b.line_contact, p.clearance_m, deflection);  // Chen 2019, Eq. (5)
      },
      [&](double normal, const ContactGeometry& g) {
        // Chen 2019 (seed 002), Eq. (9)-(12): on the race along the slip, on the rotor against it.
        const double slip = b.friction.slip_speeds == SlipSpeeds::kSpinOnly
                                ? SpinSurfaceSlip(p, j, race_speed)
                                : SurfaceSlip(p, j, g, race_speed);
        return SlipFrictionForce(b.friction, normal, slip);
      },
      out);
  const double friction = contact.friction_N;
  const double on_rotor_x = contact.on_rotor_x_N, on_rotor_y = contact.on_rotor_y_N;

  // Balls and Cb between the races, Chen 2019 (seed 002) Eq. (13)-(19), Fig. 2.
  double bearing_x = 0.0, bearing_y = 0.0;  // on the inner race
  DiscreteBallForce(bearing_, ix - ox, iy - oy, s[kCageAngle], &bearing_x, &bearing_y);
  bearing_x -= bearing_.damping_N_s_per_m * (ivx - ovx);
  bearing_y -= bearing_.damping_N_s_per_m * (ivy - ovy);

  // Inner race: Newton with its weight; the ball set turns with the cage (Harris).
  rate[kInnerX] = ivx;
  rate[kInnerY] = ivy;
  rate[kInnerVx] = (bearing_x - on_rotor_x) / b.inner_race_mass_kg;
  rate[kInnerVy] = (bearing_y - on_rotor_y) / b.inner_race_mass_kg + b.gravity_y_m_s2;
  rate[kCageAngle] = bearing_.cage_rotation ? bearing_.cage_speed_ratio * race_speed : 0.0;

  // Outer race on the support Ks, Cs (Fig. 16), or the housing itself.
  double support_x = -bearing_x, support_y = -bearing_y;  // what the housing receives
  if (b.support.enabled) {
    const BearingSupportParams& k = b.support;
    const double spring_x = k.stiffness_N_per_m * ox + k.damping_N_s_per_m * ovx;
    const double spring_y = k.stiffness_N_per_m * oy + k.damping_N_s_per_m * ovy;
    rate[kOuterX] = ovx;
    rate[kOuterY] = ovy;
    rate[kOuterVx] = (-bearing_x - spring_x) / k.outer_race_mass_kg;
    rate[kOuterVy] = (-bearing_y - spring_y) / k.outer_race_mass_kg + b.gravity_y_m_s2;
    support_x = spring_x;
    support_y = spring_y;
  }
  out->support_x_N = support_x;
  out->support_y_N = support_y;

  // Race spin, Jarroux 2019 Eq. (9) with Ft Ri (Chen 2019 Fig. 15), M1 on the ball load.
  const double bearing_load = std::sqrt(bearing_x * bearing_x + bearing_y * bearing_y);
  rate[kRaceSpin] = RaceAcceleration(p, race_speed, friction, bearing_load);
}

}  // namespace ambdrop
