#pragma once
// Seed cases whose drop is chaotic and whose paper gives no unbalance phase at the drop run the
// drop at kUnbalancePhases phases and compare medians: one phase can peak 30-50 % off another.
#include <string>
#include <vector>

namespace ambdrop {

inline constexpr int kUnbalancePhases = 8;

/// The --set override that puts unbalance `name` at phase k of kUnbalancePhases, 2 pi k / n.
std::string UnbalancePhaseOverride(const std::string& name, int k);

/// The median (the mean of the middle two of an even count); 0 for none.
double Median(std::vector<double> values);

}  // namespace ambdrop
