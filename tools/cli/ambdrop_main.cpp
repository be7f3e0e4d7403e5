// ambdrop command line: parse and dispatch; each command registers its flags and its work in
// its *_command file (cli_registry.hpp).
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "tools/cli/cli_registry.hpp"
#include "tools/cli/exit_codes.hpp"

#ifndef AMBDROP_VERSION
#define AMBDROP_VERSION "unknown"
#endif

int main(int argc, char** argv) {
  CLI::App app{"ambdrop: rotor-drop / active-magnetic-bearing emulator"};
  app.set_version_flag("--version", std::string("ambdrop ") + AMBDROP_VERSION);
  app.require_subcommand(1);
  // One registration per command, in the order `ambdrop --help` lists them.
  const std::vector<ambdrop::RegisteredCommand> commands = {
      ambdrop::AddSimCommand(app),      ambdrop::AddReplayCommand(app),
      ambdrop::AddValidateCommand(app), ambdrop::AddModesCommand(app),
      ambdrop::AddKeysCommand(app),     ambdrop::AddHilCommand(app),
      ambdrop::AddMeasureCommand(app),  ambdrop::AddFitCommand(app),
      ambdrop::AddCanExportCommand(app)};

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
    for (const ambdrop::RegisteredCommand& command : commands) {
      if (command.app->parsed()) return command.run();
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return ambdrop::kExitError;
  }
  // Unreachable while exactly one subcommand is required; kept as a safe default.
  fmt::print(stderr, "{}", app.help());
  return ambdrop::kExitUsage;
}
