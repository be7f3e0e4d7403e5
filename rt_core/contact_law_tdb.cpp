#include "rt_core/contact_law_tdb.hpp"

#include <algorithm>
#include <cmath>

#include "rt_core/tdb_common.hpp"

namespace ambdrop {

ContactLawTdb::ContactLawTdb(const TdbParams& params) : TouchdownBearing(params) {}

void ContactLawTdb::Evaluate(const JournalMotion& j, const double* state, double* state_rate,
                             TdbForce* out) const noexcept {
  const TdbParams& p = params_;
  const ContactLawParams& c = p.contact_law;
  const double race_speed = state[0];
  const ContactGeometry g = JournalGeometry(p, j);
  const double urs = g.radius_m - p.clearance_m;

  *out = TdbForce{};
  out->penetration_m = urs;
  out->tdb_spin_rad_s = race_speed;
  double normal = 0.0;
  double friction = 0.0;
  if (urs > 0.0) {
    // Jarroux 2019 Eq. (12); a receding contact cannot pull, so fn >= 0.
    if (urs >= c.ribbon_crushing_m) {
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
    // Without race masses the housing takes the whole contact force.
    out->support_x_N = out->fx_N;
    out->support_y_N = out->fy_N;
  }
  out->normal_force_N = normal;
  out->tangential_force_N = friction;
  state_rate[0] = RaceAcceleration(p, race_speed, friction, normal);
}

}  // namespace ambdrop
