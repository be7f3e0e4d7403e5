#pragma once
#include "rt_core/ball_bearing_tdb_params.hpp"

namespace ambdrop {

/// Friction force (N) on the inner race along its spin sense, for the normal force fn (N, >= 0)
/// and the slip vs - vi (m/s) of the journal surface over the race surface:
/// Chen 2019 (seed 002), Eq. (11)-(12), Ft = mu_r |Fn| c_t with c_t = sgn(vs - vi) and
///   mu_r = mu_d (vs > vi), mu_s (vs = vi), -mu_d (vs < vi)           (text after Eq. (8)).
/// "vs = vi" is the band |vs - vi| <= v_stick: there the force holds the surfaces together,
/// mu_s fn (vs - vi) / v_stick, reaching the static limit mu_s fn at the band edge. The force
/// always has the sign of the slip, so the contact only dissipates.
inline double SlipFrictionForce(const SlipFrictionParams& p, double normal_force_N,
                                double slip_m_s) noexcept {
  if (p.law == SlipFrictionLaw::kNone) return 0.0;
  if (slip_m_s > p.stick_speed_m_s) return p.kinetic_coefficient * normal_force_N;
  if (slip_m_s < -p.stick_speed_m_s) return -p.kinetic_coefficient * normal_force_N;
  if (!(p.stick_speed_m_s > 0.0)) return 0.0;  // exactly rolling, no band: c_t undefined
  return p.static_coefficient * normal_force_N * slip_m_s / p.stick_speed_m_s;
}

}  // namespace ambdrop
