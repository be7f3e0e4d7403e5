#pragma once
#include <string>
#include <vector>

namespace ambdrop {

struct KeysOptions {
  std::string config_path;
  std::vector<std::string> overrides;
  std::string key_class;  ///< empty: every class; else "physical", "measurement", ...
  bool json = false;
};

/// `ambdrop keys`: the config's key registry (io/config/config_keys.hpp): every number the config
/// declares or the readers default, with its `--set` path, value, unit, class, where it was
/// declared and the range a fit would search. Returns an ExitCode (exit_codes.hpp).
int RunKeysCommand(const KeysOptions& options);

}  // namespace ambdrop
