#pragma once
#include <cstddef>
#include <vector>

namespace ambdrop {

/// Standard deviation of white measurement noise on a sampled signal, from its second
/// differences (their variance is 6 sigma^2, and a smooth signal barely has any): robustly,
/// 1.4826 * median |d2| / sqrt(6), so that impacts and steps do not count as noise.
/// Rows [first, last) of `values`; 0 for fewer than 3.
double NoiseSigma(const std::vector<double>& values, std::size_t first, std::size_t last);

/// The median over `columns` of NoiseSigma over rows [0, last): the noise a record's sensors
/// carry (0 with no column).
double MedianNoiseSigma(const std::vector<const std::vector<double>*>& columns, std::size_t last);

}  // namespace ambdrop
