#include "rt_core/contact_law_tdb.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "rt_core/hunt_crossley.hpp"
#include "rt_core/ribbon_cross_coupled.hpp"
#include "rt_core/ribbon_dahl.hpp"
#include "rt_core/tdb_common.hpp"

namespace ambdrop {
namespace {

int StatesOf(ContactLawRibbon ribbon) {
  switch (ribbon) {
    case ContactLawRibbon::kDahl:
      return ContactLawTdb::kStatesDahl;
    case ContactLawRibbon::kCrossCoupled:
      return ContactLawTdb::kStatesCrossCoupled;
    case ContactLawRibbon::kBilinear:
      break;
  }
  return ContactLawTdb::kStatesBilinear;
}

// The massless race's balance c u' + R = F (see ContactLawTdb) for a ribbon force R without its
// damping: the deflection rate u', the normal force and the friction force on the race.
struct SeriesSolution {
  double vx_m_s = 0.0, vy_m_s = 0.0;
  double normal_N = 0.0;
  double friction_N = 0.0;
};

SeriesSolution SolveSeries(const TdbParams& p, const JournalMotion& j, const ContactGeometry& g,
                           double race_speed_rad_s, double ribbon_x_N, double ribbon_y_N,
                           double damping_N_s_per_m) noexcept {
  const ContactLawParams& c = p.contact_law();
  const double tx = -g.ny, ty = g.nx;
  const double ribbon_n = ribbon_x_N * g.nx + ribbon_y_N * g.ny;
  const double ribbon_t = ribbon_x_N * tx + ribbon_y_N * ty;
  const double delta = g.radius_m - p.clearance_m;
  SeriesSolution s;
  double rate_n = 0.0;
  if (delta > 0.0 && c.normal_law == ContactLawNormal::kHuntCrossley) {
    // Jarroux 2019 Eq. (10) on the journal/race penetration: fn = E (1 + 3/2 alpha (v_j - u')·n),
    // E = kn delta^n, linear in u'_n as Eq. (12) is, so (c + 3/2 alpha E) u'_n =
    // E (1 + 3/2 alpha v_j·n) - R·n.
    const double elastic = HuntCrossleyElastic(c.hunt_crossley, delta);
    const double viscous = 1.5 * c.hunt_crossley.damping_s_per_m * elastic;
    rate_n = (elastic + viscous * g.radial_speed_m_s - ribbon_n) / (damping_N_s_per_m + viscous);
    s.normal_N = elastic + viscous * (g.radial_speed_m_s - rate_n);
  } else if (delta > 0.0) {
    // Jarroux 2019 Eq. (12), crushed branch, on the bearing's deflection; (c + cbrg) u'_n =
    // kbrg delta + cbrg v_j·n - R·n.
    rate_n = (c.bearing_stiffness_N_per_m * delta +
              c.bearing_damping_N_s_per_m * g.radial_speed_m_s - ribbon_n) /
             (damping_N_s_per_m + c.bearing_damping_N_s_per_m);
    s.normal_N = c.bearing_stiffness_N_per_m * delta +
                 c.bearing_damping_N_s_per_m * (g.radial_speed_m_s - rate_n);
  }
  double on_race_t = 0.0;
  if (s.normal_N > 0.0) {
    // Jarroux 2019 Eq. (11), plus the viscous force on the whirl speed.
    s.friction_N = FrictionForce(p.friction, s.normal_N, SurfaceSlip(p, j, g, race_speed_rad_s));
    on_race_t = s.friction_N + p.friction.whirl_damping_N_s_per_m * g.whirl_speed_m_s;
  } else {
    // A receding contact cannot pull: the ribbon relaxes through its own damping.
    s.normal_N = 0.0;
    rate_n = -ribbon_n / damping_N_s_per_m;
  }
  const double rate_t = (on_race_t - ribbon_t) / damping_N_s_per_m;
  s.vx_m_s = rate_n * g.nx + rate_t * tx;
  s.vy_m_s = rate_n * g.ny + rate_t * ty;
  return s;
}

bool HasRaceMass(const ContactLawParams& c) {
  return c.ribbon != ContactLawRibbon::kBilinear && c.outer_race_mass_kg > 0.0;
}

}  // namespace

ContactLawTdb::ContactLawTdb(const TdbParams& params)
    : TouchdownBearing(params),
      race_velocity_index_(StatesOf(params.contact_law().ribbon)),
      state_size_(race_velocity_index_ + (HasRaceMass(params.contact_law()) ? 2 : 0)) {
  const ContactLawParams& c = params.contact_law();
  if (!HasRaceMass(c) &&
      ((c.ribbon == ContactLawRibbon::kDahl && !(c.ribbon_damping_N_s_per_m > 0.0)) ||
       (c.ribbon == ContactLawRibbon::kCrossCoupled &&
        !(c.cross_coupled.damping_N_s_per_m > 0.0)))) {
    throw std::invalid_argument("tdb '" + params.name +
                                "': a ribbon in series with the contact needs a positive damping "
                                "(its race is massless)");
  }
  if (c.ribbon == ContactLawRibbon::kCrossCoupled && HasRaceMass(c) &&
      !(c.cross_coupled.stiffness_N_per_m > 0.0)) {
    throw std::invalid_argument("tdb '" + params.name +
                                "': the cross-coupled ribbon under a race with mass needs a "
                                "positive stiffness (it carries the race's weight)");
  }
}

void ContactLawTdb::InitialState(double* state) const noexcept {
  std::fill(state, state + state_size_, 0.0);
  const ContactLawParams& c = params_.contact_law();
  if (!HasRaceMass(c)) return;
  // The race's weight rests on the ribbon, as the 4-DOF TDB's races do.
  const double weight_N = c.outer_race_mass_kg * c.gravity_y_m_s2;
  if (c.ribbon == ContactLawRibbon::kDahl) {
    state[kRibbonFy] =
        std::clamp(weight_N, DahlLowerEnvelope(c.dahl, 0.0), DahlUpperEnvelope(c.dahl, 0.0));
  } else {
    // Jarroux 2016 (seed 001), Eq. (1) at rest: no whirl, so no cross-coupling.
    state[kRibbonY] = weight_N / c.cross_coupled.stiffness_N_per_m;
  }
}

void ContactLawTdb::Evaluate(const JournalMotion& j, const double* state, double* state_rate,
                             TdbForce* out) const noexcept {
  if (HasRaceMass(params_.contact_law())) {
    EvaluateRaceWithMass(j, state, state_rate, out);
    return;
  }
  if (params_.contact_law().ribbon != ContactLawRibbon::kBilinear) {
    EvaluateInSeries(j, state, state_rate, out);
    return;
  }
  const TdbParams& p = params_;
  const ContactLawParams& c = p.contact_law();
  const double race_speed = state[0];
  const ContactGeometry g = JournalGeometry(p, j);
  const double urs = g.radius_m - p.clearance_m;

  *out = TdbForce{};
  out->penetration_m = urs;
  out->tdb_spin_rad_s = race_speed;
  double normal = 0.0;
  double friction = 0.0;
  if (urs > 0.0) {
    // Jarroux 2019 Eq. (12), or Eq. (10) on a rigid race; a receding contact cannot pull, so
    // fn >= 0.
    if (c.normal_law == ContactLawNormal::kHuntCrossley) {
      normal = HuntCrossleyForce(c.hunt_crossley, urs, g.radial_speed_m_s);
    } else if (urs >= c.ribbon_crushing_m) {
      normal = c.bearing_stiffness_N_per_m * (urs - c.ribbon_crushing_m) +
               c.bearing_damping_N_s_per_m * g.radial_speed_m_s +
               c.ribbon_stiffness_N_per_m * c.ribbon_crushing_m;
    } else {
      normal = c.ribbon_stiffness_N_per_m * urs + c.ribbon_damping_N_s_per_m * g.radial_speed_m_s;
    }
    normal = std::max(normal, 0.0);
    // Jarroux 2019 Eq. (11)
    friction = FrictionForce(p.friction, normal, SurfaceSlip(p, j, g, race_speed));
    ForceOnRotor(g, normal, -friction - p.friction.whirl_damping_N_s_per_m * g.whirl_speed_m_s,
                 &out->fx_N, &out->fy_N);
    out->torque_on_rotor_N_m = -friction * p.journal_radius_m;
    // Without race masses the housing takes the whole contact force: the reaction of the force
    // on the rotor (TdbForce::support_x_N is the force passed to the housing, as on every kind).
    out->support_x_N = -out->fx_N;
    out->support_y_N = -out->fy_N;
  }
  out->normal_force_N = normal;
  out->tangential_force_N = friction;
  state_rate[0] = RaceAcceleration(p, race_speed, friction, normal);
}

double ContactLawTdb::FreeRadius_m(const double* s) const noexcept {
  const ContactLawParams& c = params_.contact_law();
  double reach = CentreOffset_m(params_);
  if (HasRaceMass(c)) {
    // Out of contact the race moves under its ribbon and weight only (EvaluateRaceWithMass).
    reach += std::hypot(s[kRibbonX], s[kRibbonY]);
  } else if (c.ribbon != ContactLawRibbon::kBilinear) {
    // A massless race's rates resolve its ribbon's force along the journal's direction
    // (SolveSeries): they read the journal unless the ribbon is at rest and unloaded.
    for (int i = kRibbonX; i < state_size_; ++i) {
      if (s[i] != 0.0) return 0.0;
    }
  }
  return std::max(0.0, params_.clearance_m - reach);
}

void ContactLawTdb::EvaluateInSeries(const JournalMotion& j, const double* s, double* rate,
                                     TdbForce* out) const noexcept {
  const TdbParams& p = params_;
  const ContactLawParams& c = p.contact_law();
  const double race_speed = s[kRaceSpin];
  const double ux = s[kRibbonX], uy = s[kRibbonY];
  // The race's lateral speed is left out of the contact's speeds (class comment).
  const ContactGeometry g = JournalGeometry(p, j, {ux, uy, 0.0, 0.0});

  double ribbon_x = 0.0, ribbon_y = 0.0, damping = 0.0;
  SeriesSolution solution;
  if (c.ribbon == ContactLawRibbon::kDahl) {
    // Jarroux 2019 Eq. (1)-(3): the Dahl force is a state, beside the viscous ceq.
    ribbon_x = s[kRibbonFx];
    ribbon_y = s[kRibbonFy];
    damping = c.ribbon_damping_N_s_per_m;
    solution = SolveSeries(p, j, g, race_speed, ribbon_x, ribbon_y, damping);
    rate[kRibbonFx] = DahlRibbonForceRate(c.dahl, ux, solution.vx_m_s, ribbon_x);
    rate[kRibbonFy] = DahlRibbonForceRate(c.dahl, uy, solution.vy_m_s, ribbon_y);
  } else {
    // Jarroux 2016 (seed 001) Eq. (1); the sign of the race whirl from a solve without the
    // cross-coupling.
    const CrossCoupledRibbonParams& r = c.cross_coupled;
    damping = r.damping_N_s_per_m;
    const SeriesSolution direct = SolveSeries(p, j, g, race_speed, r.stiffness_N_per_m * ux,
                                              r.stiffness_N_per_m * uy, damping);
    const double whirl = WhirlSpeed(ux, uy, direct.vx_m_s, direct.vy_m_s);
    // Jarroux 2016 (seed 001), Eq. (1): sign as an arctan law.
    const double eta_s = r.cross_coupling * (2.0 / std::numbers::pi) *
                         std::atan(r.sign_regularisation_s_per_m * whirl);
    ribbon_x = r.stiffness_N_per_m * (ux - eta_s * uy);
    ribbon_y = r.stiffness_N_per_m * (eta_s * ux + uy);
    solution = SolveSeries(p, j, g, race_speed, ribbon_x, ribbon_y, damping);
  }
  rate[kRibbonX] = solution.vx_m_s;
  rate[kRibbonY] = solution.vy_m_s;

  *out = TdbForce{};
  out->penetration_m = g.radius_m - p.clearance_m;
  out->tdb_spin_rad_s = race_speed;
  out->normal_force_N = solution.normal_N;
  out->tangential_force_N = solution.friction_N;
  if (solution.normal_N > 0.0) {
    ForceOnRotor(g, solution.normal_N,
                 -solution.friction_N - p.friction.whirl_damping_N_s_per_m * g.whirl_speed_m_s,
                 &out->fx_N, &out->fy_N);
    out->torque_on_rotor_N_m = -solution.friction_N * p.journal_radius_m;
  }
  // The housing takes the ribbon's force, which the massless race makes equal to the contact's.
  out->support_x_N = ribbon_x + damping * solution.vx_m_s;
  out->support_y_N = ribbon_y + damping * solution.vy_m_s;
  rate[kRaceSpin] = RaceAcceleration(p, race_speed, solution.friction_N, solution.normal_N);
}

void ContactLawTdb::EvaluateRaceWithMass(const JournalMotion& j, const double* s, double* rate,
                                         TdbForce* out) const noexcept {
  const TdbParams& p = params_;
  const ContactLawParams& c = p.contact_law();
  const int v = race_velocity_index_;
  const double race_speed = s[kRaceSpin];
  const double ux = s[kRibbonX], uy = s[kRibbonY], vx = s[v], vy = s[v + 1];
  // The journal on the moving race, as the 4-DOF TDB's inner race meets it.
  const JournalContact contact = TouchJournal(
      p, j, {ux, uy, vx, vy}, race_speed, p.friction.whirl_damping_N_s_per_m,
      [&c](double delta, const ContactGeometry& g) {
        if (c.normal_law == ContactLawNormal::kHuntCrossley) {
          return HuntCrossleyForce(c.hunt_crossley, delta, g.radial_speed_m_s);  // Eq. (10)
        }
        // Jarroux 2019 Eq. (12), crushed branch; a receding contact cannot pull.
        return std::max(0.0, c.bearing_stiffness_N_per_m * delta +
                                 c.bearing_damping_N_s_per_m * g.radial_speed_m_s);
      },
      [&](double normal, const ContactGeometry& g) {
        return FrictionForce(p.friction, normal, SurfaceSlip(p, j, g, race_speed));  // Eq. (11)
      },
      out);

  double ribbon_x = 0.0, ribbon_y = 0.0;  // what the ribbon puts on the housing; the race feels -
  if (c.ribbon == ContactLawRibbon::kDahl) {
    // Jarroux 2019 Eq. (1)-(3), the viscous ceq beside the Dahl element.
    rate[kRibbonFx] = DahlRibbonForceRate(c.dahl, ux, vx, s[kRibbonFx]);
    rate[kRibbonFy] = DahlRibbonForceRate(c.dahl, uy, vy, s[kRibbonFy]);
    ribbon_x = s[kRibbonFx] + c.ribbon_damping_N_s_per_m * vx;
    ribbon_y = s[kRibbonFy] + c.ribbon_damping_N_s_per_m * vy;
  } else {
    // Jarroux 2016 (seed 001), Eq. (1)
    CrossCoupledRibbonForce(c.cross_coupled, ux, uy, vx, vy, &ribbon_x, &ribbon_y);
  }
  // Newton on the race (Jarroux 2019 Sec. 4.1): the journal's reaction, the ribbon, its weight.
  const double inverse_mass = 1.0 / c.outer_race_mass_kg;
  rate[kRibbonX] = vx;
  rate[kRibbonY] = vy;
  rate[v] = (-contact.on_rotor_x_N - ribbon_x) * inverse_mass;
  rate[v + 1] = (-contact.on_rotor_y_N - ribbon_y) * inverse_mass + c.gravity_y_m_s2;
  out->support_x_N = ribbon_x;
  out->support_y_N = ribbon_y;
  rate[kRaceSpin] = RaceAcceleration(p, race_speed, contact.friction_N, contact.normal_N);
}

}  // namespace ambdrop
