#pragma once
// Writes a rig config whose AMBs follow current profiles instead of a controller: the config a
// recording ran with, with [controller] kind = "none", each AMB's current_profile, the recorded
// power failure as [trigger] and the recorded duration. `ambdrop sim` runs it as it stands;
// a scenario uses it as its `base`.
#include <string>
#include <vector>

#include "rt_core/amb_params.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop {

struct ProfileConfig {
  std::string name;                              ///< the new rig's name
  std::vector<std::vector<CurrentSample>> ambs;  ///< per AMB, in the config's AMB order
  std::vector<std::string> amb_names;            ///< same order
  TriggerParams trigger;                         ///< enabled = false: no power event
  double duration_s = 0.0;
  std::vector<std::string> header_comments;  ///< written first, one "# " line each
};

/// The TOML text: `effective_toml` (a loaded config's effective text, bases resolved) with the
/// changes above; [scenario] is dropped (its power events are in [trigger]). Throws ConfigError
/// if an AMB named is missing or is not current-driven (law = "equivalent" takes no currents).
std::string ProfileConfigToml(const std::string& effective_toml, const ProfileConfig& profile);

}  // namespace ambdrop
