#include "tools/cli/can_export_command.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>

#include "io/config/config_loader.hpp"
#include "io/files/json_writer.hpp"
#include "tools/cli/can_kit_files.hpp"
#include "tools/cli/cli_registry.hpp"
#include "tools/cli/command_config.hpp"
#include "tools/cli/exit_codes.hpp"

namespace ambdrop {

int RunCanExportCommand(const CanExportOptions& options) {
  const std::optional<LoadedConfig> loaded =
      LoadCommandConfig(options.config_path, options.overrides);
  if (!loaded) return kExitConfig;
  if (!loaded->can) {
    fmt::print(stderr,
               "error: {}: no [can] table: the frame map is what can-export writes out (see "
               "configs/jarroux2019_industrial_pid_can.toml)\n",
               options.config_path);
    return kExitConfig;
  }
  const CanConfig& can = *loaded->can;
  const std::string source = std::filesystem::path(options.config_path).filename().string();
  try {
    if (!options.header_path.empty()) {
      WriteTextFile(options.header_path,
                    CanFramesHeader(can.frame_map, can.exchange_rate_Hz, source));
    }
    if (!options.dbc_path.empty()) {
      WriteTextFile(options.dbc_path, CanFramesDbc(can.frame_map, source));
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }
  return kExitOk;
}

RegisteredCommand AddCanExportCommand(CLI::App& app) {
  auto options = std::make_shared<CanExportOptions>();
  CLI::App* command = app.add_subcommand(
      "can-export",
      "The config's [can] frame map as a C header for firmware and a DBC file for CAN tools");
  command->add_option("CONFIG", options->config_path, "TOML config file with a [can] table")
      ->required();
  AddSetOption(command, &options->overrides);
  command->add_option("--header", options->header_path, "Write the C header here")
      ->type_name("FILE");
  command->add_option("--dbc", options->dbc_path, "Write the DBC file here")->type_name("FILE");
  command->callback([options] {
    if (options->header_path.empty() && options->dbc_path.empty()) {
      throw CLI::RequiredError("--header or --dbc");
    }
  });
  return {command, [options] { return RunCanExportCommand(*options); }};
}

}  // namespace ambdrop
