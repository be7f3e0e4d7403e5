#pragma once
// One TDB's contact with the journal, from the papers' equations with this generator's own
// conventions:
//  - normal force: linear spring-damper (Jarroux 2019 Eq. (12) with no ribbon) or Hunt-Crossley
//    fn = k d^n (1 + 3/2 alpha d') (Jarroux 2019 Eq. (10)), never pulling (fn >= 0);
//  - friction: Coulomb (Jarroux 2019 Eq. (11)) with the sign regularised as tanh(v / v0), not
//    the paper's (2/pi) atan(vref v);
//  - race spin, Jarroux 2019 Eq. (9): J w' = ft R_ir - Td tanh(w R_ir / v0) - Phi w, with the
//    inner-race radius R_ir the rig's (the journal radius unless given), not R_j + clearance;
//  - a generalized Dahl ribbon under the housing (Jarroux 2019 Eq. (1)-(3)), per lateral axis:
//    frd' = beta |u'| (h - frd), h = hu (u' >= 0) or hl, hu = muFN + ks u + a exp(b u),
//    hl = -muFN + ks u - a exp(-b u).
#include <cmath>

#include "rig.hpp"

namespace ambdrop_truth {

/// The journal at the TDB's station relative to the TDB's centre (m, m/s) and its spin.
struct JournalAtTdb {
  double x_m = 0.0, y_m = 0.0, vx_m_s = 0.0, vy_m_s = 0.0;
  double spin_rad_s = 0.0;
};

struct ContactForces {
  double normal_N = 0.0;
  double friction_N = 0.0;        ///< on the race, along +spin
  double fx_N = 0.0, fy_N = 0.0;  ///< on the journal
  double spin_torque_N_m = 0.0;   ///< on the rotor's spin
  double race_acceleration_rad_s2 = 0.0;
  double penetration_m = 0.0;
};

inline ContactForces EvaluateContact(const TdbRig& t, const JournalAtTdb& j,
                                     double race_speed_rad_s) {
  ContactForces out;
  const double r = std::sqrt(j.x_m * j.x_m + j.y_m * j.y_m);
  const double penetration = r - t.clearance_m;
  out.penetration_m = penetration;
  const double Rir = t.inner_race_radius_m;
  // Eq. (9)'s resisting torques act whether or not the journal touches.
  double race_torque =
      -t.race_drag_torque_N_m * std::tanh(race_speed_rad_s * Rir / t.slip_regularisation_m_s) -
      t.race_viscous_drag_N_m_s * race_speed_rad_s;
  if (penetration > 0.0 && r > 0.0) {
    const double nx = j.x_m / r;
    const double ny = j.y_m / r;
    const double radial_speed = j.vx_m_s * nx + j.vy_m_s * ny;
    const double whirl_speed = -j.vx_m_s * ny + j.vy_m_s * nx;  // along t = (-ny, nx)
    double fn = 0.0;
    if (t.contact_law == ContactLaw::kLinear) {
      fn = t.contact_stiffness * penetration + t.contact_damping * radial_speed;
    } else {
      fn = t.contact_stiffness * std::pow(penetration, t.contact_exponent) *
           (1.0 + 1.5 * t.contact_damping * radial_speed);
    }
    fn = std::max(fn, 0.0);
    const double slip = whirl_speed + j.spin_rad_s * t.journal_radius_m - race_speed_rad_s * Rir;
    const double ft = t.friction_coefficient * fn * std::tanh(slip / t.slip_regularisation_m_s);
    out.normal_N = fn;
    out.friction_N = ft;
    // The journal is pushed back along -n and dragged back along -t.
    out.fx_N = -fn * nx + ft * ny;
    out.fy_N = -fn * ny - ft * nx;
    out.spin_torque_N_m = -ft * t.journal_radius_m;
    race_torque += ft * Rir;
  }
  out.race_acceleration_rad_s2 = race_torque / t.race_inertia_kg_m2;
  return out;
}

/// Rate of one axis's Dahl ribbon force (N/s) for its deflection u (m) and rate u' (m/s).
inline double DahlForceRate(const DahlRibbonRig& d, double force_N, double u_m, double u_rate) {
  const double upper = d.slipping_threshold_N + d.slipping_stiffness_N_per_m * u_m +
                       d.hardening_N * std::exp(d.hardening_rate_per_m * u_m);
  const double lower = -d.slipping_threshold_N + d.slipping_stiffness_N_per_m * u_m -
                       d.hardening_N * std::exp(-d.hardening_rate_per_m * u_m);
  const double h = u_rate >= 0.0 ? upper : lower;
  return d.beta_per_m * std::abs(u_rate) * (h - force_N);
}

}  // namespace ambdrop_truth
