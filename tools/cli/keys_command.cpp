#include "tools/cli/keys_command.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <memory>

#include "io/config/config_loader.hpp"
#include "io/files/json_writer.hpp"
#include "tools/cli/cli_registry.hpp"
#include "tools/cli/command_config.hpp"
#include "tools/cli/exit_codes.hpp"

namespace ambdrop {

int RunKeysCommand(const KeysOptions& options) {
  const std::optional<LoadedConfig> loaded =
      LoadCommandConfig(options.config_path, options.overrides);
  if (!loaded) return kExitConfig;
  const LoadedConfig& config = *loaded;
  std::vector<const ConfigKey*> shown;
  for (const ConfigKey& k : config.keys) {
    if (options.key_class.empty() || options.key_class == KeyClassName(k.key_class)) {
      shown.push_back(&k);
    }
  }
  if (options.json) {
    JsonWriter json;
    json.BeginObject();
    json.Key("config").String(options.config_path);
    json.Key("keys").BeginArray();
    for (const ConfigKey* k : shown) {
      const FitRange range = DefaultFitRange(*k, config.keys);
      json.BeginObject();
      json.Key("path").String(k->path);
      json.Key("value").Number(k->value);
      json.Key("unit").String(k->unit);
      json.Key("class").String(KeyClassName(k->key_class));
      json.Key("declared").Bool(k->declared);
      json.Key("integer").Bool(k->integer);
      json.Key("location").String(k->location);
      json.Key("fit_range").BeginArray();
      json.Number(range.lower);
      json.Number(range.upper);
      json.EndArray();
      json.EndObject();
    }
    json.EndArray();
    json.EndObject();
    fmt::print("{}\n", json.str());
    return kExitOk;
  }
  fmt::print("{:<52} {:>14} {:<9} {:<11} {:<27} {}\n", "key (--set path)", "value", "unit", "class",
             "fit range", "declared at");
  for (const ConfigKey* k : shown) {
    const FitRange range = DefaultFitRange(*k, config.keys);
    // An integer key's range holds whole numbers only ("[0, 2] int").
    const std::string fit =
        k->key_class == KeyClass::kPhysical
            ? fmt::format("[{:.4g}, {:.4g}]{}", range.lower, range.upper, k->integer ? " int" : "")
            : std::string("-");
    fmt::print("{:<52} {:>14.6g} {:<9} {:<11} {:<27} {}\n", k->path, k->value,
               k->unit.empty() ? "-" : k->unit, KeyClassName(k->key_class), fit,
               k->declared ? k->location : std::string("(default)"));
  }
  return kExitOk;
}

RegisteredCommand AddKeysCommand(CLI::App& app) {
  auto options = std::make_shared<KeysOptions>();
  CLI::App* keys_command = app.add_subcommand(
      "keys", "Every number of a config: its --set path, value, unit, class and fit range");
  keys_command->add_option("CONFIG", options->config_path, "TOML config file")->required();
  AddSetOption(keys_command, &options->overrides);
  keys_command->add_option("--class", options->key_class, "Only keys of this class")
      ->type_name("CLASS")
      ->check(CLI::IsMember({"physical", "measurement", "solver", "run", "interface"}));
  keys_command->add_flag("--json", options->json, "JSON on stdout instead of the table");
  return {keys_command, [options] { return RunKeysCommand(*options); }};
}

}  // namespace ambdrop
