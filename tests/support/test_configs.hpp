#pragma once
#include <string>
#include <vector>

#include "io/config/config_loader.hpp"
#include "io/config/config_variants.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop::testing {

/// Path of a file in the source tree's configs/ folder.
std::string ConfigPath(const std::string& file_name);

/// Loads configs/<file_name> with optional overrides.
ModelParams LoadTestConfig(const std::string& file_name,
                           const std::vector<std::string>& overrides = {});

/// The file names of every rig in configs/ (the scenarios are runs of these), sorted.
std::vector<std::string> RigConfigFiles();
/// The independent rigs' translated configs (tests/truth/*.toml), as paths ConfigPath takes.
std::vector<std::string> TruthRigConfigFiles();

/// The ConfigError a config text (named test.toml) with `overrides` raises, or "no error".
std::string ConfigErrorOf(const std::string& text, const std::vector<std::string>& overrides = {});

/// The same kept as a tree that effects' --set overrides are applied to (what `ambdrop fit` does).
ConfigVariants LoadTestVariants(const std::string& file_name,
                                const std::vector<std::string>& overrides = {});

}  // namespace ambdrop::testing
