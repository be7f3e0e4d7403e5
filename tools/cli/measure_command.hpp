#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace ambdrop {

struct MeasureCommandOptions {
  std::string config_path;             ///< the truth rig
  std::string out_path;                ///< the record (CSV)
  std::vector<std::string> overrides;  ///< "dotted.key=value", applied in order
  double rate_Hz = 0.0;                ///< 0: the truth config's controller.rate_Hz
  /// Comma list of channel groups: displacement, current, tdb_normal_force, tdb_speed,
  /// rotor_speed.
  std::string channels = "displacement,current,tdb_normal_force,tdb_speed,rotor_speed";
  std::string measurement_toml_path;  ///< "": none; else the [measurement] table written there
  double current_noise_A = 0.0;
  double force_noise_N = 0.0;
  double speed_noise_rad_s = 0.0;
  std::uint64_t seed = 1;
  double from_s = 0.0;
  bool quiet = false;  ///< no summary on stdout, no progress bar
};

/// `ambdrop measure`: runs a truth rig offline and writes what a logger on the rig would have
/// recorded (tools/fit/measured_record_maker.hpp) as a measured-record CSV, and optionally the
/// [measurement] table an analysed config needs to read it. Returns an ExitCode: 2 for a config
/// error, 3 if the truth run diverged (no record is written), 64 for a bad option value.
int RunMeasureCommand(const MeasureCommandOptions& options);

}  // namespace ambdrop
