#include "io/config/config_loader.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <optional>
#include <sstream>

#include "io/config/config_base.hpp"
#include "io/config/config_file.hpp"
#include "io/config/config_measurement.hpp"
#include "io/config/config_overrides.hpp"
#include "io/config/config_readers.hpp"
#include "io/config/config_realtime.hpp"
#include "io/config/config_scenario.hpp"
#include "io/config/config_tree.hpp"
#include "io/config/toml_reader.hpp"

namespace ambdrop {
namespace {

using config_detail::TableReader;

toml::table Parse(const std::string& text, const std::string& source_name) {
  try {
    return toml::parse(text, std::string_view(source_name));
  } catch (const toml::parse_error& error) {
    throw ConfigError(fmt::format("{}:{}: {} (column {})", source_name, error.source().begin.line,
                                  error.description(), error.source().begin.column));
  }
}

ModelParams ReadModel(const TableReader& root) {
  root.AllowOnly({"name", "simulation", "gravity", "trigger", "rotor", "bearing", "amb", "sensor",
                  "tdb", "unbalance", "controller", "can", "realtime", "scenario", "measurement"});
  ModelParams params;
  params.name = root.String("name", "");
  params.simulation = config_detail::ReadSimulation(root);
  params.gravity = config_detail::ReadGravity(root);
  params.trigger = config_detail::ReadTrigger(root);
  params.rotor = config_detail::ReadRotor(root);
  const config_detail::AxialRange position = config_detail::ShaftRange(params.rotor);
  params.bearings = config_detail::ReadBearings(root, position);
  params.ambs = config_detail::ReadAmbs(root, position);
  // Before the sensors: they are sampled at its rate, or at every step without a controller
  // (as `ambdrop sim` drives a profile-driven rig).
  params.controller = config_detail::ReadController(root, params.simulation.step_s);
  const config_detail::SensorSampling sampling =
      params.controller.kind == ControllerKind::kNone
          ? config_detail::SensorSampling{params.simulation.step_s,
                                          "the step (simulation.step_s; [controller] kind = "
                                          "\"none\")"}
          : config_detail::SensorSampling{1.0 / params.controller.rate_Hz,
                                          "the controller period (1/controller.rate_Hz)"};
  params.sensors = config_detail::ReadSensors(root, position, sampling);
  if (params.simulation.settle_s > 0.0 && params.controller.kind != ControllerKind::kInternalPid) {
    root.OptionalTable("simulation")
        ->Fail("settle_s",
               "0 unless [controller] kind is \"internal_pid\" or \"internal_linear\": only the "
               "in-process controller's "
               "own loop can be settled before the run");
  }
  params.tdbs = config_detail::ReadTdbs(root, position);
  params.unbalances = config_detail::ReadUnbalances(root, position);
  return params;
}

}  // namespace

LoadedConfig LoadConfig(const std::filesystem::path& path,
                        const std::vector<std::string>& overrides) {
  std::string why;
  const std::optional<std::string> text = config_detail::ReadConfigFile(path, &why);
  if (!text)
    throw ConfigError(fmt::format("{}: not a readable config file: {}", path.string(), why));
  return LoadConfigFromString(*text, path.string(), overrides);
}

LoadedConfig LoadConfigFromString(const std::string& text, const std::string& source_name,
                                  const std::vector<std::string>& overrides) {
  return config_detail::ReadLoadedConfig(config_detail::ConfigTree(text, source_name, overrides),
                                         text, source_name);
}

namespace config_detail {

toml::table ConfigTree(const std::string& text, const std::string& source_name,
                       const std::vector<std::string>& overrides) {
  const std::filesystem::path directory = std::filesystem::path(source_name).parent_path();
  toml::table root = ResolveBase(Parse(text, source_name), directory, source_name);
  for (const std::string& override_text : overrides) ApplyOverride(root, override_text);
  return root;
}

LoadedConfig ReadLoadedConfig(const toml::table& root, const std::string& text,
                              const std::string& source_name) {
  LoadedConfig loaded;
  loaded.source_path = source_name;
  loaded.source_text = text;
  std::ostringstream effective;
  effective << root << '\n';
  loaded.effective_toml = effective.str();
  KeyLog keys;
  const TableReader root_reader(root, "", source_name, &keys);
  loaded.params = ReadModel(root_reader);
  loaded.realtime = ReadRealtimeConfig(root_reader);
  if (const std::optional<TableReader> scenario = root_reader.OptionalTable("scenario")) {
    loaded.scenario = ReadScenario(*scenario, loaded.params);
  }
  if (const std::optional<TableReader> measurement = root_reader.OptionalTable("measurement")) {
    loaded.measurement = ReadMeasurement(*measurement, loaded.params);
  }
  if (const std::optional<TableReader> can = root_reader.OptionalTable("can")) {
    const CanNames names = CanNamesOf(loaded.params);
    loaded.can = ReadCanConfig(*can, &names);
  }
  loaded.keys = keys.Take();
  return loaded;
}

}  // namespace config_detail

}  // namespace ambdrop
