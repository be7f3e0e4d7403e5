#pragma once
#include <cmath>

#include "rt_core/rotor_params.hpp"

namespace ambdrop {

/// Torque on the rotor from its coast-down losses at spin speed W (N m, along +spin): a constant
/// (Coulomb) torque, a viscous torque and a windage torque, each opposing the spin,
///   T = -(T0 s(W) + c1 W + c2 W |W|),  s(W) = k W / sqrt(1 + (k W)^2),
/// the three-term loss law of coast-down testing (constant, linear and quadratic in speed: SAE
/// J2263, road load A + B v + C v^2), here as torques on the spin. The smooth sign is the one the
/// TDB races use (tdb_common.hpp). The caller applies it only while the drive is off.
inline double CoastDownTorque(const CoastDownParams& c, double spin_rad_s) noexcept {
  const double x = c.sign_regularisation_s_per_rad * spin_rad_s;
  const double sign = x / std::sqrt(1.0 + x * x);
  return -(c.constant_torque_N_m * sign + c.viscous_N_m_s * spin_rad_s +
           c.windage_N_m_s2 * spin_rad_s * std::abs(spin_rad_s));
}

}  // namespace ambdrop
