#pragma once
// A rig dropped as `ambdrop sim` drops it (RunOffline: the config's trigger, AMB currents or
// controller, an observation every output interval), summarised per TDB for the seed checks.
#include <limits>
#include <string>
#include <vector>

#include "tools/fit/whirl_classifier.hpp"
#include "tools/validation/tdb_peaks.hpp"

namespace ambdrop {

struct OfflineDrop {
  std::vector<TdbPeaks> tdbs;  ///< peaks from the trigger on
  /// Per TDB, the motion after the transient (RunSummary::Whirl: the second half of the time
  /// after the trigger), Jarroux 2016 (seed 001) Sec. 3.
  std::vector<WhirlClassification> whirl;
  bool ok = false;  ///< the simulation ran to the end
  std::string failure_message;
};

/// Loads `config_path` with `overrides` and runs it to its configured duration.
/// `late_after_trigger_s`: from how long after the trigger TdbPeaks::late_normal_N counts.
OfflineDrop RunOfflineDrop(const std::string& config_path,
                           const std::vector<std::string>& overrides,
                           double late_after_trigger_s = std::numeric_limits<double>::infinity());

}  // namespace ambdrop
