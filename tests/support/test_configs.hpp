#pragma once
#include <string>
#include <vector>

#include "io/config_loader.hpp"
#include "io/config_variants.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop::testing {

/// Path of a file in the source tree's configs/ folder.
std::string ConfigPath(const std::string& file_name);

/// Loads configs/<file_name> with optional overrides.
ModelParams LoadTestConfig(const std::string& file_name,
                           const std::vector<std::string>& overrides = {});

/// The same kept as a tree that effects' --set overrides are applied to (what `ambdrop fit` does).
ConfigVariants LoadTestVariants(const std::string& file_name,
                                const std::vector<std::string>& overrides = {});

}  // namespace ambdrop::testing
