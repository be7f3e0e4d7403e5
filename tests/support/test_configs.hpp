#pragma once
#include <string>
#include <vector>

#include "io/config_loader.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop::testing {

/// Path of a file in the source tree's configs/ folder.
std::string ConfigPath(const std::string& file_name);

/// Loads configs/<file_name> with optional overrides.
ModelParams LoadTestConfig(const std::string& file_name,
                           const std::vector<std::string>& overrides = {});

}  // namespace ambdrop::testing
