#include "tools/cli/fit_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "io/config/config_loader.hpp"
#include "io/config/config_variants.hpp"
#include "io/files/event_log.hpp"
#include "io/files/json_writer.hpp"
#include "io/files/measured_csv.hpp"
#include "io/files/measured_record_si.hpp"
#include "tools/cli/cli_registry.hpp"
#include "tools/cli/exit_codes.hpp"
#include "tools/fit/fit_record.hpp"
#include "tools/fit/fit_report.hpp"
#include "tools/fit/model_discrepancy.hpp"
#include "tools/fit/run_record_measurement.hpp"
#include "tools/fit/spinup_fit.hpp"
#include "tools/record/run_record_reader.hpp"

namespace ambdrop {
namespace {

namespace fs = std::filesystem;

// Far beyond any rig, yet far inside a double: a value past it is a broken logger or file, and
// would otherwise swamp its channel's noise estimate and drop the channel without a word.
struct PhysicalBound {
  double bound;
  const char* unit;
};
PhysicalBound BoundOf(MeasuredQuantity q) {
  switch (q) {
    case MeasuredQuantity::kDisplacement:
      return {1.0, "m"};
    case MeasuredQuantity::kCurrent:
    case MeasuredQuantity::kControllerCommand:
      return {1e4, "A"};
    case MeasuredQuantity::kTdbNormalForce:
    case MeasuredQuantity::kTdbSupportForce:
      return {1e9, "N"};
    case MeasuredQuantity::kTdbSpeed:
    case MeasuredQuantity::kRotorSpeed:
      return {1e7, "rad/s"};
  }
  return {0.0, ""};
}

// Every channel's column is in the record, its values are physical, and the record is sampled
// as declared.
void CheckRecord(const MeasurementParams& m, const MeasuredRecord& r, const std::string& config) {
  std::string missing;
  for (const MeasurementChannel& ch : m.channels) {
    if (r.Column(ch.column) < 0) missing += " '" + ch.column + "'";
  }
  if (!missing.empty()) {
    std::string have;
    for (const std::string& c : r.columns) have += " '" + c + "'";
    throw MeasuredRecordError(
        fmt::format("{}: the columns{} of {}'s [measurement] are not in the record; it has:{}",
                    r.source, missing, config, have));
  }
  for (const MeasurementChannel& ch : m.channels) {
    const PhysicalBound b = BoundOf(ch.quantity);
    const std::vector<double>& v = r.values[r.Column(ch.column)];
    for (std::size_t row = 0; row < v.size(); ++row) {
      if (!(std::abs(v[row]) <= b.bound)) {
        throw MeasuredRecordError(fmt::format(
            "{}: column '{}' ({}) at t = {:.9g} s (data row {}): expected |value| <= {:g} {}, "
            "found {:g}",
            r.source, ch.column, MeasuredQuantityName(ch.quantity), r.time_s[row], row + 1, b.bound,
            b.unit, v[row]));
      }
    }
  }
  const double rate = 1.0 / r.SampleInterval();
  if (std::abs(rate / m.sample_rate_Hz - 1.0) > 0.01) {
    throw MeasuredRecordError(
        fmt::format("{}: sampled at {:.6g} Hz, but {}'s measurement.sample_rate_Hz is {:.6g} Hz",
                    r.source, rate, config, m.sample_rate_Hz));
  }
}

// An LCM event log (an ambdrop run record) starts with the log's sync word, big-endian; a CSV
// record starts with text.
bool IsEventLog(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<unsigned char, 4> head{};
  if (!in.read(reinterpret_cast<char*>(head.data()), head.size())) return false;
  const std::uint32_t word = (std::uint32_t{head[0]} << 24) | (std::uint32_t{head[1]} << 16) |
                             (std::uint32_t{head[2]} << 8) | std::uint32_t{head[3]};
  return word == kEventLogSync;
}

// The index of the sensor, AMB or TDB named `name` in `list`; a ConfigError if it has none.
template <typename Params>
int IndexByName(const std::vector<Params>& list, const std::string& name, const char* what,
                const std::string& config) {
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (list[i].name == name) return static_cast<int>(i);
  }
  throw ConfigError(
      fmt::format("the record has a {} '{}' that {} does not declare", what, name, config));
}

// A run record's own measurement is in its recorded rig's order: the declared config's order
// may differ, so its channels are found again by name.
MeasurementParams InDeclaredOrder(MeasurementParams m, const ModelParams& recorded,
                                  const ModelParams& declared, const std::string& config) {
  for (MeasurementChannel& c : m.channels) {
    switch (c.quantity) {
      case MeasuredQuantity::kDisplacement:
        c.index =
            IndexByName(declared.sensors, recorded.sensors.at(c.index).name, "sensor", config);
        break;
      case MeasuredQuantity::kCurrent:
      case MeasuredQuantity::kControllerCommand:
        c.index = IndexByName(declared.ambs, recorded.ambs.at(c.index).name, "AMB", config);
        break;
      case MeasuredQuantity::kTdbNormalForce:
      case MeasuredQuantity::kTdbSupportForce:
      case MeasuredQuantity::kTdbSpeed:
        c.index = IndexByName(declared.tdbs, recorded.tdbs.at(c.index).name, "TDB", config);
        break;
      case MeasuredQuantity::kRotorSpeed:
        break;
    }
  }
  return m;
}

}  // namespace

