// ambdrop command line: argument wiring only; the work is in the *_command files.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <string>

#include "tools/exit_codes.hpp"
#include "tools/modes_command.hpp"
#include "tools/sim_command.hpp"

#ifndef AMBDROP_VERSION
#define AMBDROP_VERSION "unknown"
#endif

namespace {

// Repeatable `--set key=value`. One value per occurrence: otherwise CLI11 would let a vector
// option swallow the following positional (`--set a=1 CONFIG`).
CLI::Option* AddSetOption(CLI::App* command, std::vector<std::string>* overrides) {
  return command
      ->add_option("--set", *overrides,
                   "Override a config value, e.g. --set simulation.duration_s=0.3 (TOML value "
                   "syntax; repeatable, applied in order)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ambdrop: rotor-drop / active-magnetic-bearing emulator"};
  app.set_version_flag("--version", std::string("ambdrop ") + AMBDROP_VERSION);
  app.require_subcommand(1);

  ambdrop::SimOptions sim;
  CLI::App* sim_command = app.add_subcommand(
      "sim", "Simulate a rotor drop offline; write timeseries.csv and summary.json");
  sim_command->add_option("CONFIG", sim.config_path, "TOML config file")->required();
  sim_command->add_option("--out", sim.out_dir, "Output directory")
      ->type_name("DIR")
      ->capture_default_str();
  AddSetOption(sim_command, &sim.overrides);
  sim_command->add_flag("--quiet,-q", sim.quiet, "No summary on stdout and no progress bar");

  ambdrop::ModesOptions modes;
  double speed_rpm = 0.0;
  CLI::App* modes_command = app.add_subcommand(
      "modes", "Natural frequencies: free-free, supported at speed, reduced model at speed");
  modes_command->add_option("CONFIG", modes.config_path, "TOML config file")->required();
  CLI::Option* speed_option =
      modes_command
          ->add_option("--speed-rpm", speed_rpm,
                       "Spin speed in rpm (default: the config's simulation.spin_speed_rad_s)")
          ->type_name("R");
  modes_command->add_option("--count", modes.count, "Frequencies per list at most")
      ->type_name("N")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  AddSetOption(modes_command, &modes.overrides);
  modes_command->add_option("--out", modes.out_dir, "Output directory")
      ->type_name("DIR")
      ->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version arrive as "errors" with exit code 0.
    if (e.get_exit_code() == 0) return app.exit(e);
    // CLI11 reports `ambdrop frobnicate` as a missing subcommand; name the word it rejected.
    if (app.get_subcommands().empty() && argc > 1 && argv[1][0] != '-') {
      fmt::print(stderr, "error: unknown subcommand '{}'\n\n{}", argv[1], app.help());
      return ambdrop::kExitUsage;
    }
    // A usage error: say what was wrong and show the help of the command that was meant
    // (App::help() answers for the selected subcommand, if any).
    fmt::print(stderr, "error: {}\n\n{}", e.what(), app.help());
    return ambdrop::kExitUsage;
  }

  try {
    if (sim_command->parsed()) return ambdrop::RunSimCommand(sim);
    if (modes_command->parsed()) {
      if (speed_option->count() > 0) modes.speed_rpm = speed_rpm;
      return ambdrop::RunModesCommand(modes);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return ambdrop::kExitError;
  }
  // Unreachable while exactly one subcommand is required; kept as a safe default.
  fmt::print(stderr, "{}", app.help());
  return ambdrop::kExitUsage;
}
