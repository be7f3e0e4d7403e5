#include "tools/cli/modes_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "io/config/config_loader.hpp"
#include "io/files/json_writer.hpp"
#include "rt_core/modal_analysis.hpp"
#include "tools/cli/cli_registry.hpp"
#include "tools/cli/command_config.hpp"
#include "tools/cli/exit_codes.hpp"

namespace ambdrop {
namespace {

namespace fs = std::filesystem;

constexpr double kRadPerSecondPerRpm = 2.0 * std::numbers::pi / 60.0;

std::vector<double> ToHz(const std::vector<double>& rad_s) {
  std::vector<double> hz;
  hz.reserve(rad_s.size());
  for (double value : rad_s) hz.push_back(value / (2.0 * std::numbers::pi));
  return hz;
}

void WriteList(JsonWriter* json, const char* key, const std::vector<double>& rad_s) {
  json->Key(key).BeginObject();
  json->Key("rad_s").NumberArray(rad_s);
  json->Key("Hz").NumberArray(ToHz(rad_s));
  json->EndObject();
}

std::string Cell(const std::vector<double>& values, std::size_t i, double scale) {
  return i < values.size() ? fmt::format("{:.6g}", values[i] * scale) : std::string();
}

// The three lists side by side: same mode index on one line makes the effect of the supports
// and of the reduction visible at a glance.
void PrintTable(const ModalAnalysis& modes) {
  const double to_hz = 1.0 / (2.0 * std::numbers::pi);
  fmt::print("{:>3}  {:>25}  {:>25}  {:>25}\n", "", "free-free (at rest)", "supported (at speed)",
             "reduced model (at speed)");
  fmt::print("{:>3}  {:>12} {:>12}  {:>12} {:>12}  {:>12} {:>12}\n", "#", "rad/s", "Hz", "rad/s",
             "Hz", "rad/s", "Hz");
  const std::size_t rows = std::max({modes.free_free_rad_s.size(), modes.supported_rad_s.size(),
                                     modes.reduced_supported_rad_s.size()});
  for (std::size_t i = 0; i < rows; ++i) {
    fmt::print("{:>3}  {:>12} {:>12}  {:>12} {:>12}  {:>12} {:>12}\n", i + 1,
               Cell(modes.free_free_rad_s, i, 1.0), Cell(modes.free_free_rad_s, i, to_hz),
               Cell(modes.supported_rad_s, i, 1.0), Cell(modes.supported_rad_s, i, to_hz),
               Cell(modes.reduced_supported_rad_s, i, 1.0),
               Cell(modes.reduced_supported_rad_s, i, to_hz));
  }
}

}  // namespace

int RunModesCommand(const ModesOptions& options) {
  const std::optional<LoadedConfig> config =
      LoadCommandConfig(options.config_path, options.overrides);
  if (!config) return kExitConfig;
  const ModelParams& params = config->params;

  // Without --speed-rpm the natural choice is the speed the config runs at before the drop.
  const double speed_rad_s = options.speed_rpm ? *options.speed_rpm * kRadPerSecondPerRpm
                                               : params.simulation.spin_speed_rad_s;
  // Echo a given rpm as typed rather than as the round trip through rad/s.
  const double speed_rpm = options.speed_rpm.value_or(speed_rad_s / kRadPerSecondPerRpm);

  ModalAnalysis modes;
  try {
    modes = AnalyseModes(params, speed_rad_s, options.count);
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "error: {}: cannot analyse the modes: {}\n", options.config_path, e.what());
    return kExitConfig;
  }

  JsonWriter json;
  json.BeginObject();
  json.Key("config").String(options.config_path);
  json.Key("name").String(params.name);
  json.Key("speed_rpm").Number(speed_rpm);
  json.Key("speed_rad_s").Number(speed_rad_s);
  json.Key("count").Integer(options.count);
  WriteList(&json, "free_free", modes.free_free_rad_s);
  WriteList(&json, "supported", modes.supported_rad_s);
  WriteList(&json, "reduced_supported", modes.reduced_supported_rad_s);
  json.EndObject();

  const fs::path out_dir(options.out_dir);
  const fs::path json_path = out_dir / "modes.json";
  try {
    fs::create_directories(out_dir);
    WriteTextFile(json_path, json.str());
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }

  fmt::print("{}: natural frequencies at {:.6g} rpm ({:.6g} rad/s)\n",
             params.name.empty() ? options.config_path : params.name, speed_rpm, speed_rad_s);
  PrintTable(modes);
  fmt::print("wrote {}\n", json_path.string());
  return kExitOk;
}

RegisteredCommand AddModesCommand(CLI::App& app) {
  auto options = std::make_shared<ModesOptions>();
  auto speed_rpm = std::make_shared<double>(0.0);
  CLI::App* modes_command = app.add_subcommand(
      "modes", "Natural frequencies: free-free, supported at speed, reduced model at speed");
  modes_command->add_option("CONFIG", options->config_path, "TOML config file")->required();
  CLI::Option* speed_option =
      modes_command
          ->add_option("--speed-rpm", *speed_rpm,
                       "Spin speed in rpm (default: the config's simulation.spin_speed_rad_s)")
          ->type_name("R")
          ->check(kFinite & CLI::Range(-1e7, 1e7));
  modes_command->add_option("--count", options->count, "Frequencies per list at most")
      ->type_name("N")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  AddSetOption(modes_command, &options->overrides);
  modes_command->add_option("--out", options->out_dir, "Output directory")
      ->type_name("DIR")
      ->capture_default_str();
  return {modes_command, [options, speed_rpm, speed_option] {
            if (speed_option->count() > 0) options->speed_rpm = *speed_rpm;
            return RunModesCommand(*options);
          }};
}

}  // namespace ambdrop
