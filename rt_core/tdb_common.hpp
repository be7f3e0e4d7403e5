#pragma once
#include <cmath>
#include <numbers>

#include "rt_core/regularised_coulomb.hpp"
#include "rt_core/tdb_params.hpp"
#include "rt_core/touchdown_bearing.hpp"

namespace ambdrop {

/// Journal position relative to the TDB centre (which misalignment moves off the magnetic
/// centre), split into radial and tangential parts.
struct ContactGeometry {
  double nx = 1.0, ny = 0.0;  ///< unit normal from the TDB centre towards the journal
  double radius_m = 0.0;      ///< journal centre distance from the TDB centre
  double radial_speed_m_s = 0.0;
  double whirl_speed_m_s = 0.0;  ///< tangential speed of the journal centre, along +spin
};

inline ContactGeometry JournalGeometry(const TdbParams& p, const JournalMotion& j) noexcept {
  ContactGeometry g;
  double dx = j.x_m;
  double dy = j.y_m;
  if (p.misalignment.enabled) {
    dx -= p.misalignment.x_m;
    dy -= p.misalignment.y_m;
  }
  g.radius_m = std::sqrt(dx * dx + dy * dy);
  if (g.radius_m > 0.0) {
    g.nx = dx / g.radius_m;
    g.ny = dy / g.radius_m;
  }
  g.radial_speed_m_s = j.vx_m_s * g.nx + j.vy_m_s * g.ny;
  g.whirl_speed_m_s = -j.vx_m_s * g.ny + j.vy_m_s * g.nx;
  return g;
}

/// Friction force on the race along +spin for a slip speed (journal surface minus race surface).
inline double FrictionForce(const FrictionParams& f, double normal_force_N,
                            double slip_speed_m_s) noexcept {
  switch (f.law) {
    case FrictionLaw::kRegularisedCoulomb:
      return RegularisedCoulomb(f.coefficient, normal_force_N, f.regularisation_s_per_m,
                                slip_speed_m_s);
    case FrictionLaw::kNone:
      break;
  }
  return 0.0;
}

/// Inner-race acceleration, Jarroux 2019 Eq. (9), with the Palmgren load torque M1 = f1 fn dm
/// and a constant drag torque, both opposing the race's rotation. Their sign is regularised
/// algebraically, x / sqrt(1 + x^2) with x = vref * race surface speed: the same smooth sign as
/// Eq. (11)'s atan at a fraction of the cost.
inline double RaceAcceleration(const TdbParams& p, double race_speed_rad_s, double friction_N,
                               double normal_force_N) noexcept {
  if (!p.spin.enabled) return 0.0;
  const double inner_race_radius_m = p.journal_radius_m + p.clearance_m;
  double resisting =
      p.spin.palmgren_f1 * normal_force_N * p.spin.pitch_diameter_m + p.spin.drag_torque_N_m;
  if (resisting != 0.0) {
    const double x = p.friction.regularisation_s_per_m * race_speed_rad_s * inner_race_radius_m;
    resisting *= x / std::sqrt(1.0 + x * x);
  }
  return (friction_N * inner_race_radius_m - resisting -
          p.spin.rotational_damping_N_m_s * race_speed_rad_s) /
         p.spin.inertia_kg_m2;
}

}  // namespace ambdrop
