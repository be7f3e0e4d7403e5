#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "tools/record/profile_export.hpp"

namespace ambdrop {

struct ReplayOptions {
  std::string record_path;             ///< FILE.lcm written by `sim --record` or `hil --record`
  std::string config_path;             ///< "": the config stored in the record
  std::vector<std::string> overrides;  ///< applied to whichever config is used
  std::string out_dir = "out";
  bool quiet = false;
  /// Not "": write the record's currents as a profile-driven rig config there instead of
  /// replaying (tools/record/profile_export.hpp).
  std::string export_profile_path;
  ProfileWindow profile;  ///< the part exported, and the points per AMB
  /// `--strict`: exit 4 unless every recorded sensor sample is reproduced within the tolerance.
  bool strict = false;
  /// `--tolerance-m`: by value (-0 equals 0); < 0: the default, 0 for an ambdrop record and half
  /// the frame map's coarsest sensor count for a candump log.
  double tolerance_m = -1.0;
  /// `--align time|sequence`: how a candump log's frames are placed at steps.
  std::string align = "time";
};

/// `ambdrop replay`: re-runs a recorded run offline from its recorded inputs at their recorded
/// steps and compares the sensor samples with those sent live. Writes timeseries.csv,
/// summary.json (with a "replay" object: identical or the first difference) and
/// effective_config.toml. With the recorded config the outputs must be bit-identical: a
/// difference then exits with kExitRunFailed. With another config (--config, --set) the
/// differences are the answer, reported, and the exit is 0.
int RunReplayCommand(const ReplayOptions& options);

}  // namespace ambdrop
