#pragma once
#include "rt_core/four_dof_params.hpp"

namespace ambdrop {

/// Kelvin-Voigt ribbon restoring force (N) for a deflection u (m) and its rate u' (m/s):
/// Jarroux 2019 Eq. (4), frd = crd u' + krd u. The force on the outer race is -frd.
inline double KelvinVoigtRibbonForce(const KelvinVoigtRibbonParams& p, double deflection_m,
                                     double rate_m_s) noexcept {
  // Jarroux 2019, Eq. (4)
  return p.damping_N_s_per_m * rate_m_s + p.stiffness_N_per_m * deflection_m;
}

}  // namespace ambdrop
