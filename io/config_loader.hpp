#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "rt_core/model_params.hpp"

namespace ambdrop {

/// A config that cannot be used. what() names the file, line, key, the value found and what
/// was expected, e.g.
///   configs/x.toml:12: key 'tdb.de.clearance_m': expected a positive number (m), found -0.001
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LoadedConfig {
  ModelParams params;
  std::string source_path;
  std::string source_text;     ///< the file as read
  std::string effective_toml;  ///< after --set overrides, re-serialised
};

/// Loads and validates a TOML config strictly. `overrides` are "dotted.key=value" strings
/// (value in TOML syntax; a bare word is taken as a string), applied before validation.
LoadedConfig LoadConfig(const std::filesystem::path& path,
                        const std::vector<std::string>& overrides = {});

/// Same, from text (tests); `source_name` stands in for the file name in messages.
LoadedConfig LoadConfigFromString(const std::string& text, const std::string& source_name,
                                  const std::vector<std::string>& overrides = {});

}  // namespace ambdrop
