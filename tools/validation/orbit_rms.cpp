#include "tools/validation/orbit_rms.hpp"

#include <algorithm>
#include <cmath>

namespace ambdrop {

void OrbitRms::Add(double x_m, double y_m) noexcept {
  sx_ += x_m;
  sy_ += y_m;
  sxx_ += x_m * x_m;
  syy_ += y_m * y_m;
  ++n_;
}

double OrbitRms::rms_m() const noexcept {
  if (n_ == 0) return 0.0;
  const double n = static_cast<double>(n_);
  const double mx = sx_ / n, my = sy_ / n;
  // Variance about the mean, summed over x and y; clamped against rounding below zero.
  return std::sqrt(std::max(0.0, sxx_ / n - mx * mx + syy_ / n - my * my));
}

}  // namespace ambdrop
