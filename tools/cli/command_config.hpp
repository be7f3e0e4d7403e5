#pragma once
// The start every config-reading command shares: the config with its --set overrides, then the
// model. Errors are said once, the same way for every command (file, line and key from the
// loader), and the command exits kExitConfig.
#include <optional>
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "rt_core/model.hpp"

namespace ambdrop {

/// The config at `path` with `overrides` applied; nullopt after saying on stderr why not.
std::optional<LoadedConfig> LoadCommandConfig(const std::string& path,
                                              const std::vector<std::string>& overrides);

/// The model of `params` with its controller period checked to be whole steps (a config error
/// then, not an exception mid-run); nullopt after saying on stderr why not.
std::optional<Model> BuildCommandModel(const std::string& path, const ModelParams& params);

}  // namespace ambdrop
