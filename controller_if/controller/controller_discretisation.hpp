#pragma once
// Continuous sections and their discretisation at the controller period: Tustin (bilinear,
// optionally prewarped), zero-order hold and backward Euler. See docs/equations.md.
#include <array>

#include "controller_if/controller/biquad.hpp"
#include "rt_core/controller_form_params.hpp"

namespace ambdrop {

/// H(s) = (n[0] s^2 + n[1] s + n[2]) / (d[0] s^2 + d[1] s + d[2]).
struct ContinuousSection {
  std::array<double, 3> numerator{};
  std::array<double, 3> denominator{0.0, 0.0, 1.0};
};

/// A shorthand (gain, PID, lead/lag, notch, low-pass) or s_biquad as its s-domain section.
ContinuousSection ContinuousForm(const ControllerSectionParams& section);

/// The section as a z-domain biquad at period `period_s`. Throws std::invalid_argument for an
/// improper section under Tustin or zero-order hold, or a prewarp at or beyond Nyquist.
BiquadCoefficients Discretise(const ContinuousSection& section, Discretisation method,
                              double period_s, double prewarp_Hz);

/// Any section of a [controller.linear] cascade (z_biquad ones taken as they are).
BiquadCoefficients SectionBiquad(const ControllerSectionParams& section, double period_s);

/// e^{M} of a small square matrix by scaling and squaring of its Taylor series: additions and
/// multiplications only, so the same bits on every machine (used at construction, not per step).
template <int N>
std::array<std::array<double, N>, N> SmallMatrixExp(const std::array<std::array<double, N>, N>& m);

}  // namespace ambdrop
