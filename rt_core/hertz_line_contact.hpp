#pragma once
#include <cmath>
#include <numbers>

#include "rt_core/ball_bearing_tdb_params.hpp"

namespace ambdrop {

/// Normal force (N, >= 0) of the un-lubricated Hertz line contact between journal and inner
/// race for the deflection delta (m) beyond the radial clearance c = Ri - Rs (m):
/// Chen 2019 (seed 002), Eq. (5)-(6),
///   |Fn| = pi/2 delta E L sqrt(delta / (2 (c + delta)))  for delta > 0, else 0.
/// The law is purely elastic: the paper's contact has no damping term.
inline double LineContactForce(const LineContactParams& p, double clearance_m,
                               double deflection_m) noexcept {
  if (!(deflection_m > 0.0)) return 0.0;
  // Chen 2019 (seed 002), Eq. (5)
  return std::numbers::pi / 2.0 * deflection_m * p.youngs_modulus_Pa * p.length_m *
         std::sqrt(deflection_m / (2.0 * (clearance_m + deflection_m)));
}

}  // namespace ambdrop
