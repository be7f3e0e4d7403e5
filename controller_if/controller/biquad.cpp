#include "controller_if/controller/biquad.hpp"

#include <cmath>

namespace ambdrop {

bool BiquadCoefficients::Integrates() const noexcept {
  // A(1) = 1 + a1 + a2 vanishes up to the rounding of the discretisation.
  return std::abs(1.0 + a1 + a2) <= 1e-9 * (1.0 + std::abs(a1) + std::abs(a2));
}

}  // namespace ambdrop
