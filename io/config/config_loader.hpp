#pragma once
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/config/config_can.hpp"
#include "io/config/config_keys.hpp"
#include "io/config/config_measurement.hpp"
#include "io/config/config_realtime.hpp"
#include "rt_core/model_params.hpp"
#include "rt_core/scenario_params.hpp"

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
  /// The [can] table (frame map and bus), if the config has one; its AMB and sensor names are
  /// the model's, indexed in params' order.
  std::optional<CanConfig> can;
  /// The [realtime] table (defaults when absent): scheduling of `ambdrop hil`'s loop thread.
  RealtimeConfig realtime;
  /// The [scenario] table of a scenario file (io/config/config_scenario.hpp), if there is one.
  std::optional<ScenarioParams> scenario;
  /// The [measurement] table (io/config/config_measurement.hpp), if there is one: how a measured
  /// record's columns map onto the model, for `ambdrop fit`. Its names are the model's, indexed
  /// in params' order.
  std::optional<MeasurementParams> measurement;
  /// Every number the readers took (or defaulted), with its `--set` path, unit, class and
  /// accepted range: the key registry (io/config/config_keys.hpp).
  std::vector<ConfigKey> keys;
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
