#pragma once
// One registration per command: each *_command.cpp adds its subcommand with its flags and says
// what runs it (ambdrop_main.cpp only parses and dispatches). The flag helpers every command
// shares are here.
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace ambdrop {

/// A subcommand of `ambdrop` and what runs it once the command line named it.
struct RegisteredCommand {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

/// Repeatable `--set key=value`, one value per occurrence (otherwise CLI11 would let a vector
/// option swallow the following positional: `--set a=1 CONFIG`).
CLI::Option* AddSetOption(CLI::App* command, std::vector<std::string>* overrides);

/// CLI11 reads "nan" and "inf" into a double, and its Range and PositiveNumber let NaN through
/// (every comparison with it is false): each number flag is checked finite first.
extern const CLI::Validator kFinite;

RegisteredCommand AddSimCommand(CLI::App& app);
RegisteredCommand AddReplayCommand(CLI::App& app);
RegisteredCommand AddValidateCommand(CLI::App& app);
RegisteredCommand AddModesCommand(CLI::App& app);
RegisteredCommand AddKeysCommand(CLI::App& app);
RegisteredCommand AddHilCommand(CLI::App& app);
RegisteredCommand AddMeasureCommand(CLI::App& app);
RegisteredCommand AddFitCommand(CLI::App& app);
RegisteredCommand AddCanExportCommand(CLI::App& app);

}  // namespace ambdrop
