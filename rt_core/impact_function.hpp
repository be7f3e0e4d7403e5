#pragma once
#include <cmath>

namespace ambdrop {

/// Normal contact of seed 003 (catcher-bearing paper, Sec. 2.3), MSC ADAMS's IMPACT function:
///   F = 0                                         for delta <= 0,
///   F = k delta^e + cm delta' STEP(delta, 0, 0, dm, 1)   for delta > 0,        Eq. (1)
/// with delta = s - s0 the penetration (m), delta' its rate (m/s, > 0 approaching), e = 3/2 for a
/// point contact and 10/9 for a line contact, cm the maximum damping and dm the penetration at
/// which the damping reaches cm. The extracted text prints STEP(s, s0 - dm, 1, s0, 0), which
/// would switch the damping off inside the contact; the intent (ADAMS's IMPACT) is a cubic ramp
/// from 0 at first contact to 1 at delta = dm, so the force has no jump at contact.
/// A receding contact cannot pull: F >= 0 (ADAMS's IMPACT does the same).
struct ImpactParams {
  double stiffness_N_per_m_e = 0.0;         ///< k (N/m^e)
  double exponent = 1.5;                    ///< e: 3/2 point contact, 10/9 line contact
  double max_damping_N_s_per_m = 0.0;       ///< cm
  double full_damping_penetration_m = 0.0;  ///< dm (paper: 0.01 mm)
  friend bool operator==(const ImpactParams&, const ImpactParams&) = default;
};

/// ADAMS's STEP(x, x0, h0, x1, h1): h0 for x <= x0, h1 for x >= x1, in between the cubic
/// h0 + (h1 - h0) a^2 (3 - 2 a), a = (x - x0) / (x1 - x0) (seed 003, Eq. (1)).
inline double AdamsStep(double x, double x0, double h0, double x1, double h1) noexcept {
  if (x <= x0) return h0;
  if (x >= x1) return h1;
  const double a = (x - x0) / (x1 - x0);
  return h0 + (h1 - h0) * a * a * (3.0 - 2.0 * a);
}

/// Line-contact stiffness of seed 003, Eq. (2): k = 7.85e10 L^(8/9) (N/m^(10/9)) for a contact
/// length L (m). In SI units this is Palmgren's steel line contact, delta = 3.84e-5 Q^0.9 /
/// L^0.8 (mm, N), solved for Q.
inline double LineContactStiffness(double contact_length_m) noexcept {
  return 7.85e10 * std::pow(contact_length_m, 8.0 / 9.0);
}

/// Elastic part k delta^e of Eq. (1), for delta > 0.
inline double ImpactElasticForce(const ImpactParams& p, double penetration_m) noexcept {
  if (p.exponent == 1.5) return p.stiffness_N_per_m_e * penetration_m * std::sqrt(penetration_m);
  if (p.exponent == 1.0) return p.stiffness_N_per_m_e * penetration_m;
  return p.stiffness_N_per_m_e * std::pow(penetration_m, p.exponent);
}

/// Impact force (N, >= 0) of seed 003 Eq. (1) for a penetration (m) and its rate (m/s).
inline double ImpactForce(const ImpactParams& p, double penetration_m, double rate_m_s) noexcept {
  if (!(penetration_m > 0.0)) return 0.0;
  // Seed 003, Eq. (1)
  const double damping = p.max_damping_N_s_per_m * rate_m_s *
                         AdamsStep(penetration_m, 0.0, 0.0, p.full_damping_penetration_m, 1.0);
  const double force = ImpactElasticForce(p, penetration_m) + damping;
  return force > 0.0 ? force : 0.0;
}

}  // namespace ambdrop