int RunSpinUpFit(const FitOptions& options) {
  LoadedConfig config;
  std::map<std::string, double> measured;
  try {
    config = LoadConfig(options.config_path, options.overrides);
    std::stringstream list(options.spin_up_times);
    std::string item;
    while (std::getline(list, item, ',')) {
      const std::size_t eq = item.find('=');
      const std::string name = item.substr(0, eq);
      const bool known = std::any_of(config.params.tdbs.begin(), config.params.tdbs.end(),
                                     [&](const TdbParams& t) { return t.name == name; });
      double value = 0.0;
      if (eq == std::string::npos || !known ||
          std::from_chars(item.data() + eq + 1, item.data() + item.size(), value).ec !=
              std::errc{} ||
          !(value > 0.0)) {
        throw ConfigError(fmt::format(
            "--spin-up-times: '{}': expected TDB=SECONDS with a TDB of {} and a positive time",
            item, options.config_path));
      }
      measured[name] = value;
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitConfig;
  }
  const std::vector<SpinUpCandidate> candidates = ExplainSpinUpTimes(config.params, measured);
  JsonWriter json;
  json.BeginObject();
  json.Key("measured_s").BeginObject(true);
  for (const auto& [name, t] : measured) json.Key(name).Number(t);
  json.EndObject();
  json.Key("candidates").BeginArray();
  for (const SpinUpCandidate& c : candidates) {
    json.BeginObject();
    json.Key("change").String(c.name);
    json.Key("parameter").String(c.parameter);
    json.Key("declared").Number(c.declared);
    json.Key("fitted").Number(c.fitted);
    json.Key("times_s").BeginObject(true);
    for (const auto& [name, t] : c.times_s) json.Key(name).Number(t);
    json.EndObject();
    json.Key("rms_relative_error_before").Number(c.rms_before);
    json.Key("rms_relative_error_after").Number(c.rms_after);
    json.EndObject();
  }
  json.EndArray();
  json.EndObject();
  try {
    fs::create_directories(options.out_dir);
    WriteTextFile(fs::path(options.out_dir) / "spinup_fit.json", json.str());
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }
  if (!options.quiet) {
    fmt::print("{:<30} {:>10} {:>10}", "single change", "declared", "fitted");
    for (const auto& [name, t] : measured) fmt::print(" {:>8}", name + " (s)");
    fmt::print("  RMS relative error\n");
    for (const SpinUpCandidate& c : candidates) {
      fmt::print("{:<30} {:>10.4g} {:>10.4g}", c.name, c.declared, c.fitted);
      for (const auto& [name, t] : measured) fmt::print(" {:>8.4f}", c.times_s.at(name));
      fmt::print("  {:.1f} % -> {:.2f} %\n", 100 * c.rms_before, 100 * c.rms_after);
    }
  }
  return kExitOk;
}

// One record's fit into `out_dir`; `summary` (optional) receives its verdict and discrepancy.
namespace {

int FitOneRecord(const FitOptions& options, const std::string& measured_path,
                 const std::string& out_dir, RecordDiscrepancy* summary) {
  const auto start = std::chrono::steady_clock::now();
  // The declared config, kept as a tree: each candidate effect is read through it with its own
  // --set overrides.
  std::optional<ConfigVariants> variants;
  MeasuredRecord record;
  std::optional<MeasurementParams> from_record;  // an ambdrop run record's own measurement
  try {
    variants.emplace(ConfigVariants::Load(options.config_path, options.overrides));
    const LoadedConfig& config = variants->declared();
    if (IsEventLog(measured_path)) {
      RunRecordFile file;
      try {
        file = ReadRunRecord(measured_path);
      } catch (const std::exception& e) {
        throw MeasuredRecordError(e.what());
      }
      for (const std::string& w : file.warnings) fmt::print(stderr, "warning: {}\n", w);
      // The recorded rig names the columns and gives the flux decay the currents followed; if
      // its config no longer loads, the declared one stands in.
      std::optional<LoadedConfig> recorded;
      try {
        recorded =
            LoadConfigFromString(file.header.config_toml, measured_path + " (recorded config)");
      } catch (const std::exception& e) {
        fmt::print(stderr, "warning: {}; the record is read with {}'s rig\n", e.what(),
                   options.config_path);
      }
      const ModelParams& rig = recorded ? recorded->params : config.params;
      RecordAsMeasurement converted;
      try {
        converted = MeasurementFromRunRecord(file, rig);
      } catch (const std::invalid_argument& e) {
        throw MeasuredRecordError(measured_path + ": " + e.what());
      }
      record = std::move(converted.record);
      record.source = measured_path;
      const double interval = 1.0 / converted.measurement.sample_rate_Hz;
      if (std::abs(record.SampleInterval() / interval - 1.0) > 0.01) {
        throw MeasuredRecordError(fmt::format(
            "{}: sensor samples are missing: {} samples over {:.6g} s, at a period of {:.6g} s",
            measured_path, record.time_s.size(), record.time_s.back() - record.time_s.front(),
            interval));
      }
      if (!config.measurement) {
        from_record =
            InDeclaredOrder(converted.measurement, rig, config.params, options.config_path);
      }
    } else {
      if (!config.measurement) {
        throw ConfigError(options.config_path +
                          ": no [measurement] table: say which record column is which quantity "
                          "(see io/config/config_measurement.hpp)");
      }
      record = ReadMeasuredRecord(measured_path, *config.measurement);
    }
    CheckRecord(from_record ? *from_record : *config.measurement, record, options.config_path);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitConfig;
  }
  const LoadedConfig& config = variants->declared();
  const MeasurementParams& m = from_record ? *from_record : *config.measurement;

  FitRecordOptions fit_options;
  fit_options.run.lead_s = options.lead_s;
  fit_options.rules.threads = options.threads;
  fit_options.rules.max_runs_per_start = options.max_runs_per_start;
  fit_options.rules.tolerance = options.tolerance;
  fit_options.rules.jitter_draws = options.jitter_draws;
  fit_options.choose_step = !options.declared_step;
  std::unique_ptr<FitResult> fit;
  try {
    fit = FitRecord(*variants, m, record, fit_options);
  } catch (const DeclaredModelStopped& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitRunFailed;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitConfig;
  }
  for (const std::string& channel : fit->left_out) {
    fmt::print(stderr, "warning: channel {} never moves beyond its noise: left out of the fit\n",
               channel);
  }
  const Selection& selection = fit->selection;
  FitOutcome outcome;
  outcome.config_path = options.config_path;
  outcome.measured_path = measured_path;
  outcome.before = fit->residual_before;
  outcome.after = fit->residual_after;
  outcome.selection = &selection;
  outcome.step = &fit->step;
  outcome.sensor_noise = &fit->sensor_noise;
  outcome.library = &fit->library;
  outcome.chosen = fit->chosen;
  outcome.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const Discrepancy discrepancy = DescribeDiscrepancy(config.params, fit->measurement, record,
                                                      fit->after, fit->residual_after, selection);
  outcome.discrepancy = &discrepancy;
  if (summary != nullptr) {
    summary->record = measured_path;
    summary->verdict = selection.verdict;
    summary->discrepancy = discrepancy;
    summary->signatures = fit->residual_before.signatures;
    summary->chosen = selection.chosen;
  }
  try {
    const fs::path out(out_dir);
    fs::create_directories(out);
    WriteTextFile(out / "fit.json", FitJson(outcome, config.params, fit->measurement));
    WriteFitReport(out, outcome, config.params, fit->measurement, record, fit->before, fit->after);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }
  if (!options.quiet) {
    fmt::print("{}: {} ({})\n", measured_path, selection.verdict, selection.reason);
    fmt::print("  overall relative RMS {:.4g} -> {:.4g}; chosen: {}\n", selection.rms_before,
               selection.rms_after,
               selection.chosen.empty() ? std::string("none")
                                        : fmt::format("{}", fmt::join(selection.chosen, ", ")));
    for (const ParameterEstimate& p : selection.chosen_fit.parameters) {
      fmt::print("    {} {} = {:.6g} +- {:.2g}{}\n", p.effect, p.name, p.value, p.sigma,
                 p.decided ? "" : " (not decided by the record: report.md says why)");
    }
    const auto fitted = std::count_if(selection.candidates.begin(), selection.candidates.end(),
                                      [](const CandidateScore& c) { return c.tried; });
    fmt::print("  {} of {} candidates fitted in {:.1f} s; {}/fit.json, {}/report.md\n", fitted,
               selection.candidates.size(), outcome.wall_time_s, out_dir, out_dir);
  }
  return kExitOk;
}

// Several records of one rig: each fitted into its own directory, then what they share.
int FitSeveralRecords(const FitOptions& options) {
  const fs::path out(options.out_dir);
  std::vector<RecordDiscrepancy> records;
  std::vector<std::string> dirs;
  int exit_code = kExitOk;
  for (std::size_t i = 0; i < options.measured_paths.size(); ++i) {
    const std::string& path = options.measured_paths[i];
    // One directory per record, named by its file and its place on the command line (two
    // records of one name in different folders stay apart).
    const std::string dir =
        (out / fmt::format("{:02d}_{}", i + 1, fs::path(path).stem().string())).string();
    RecordDiscrepancy r;
    const int code = FitOneRecord(options, path, dir, &r);
    if (code != kExitOk) {
      exit_code = exit_code == kExitOk ? code : exit_code;
      continue;
    }
    records.push_back(std::move(r));
    dirs.push_back(dir);
  }
  const std::vector<std::string> shared = SharedDiscrepancies(records);
  try {
    fs::create_directories(out);
    JsonWriter json;
    json.BeginObject();
    json.Key("schema_version").Integer(1);
    json.Key("config").String(options.config_path);
    json.Key("records").BeginArray();
    for (std::size_t i = 0; i < records.size(); ++i) {
      const RecordDiscrepancy& r = records[i];
      json.BeginObject();
      json.Key("record").String(r.record);
      json.Key("out").String(dirs[i]);
      json.Key("verdict").String(r.verdict);
      json.Key("discrepancy");
      DiscrepancyJson(json, r.discrepancy);
      json.EndObject();
    }
    json.EndArray();
    json.Key("failed_records")
        .Integer(static_cast<std::int64_t>(options.measured_paths.size() - records.size()));
    json.Key("shared").BeginArray();
    for (const std::string& line : shared) json.String(line);
    json.EndArray();
    json.EndObject();
    WriteTextFile(out / "shared.json", json.str());
    std::string md = fmt::format("# {} records of {}\n\n", records.size(), options.config_path);
    md += "| record | verdict | residual left mostly on | shape |\n|---|---|---|---|\n";
    for (const RecordDiscrepancy& r : records) {
      md += fmt::format("| {} | {} | {} | {} |\n", r.record, r.verdict,
                        r.discrepancy.dominant ? r.discrepancy.channel : "-",
                        r.discrepancy.dominant ? r.discrepancy.shape : "-");
    }
    md += "\n## What the records share\n\n";
    if (shared.empty()) md += "Nothing: each record's residual is its own.\n";
    for (const std::string& line : shared) md += "- " + line + "\n";
    if (records.size() < options.measured_paths.size()) {
      md += fmt::format("\n{} record(s) could not be fitted (see stderr).\n",
                        options.measured_paths.size() - records.size());
    }
    WriteTextFile(out / "shared.md", md);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }
  if (!options.quiet) {
    fmt::print("{} of {} records fitted; shared by all: {}\n", records.size(),
               options.measured_paths.size(), shared.empty() ? "nothing" : "");
    for (const std::string& line : shared) fmt::print("  - {}\n", line);
    fmt::print("  {}/shared.md, {}/shared.json\n", options.out_dir, options.out_dir);
  }
  return exit_code;
}

}  // namespace

int RunFitCommand(const FitOptions& options) {
  if (!options.spin_up_times.empty()) return RunSpinUpFit(options);
  if (options.measured_paths.empty()) {
    fmt::print(stderr, "error: give the record (--measured FILE...) or --spin-up-times\n");
    return kExitUsage;
  }
  if (options.measured_paths.size() == 1) {
    return FitOneRecord(options, options.measured_paths.front(), options.out_dir, nullptr);
  }
  return FitSeveralRecords(options);
}

RegisteredCommand AddFitCommand(CLI::App& app) {
  auto options = std::make_shared<FitOptions>();
  CLI::App* fit_command = app.add_subcommand(
      "fit",
      "Hold the model against a measured record: residuals, the missing effect, its parameters, "
      "and the error before and after");
  fit_command->add_option("CONFIG", options->config_path, "The declared model, with [measurement]")
      ->required();
  CLI::Option* measured_option =
      fit_command
          ->add_option("--measured", options->measured_paths,
                       "The measured record: CSV, or an ambdrop run record (.lcm); several "
                       "records of one rig: each fitted, and what they share")
          ->type_name("FILE...");
  CLI::Option* spin_up_option =
      fit_command
          ->add_option("--spin-up-times", options->spin_up_times,
                       "Instead of a record: measured TDB spin-up times after the trigger, "
                       "e.g. de=0.11,nde=0.129; which single parameter change explains them")
          ->type_name("TDB=S,...");
  measured_option->excludes(spin_up_option);
  fit_command
      ->add_option("--out", options->out_dir, "Output directory (options->json, report.md, plots)")
      ->type_name("DIR")
      ->capture_default_str();
  AddSetOption(fit_command, &options->overrides);
  fit_command
      ->add_option("--lead-s", options->lead_s,
                   "Simulate from this long before the trigger, from the measured state")
      ->check(kFinite & CLI::PositiveNumber)
      ->capture_default_str();
  fit_command->add_option("--threads", options->threads, "Candidates fitted in parallel")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  fit_command
      ->add_option("--max-runs", options->max_runs_per_start,
                   "Model runs per start of each candidate's search")
      ->check(CLI::Range(4, 10000))
      ->capture_default_str();
  fit_command
      ->add_option("--tolerance", options->tolerance,
                   "A relative RMS residual within which model and record agree anyway, added "
                   "in quadrature to the limit the record's noise and the model's sensitivity "
                   "set (0: the record alone decides)")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->capture_default_str();
  fit_command
      ->add_option("--jitter-draws", options->jitter_draws,
                   "Where the declared model agrees with the drop's start and departs after "
                   "it: this many runs of it with its rotor's jitter at the trigger drawn, "
                   "before any effect is taken for the departure (four times as many where the "
                   "closest came within 1.25 times the limit; and four times as many of the "
                   "fitted model, before a second effect is fitted to its speeds); up to 8 of "
                   "them also span the start's own sensitivity to that jitter (0: none)")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  fit_command->add_flag("--declared-step", options->declared_step,
                        "Run every model at the config's step (default: up to 4x coarser "
                        "where that widens no agreement limit by over 5 %: a move under 0.2 of "
                        "the record's noise, or within the model's sensitivity to its start)");
  fit_command->add_flag("--quiet,-q", options->quiet, "No summary on stdout");
  return {fit_command, [options] { return RunFitCommand(*options); }};
}

}  // namespace ambdrop
