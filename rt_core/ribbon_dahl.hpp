#pragma once
#include <cmath>

#include "rt_core/deterministic_exp.hpp"
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
         p.upper_hardening_N * DeterministicExp(p.upper_hardening_rate_per_m * deflection_m);
}

/// Lower envelope hl(u) (N), followed while unloading: Jarroux 2019 Eq. (3),
/// hl = -muFN + kslip u - c exp(-d u).
inline double DahlLowerEnvelope(const DahlRibbonParams& p, double deflection_m) noexcept {
  // Jarroux 2019, Eq. (3)
  return -DahlSlippingThreshold(p) + p.slipping_stiffness_N_per_m * deflection_m -
         p.lower_hardening_N * DeterministicExp(-p.lower_hardening_rate_per_m * deflection_m);
}

/// Rate of the Dahl ribbon force frd (N/s) for deflection u (m), its rate u' (m/s) and the
/// current force: Jarroux 2019 Eq. (1)-(2) in the form that relaxes to the envelope the motion
/// heads for (see seeds/INDEX.md), frd' = beta |u'| (h - frd), h = hu if u' > 0, hl if u' < 0.
/// The force on the outer race is -frd.
inline double DahlRibbonForceRate(const DahlRibbonParams& p, double deflection_m, double rate_m_s,
                                  double force_N) noexcept {
  // Jarroux 2019, Eq. (1)-(3): only the envelope the sign of u' selects is needed. It is picked
  // by selecting its coefficients rather than by branching: the outer race's motion reverses
  // often, and a mispredicted branch per axis and stage cost more than the selection (the
  // same sums as DahlUpperEnvelope / DahlLowerEnvelope, so the same bits).
  const bool loading = rate_m_s > 0.0;
  const double threshold_N = loading ? DahlSlippingThreshold(p) : -DahlSlippingThreshold(p);
  const double hardening_N = loading ? p.upper_hardening_N : -p.lower_hardening_N;
  const double hardening_rate_per_m =
      loading ? p.upper_hardening_rate_per_m : -p.lower_hardening_rate_per_m;
  const double envelope_N = threshold_N + p.slipping_stiffness_N_per_m * deflection_m +
                            hardening_N * DeterministicExp(hardening_rate_per_m * deflection_m);
  return p.beta_per_m * std::abs(rate_m_s) * (envelope_N - force_N);
}

}  // namespace ambdrop
