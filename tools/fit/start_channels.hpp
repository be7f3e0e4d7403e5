#pragma once
// The drop's start sensor by sensor. A gain or a lag of one sensor's chain moves that sensor's
// channel alone, and the start's one RMS over every channel (17 on the 4-DOF truth rig) dilutes
// it below its limit: there a gained sensor's fall came out 1.1-1.2 times the model's and was
// called `no_effect_needed`. Each displacement channel is held to a limit of its own.
#include <Eigen/Core>
#include <vector>

#include "io/config/config_variants.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/record_cost.hpp"

namespace ambdrop {

/// Each measurement channel's numbers on the drop's start (0 for a channel not compared), on
/// the scale of sqrt(RecordCost::ChannelNoiseSse()).
struct StartChannels {
  std::vector<double> rms;      ///< the declared model's residual
  std::vector<double> noise;    ///< the record's noise
  std::vector<double> step;     ///< the move at half the step
  std::vector<double> start;    ///< the widest move of a start probe or a drawn jitter
  std::vector<double> limit;    ///< AgreementLimit of the three
  std::vector<bool> departing;  ///< a displacement channel beyond its limit
  bool Departs() const;
  /// The quadrature mean of `v` over the departing channels: the part they make together
  /// (OverallRms's scale).
  double OverDeparting(const std::vector<double>& v) const;
};

/// `early`: a CostScope::kEarly cost, `early_before` its residual for the declared model. Empty
/// vectors where the start's jitter is not drawn (SelectionRules::jitter_draws 0, open loop, or
/// the state at the trigger from the record): the widest draw is what each channel is held to.
StartChannels JudgeStartChannels(const ConfigVariants& declared, const RecordCost& early,
                                 const Eigen::VectorXd& early_before, const SelectionRules& rules);

}  // namespace ambdrop
