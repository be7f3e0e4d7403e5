#pragma once
#include <cmath>
#include <numbers>

namespace ambdrop {

/// Regularised Coulomb friction, Jarroux 2019 Eq. (11): ft = mu fn (2/pi) atan(vref vs).
inline double RegularisedCoulomb(double mu, double normal_force_N, double vref_s_per_m,
                                 double slip_speed_m_s) noexcept {
  return mu * normal_force_N * (2.0 / std::numbers::pi) * std::atan(vref_s_per_m * slip_speed_m_s);
}

}  // namespace ambdrop
