#pragma once
// The [measurement] table: how the columns of a measured record (io/measured_csv.hpp) map onto
// the model's quantities, for `ambdrop fit`. Example:
//
//   [measurement]
//   sample_rate_Hz = 20000.0        # the record's; its t column is checked against it
//   trigger_time_s = 0.2            # or: trigger = "detect" (from the coil currents)
//   [[measurement.channel]]
//   column = "x_de"                 # header name in the CSV
//   quantity = "displacement"       # displacement | current | tdb_normal_force | tdb_speed |
//   sensor = "de"                   #   rotor_speed
//   axis = "x"
//
// displacement: sensor + axis (m, the sensor's reading); current: amb + axis (A, control
// current); tdb_normal_force: tdb (N); tdb_speed: tdb (rad/s, inner race); rotor_speed (rad/s).
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rt_core/model_params.hpp"

namespace ambdrop {

// Declared, not included: io/config_loader.hpp includes this header, and toml++ (which
// io/toml_reader.hpp brings) must stay inside io, the one target built with its library flags.
namespace config_detail {
class TableReader;
}  // namespace config_detail

enum class MeasuredQuantity {
  kDisplacement,
  kCurrent,
  kTdbNormalForce,
  kTdbSpeed,
  kRotorSpeed,
};

/// The config spelling of a quantity: "displacement", "current", "tdb_normal_force", ...
std::string_view MeasuredQuantityName(MeasuredQuantity quantity);

struct MeasurementChannel {
  std::string column;  ///< CSV header name
  MeasuredQuantity quantity = MeasuredQuantity::kDisplacement;
  int index = -1;  ///< sensor, AMB or TDB index in the model's order; -1 for rotor_speed
  int axis = -1;   ///< 0 = x, 1 = y for displacement and current; -1 otherwise
  std::string Describe(const ModelParams& params) const;  ///< "displacement de x"
  static MeasurementChannel Of(std::string column, MeasuredQuantity quantity, int index, int axis) {
    return {std::move(column), quantity, index, axis};
  }
};

/// "x" for axis 0, "y" otherwise: the axis as column names and the [measurement] table spell it.
inline const char* MeasurementAxisName(int axis) {
  return axis == 0 ? "x" : "y";
}

struct MeasurementParams {
  double sample_rate_Hz = 0.0;
  /// The time power failed, in record time; empty with detect_trigger.
  std::optional<double> trigger_time_s;
  bool detect_trigger = false;
  std::vector<MeasurementChannel> channels;  ///< in the config's order; columns are unique
};

namespace config_detail {
/// Reads [measurement] strictly (unknown keys, unknown sensor/AMB/TDB names, a key that the
/// quantity does not take, a duplicate column, neither or both of trigger_time_s and trigger:
/// each a ConfigError naming file, line and key).
MeasurementParams ReadMeasurement(const TableReader& table, const ModelParams& params);
}  // namespace config_detail

}  // namespace ambdrop
