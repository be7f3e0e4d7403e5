#pragma once
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "rt_core/model.hpp"
#include "rt_core/simulator.hpp"

namespace ambdrop {

/// Writes observations as CSV: one header row whose column names carry their units, then one
/// row per observation. Every number is printed with 17 significant digits, so the file holds
/// the exact doubles the simulator produced (two runs can be compared with `cmp`).
///
/// Columns, sensors and TDBs in model order:
///   time_s,
///   sensor_<name>_x_m, sensor_<name>_y_m            (per sensor)
///   spin_speed_rad_s,
///   tdb_<name>_normal_force_N, tdb_<name>_tangential_force_N, tdb_<name>_penetration_m,
///   tdb_<name>_spin_speed_rad_s, tdb_<name>_journal_x_m, tdb_<name>_journal_y_m  (per TDB)
/// and, written with the AMBs' currents (amb_currents), last:
///   amb_<name>_x_command_A, amb_<name>_y_command_A, amb_<name>_x_coil_A, amb_<name>_y_coil_A
///   (per AMB; AmbCurrents says what each is).
class TimeseriesCsvWriter {
 public:
  /// Opens (truncates) `path` and writes the header; throws std::runtime_error if it cannot,
  /// std::invalid_argument if there are more names than an Observation has slots.
  TimeseriesCsvWriter(const std::filesystem::path& path, std::vector<std::string> sensor_names,
                      std::vector<std::string> tdb_names, std::vector<std::string> amb_names = {});
  /// Sensor and TDB names from the model's parameters.
  TimeseriesCsvWriter(const std::filesystem::path& path, const Model& model);
  /// With `amb_currents`, every AMB's currents as the last columns (rows through Write(obs, c)).
  TimeseriesCsvWriter(const std::filesystem::path& path, const Model& model, bool amb_currents);
  ~TimeseriesCsvWriter();

  TimeseriesCsvWriter(const TimeseriesCsvWriter&) = delete;
  TimeseriesCsvWriter& operator=(const TimeseriesCsvWriter&) = delete;

  static std::vector<std::string> ColumnNames(const std::vector<std::string>& sensor_names,
                                              const std::vector<std::string>& tdb_names,
                                              const std::vector<std::string>& amb_names = {});

  /// Appends one row (buffered; I/O errors surface at Flush or Close).
  /// Without AMB columns only (std::logic_error otherwise: the row would be short).
  void Write(const Observation& observation);
  /// With AMB columns: the row's currents (currents of a writer without AMB columns are dropped).
  void Write(const Observation& observation, const AmbCurrents& currents);
  /// Hands the buffered rows to the file; throws std::runtime_error on an I/O error.
  void Flush();
  /// Flushes and closes; throws std::runtime_error on an I/O error. Idempotent.
  void Close();

  std::int64_t rows() const noexcept { return rows_; }
  const std::filesystem::path& path() const noexcept { return path_; }

 private:
  std::filesystem::path path_;
  std::vector<std::string> sensor_names_;
  std::vector<std::string> tdb_names_;
  std::vector<std::string> amb_names_;  ///< empty: no current columns
  std::ofstream out_;
  std::string buffer_;  ///< rows formatted but not yet handed to out_
  std::int64_t rows_ = 0;
};

}  // namespace ambdrop
