#include "tools/fit/noise_floor.hpp"

#include <algorithm>
#include <cmath>

namespace ambdrop {

double NoiseSigma(const std::vector<double>& v, std::size_t first, std::size_t last) {
  last = std::min(last, v.size());
  if (last < first + 3) return 0.0;
  std::vector<double> d2;
  d2.reserve(last - first - 2);
  for (std::size_t j = first + 1; j + 1 < last; ++j) {
    d2.push_back(std::abs(v[j + 1] - 2.0 * v[j] + v[j - 1]));
  }
  auto mid = d2.begin() + static_cast<std::ptrdiff_t>(d2.size() / 2);
  std::nth_element(d2.begin(), mid, d2.end());
  return 1.4826 * *mid / std::sqrt(6.0);
}

double MedianNoiseSigma(const std::vector<const std::vector<double>*>& columns, std::size_t last) {
  std::vector<double> sigmas;
  for (const std::vector<double>* c : columns) sigmas.push_back(NoiseSigma(*c, 0, last));
  if (sigmas.empty()) return 0.0;
  std::nth_element(sigmas.begin(), sigmas.begin() + sigmas.size() / 2, sigmas.end());
  return sigmas[sigmas.size() / 2];
}

}  // namespace ambdrop
