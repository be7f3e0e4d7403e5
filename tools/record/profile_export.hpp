#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "tools/record/run_record_reader.hpp"

namespace ambdrop {

struct ProfileExport {
  std::string toml;                  ///< the rig config (io/config/profile_config.hpp)
  std::size_t recorded_samples = 0;  ///< current samples in the record (start included)
  std::size_t points = 0;            ///< profile points written per AMB
  double max_error_A = 0.0;          ///< largest interpolation error left by the decimation
  std::vector<std::string> notes;    ///< what the rig cannot carry over (told to the user)
};

/// The part of a record to export, in record time.
struct ProfileWindow {
  double from_s = 0.0;
  double to_s = -1.0;             ///< < 0: the record's end
  std::size_t max_points = 1024;  ///< per AMB; kMaxProfilePoints at most
};

/// `ambdrop replay RECORD --export-profile FILE.toml`: the record's coil currents over the window
/// as current profiles timed from its start, its first power failure in the window (and the
/// restore after it) as the rig's [trigger], on the config it was recorded with.
/// Throws (ConfigError, std::runtime_error) when the record's config cannot take a profile or
/// the window is not inside the record.
ProfileExport ExportCurrentProfile(const RunRecordFile& record, const std::string& record_path,
                                   const ProfileWindow& window);

}  // namespace ambdrop
