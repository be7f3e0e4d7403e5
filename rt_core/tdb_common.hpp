#pragma once
#include <cmath>
#include <numbers>

#include "rt_core/regularised_coulomb.hpp"
#include "rt_core/tdb_params.hpp"
#include "rt_core/touchdown_bearing.hpp"

namespace ambdrop {

/// A race's lateral motion relative to the TDB centre: position (m) and velocity (m/s).
struct RaceMotion {
  double x_m = 0.0, y_m = 0.0;
  double vx_m_s = 0.0, vy_m_s = 0.0;
};

/// The journal relative to the race it meets (the TDB centre, which misalignment moves off the
/// magnetic centre, for models without race masses), split into radial and tangential parts.
struct ContactGeometry {
  double nx = 1.0, ny = 0.0;      ///< unit normal from the race centre towards the journal
  double radius_m = 0.0;          ///< journal centre distance from the race centre
  double radial_speed_m_s = 0.0;  ///< relative speed along n (> 0 approaching the race)
  double whirl_speed_m_s = 0.0;   ///< relative speed along t = (-ny, nx), the +spin sense
};

/// Rir in use: the declared inner_race_radius_m, or journal radius + clearance when it is 0 (the
/// same sum as before the key, so the same bits).
inline double InnerRaceRadius(const TdbParams& p) noexcept {
  return p.inner_race_radius_m > 0.0 ? p.inner_race_radius_m : p.journal_radius_m + p.clearance_m;
}

/// How far the bearing's centre sits from the machine axis (its misalignment, if on).
inline double CentreOffset_m(const TdbParams& p) noexcept {
  return p.misalignment.enabled ? std::hypot(p.misalignment.x_m, p.misalignment.y_m) : 0.0;
}

inline ContactGeometry JournalGeometry(const TdbParams& p, const JournalMotion& j,
                                       const RaceMotion& race = {}) noexcept {
  ContactGeometry g;
  double jx = j.x_m;
  double jy = j.y_m;
  if (p.misalignment.enabled) {
    jx -= p.misalignment.x_m;
    jy -= p.misalignment.y_m;
  }
  const double dx = jx - race.x_m;
  const double dy = jy - race.y_m;
  g.radius_m = std::sqrt(dx * dx + dy * dy);
  if (g.radius_m > 0.0) {
    const double inverse_radius = 1.0 / g.radius_m;
    g.nx = dx * inverse_radius;
    g.ny = dy * inverse_radius;
  }
  const double rvx = j.vx_m_s - race.vx_m_s;
  const double rvy = j.vy_m_s - race.vy_m_s;
  g.radial_speed_m_s = rvx * g.nx + rvy * g.ny;
  g.whirl_speed_m_s = -rvx * g.ny + rvy * g.nx;
  return g;
}

/// Slip of the journal surface over the inner-race surface (m/s, along +spin): Jarroux 2019
/// Eq. (11), Chen 2019 (seed 002) Eq. (9)-(10): the relative whirl plus the surface speeds.
inline double SurfaceSlip(const TdbParams& p, const JournalMotion& j, const ContactGeometry& g,
                          double race_speed_rad_s) noexcept {
  const double inner_race_radius_m = InnerRaceRadius(p);
  return g.whirl_speed_m_s + j.spin_rad_s * p.journal_radius_m -
         race_speed_rad_s * inner_race_radius_m;
}

/// Slip of the journal's spin surface speed over the race's, whirl left out (m/s, along +spin):
/// Chen 2019 (seed 002) Eq. (9)-(10), vs - vi with vs = omega_s Rs, vi = omega_i Ri. (SurfaceSlip
/// does not call it: its sum keeps its order, and every run its bits.)
inline double SpinSurfaceSlip(const TdbParams& p, const JournalMotion& j,
                              double race_speed_rad_s) noexcept {
  const double inner_race_radius_m = InnerRaceRadius(p);
  return j.spin_rad_s * p.journal_radius_m - race_speed_rad_s * inner_race_radius_m;
}

/// Contact force on the rotor: the normal force pushes the journal back along -n, the
/// tangential one acts along t = (-ny, nx).
inline void ForceOnRotor(const ContactGeometry& g, double normal_N, double tangential_N,
                         double* fx_N, double* fy_N) noexcept {
  *fx_N = -normal_N * g.nx - tangential_N * g.ny;
  *fy_N = -normal_N * g.ny + tangential_N * g.nx;
}

/// The journal / inner-race contact as the 4-DOF, catcher-bearing and ball-bearing TDBs share it:
/// penetration beyond the clearance along n from the race centre, the kind's normal law
/// `normal(penetration_m, g)` and friction law `friction(normal_N, g)` (force on the race along
/// +spin), the force on the rotor against both plus the whirl damping, the torque on the rotor.
struct JournalContact {
  ContactGeometry g;
  double normal_N = 0.0;
  double friction_N = 0.0;
  double on_rotor_x_N = 0.0, on_rotor_y_N = 0.0;
};
template <class NormalLaw, class FrictionLaw>
inline JournalContact TouchJournal(const TdbParams& p, const JournalMotion& j,
                                   const RaceMotion& race, double race_speed_rad_s,
                                   double whirl_damping_N_s_per_m, NormalLaw normal,
                                   FrictionLaw friction, TdbForce* out) noexcept {
  JournalContact c;
  c.g = JournalGeometry(p, j, race);
  const double penetration = c.g.radius_m - p.clearance_m;
  *out = TdbForce{};
  out->penetration_m = penetration;
  out->tdb_spin_rad_s = race_speed_rad_s;
  if (penetration > 0.0) {
    c.normal_N = normal(penetration, c.g);
    c.friction_N = friction(c.normal_N, c.g);
    ForceOnRotor(c.g, c.normal_N, -c.friction_N - whirl_damping_N_s_per_m * c.g.whirl_speed_m_s,
                 &c.on_rotor_x_N, &c.on_rotor_y_N);
    out->torque_on_rotor_N_m = -c.friction_N * p.journal_radius_m;
  }
  out->fx_N = c.on_rotor_x_N;
  out->fy_N = c.on_rotor_y_N;
  out->normal_force_N = c.normal_N;
  out->tangential_force_N = c.friction_N;
  return c;
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
/// Eq. (11)'s atan at a fraction of the cost. With drag_regularisation_s_per_rad set, the drag
/// torque takes x = k * race speed instead (a drag measured on a coasting race need not share
/// the contact's slip scale); M1 keeps the friction's.
inline double RaceAcceleration(const TdbParams& p, double race_speed_rad_s, double friction_N,
                               double normal_force_N) noexcept {
  if (!p.spin.enabled) return 0.0;
  const double inner_race_radius_m = InnerRaceRadius(p);
  double resisting = 0.0;
  if (p.spin.drag_regularisation_s_per_rad > 0.0) {
    resisting = p.spin.palmgren_f1 * normal_force_N * p.spin.pitch_diameter_m;
    if (resisting != 0.0) {
      const double x = p.friction.regularisation_s_per_m * race_speed_rad_s * inner_race_radius_m;
      resisting *= x / std::sqrt(1.0 + x * x);
    }
    const double xd = p.spin.drag_regularisation_s_per_rad * race_speed_rad_s;
    resisting += p.spin.drag_torque_N_m * (xd / std::sqrt(1.0 + xd * xd));
  } else {
    // Shared sign (the default): this branch keeps the bits of every run before the key.
    resisting =
        p.spin.palmgren_f1 * normal_force_N * p.spin.pitch_diameter_m + p.spin.drag_torque_N_m;
    if (resisting != 0.0) {
      const double x = p.friction.regularisation_s_per_m * race_speed_rad_s * inner_race_radius_m;
      resisting *= x / std::sqrt(1.0 + x * x);
    }
  }
  return (friction_N * inner_race_radius_m - resisting -
          p.spin.rotational_damping_N_m_s * race_speed_rad_s) /
         p.spin.inertia_kg_m2;
}

}  // namespace ambdrop
