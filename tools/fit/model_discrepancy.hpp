#pragma once
// Issue 24 item 7: when a residual that no candidate removes dominates a record, the report
// names it as a mismatch between the declared model and the rig: the channel it sits on, its
// shape in words ("after the trigger the rotor speed falls 9.8x faster than the model's") and
// the config key families that could explain it. Over several records of one rig
// (SharedDiscrepancies) it says which of these the records share.
#include <string>
#include <vector>

#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "rt_core/model_params.hpp"
#include "tools/fit/effect_selection.hpp"
#include "tools/fit/residuals.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

struct Discrepancy {
  /// The verdict left most of the residual unexplained (unexplained or partly_explained): the
  /// declared model, with whatever the fit chose, does not match the rig.
  bool dominant = false;
  std::string channel;      ///< the column with the largest share of the residual left
  std::string description;  ///< "rotor speed", "displacement de y"
  double share = 0.0;       ///< of the fit's cost after the chosen effects
  /// Where along the record it is largest: "levitated" (before the trigger), "drop" (from the
  /// trigger until the settled phase), "settled"; "after_trigger" for speeds.
  std::string phase;
  std::string shape;          ///< one sentence, with the record's and the model's numbers
  double record_value = 0.0;  ///< the numbers the shape compares (SI)
  double model_value = 0.0;
  /// Config key families that could explain it (patterns, `*` for any name).
  std::vector<std::string> key_families;
};

/// `model` and `residual` are the fitted model's (the declared one's when nothing was chosen).
Discrepancy DescribeDiscrepancy(const ModelParams& params, const MeasurementParams& measurement,
                                const MeasuredRecord& record, const SimulatedRecord& model,
                                const ResidualReport& residual, const Selection& selection);

/// One record's part in a fit over several records of one rig.
struct RecordDiscrepancy {
  std::string record;  ///< its path
  std::string verdict;
  Discrepancy discrepancy;
  std::vector<Signature> signatures;  ///< the declared model's residual signatures
  std::vector<std::string> chosen;    ///< effects chosen on it
};

/// What every one of the records shows alike: the same channel and phase dominating with the
/// model off in the same direction, the same residual signature (kind, channel, sign), the same
/// effect chosen. Each line is one finding in words; empty when they share nothing.
std::vector<std::string> SharedDiscrepancies(const std::vector<RecordDiscrepancy>& records);

}  // namespace ambdrop
