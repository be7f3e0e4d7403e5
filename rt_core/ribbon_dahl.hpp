#pragma once
#include <cmath>

#include "rt_core/four_dof_params.hpp"

namespace ambdrop {

/// Slipping threshold muFN (N) in use: the harmonic-test value times its scale factor.
inline double DahlSlippingThreshold(const DahlRibbonParams& p) noexcept {
  return p.slipping_threshold_N * p.threshold_scale;
}

/// Upper envelope hu(u) (N), followed while loading: Jarroux 2019 Eq. (3),
/// hu = muFN + kslip u + a exp(b u).
inline double DahlUpperEnvelope(const DahlRibbonParams& p, double deflection_m) noexcept {
  // Jarroux 2019, Eq. (3)
  return DahlSlippingThreshold(p) + p.slipping_stiffness_N_per_m * deflection_m +
         p.upper_hardening_N * std::exp(p.upper_hardening_rate_per_m * deflection_m);
}

/// Lower envelope hl(u) (N), followed while unloading: Jarroux 2019 Eq. (3),
/// hl = -muFN + kslip u - c exp(-d u).
inline double DahlLowerEnvelope(const DahlRibbonParams& p, double deflection_m) noexcept {
  // Jarroux 2019, Eq. (3)
  return -DahlSlippingThreshold(p) + p.slipping_stiffness_N_per_m * deflection_m -
         p.lower_hardening_N * std::exp(-p.lower_hardening_rate_per_m * deflection_m);
}

/// Rate of the Dahl ribbon force frd (N/s) for deflection u (m), its rate u' (m/s) and the
/// current force: Jarroux 2019 Eq. (1)-(2) in the form that relaxes to the envelope the motion
/// heads for (see seeds/INDEX.md), frd' = beta |u'| (h - frd), h = hu if u' > 0, hl if u' < 0.
/// The force on the outer race is -frd.
inline double DahlRibbonForceRate(const DahlRibbonParams& p, double deflection_m, double rate_m_s,
                                  double force_N) noexcept {
  // Jarroux 2019, Eq. (1)-(2): only the envelope the sign of u' selects is needed.
  if (rate_m_s > 0.0) {
    return p.beta_per_m * rate_m_s * (DahlUpperEnvelope(p, deflection_m) - force_N);
  }
  if (rate_m_s < 0.0) {
    return p.beta_per_m * -rate_m_s * (DahlLowerEnvelope(p, deflection_m) - force_N);
  }
  return 0.0;
}

}  // namespace ambdrop
