#include "rt_core/catcher_bearing_tdb.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rt_core/impact_function.hpp"
#include "rt_core/tdb_common.hpp"

namespace ambdrop {
namespace {

bool Positive(double v) {
  return v > 0.0;
}

void CheckRace(const TdbParams& p, const RaceParams& r, const char* what) {
  if (!Positive(r.mass_kg) || !Positive(r.polar_inertia_kg_m2)) {
    throw std::invalid_argument("tdb '" + p.name + "': " + what +
                                " mass and polar inertia must be positive");
  }
}

// Upward force (N) of a bearing whose inner ring sits `drop_m` (> 0) below the outer ring, at
// rest with the cage at zero.
double LiftAt(const BallRow& row, double drop_m) noexcept {
  double fx = 0.0, fy = 0.0;
  BallRowForce(row, 0.0, 0.0, -drop_m, 0.0, 0.0, &fx, &fy);
  return fy;
}

// The inner ring's drop below the outer ring (m) at which the bearing carries `weight_N` (>= 0):
// bisection on the monotone lift.
double StaticDrop(const BallRow& row, double weight_N) noexcept {
  if (!(weight_N > 0.0)) return 0.0;
  double lo = 0.0;
  double hi = row.radial_clearance_m + 1e-9;
  for (int i = 0; i < 200 && LiftAt(row, hi) < weight_N; ++i) hi *= 2.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (LiftAt(row, mid) < weight_N ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Body outside the inner bearing: position, velocity and spin (zero for a house or ground).
struct Ring {
  double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0, spin = 0.0;
};

}  // namespace

CatcherBearingTdb::CatcherBearingTdb(const TdbParams& params)
    : TouchdownBearing(params),
      inner_bearing_(MakeBallRow(params.catcher().inner_bearing, "inner bearing")) {
  const CatcherBearingParams& c = params.catcher();
  if (c.decks != 1 && c.decks != 2) {
    throw std::invalid_argument("tdb '" + params.name + "': decks must be 1 or 2");
  }
  if (!Positive(c.impact.stiffness_N_per_m_e) || !(c.impact.exponent >= 1.0) ||
      !(c.impact.max_damping_N_s_per_m >= 0.0) || !(c.impact.full_damping_penetration_m >= 0.0)) {
    throw std::invalid_argument("tdb '" + params.name +
                                "': impact stiffness > 0, exponent >= 1, damping >= 0 required");
  }
  CheckRace(params, c.inner_race, "inner race");
  if (c.decks == 2) {
    CheckRace(params, c.intermediate_race, "intermediate race");
    outer_bearing_ = MakeBallRow(c.outer_bearing, "outer bearing");
    intermediate_ = state_size_;
    state_size_ += kRaceStates;
  }
  if (c.mount == CatcherMount::kMetalRubberRing) {
    if (!Positive(c.ring.house_mass_kg) || !Positive(c.ring.stiffness_N_per_m) ||
        !(c.ring.damping_N_s_per_m >= 0.0)) {
      throw std::invalid_argument("tdb '" + params.name +
                                  "': metal rubber ring needs house mass, Krr > 0, Crr >= 0");
    }
    house_ = state_size_;
    state_size_ += kHouseStates;
  }
}

void CatcherBearingTdb::InitialState(double* s) const noexcept {
  const CatcherBearingParams& c = params_.catcher();
  std::fill(s, s + state_size_, 0.0);
  const double g = -c.gravity_y_m_s2;  // >= 0 with gravity along -y
  const double inner_weight = c.inner_race.mass_kg * g;
  const double mid_weight = c.decks == 2 ? c.intermediate_race.mass_kg * g : 0.0;
  // House on the ring carries everything: Krr y = (m_i + m_m + m_o) g_y (seed 004 Eq. (2)).
  double outside_y = 0.0;
  if (house_ >= 0) {
    outside_y = -(inner_weight + mid_weight + c.ring.house_mass_kg * g) / c.ring.stiffness_N_per_m;
    s[house_ + kHouseY] = outside_y;
  }
  if (intermediate_ >= 0) {
    outside_y -= StaticDrop(outer_bearing_, inner_weight + mid_weight);
    s[intermediate_ + kY] = outside_y;
  }
  s[kY] = outside_y - StaticDrop(inner_bearing_, inner_weight);
}

void CatcherBearingTdb::Evaluate(const JournalMotion& j, const double* s, double* rate,
                                 TdbForce* out) const noexcept {
  const TdbParams& p = params_;
  const CatcherBearingParams& c = p.catcher();
  const double vref = p.friction.regularisation_s_per_m;
  const double wi = s[kSpin];
  const double ix = s[kX], iy = s[kY], ivx = s[kVx], ivy = s[kVy];

  // Journal / inner race: penetration beyond the clearance, normal n from the race centre.
  const JournalContact contact = TouchJournal(
      p, j, {ix, iy, ivx, ivy}, wi, p.friction.whirl_damping_N_s_per_m,
      [&c](double penetration, const ContactGeometry& g) {
        return ImpactForce(c.impact, penetration, g.radial_speed_m_s);  // Seed 003, Eq. (1)
      },
      [&](double normal, const ContactGeometry& g) {
        return FrictionForce(p.friction, normal,
                             SurfaceSlip(p, j, g, wi));  // Jarroux 2019, Eq. (11)
      },
      out);
  const double friction = contact.friction_N;
  const double on_rotor_x = contact.on_rotor_x_N, on_rotor_y = contact.on_rotor_y_N;
  const double inner_race_radius = InnerRaceRadius(p);  // Rb

  // The house (metal rubber ring) or the rigid ground.
  Ring house;
  if (house_ >= 0) {
    house = {s[house_ + kHouseX], s[house_ + kHouseY], s[house_ + kHouseVx], s[house_ + kHouseVy],
             0.0};
  }
  // What the inner bearing's outer ring sits in: the intermediate race or the house.
  Ring next = house;
  if (intermediate_ >= 0) {
    const double* m = s + intermediate_;
    next = {m[kX], m[kY], m[kVx], m[kVy], m[kSpin]};
  }

  // Inner bearing, seed 003 Eq. (1) per ball (Table 2), and its friction moment.
  double bix = 0.0, biy = 0.0;  // on the inner race
  BallRowForce(inner_bearing_, s[kCage], ix - next.x, iy - next.y, ivx - next.vx, ivy - next.vy,
               &bix, &biy);
  const double inner_load = std::sqrt(bix * bix + biy * biy);
  const double inner_moment = BallRowMoment(inner_bearing_, wi - next.spin, inner_load,
                                            0.5 * c.inner_bearing.pitch_diameter_m, vref);

  // Inner race: lateral Newton, spin (seed 004 Eq. (3): J w' = Ft Rb - T), cage kinematics.
  rate[kX] = ivx;
  rate[kY] = ivy;
  rate[kVx] = (bix - on_rotor_x) / c.inner_race.mass_kg;
  rate[kVy] = (biy - on_rotor_y) / c.inner_race.mass_kg + c.gravity_y_m_s2;
  rate[kSpin] =
      c.race_spin ? (friction * inner_race_radius - inner_moment) / c.inner_race.polar_inertia_kg_m2
                  : 0.0;
  rate[kCage] = c.ball_passage ? inner_bearing_.cage_inner_factor * wi +
                                     inner_bearing_.cage_outer_factor * next.spin
                               : 0.0;

  // Force the last bearing puts on the body inside the house.
  double last_x = bix, last_y = biy;
  if (intermediate_ >= 0) {
    // Outer bearing, intermediate race / house; the intermediate race takes -inner bearing.
    const double* m = s + intermediate_;
    double* mr = rate + intermediate_;
    double box = 0.0, boy = 0.0;
    BallRowForce(outer_bearing_, m[kCage], next.x - house.x, next.y - house.y, next.vx - house.vx,
                 next.vy - house.vy, &box, &boy);
    const double outer_load = std::sqrt(box * box + boy * boy);
    const double outer_moment = BallRowMoment(outer_bearing_, next.spin, outer_load,
                                              0.5 * c.outer_bearing.pitch_diameter_m, vref);
    mr[kX] = next.vx;
    mr[kY] = next.vy;
    mr[kVx] = (box - bix) / c.intermediate_race.mass_kg;
    mr[kVy] = (boy - biy) / c.intermediate_race.mass_kg + c.gravity_y_m_s2;
    mr[kSpin] =
        c.race_spin ? (inner_moment - outer_moment) / c.intermediate_race.polar_inertia_kg_m2 : 0.0;
    mr[kCage] = c.ball_passage ? outer_bearing_.cage_inner_factor * next.spin : 0.0;
    last_x = box;
    last_y = boy;
  }

  // Housing: rigid (it takes -last), or seed 004 Eq. (2) on the metal rubber ring.
  if (house_ >= 0) {
    const double ring_x = -c.ring.stiffness_N_per_m * house.x - c.ring.damping_N_s_per_m * house.vx;
    const double ring_y = -c.ring.stiffness_N_per_m * house.y - c.ring.damping_N_s_per_m * house.vy;
    double* hr = rate + house_;
    hr[kHouseX] = house.vx;
    hr[kHouseY] = house.vy;
    hr[kHouseVx] = (ring_x - last_x) / c.ring.house_mass_kg;
    hr[kHouseVy] = (ring_y - last_y) / c.ring.house_mass_kg + c.gravity_y_m_s2;
    out->support_x_N = ring_x;
    out->support_y_N = ring_y;
  } else {
    out->support_x_N = last_x;
    out->support_y_N = last_y;
  }
}

}  // namespace ambdrop
