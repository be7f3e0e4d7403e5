#pragma once
// Issue 6, published summary numbers: which single parameter change explains measured TDB
// spin-up times (seed 000, Table 3: DE 0.11 s, NDE 0.129 s after a drop at 6500 rpm)? Each
// candidate changes one parameter, of one TDB or of both; its value is fitted with Eigen's
// Levenberg-Marquardt to the times' relative errors, from a few starts.
#include <map>
#include <string>
#include <vector>

#include "rt_core/model_params.hpp"

namespace ambdrop {

/// Seconds from the trigger until each TDB's surface speed first reaches 95 % of the journal's
/// (as Jarroux 2019 reads its measured race speeds); -1 for a TDB that never does.
std::map<std::string, double> TdbSpinUpTimes(const ModelParams& params);

struct SpinUpCandidate {
  std::string name;       ///< "tdb_drag_torque:de"
  std::string parameter;  ///< with its unit: "drag_torque_N_m"
  double declared = 0.0;  ///< its value in the rig as declared
  double fitted = 0.0;
  std::map<std::string, double> times_s;  ///< with the fitted value
  double rms_before = 0.0;                ///< RMS relative error of the times, as declared
  double rms_after = 0.0;
};

/// Every candidate, best (lowest rms_after) first. `measured` names TDBs of `rig`.
std::vector<SpinUpCandidate> ExplainSpinUpTimes(const ModelParams& rig,
                                                const std::map<std::string, double>& measured);

}  // namespace ambdrop
