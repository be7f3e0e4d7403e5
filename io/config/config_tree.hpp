#pragma once
// The two halves of LoadConfig, for code that reads one config many times with different
// overrides (io/config/config_variants.hpp): the parsed tree (base resolved, overrides applied) and
// the strict read of a tree into a LoadedConfig. Inside io only: it exposes toml++.
#include <toml++/toml.h>

#include <string>
#include <vector>

#include "io/config/config_loader.hpp"

namespace ambdrop::config_detail {

/// Parses `text`, resolves its `base` chain (relative to `source_name`'s directory) and applies
/// the "dotted.key=value" overrides, as LoadConfigFromString does. Throws ConfigError.
toml::table ConfigTree(const std::string& text, const std::string& source_name,
                       const std::vector<std::string>& overrides);

/// Reads a tree strictly into a LoadedConfig (`text` and `source_name` are kept as its source).
LoadedConfig ReadLoadedConfig(const toml::table& root, const std::string& text,
                              const std::string& source_name);

}  // namespace ambdrop::config_detail
