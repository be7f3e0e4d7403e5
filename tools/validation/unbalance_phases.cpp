#include "tools/validation/unbalance_phases.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numbers>

namespace ambdrop {

std::string UnbalancePhaseOverride(const std::string& name, int k) {
  return fmt::format("unbalance.{}.phase_rad={:.17g}", name,
                     2.0 * std::numbers::pi * k / kUnbalancePhases);
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  if (n == 0) return 0.0;
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace ambdrop
