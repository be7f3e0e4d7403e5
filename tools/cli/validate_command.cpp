#include "tools/cli/validate_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <memory>

#include "io/files/json_writer.hpp"
#include "tools/cli/cli_registry.hpp"
#include "tools/cli/exit_codes.hpp"
#include "tools/validation/validation_cases.hpp"

namespace ambdrop {

int RunValidateCommand(const ValidateOptions& options) {
  // Every case reads its rig from there: without it each would fail alone, and -q say nothing.
  std::error_code ec;
  if (!std::filesystem::is_directory(options.configs_dir, ec)) {
    fmt::print(stderr, "error: --configs {}: not a folder of seed rig configs\n",
               options.configs_dir);
    return kExitConfig;
  }
  std::vector<ValidationCase> cases = AllValidationCases();
  if (!options.cases.empty()) {
    for (const std::string& name : options.cases) {
      const bool known = std::any_of(cases.begin(), cases.end(),
                                     [&](const ValidationCase& c) { return c.name == name; });
      if (!known) {
        std::string names;
        for (const ValidationCase& c : cases) names += " " + c.name;
        fmt::print(stderr, "error: --case {}: no such case; the cases are:{}\n", name, names);
        return kExitUsage;
      }
    }
    std::erase_if(cases, [&](const ValidationCase& c) {
      return std::find(options.cases.begin(), options.cases.end(), c.name) == options.cases.end();
    });
  }

  std::vector<ValidationCheck> checks;
  for (const ValidationCase& c : cases) {
    const auto start = std::chrono::steady_clock::now();
    try {
      std::vector<ValidationCheck> got = c.run(options.configs_dir);
      checks.insert(checks.end(), got.begin(), got.end());
    } catch (const std::exception& e) {
      checks.push_back(TrendCheck(c.name, "the case runs", "yes", e.what(), false));
    }
    if (!options.quiet) {
      fmt::print(stderr, "{}: {:.1f} s\n", c.name,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
  }

  int failed = 0, known = 0;
  for (const ValidationCheck& c : checks) {
    if (c.pass) continue;
    if (c.known_failure.empty()) {
      ++failed;
    } else {
      ++known;
    }
  }
  if (!options.quiet) {
    fmt::print("{:<36} {:<44} {:>20} {:>20} {:>10}  {}\n", "case", "quantity", "published",
               "ambdrop", "deviation", "result");
    for (const ValidationCheck& c : checks) {
      const std::string deviation =
          std::isfinite(c.deviation) ? fmt::format("{:+.1f} %", c.deviation * 100.0) : "-";
      const char* result = c.pass ? "pass" : c.known_failure.empty() ? "FAIL" : "FAIL (known)";
      fmt::print("{:<36} {:<44} {:>20} {:>20} {:>10}  {} ({})\n", c.case_name, c.quantity,
                 c.published, c.ambdrop, deviation, result, c.criterion);
    }
    for (const ValidationCheck& c : checks) {
      if (!c.pass && !c.known_failure.empty()) {
        fmt::print("known failure: {}: {}: {}\n", c.case_name, c.quantity, c.known_failure);
      }
    }
    fmt::print("{} checks: {} pass, {} fail, {} known failures\n", checks.size(),
               checks.size() - static_cast<std::size_t>(failed + known), failed, known);
  }

  JsonWriter json;
  json.BeginArray();
  for (const ValidationCheck& c : checks) {
    json.BeginObject();
    json.Key("case").String(c.case_name);
    json.Key("quantity").String(c.quantity);
    json.Key("published").String(c.published);
    json.Key("ambdrop").String(c.ambdrop);
    json.Key("deviation");
    if (std::isfinite(c.deviation)) {
      json.Number(c.deviation);
    } else {
      json.Null();
    }
    json.Key("criterion").String(c.criterion);
    json.Key("pass").Bool(c.pass);
    if (!c.known_failure.empty()) json.Key("known_failure").String(c.known_failure);
    json.EndObject();
  }
  json.EndArray();
  try {
    std::filesystem::create_directories(options.out_dir);
    WriteTextFile(std::filesystem::path(options.out_dir) / "validate.json", json.str());
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }
  // -q prints no table; the exit code alone would not say why.
  if (failed > 0 || (known > 0 && !options.allow_known_failures)) {
    for (const ValidationCheck& c : checks) {
      if (c.pass || (!c.known_failure.empty() && options.allow_known_failures)) continue;
      fmt::print(stderr, "error: {}: {}: expected {}, got {} ({}){}\n", c.case_name, c.quantity,
                 c.published, c.ambdrop, c.criterion,
                 c.known_failure.empty() ? "" : " (known failure)");
    }
    return kExitError;
  }
  return kExitOk;
}

RegisteredCommand AddValidateCommand(CLI::App& app) {
  auto options = std::make_shared<ValidateOptions>();
  CLI::App* validate_command = app.add_subcommand(
      "validate", "Run every seed paper's case and compare with its published numbers");
  validate_command->add_option("--out", options->out_dir, "Output directory (options->json)")
      ->type_name("DIR")
      ->capture_default_str();
  validate_command->add_option("--configs", options->configs_dir, "The seed rigs' config folder")
      ->type_name("DIR")
      ->capture_default_str();
  validate_command->add_option("--case", options->cases, "Run only this case (repeatable)")
      ->type_name("NAME");
  validate_command->add_flag("--allow-known-failures", options->allow_known_failures,
                             "Checks marked as known failures (open issues) do not fail the exit "
                             "code; they are still reported");
  validate_command->add_flag("--quiet,-q", options->quiet, "No table on stdout");
  return {validate_command, [options] { return RunValidateCommand(*options); }};
}

}  // namespace ambdrop
