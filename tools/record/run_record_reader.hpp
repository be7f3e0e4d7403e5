#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "controller_if/loop/run_record.hpp"
#include "rt_core/limits.hpp"
#include "tools/record/run_record_writer.hpp"

namespace ambdrop {

struct RecordHeader {
  std::string ambdrop_version;
  std::string source;
  std::string controller;
  std::string config_toml;
  std::string config_hash;
  double step_s = 0.0;
  std::int64_t sensor_every_steps = 0;
  std::int64_t output_every_steps = 1;
  std::int64_t total_steps = 0;
};

struct RecordFooter {
  std::string status;
  std::int64_t final_step = 0;
  RecordCounts produced;
  RecordCounts written;
};

/// One periodic state event (AMBDROP_STATE) as read back: what the run observed at that step.
/// A replay recomputes the state; a record read as a measurement (tools/fit/) reads these.
struct RecordedStateSample {
  std::int64_t step = 0;
  double time_s = 0.0;
  bool power_on = true;
  double spin_speed_rad_s = 0.0;
  double spin_angle_rad = 0.0;
  int tdb_count = 0;  ///< entries at and beyond it are zero
  std::array<double, kMaxTdbs> tdb_normal_force_N{};
  std::array<double, kMaxTdbs> tdb_tangential_force_N{};
  std::array<double, kMaxTdbs> tdb_penetration_m{};
  std::array<double, kMaxTdbs> tdb_race_speed_rad_s{};
  std::array<std::array<double, 2>, kMaxTdbs> tdb_journal_xy_m{};
  std::int64_t fault_count = 0;
};

/// A run record as read back: the trusted part of it, and what was wrong with the rest.
struct RunRecordFile {
  RecordHeader header;
  RecordedRun run;
  std::vector<RecordedSensors> sensors;     ///< the samples sent live, in step order
  std::vector<RecordedStateSample> states;  ///< the periodic states, in step order
  std::optional<RecordFooter> footer;
  std::int64_t events_read = 0;  ///< trusted events (checks excluded)
  /// Damage or inconsistency, each saying where (byte offset, event number, step). Empty for a
  /// sound record.
  std::vector<std::string> warnings;
  bool damaged = false;  ///< the replay covers only the part before the damage
};

/// Reads a record written by RunRecordWriter. Throws std::runtime_error only when nothing can
/// be used (no file, no valid header); damage after the header ends the reading with a warning:
/// events in a check block that fails, or after a corrupt spot, are not used; events after the
/// last check of a truncated file are used (they parsed whole) with a warning.
RunRecordFile ReadRunRecord(const std::filesystem::path& path);

}  // namespace ambdrop
