#include "tools/cli/measure_command.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "io/config/config_loader.hpp"
#include "io/files/json_writer.hpp"
#include "io/files/measured_csv.hpp"
#include "tools/cli/cli_registry.hpp"
#include "tools/cli/command_config.hpp"
#include "tools/cli/exit_codes.hpp"
#include "tools/cli/progress_bar.hpp"
#include "tools/fit/measured_record_maker.hpp"

namespace ambdrop {
namespace {

constexpr std::string_view kGroupNames =
    "displacement, current, tdb_normal_force, tdb_speed, rotor_speed, controller_command, "
    "tdb_support_force";

/// "displacement,current" → the groups; nullopt (after saying why) for an unknown or no name.
std::optional<MeasureChannelGroups> ParseGroups(const std::string& list) {
  MeasureChannelGroups groups{false, false, false, false, false, false, false};
  bool any = false;
  std::size_t begin = 0;
  while (begin <= list.size()) {
    std::size_t end = list.find(',', begin);
    if (end == std::string::npos) end = list.size();
    std::string_view name(list.data() + begin, end - begin);
    while (!name.empty() && name.front() == ' ') name.remove_prefix(1);
    while (!name.empty() && name.back() == ' ') name.remove_suffix(1);
    begin = end + 1;
    if (name.empty()) continue;
    bool* flag = name == "displacement"         ? &groups.displacement
                 : name == "current"            ? &groups.current
                 : name == "tdb_normal_force"   ? &groups.tdb_normal_force
                 : name == "tdb_speed"          ? &groups.tdb_speed
                 : name == "rotor_speed"        ? &groups.rotor_speed
                 : name == "controller_command" ? &groups.controller_command
                 : name == "tdb_support_force"  ? &groups.tdb_support_force
                                                : nullptr;
    if (flag == nullptr) {
      fmt::print(stderr, "error: --channels: no group '{}'; the groups are {}\n", name,
                 kGroupNames);
      return std::nullopt;
    }
    *flag = true;
    any = true;
  }
  if (!any) {
    fmt::print(stderr, "error: --channels: name at least one of {}\n", kGroupNames);
    return std::nullopt;
  }
  return groups;
}

}  // namespace

int RunMeasureCommand(const MeasureCommandOptions& options) {
  MeasureOptions measure;
  if (const std::optional<MeasureChannelGroups> groups = ParseGroups(options.channels)) {
    measure.channels = *groups;
  } else {
    return kExitUsage;
  }
  measure.rate_Hz = options.rate_Hz;
  measure.current_noise_A = options.current_noise_A;
  measure.force_noise_N = options.force_noise_N;
  measure.speed_noise_rad_s = options.speed_noise_rad_s;
  measure.seed = options.seed;
  measure.from_s = options.from_s;

  const std::optional<LoadedConfig> config =
      LoadCommandConfig(options.config_path, options.overrides);
  if (!config) return kExitConfig;
  const ModelParams& truth = config->params;

  // Option values that cannot fit this rig are command-line errors, caught before the run.
  try {
    StepsPerSample(truth.simulation,
                   options.rate_Hz > 0.0 ? options.rate_Hz : truth.controller.rate_Hz);
  } catch (const std::invalid_argument& e) {
    const bool given = options.rate_Hz > 0.0;
    fmt::print(stderr, "error: {}{}\n", given ? "--rate-Hz: " : "controller.rate_Hz: ", e.what());
    return given ? kExitUsage : kExitConfig;
  }
  if (options.from_s > truth.simulation.duration_s) {
    fmt::print(stderr, "error: --from-s {} s: after the end of the run ({} s)\n", options.from_s,
               truth.simulation.duration_s);
    return kExitUsage;
  }

  ProgressBar progress(!options.quiet && ProgressBar::IsTerminal(2));
  measure.on_progress = [&progress](double fraction) { progress.Update(fraction); };
  SyntheticMeasurement made;
  try {
    made = MakeMeasuredRecord(truth, measure);
  } catch (const TruthRunDiverged& e) {
    progress.Finish();
    // The message may end with its own newline (state dumps do); print exactly one.
    std::string_view message = e.what();
    while (!message.empty() && message.back() == '\n') message.remove_suffix(1);
    fmt::print(stderr, "error: {}: {}\nno record written\n", options.config_path, message);
    return kExitRunFailed;
  } catch (const std::invalid_argument& e) {
    progress.Finish();
    fmt::print(stderr, "error: {}: {}\n", options.config_path, e.what());
    return kExitConfig;
  }
  progress.Finish();

  made.record.source = options.out_path;
  try {
    WriteMeasuredCsv(options.out_path, made.record);
    if (!options.measurement_toml_path.empty()) {
      const std::string text =
          fmt::format("# The [measurement] table of {}, made by `ambdrop measure {}`.\n",
                      options.out_path, options.config_path) +
          MeasurementTableToml(truth, made.measurement);
      WriteTextFile(options.measurement_toml_path, text);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }

  if (!options.quiet) {
    const MeasuredRecord& r = made.record;
    fmt::print("{}: {} rows x {} channels at {} Hz, t = {:.6g} .. {:.6g} s, from {}\n",
               options.out_path, r.time_s.size(), r.columns.size(), made.measurement.sample_rate_Hz,
               r.time_s.front(), r.time_s.back(), options.config_path);
    if (!options.measurement_toml_path.empty()) {
      fmt::print("{}: its [measurement] table\n", options.measurement_toml_path);
    }
  }
  std::fflush(stdout);
  return kExitOk;
}

RegisteredCommand AddMeasureCommand(CLI::App& app) {
  auto options = std::make_shared<MeasureCommandOptions>();
  CLI::App* measure_command = app.add_subcommand(
      "measure",
      "Make a measured-like record (CSV) from a truth rig: sensor readings, coil currents, TDB "
      "loads and speeds, with noise, for testing `fit`");
  measure_command->add_option("TRUTH_CONFIG", options->config_path, "TOML config of the truth rig")
      ->required();
  measure_command->add_option("--out", options->out_path, "The record to write")
      ->type_name("FILE.csv")
      ->required();
  AddSetOption(measure_command, &options->overrides);
  measure_command
      ->add_option("--rate-Hz", options->rate_Hz,
                   "Sample rate, a whole number of physics steps per sample (default: the "
                   "config's controller.rate_Hz)")
      ->type_name("R")
      ->check(kFinite & CLI::PositiveNumber);
  measure_command
      ->add_option("--channels", options->channels,
                   "Comma list of channel groups: displacement, current, tdb_normal_force, "
                   "tdb_speed, rotor_speed, controller_command, tdb_support_force")
      ->type_name("LIST")
      ->capture_default_str();
  measure_command
      ->add_option("--measurement-toml", options->measurement_toml_path,
                   "Also write the [measurement] table that maps the record's columns, for an "
                   "analysed config")
      ->type_name("FILE");
  measure_command
      ->add_option("--current-noise-A", options->current_noise_A,
                   "Standard deviation of the noise added to the currents (A)")
      ->type_name("S")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->capture_default_str();
  measure_command
      ->add_option("--force-noise-N", options->force_noise_N,
                   "Standard deviation of the noise added to the TDB normal forces (N)")
      ->type_name("S")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->capture_default_str();
  measure_command
      ->add_option("--speed-noise-rad-s", options->speed_noise_rad_s,
                   "Standard deviation of the noise added to the TDB and rotor speeds (rad/s)")
      ->type_name("S")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->capture_default_str();
  measure_command
      ->add_option("--seed", options->seed,
                   "Seed of the added noise (the sensors' noise keeps the config's seeds)")
      ->type_name("N")
      ->capture_default_str();
  measure_command
      ->add_option("--from-s", options->from_s,
                   "Leave out the rows before this run time (t stays run time)")
      ->type_name("T0")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->capture_default_str();
  measure_command->add_flag("--quiet,-q", options->quiet,
                            "No summary on stdout and no progress bar");
  return {measure_command, [options] { return RunMeasureCommand(*options); }};
}

}  // namespace ambdrop
