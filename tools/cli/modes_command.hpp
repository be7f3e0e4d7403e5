#pragma once
#include <optional>
#include <string>
#include <vector>

namespace ambdrop {

struct ModesOptions {
  std::string config_path;
  std::optional<double> speed_rpm;  ///< absent: the config's simulation.spin_speed_rad_s
  int count = 12;
  std::vector<std::string> overrides;
  std::string out_dir = "out";
};

/// `ambdrop modes`: natural frequencies of the config's rotor (free-free at rest, on its
/// linear bearings at speed, and the reduced model at speed), printed in rad/s and Hz and
/// written to options.out_dir/modes.json. Returns an ExitCode (exit_codes.hpp).
int RunModesCommand(const ModesOptions& options);

}  // namespace ambdrop
