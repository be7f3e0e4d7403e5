#include "rt_core/four_dof_tdb.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rt_core/hunt_crossley.hpp"
#include "rt_core/ribbon_cross_coupled.hpp"
#include "rt_core/ribbon_dahl.hpp"
#include "rt_core/ribbon_kelvin_voigt.hpp"
#include "rt_core/tdb_common.hpp"

namespace ambdrop {

FourDofTdb::FourDofTdb(const TdbParams& params)
    : TouchdownBearing(params),
      bearing_(BallBearingFromHertz(params.four_dof().bearing)),
      state_size_(params.four_dof().ribbon == RibbonLaw::kDahl ? kStatesDahl : kStatesKelvinVoigt),
      inverse_inner_mass_(1.0 / params.four_dof().inner_race_mass_kg),
      inverse_outer_mass_(1.0 / params.four_dof().outer_race_mass_kg) {
  const FourDofParams& f = params.four_dof();
  if (!(f.inner_race_mass_kg > 0.0) || !(f.outer_race_mass_kg > 0.0)) {
    throw std::invalid_argument("tdb '" + params.name + "': race masses must be positive");
  }
  if (f.ribbon == RibbonLaw::kCrossCoupled && !(f.cross_coupled.stiffness_N_per_m > 0.0)) {
    throw std::invalid_argument("tdb '" + params.name +
                                "': the cross-coupled ribbon's stiffness must be positive");
  }
}

void FourDofTdb::InitialState(double* s) const noexcept {
  const FourDofParams& f = params_.four_dof();
  std::fill(s, s + state_size_, 0.0);
  // Both races' weight rests on the ribbon, the inner race's on the bearing.
  const double races_weight_N = (f.inner_race_mass_kg + f.outer_race_mass_kg) * f.gravity_y_m_s2;
  const double inner_weight_N = f.inner_race_mass_kg * f.gravity_y_m_s2;
  if (f.ribbon == RibbonLaw::kKelvinVoigt) {
    s[kOuterY] = races_weight_N / f.kelvin_voigt.stiffness_N_per_m;  // Eq. (4), u' = 0
  } else if (f.ribbon == RibbonLaw::kCrossCoupled) {
    // Jarroux 2016 (seed 001), Eq. (1) at rest: no whirl, so no cross-coupling.
    s[kOuterY] = races_weight_N / f.cross_coupled.stiffness_N_per_m;
  } else {
    s[kRibbonFy] =
        std::clamp(races_weight_N, DahlLowerEnvelope(f.dahl, 0.0), DahlUpperEnvelope(f.dahl, 0.0));
  }
  double bearing_deflection_m = inner_weight_N / bearing_.stiffness_N_per_m;
  if (f.bearing.law == BearingLaw::kHertz) {
    // Eq. (5): K |d|^(3/2) = |W|.
    const double ratio = std::abs(inner_weight_N) / bearing_.radial_constant_N_per_m1_5;
    bearing_deflection_m = std::copysign(std::cbrt(ratio * ratio), inner_weight_N);
  } else if (f.bearing.law == BearingLaw::kQuadratic) {
    // Jarroux 2016 (seed 001), Sec. 2: kq d^2 = |W|.
    bearing_deflection_m = std::copysign(
        std::sqrt(std::abs(inner_weight_N) / bearing_.quadratic_constant_N_per_m2), inner_weight_N);
  }
  s[kInnerY] = s[kOuterY] + bearing_deflection_m;
}

double FourDofTdb::FreeRadius_m(const double* s) const noexcept {
  // Out of contact the races move under their weight, ribbon and bearing only (Evaluate).
  const double reach = CentreOffset_m(params_) + std::hypot(s[kInnerX], s[kInnerY]);
  return std::max(0.0, params_.clearance_m - reach);
}

void FourDofTdb::Evaluate(const JournalMotion& j, const double* s, double* rate,
                          TdbForce* out) const noexcept {
  const TdbParams& p = params_;
  const FourDofParams& f = p.four_dof();
  const double race_speed = s[kRaceSpin];
  const double ix = s[kInnerX], iy = s[kInnerY], ivx = s[kInnerVx], ivy = s[kInnerVy];
  const double ox = s[kOuterX], oy = s[kOuterY], ovx = s[kOuterVx], ovy = s[kOuterVy];
  // Journal / inner race: penetration beyond the clearance, normal n from the race centre.
  const JournalContact contact = TouchJournal(
      p, j, {ix, iy, ivx, ivy}, race_speed, p.friction.whirl_damping_N_s_per_m,
      [&f](double urs, const ContactGeometry& g) {
        return HuntCrossleyForce(f.inner_contact, urs,
                                 g.radial_speed_m_s);  // Jarroux 2019, Eq. (10)
      },
      [&](double normal, const ContactGeometry& g) {
        return FrictionForce(p.friction, normal, SurfaceSlip(p, j, g, race_speed));  // Eq. (11)
      },
      out);
  const double friction = contact.friction_N;
  const double on_rotor_x = contact.on_rotor_x_N, on_rotor_y = contact.on_rotor_y_N;

  // Ball bearing between the races, Jarroux 2019 Eq. (5)-(8).
  double bearing_x = 0.0, bearing_y = 0.0;  // on the inner race
  BallBearingForce(f.bearing.law, bearing_, ix - ox, iy - oy, ivx - ovx, ivy - ovy, &bearing_x,
                   &bearing_y);

  // Ribbon restoring force frd per axis (the outer race feels -frd).
  double ribbon_x = 0.0, ribbon_y = 0.0;
  switch (f.ribbon) {
    case RibbonLaw::kKelvinVoigt:
      // Jarroux 2019, Eq. (4)
      ribbon_x = KelvinVoigtRibbonForce(f.kelvin_voigt, ox, ovx);
      ribbon_y = KelvinVoigtRibbonForce(f.kelvin_voigt, oy, ovy);
      break;
    case RibbonLaw::kDahl:
      // Jarroux 2019, Eq. (1)-(3)
      ribbon_x = s[kRibbonFx];
      ribbon_y = s[kRibbonFy];
      rate[kRibbonFx] = DahlRibbonForceRate(f.dahl, ox, ovx, ribbon_x);
      rate[kRibbonFy] = DahlRibbonForceRate(f.dahl, oy, ovy, ribbon_y);
      break;
    case RibbonLaw::kCrossCoupled:
      // Jarroux 2016 (seed 001), Eq. (1)
      CrossCoupledRibbonForce(f.cross_coupled, ox, oy, ovx, ovy, &ribbon_x, &ribbon_y);
      break;
  }

  // Outer race / housing: Hunt-Crossley, Eq. (10), beyond the ribbon clearance (Jarroux 2016
  // (seed 001), Sec. 2: "modeled as the rotor to inner race normal contact force").
  double housing_x = 0.0, housing_y = 0.0;  // on the outer race
  // The root is taken only once the ribbon clearance is used up, which the races rarely do.
  const double outer_radius_squared = ox * ox + oy * oy;
  if (f.housing_contact_enabled &&
      outer_radius_squared > f.ribbon_clearance_m * f.ribbon_clearance_m) {
    const double outer_radius = std::sqrt(outer_radius_squared);
    const double uh = outer_radius - f.ribbon_clearance_m;
    const double inverse_radius = 1.0 / outer_radius;
    const double onx = ox * inverse_radius;
    const double ony = oy * inverse_radius;
    // Jarroux 2019, Eq. (10)
    const double fh = HuntCrossleyForce(f.housing_contact, uh, ovx * onx + ovy * ony);
    housing_x = -fh * onx;
    housing_y = -fh * ony;
  }

  // Race motion: Newton on each race, with the races' weight.
  rate[kInnerX] = ivx;
  rate[kInnerY] = ivy;
  rate[kInnerVx] = (bearing_x - on_rotor_x) * inverse_inner_mass_;
  rate[kInnerVy] = (bearing_y - on_rotor_y) * inverse_inner_mass_ + f.gravity_y_m_s2;
  rate[kOuterX] = ovx;
  rate[kOuterY] = ovy;
  rate[kOuterVx] = (housing_x - bearing_x - ribbon_x) * inverse_outer_mass_;
  rate[kOuterVy] = (housing_y - bearing_y - ribbon_y) * inverse_outer_mass_ + f.gravity_y_m_s2;

  // Race spin, Jarroux 2019 Eq. (9), M1 on the load the balls carry.
  const double bearing_load = std::sqrt(bearing_x * bearing_x + bearing_y * bearing_y);
  rate[kRaceSpin] = RaceAcceleration(p, race_speed, friction, bearing_load);

  // What the housing (the rig's load cells) receives: +frd from the ribbon, minus the contact.
  const double support_x = ribbon_x - housing_x;
  const double support_y = ribbon_y - housing_y;
  out->support_x_N = support_x;
  out->support_y_N = support_y;
}

}  // namespace ambdrop
