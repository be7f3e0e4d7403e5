#pragma once
#include <cmath>

#include "rt_core/four_dof_params.hpp"

namespace ambdrop {

/// The elastic part kn u^n of Hunt-Crossley's law (N) for a penetration u > 0 (m).
inline double HuntCrossleyElastic(const HuntCrossleyParams& p, double penetration_m) noexcept {
  if (p.exponent == 1.0) return p.stiffness_N_per_m_n * penetration_m;
  if (p.exponent == 1.5) return p.stiffness_N_per_m_n * penetration_m * std::sqrt(penetration_m);
  return p.stiffness_N_per_m_n * std::pow(penetration_m, p.exponent);
}

/// Hunt-Crossley normal contact force (N, >= 0) for a penetration u (m, > 0 in contact) and its
/// rate u' (m/s, > 0 approaching): Jarroux 2019 Eq. (10), fn = kn u^n (1 + 3/2 alpha u'), with
/// Hunt & Crossley's exponent n. A fast receding contact cannot pull, so fn >= 0.
inline double HuntCrossleyForce(const HuntCrossleyParams& p, double penetration_m,
                                double rate_m_s) noexcept {
  if (!(penetration_m > 0.0)) return 0.0;
  // Jarroux 2019, Eq. (10)
  const double force =
      HuntCrossleyElastic(p, penetration_m) * (1.0 + 1.5 * p.damping_s_per_m * rate_m_s);
  return force > 0.0 ? force : 0.0;
}

}  // namespace ambdrop
