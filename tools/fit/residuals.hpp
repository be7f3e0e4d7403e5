#pragma once
// Step b of `ambdrop fit`: how far the model's prediction is from the record, per channel, per
// phase of the drop, and overall. Channels have different units, so the overall figure is the
// RMS of each channel's residual over that channel's measured range (a relative error).
#include <limits>
#include <string>
#include <vector>

#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "tools/fit/drop_features.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

/// Record-time windows: before the trigger (the simulated lead), the impact phase (the first
/// third of what follows the trigger, at most 0.1 s) and the settled phase (the last third,
/// at most 0.1 s).
struct FitWindows {
  double start_s = 0.0;
  double trigger_s = 0.0;
  double impact_end_s = 0.0;
  double settled_start_s = 0.0;
  double end_s = 0.0;
};

struct ChannelResidual {
  std::string column;
  std::string description;  ///< "displacement de x"
  double scale = 1.0;       ///< measured range (max - min) over the compared rows, SI
  double rms = 0.0;         ///< over every compared row, SI
  double rms_before = 0.0;  ///< NaN where the window has no compared row
  double rms_impact = 0.0;
  double rms_settled = 0.0;
  std::size_t samples = 0;
  /// The channel's share of the fit's cost (RecordCost::ChannelSse over the total): which
  /// channels the overall residual comes from. NaN where not set.
  double cost_share = std::numeric_limits<double>::quiet_NaN();
};

struct ResidualReport {
  FitWindows windows;
  std::vector<ChannelResidual> channels;  ///< in measurement order
  double overall = 0.0;  ///< the fit's overall relative RMS (RecordCost), set by the caller
  std::vector<FeatureComparison> features;  ///< the drop's features, record against model
  std::vector<Signature> signatures;        ///< what stands out in the residual
};

/// `start_s`: where the comparison starts (RecordCost::compare_from_s).
FitWindows WindowsOf(const MeasuredRecord& record, const SimulatedRecord& sim, double start_s);

/// Per channel and phase, sample by sample (what a person reads). Open loop, currents before
/// the trigger are the run's inputs, not predictions: they are not compared. A run that stopped
/// early is compared over what it simulated. `overall` is left for the caller to set from the
/// fit's cost (RecordCost), which is what the fit judges by.
ResidualReport ComputeResiduals(const ModelParams& params, const MeasurementParams& measurement,
                                const MeasuredRecord& record, const SimulatedRecord& sim,
                                double start_s);

/// The residual series of channel c (measured - model), NaN where not compared: outside the
/// channel's window, currents and commands before the trigger open loop, and commands open loop
/// throughout (no controller runs to predict them).
std::vector<double> ResidualSeries(const MeasurementParams& measurement,
                                   const MeasuredRecord& record, const SimulatedRecord& sim,
                                   std::size_t c);

}  // namespace ambdrop
