#include "tools/cli/replay_command.hpp"

#include <fmt/format.h>

#include <chrono>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>

#include "controller_if/loop/replay_run.hpp"
#include "io/config/config_loader.hpp"
#include "io/files/json_writer.hpp"
#include "io/files/timeseries_csv.hpp"
#include "rt_core/model.hpp"
#include "tools/cli/cli_registry.hpp"
#include "tools/cli/exit_codes.hpp"
#include "tools/record/candump_record.hpp"
#include "tools/record/profile_export.hpp"
#include "tools/record/run_record_reader.hpp"
#include "tools/record/sensor_diff.hpp"
#include "tools/record/trajectory_hasher.hpp"
#include "tools/validation/run_summary.hpp"
#include "tools/validation/tdb_summary_json.hpp"

namespace ambdrop {
namespace {

namespace fs = std::filesystem;

const char* StatusText(const ReplayResult& result) {
  if (result.watchdog_stop) return "watchdog_stop";
  return result.status == StepStatus::kOk ? "ok" : "diverged";
}

int ExportProfile(const RunRecordFile& record, const ReplayOptions& options) {
  ProfileExport exported;
  try {
    exported = ExportCurrentProfile(record, options.record_path, options.profile);
  } catch (const ConfigError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitConfig;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }
  try {
    WriteTextFile(options.export_profile_path, exported.toml);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }
  for (const std::string& n : exported.notes) fmt::print(stderr, "note: {}\n", n);
  if (!options.quiet) {
    fmt::print("{}: {} recorded current samples as {} profile points per AMB (within {:.3g} A)\n",
               options.export_profile_path, exported.recorded_samples, exported.points,
               exported.max_error_A);
  }
  return kExitOk;
}

}  // namespace

int RunReplayCommand(const ReplayOptions& options) {
  const bool candump = IsCandumpLog(options.record_path);
  if (candump && options.config_path.empty()) {
    fmt::print(stderr,
               "error: {} is a candump log: give the config whose [can] frame map it follows "
               "(--config)\n",
               options.record_path);
    return kExitUsage;
  }
  RunRecordFile record;
  if (!candump) {
    try {
      record = ReadRunRecord(options.record_path);
    } catch (const std::exception& e) {
      fmt::print(stderr, "error: {}\n", e.what());
      return kExitError;
    }
  }
  for (const std::string& w : record.warnings) fmt::print(stderr, "warning: {}\n", w);
  if (!options.export_profile_path.empty()) {
    if (candump) {
      fmt::print(stderr, "error: --export-profile takes an ambdrop record, not a candump log\n");
      return kExitUsage;
    }
    return ExportProfile(record, options);
  }

  const bool recorded_config = !candump && options.config_path.empty() && options.overrides.empty();
  LoadedConfig config;
  std::optional<Model> model;
  try {
    config =
        options.config_path.empty()
            ? LoadConfigFromString(record.header.config_toml,
                                   options.record_path + " (recorded config)", options.overrides)
            : LoadConfig(options.config_path, options.overrides);
    model.emplace(BuildModel(config.params));
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitConfig;
  }
  std::optional<CandumpRecord> dump;  // its counts go into summary.json
  if (candump) {
    if (!config.can) {
      fmt::print(stderr, "error: {}: no [can] table to read the candump log with\n",
                 options.config_path);
      return kExitConfig;
    }
    try {
      dump = ReadCandumpRecord(
          options.record_path, *model, *config.can,
          options.align == "sequence" ? CandumpAlign::kSequence : CandumpAlign::kTime);
      for (const std::string& w : dump->warnings) fmt::print(stderr, "warning: {}\n", w);
      if (!options.quiet) {
        fmt::print(
            "{}: {} frames, {} from the controller, {} sensor sets, {} unknown, {} "
            "malformed lines, {} out of order, {} after the run's end\n",
            options.record_path, dump->frames, dump->controller_frames, dump->sensors.size(),
            dump->unknown_frames, dump->malformed_lines, dump->out_of_order_lines,
            dump->frames_after_end);
      }
      record.run = std::move(dump->run);
      record.sensors = std::move(dump->sensors);
      record.warnings = dump->warnings;
      record.damaged = dump->damaged();
      record.header.source = "candump";
      record.header.step_s = model->params.simulation.step_s;
    } catch (const std::exception& e) {
      fmt::print(stderr, "error: {}\n", e.what());
      return kExitError;
    }
  }
  // The record's end is bounded by its header; a config given here may be shorter (as the
  // candump path bounds it by the config too).
  if (record.run.end_step > model->total_steps) {
    fmt::print(stderr,
               "warning: the record ends at step {}, beyond the config's {} steps: the replay "
               "stops there\n",
               record.run.end_step, model->total_steps);
    record.run.end_step = model->total_steps;
  }
  if (model->params.simulation.step_s != record.header.step_s) {
    fmt::print(stderr,
               "error: the config's simulation.step_s ({} s) differs from the record's ({} s): "
               "recorded steps would fall at other times\n",
               model->params.simulation.step_s, record.header.step_s);
    return kExitConfig;
  }

  const fs::path out_dir(options.out_dir);
  std::optional<TimeseriesCsvWriter> csv;
  try {
    fs::create_directories(out_dir);
    WriteTextFile(out_dir / "effective_config.toml", config.effective_toml);
    csv.emplace(out_dir / "timeseries.csv", *model);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitError;
  }

  std::vector<std::string> sensor_names;
  for (const SensorParams& s : model->params.sensors) sensor_names.push_back(s.name);
  // By value within this tolerance (replay --strict): an ambdrop record's readings are the
  // emulator's own doubles (0: -0 equals 0, nothing else does); a candump log's are the frame
  // map's counts, so half the coarsest sensor count.
  double tolerance_m = options.tolerance_m;
  if (tolerance_m < 0.0) {
    tolerance_m = 0.0;
    if (dump) {
      for (const CanSignalSpec& signal : config.can->frame_map.spec().signals) {
        if (signal.role == CanSignalRole::kSensor) {
          tolerance_m = std::max(tolerance_m, 0.5 * std::abs(signal.scaling.scale));
        }
      }
    }
  }
  SensorDiff diff(record.sensors, sensor_names, tolerance_m);
  RunSummary summary(model->params);
  std::string output_error;
  TrajectoryHasher hasher(model->params.sensors.size());
  hasher.HashSensorsUpTo(record.sensors.empty() ? -1 : record.sensors.back().step);
  const auto start = std::chrono::steady_clock::now();
  const ReplayResult result = ReplayRun(
      *model, record.run,
      [&](const Observation& o) {
        summary.Add(o);
        if (!output_error.empty()) return;
        try {
          csv->Write(o);
        } catch (const std::exception& e) {
          output_error = e.what();
        }
      },
      [&](const RecordedSensors& s) { diff.Add(s); }, {}, &hasher);
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  try {
    csv->Close();
  } catch (const std::exception& e) {
    if (output_error.empty()) output_error = e.what();
  }

  const double dt = model->params.simulation.step_s;
  JsonWriter json;
  json.BeginObject();
  json.Key("record").String(options.record_path);
  json.Key("source").String(record.header.source);
  json.Key("recorded_with").String(record.header.ambdrop_version);
  json.Key("config").String(recorded_config ? "recorded" : options.config_path);
  json.Key("config_hash_recorded").String(record.header.config_hash);
  // A replay whose outputs failed is not ok, even if its physics was.
  // Nor is a strict replay that does not reproduce its record.
  const bool physics_ok = result.status == StepStatus::kOk && !result.watchdog_stop;
  json.Key("status").String(physics_ok && !output_error.empty() ? "output_error"
                            : physics_ok && options.strict && !diff.within_tolerance()
                                ? "replay_differs"
                                : StatusText(result));
  json.Key("output_error");
  if (output_error.empty()) {
    json.Null();
  } else {
    json.String(output_error);
  }
  json.Key("recorded_status").String(record.footer ? record.footer->status : "unknown");
  json.Key("steps").Integer(result.steps);
  json.Key("damaged").Bool(record.damaged);
  json.Key("wall_time_s").Number(wall_s);
  json.Key("trajectory_hash").String(hasher.Hex());
  json.Key("replay").BeginObject();
  json.Key("strict").Bool(options.strict);
  if (dump) json.Key("align").String(options.align);
  diff.WriteJson(json, dt);
  json.EndObject();
  if (dump) {
    json.Key("candump").BeginObject();
    json.Key("frames").Integer(dump->frames);
    json.Key("controller_frames").Integer(dump->controller_frames);
    json.Key("unknown_frames").Integer(dump->unknown_frames);
    json.Key("malformed_lines").Integer(dump->malformed_lines);
    json.Key("out_of_order_lines").Integer(dump->out_of_order_lines);
    json.Key("frames_after_end").Integer(dump->frames_after_end);
    json.EndObject();
  }
  json.Key("warnings").BeginArray();
  for (const std::string& w : record.warnings) json.String(w);
  json.EndArray();
  WriteTdbSummaries(json, summary);
  json.EndObject();
  try {
    WriteTextFile(out_dir / "summary.json", json.str());
  } catch (const std::exception& e) {
    if (output_error.empty()) output_error = e.what();
  }

  if (!options.quiet) {
    fmt::print("{}: replayed {} steps ({:.3f} s simulated) in {:.2f} s: {}\n", options.record_path,
               result.steps, result.steps * dt, wall_s, StatusText(result));
    fmt::print("sensor outputs vs the record: {}\n", diff.Describe(dt));
  }
  if (!output_error.empty()) {
    fmt::print(stderr, "error: {}\n", output_error);
    return kExitError;
  }
  if (result.status != StepStatus::kOk && !result.failure_message.empty()) {
    fmt::print(stderr, "replay stopped: {}\n", result.failure_message);
  }
  if (options.strict && !diff.within_tolerance()) {
    fmt::print(stderr,
               "error: --strict: the replay does not reproduce the record within {:.3g} m: {} "
               "of {} samples beyond it, {} not reproduced\n",
               tolerance_m, diff.beyond_tolerance(), diff.compared(), diff.missing());
    return kExitExpectationFailed;
  }
  if (recorded_config && !diff.identical() && !record.damaged) {
    fmt::print(stderr,
               "error: with the recorded config the replay must reproduce the record bit for bit, "
               "and it does not: {}\n",
               diff.Describe(dt));
    return kExitRunFailed;
  }
  return kExitOk;
}

RegisteredCommand AddReplayCommand(CLI::App& app) {
  auto options = std::make_shared<ReplayOptions>();
  CLI::App* replay_command = app.add_subcommand(
      "replay", "Re-run a recorded run offline from its inputs and compare with the record");
  replay_command->add_option("RECORD", options->record_path, "LCM event log from --record")
      ->required();
  replay_command->add_option("--config", options->config_path,
                             "Replay with this config instead of the recorded one (reports the "
                             "differences)");
  replay_command->add_flag("--strict", options->strict,
                           "Exit 4 unless every recorded sensor sample is reproduced within "
                           "--tolerance-m (by value: -0 equals 0)");
  replay_command
      ->add_option("--tolerance-m", options->tolerance_m,
                   "Tolerance of --strict (m); default 0 for an ambdrop record, half the frame "
                   "map's coarsest sensor count for a candump log")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->type_name("M");
  replay_command
      ->add_option("--align", options->align,
                   "How a candump log's frames are placed at steps: time (receive times, a live "
                   "run) or sequence (the k-th sensor frame is the k-th exchange: a lock-step "
                   "capture)")
      ->check(CLI::IsMember({"time", "sequence"}))
      ->capture_default_str();
  replay_command->add_option("--out", options->out_dir, "Output directory")
      ->type_name("DIR")
      ->capture_default_str();
  AddSetOption(replay_command, &options->overrides);
  replay_command->add_flag("--quiet,-q", options->quiet, "No report on stdout");
  CLI::Option* export_profile =
      replay_command
          ->add_option("--export-profile", options->export_profile_path,
                       "Instead of replaying, write the recorded coil currents as a rig config "
                       "driven by current profiles ([controller] kind = \"none\"), for "
                       "`ambdrop sim` or a scenario's base")
          ->type_name("FILE.toml");
  replay_command
      ->add_option("--profile-points", options->profile.max_points,
                   "At most this many points per AMB profile")
      ->check(CLI::Range(2, 1024))
      ->needs(export_profile)
      ->capture_default_str();
  replay_command
      ->add_option("--profile-from", options->profile.from_s,
                   "Export from this record time (s); the profile starts there at 0 s")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->needs(export_profile)
      ->capture_default_str();
  replay_command
      ->add_option("--profile-to", options->profile.to_s, "Export up to this record time (s)")
      ->check(kFinite & CLI::PositiveNumber)
      ->needs(export_profile);
  return {replay_command, [options] { return RunReplayCommand(*options); }};
}

}  // namespace ambdrop
