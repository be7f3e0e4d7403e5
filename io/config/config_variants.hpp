#pragma once
// One declared config read many times with different "dotted.key=value" overrides, through the
// same path as `--set`: what `ambdrop fit` does with each candidate effect, so that a fitted
// effect is exactly the `--set` lines the report prints and every value passes the config's
// own checks. The tree is parsed once; each variant copies it, applies its overrides and reads it.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "io/config/config_keys.hpp"
#include "io/config/config_loader.hpp"

namespace ambdrop {

class ConfigVariants {
 public:
  /// Loads `path` with the user's own overrides (the declared config). Throws ConfigError.
  static ConfigVariants Load(const std::filesystem::path& path,
                             const std::vector<std::string>& overrides = {});
  /// The same from text (tests); `source_name` stands in for the file name.
  static ConfigVariants FromString(const std::string& text, const std::string& source_name,
                                   const std::vector<std::string>& overrides = {});
  ConfigVariants(ConfigVariants&&) noexcept;
  ConfigVariants& operator=(ConfigVariants&&) noexcept;
  ~ConfigVariants();

  /// The declared config (no further overrides).
  const LoadedConfig& declared() const { return declared_; }
  /// The declared config with `overrides` applied after the user's own. Throws ConfigError
  /// (naming the override) when a value is refused.
  LoadedConfig With(const std::vector<std::string>& overrides) const;

 private:
  struct Tree;
  ConfigVariants(std::unique_ptr<Tree> tree, LoadedConfig declared);
  std::unique_ptr<Tree> tree_;
  LoadedConfig declared_;
};

/// A number as an override value: the shortest text that reads back to the same double, always
/// with a decimal point or exponent (TOML reads "1" as an integer). Finite values only.
std::string OverrideNumber(double value);

/// An integer as an override value, with no decimal point: what TableReader::Integer accepts
/// (ConfigKey::integer), which refuses "2.0".
std::string OverrideInteger(std::int64_t value);

/// "path=value" for a registry key: OverrideInteger of the nearest whole number for an integer
/// key, OverrideNumber otherwise. Finite values only.
std::string OverrideFor(const ConfigKey& key, double value);

}  // namespace ambdrop
